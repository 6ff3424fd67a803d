"""Depth and color files.

Representation rules, set here once:

- A depth file is read in its own dtype (uint8, uint16, float32, ...), as a
  2-D array; 0 (and NaN in float files) means "no measurement". The library
  (:func:`depthrefine.refine`) turns it into float32 with NaN for invalid.
- A depth map is written in the dtype of the input file: integer types are
  rounded and clipped to ``[1, max]`` for valid pixels so that a valid depth
  never becomes 0; invalid pixels (NaN) are written as 0 in every format.
- A color file is read as RGB (H, W, 3) uint8 or uint16 (never BGR); a gray
  image is repeated to three channels and an alpha channel is dropped.

Formats: PNG (8/16-bit), TIFF (any dtype, float32 for metric depth), NumPy
``.npy``; color also JPEG/BMP and anything else OpenCV reads.
"""

from __future__ import annotations

import os
from pathlib import Path

import cv2
import numpy as np
import tifffile

from .._validate import check_rgb
from ._files import InputFileError, atomic_write, check_output

__all__ = [
    "read_depth",
    "write_depth",
    "read_rgb",
    "write_rgb",
    "DEPTH_SUFFIXES",
    "depth_to_dtype",
]

DEPTH_SUFFIXES = (".png", ".tif", ".tiff", ".npy", ".pgm")
_INTEGER_SUFFIXES = (".png", ".pgm")


def _existing(path: str | os.PathLike, what: str) -> Path:
    p = Path(path)
    if not p.exists():
        raise InputFileError(f"{what} file {p} does not exist.")
    if p.is_dir():
        raise InputFileError(f"{what} file {p} is a folder; give an image file.")
    if not os.access(p, os.R_OK):
        raise InputFileError(f"{what} file {p} is not readable (permissions).")
    return p


def _read_any(p: Path, what: str) -> np.ndarray:
    suffix = p.suffix.lower()
    try:
        if suffix == ".npy":
            arr = np.load(p, allow_pickle=False)
        elif suffix in (".tif", ".tiff"):
            arr = tifffile.imread(p)
        else:
            arr = cv2.imread(str(p), cv2.IMREAD_UNCHANGED)
            if arr is None:
                raise InputFileError(
                    f"{what} file {p} cannot be read as an image (truncated, or not an image file)."
                )
    except InputFileError:
        raise
    except Exception as exc:  # noqa: BLE001 - any decoder failure is a bad file
        raise InputFileError(f"{what} file {p} cannot be read: {type(exc).__name__}: {exc}") from None
    if not isinstance(arr, np.ndarray) or arr.dtype == object:
        raise InputFileError(f"{what} file {p} does not hold a numeric image.")
    return arr


def read_depth(path: str | os.PathLike) -> np.ndarray:
    """Read a depth map in its own dtype; 0 (or NaN) marks missing pixels.

    Parameters
    ----------
    path : str or path-like
        ``.png`` (8/16-bit), ``.tif``/``.tiff`` (any dtype), ``.npy`` or ``.pgm``.

    Returns
    -------
    (h, w) ndarray
        uint8, uint16, int16, int32, float32 or float64, as stored.

    Raises
    ------
    InputFileError (a ValueError)
        Missing, unreadable or non-depth file (e.g. a color image).
    """
    p = _existing(path, "depth")
    arr = _read_any(p, "depth")
    if arr.ndim == 3 and arr.shape[2] in (3, 4) and p.suffix.lower() not in (".npy", ".tif", ".tiff"):
        # A gray depth map saved as RGB: accept when the channels agree.
        if np.array_equal(arr[:, :, 0], arr[:, :, 1]) and np.array_equal(arr[:, :, 0], arr[:, :, 2]):
            arr = arr[:, :, 0]
    if arr.ndim == 3 and arr.shape[2] == 1:
        arr = arr[:, :, 0]
    if arr.ndim != 2:
        raise InputFileError(
            f"depth file {p} holds an array of shape {arr.shape}; a depth map is one channel "
            "(rows, cols). Is this the color image?"
        )
    if arr.dtype.kind not in "uif" or arr.dtype.itemsize > 8 or arr.dtype == np.uint32 or arr.dtype == np.uint64:
        raise InputFileError(f"depth file {p} has unsupported dtype {arr.dtype}; use 8/16-bit PNG or float TIFF.")
    if arr.dtype == np.int8:
        arr = arr.astype(np.int16)
    if arr.dtype == np.float16:
        arr = arr.astype(np.float32)
    if arr.size == 0:
        raise InputFileError(f"depth file {p} is empty.")
    return np.ascontiguousarray(arr)


def depth_to_dtype(depth: np.ndarray, dtype: np.dtype | type) -> np.ndarray:
    """Convert a float depth map (NaN = invalid) to ``dtype`` for writing.

    Integers: rounded, valid pixels clipped to ``[1, max]``, NaN -> 0.
    Floats: NaN -> 0 (0 means no measurement in a file).

    Examples
    --------
    >>> depth_to_dtype(np.array([np.nan, 0.2, 7.6, 300.0], np.float32), np.uint8).tolist()
    [0, 1, 8, 255]
    """
    dtype = np.dtype(dtype)
    depth = np.asarray(depth, dtype=np.float64)
    invalid = ~np.isfinite(depth)
    if dtype.kind in "ui":
        info = np.iinfo(dtype)
        out = np.clip(np.floor(np.where(invalid, 0, depth) + 0.5), max(1, info.min), info.max)
        out[invalid] = 0
        return out.astype(dtype)
    out = np.where(invalid, 0, depth).astype(dtype)
    return out


def write_depth(
    path: str | os.PathLike, depth: np.ndarray, *, dtype: np.dtype | type | None = None, overwrite: bool = False
) -> Path:
    """Write a depth map, atomically, in ``dtype`` (default: the array's own).

    Raises
    ------
    InputFileError
        The file exists (without ``overwrite``), its folder is missing, the
        format cannot hold ``dtype`` (float in PNG) or is unknown.
    """
    p = check_output(path, overwrite=overwrite, what="output")
    suffix = p.suffix.lower()
    dtype = np.dtype(depth.dtype if dtype is None else dtype)
    if suffix not in DEPTH_SUFFIXES:
        raise InputFileError(
            f"output {p}: unknown depth format {suffix!r}; use one of {', '.join(DEPTH_SUFFIXES)}."
        )
    if suffix in _INTEGER_SUFFIXES and dtype not in (np.uint8, np.uint16):
        raise InputFileError(
            f"output {p}: {suffix} holds 8- or 16-bit integers, but the depth is {dtype}; "
            "write .tif or .npy to keep it."
        )
    data = depth_to_dtype(depth, dtype)

    def _write(tmp: Path) -> None:
        if suffix == ".npy":
            with open(tmp, "wb") as fh:
                np.save(fh, data, allow_pickle=False)
        elif suffix in (".tif", ".tiff"):
            tifffile.imwrite(tmp, data)
        elif not cv2.imwrite(str(tmp), data):
            raise OSError(f"OpenCV could not write {p}")

    return atomic_write(p, _write)


def read_rgb(path: str | os.PathLike) -> np.ndarray:
    """Read a color image as RGB (H, W, 3) uint8 or uint16 (float TIFF: float32 in [0, 1]).

    Gray images are repeated to three channels, alpha is dropped.
    """
    p = _existing(path, "color")
    arr = _read_any(p, "color")
    if arr.ndim == 3 and arr.shape[2] in (3, 4) and p.suffix.lower() not in (".npy", ".tif", ".tiff"):
        arr = cv2.cvtColor(arr, cv2.COLOR_BGRA2RGB if arr.shape[2] == 4 else cv2.COLOR_BGR2RGB)
    if arr.dtype == np.float64:
        arr = arr.astype(np.float32)
    try:
        return np.ascontiguousarray(check_rgb(arr, name=f"color file {p}"))
    except (TypeError, ValueError) as exc:
        raise InputFileError(str(exc)) from None


def write_rgb(path: str | os.PathLike, rgb: np.ndarray, *, overwrite: bool = False) -> Path:
    """Write an RGB uint8 image (PNG or JPEG by extension), atomically."""
    p = check_output(path, overwrite=overwrite, what="output")
    bgr = cv2.cvtColor(np.ascontiguousarray(rgb), cv2.COLOR_RGB2BGR)

    def _write(tmp: Path) -> None:
        if not cv2.imwrite(str(tmp), bgr):
            raise OSError(f"OpenCV could not write {p}")

    return atomic_write(p, _write)
