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
- Saturated pixels: many ToF cameras write the largest code of the file's
  integer type (255, 65535) for a saturated or out-of-range pixel. That code
  is a valid depth by default (255 is the nearest level of the thesis's 8-bit
  depth intensity); ``read_depth(..., saturated_invalid=True)`` (CLI
  ``--saturated-invalid``) reads it as 0, no measurement. In float files
  inf, NaN, 0 and negative values are always invalid.
- Size: before decoding, the image's size is read from its header (PNG,
  JPEG, BMP, TIFF, ``.npy``) and checked by
  :func:`depthrefine._validate.check_pixels` (``max_pixels`` and the memory
  the machine has), so an absurdly large file is refused up front.

Formats: PNG (8/16-bit), TIFF (any dtype, float32 for metric depth), NumPy
``.npy``; color also JPEG/BMP and anything else OpenCV reads.
"""

from __future__ import annotations

import contextlib
import io
import math
import os
import sys
import tempfile
from pathlib import Path
from typing import Iterator

import numpy as np

from .._lazy import cv2, tifffile
from .._validate import check_pixels, check_rgb, largest_beyond_limit, no_valid_pixel_message, too_deep_message
from ._files import InputFileError, atomic_write, check_output, existing_input

__all__ = [
    "read_depth",
    "write_depth",
    "encode_depth",
    "read_rgb",
    "write_rgb",
    "encode_rgb",
    "DEPTH_SUFFIXES",
    "check_depth_format",
    "depth_to_dtype",
    "scale_to_dtype",
    "write_figure",
    "write_bytes",
    "image_shape",
]

DEPTH_SUFFIXES = (".png", ".tif", ".tiff", ".npy", ".pgm")
_INTEGER_SUFFIXES = (".png", ".pgm")


def image_shape(path: str | os.PathLike) -> tuple[int, ...] | None:
    """``(rows, cols)`` of an image file from its header, without decoding it.

    PNG, JPEG, BMP, TIFF and ``.npy`` are understood; ``None`` for other
    formats or a header that cannot be parsed (the decoder will then judge
    the file).
    """
    p = Path(path)
    suffix = p.suffix.lower()
    try:
        if suffix == ".npy":
            with open(p, "rb") as fh:
                version = np.lib.format.read_magic(fh)
                reader = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
                shape = reader(fh)[0]
            return tuple(int(n) for n in shape[:2]) if len(shape) >= 2 else None
        if suffix in (".tif", ".tiff"):
            with tifffile.TiffFile(p) as tif:
                page = tif.pages[0]
                return (int(page.imagelength), int(page.imagewidth))
        with open(p, "rb") as fh:
            head = fh.read(32)
            if head[:8] == b"\x89PNG\r\n\x1a\n" and head[12:16] == b"IHDR":
                return (int.from_bytes(head[20:24], "big"), int.from_bytes(head[16:20], "big"))
            if head[:2] == b"BM" and len(head) >= 26:
                return (abs(int.from_bytes(head[22:26], "little", signed=True)),
                        int.from_bytes(head[18:22], "little", signed=True))
            if head[:2] == b"\xff\xd8":
                return _jpeg_shape(fh)
    except Exception:  # noqa: BLE001 - a damaged header: let the decoder report it
        return None
    return None


def _jpeg_shape(fh) -> tuple[int, int] | None:
    """Scan JPEG markers for the start-of-frame segment and read its size."""
    fh.seek(2)
    while True:
        marker = fh.read(2)
        if len(marker) < 2 or marker[0] != 0xFF:
            return None
        kind = marker[1]
        if kind == 0xFF:  # fill byte
            fh.seek(-1, os.SEEK_CUR)
            continue
        if kind in (0x01,) or 0xD0 <= kind <= 0xD7:  # markers without a length
            continue
        length = int.from_bytes(fh.read(2), "big")
        if length < 2:
            return None
        if 0xC0 <= kind <= 0xCF and kind not in (0xC4, 0xC8, 0xCC):
            seg = fh.read(5)
            return (int.from_bytes(seg[1:3], "big"), int.from_bytes(seg[3:5], "big"))
        fh.seek(length - 2, os.SEEK_CUR)


def _check_size(p: Path, what: str, max_pixels: int | None, shape: tuple[int, ...] | None = None) -> None:
    """Refuse a file whose image is over the pixel or memory limit (header first, no decoding)."""
    shape = image_shape(p) if shape is None else shape
    if shape is None or len(shape) < 2:
        return
    try:
        check_pixels(shape, max_pixels=max_pixels, name=f"{what} file {p}")
    except ValueError as exc:
        raise InputFileError(str(exc)) from None


def _bad_file(p: Path, what: str, detail: str) -> InputFileError:
    detail = " ".join(detail.split())
    return InputFileError(
        f"{what} file {p} cannot be read ({detail}); it is truncated, damaged or not an image: "
        "check it or save it again."
    )


def _truncated(p: Path) -> str | None:
    """Why a PNG or JPEG file seems cut short (no end marker near its end), else ``None``."""
    with open(p, "rb") as fh:
        head = fh.read(8)
        fh.seek(max(0, p.stat().st_size - 64))
        tail = fh.read()
    if head[:8] == b"\x89PNG\r\n\x1a\n" and b"IEND" not in tail:
        return "the PNG has no IEND chunk"
    if head[:2] == b"\xff\xd8" and b"\xff\xd9" not in tail:
        return "the JPEG has no end-of-image marker"
    return None


@contextlib.contextmanager
def _captured_stderr_fd() -> Iterator[list[str]]:
    """Collect what C libraries (libpng, libjpeg, OpenCV) print on file descriptor 2.

    Decoders report damage by printing; the command line must show one line
    only, so their words are caught here and put into our message.
    """
    out: list[str] = []
    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, ValueError, AttributeError):
        yield out
        return
    with tempfile.TemporaryFile() as tmp:
        os.dup2(tmp.fileno(), 2)
        try:
            yield out
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            tmp.seek(0)
            out.append(tmp.read().decode("utf-8", "replace").strip())


#: File signatures of recordings that `depthrefine batch` reads, not single images.
_RECORDINGS = ((b"\x1a\x45\xdf\xa3", "a Matroska recording (.mkv, e.g. Azure Kinect)"),
               (b"#ROSBAG", "a ROS 1 bag"), (b"\x89MCAP", "an MCAP bag"), (b"SQLite format 3\x00", "a ROS 2 bag (.db3)"))


def _recording(p: Path) -> str | None:
    """What recording ``p`` is (from its first bytes), else None."""
    try:
        with open(p, "rb") as fh:
            head = fh.read(16)
    except OSError:
        return None
    return next((kind for magic, kind in _RECORDINGS if head.startswith(magic)), None)


def _read_any(p: Path, what: str) -> np.ndarray:
    kind = _recording(p)
    if kind is not None:
        raise InputFileError(f"{what} file {p} is {kind}, not an image; refine its frames with "
                             f"`depthrefine batch {p} -o OUTDIR`.")
    suffix = p.suffix.lower()
    try:
        if suffix == ".npy":
            arr = np.load(p, allow_pickle=False)
        elif suffix in (".tif", ".tiff"):
            arr = tifffile.imread(p)
        else:
            with _captured_stderr_fd() as said:
                arr = cv2.imread(str(p), cv2.IMREAD_UNCHANGED)
            said_text = " ".join(said).strip()
            if arr is None or any(word in said_text for word in ("Premature end", "Corrupt", "rror")):
                reason = "; ".join(r for r in (_truncated(p), said_text) if r)
                raise _bad_file(p, what, reason or "OpenCV cannot decode it")
    except InputFileError:
        raise
    except Exception as exc:  # noqa: BLE001 - any decoder failure is a bad file
        raise _bad_file(p, what, f"{type(exc).__name__}: {exc}") from None
    if not isinstance(arr, np.ndarray) or arr.dtype == object:
        raise InputFileError(f"{what} file {p} does not hold a numeric image; save the image as PNG, TIFF or .npy.")
    return arr


def read_depth(
    path: str | os.PathLike, *, max_pixels: int | None = None, saturated_invalid: bool = False
) -> np.ndarray:
    """Read a depth map in its own dtype; 0 (or NaN) marks missing pixels.

    Parameters
    ----------
    path : str or path-like
        ``.png`` (8/16-bit), ``.tif``/``.tiff`` (any dtype), ``.npy`` or ``.pgm``.
    max_pixels : int, optional
        Refuse a larger image before decoding it (see
        :func:`depthrefine._validate.check_pixels`; the memory check always applies).
    saturated_invalid : bool
        Read the largest code of an integer file (255, 65535, ...) as 0, no
        measurement: the saturation code of many ToF cameras.

    Returns
    -------
    (h, w) ndarray
        uint8, uint16, int16, int32, float32 or float64, as stored.

    Raises
    ------
    InputFileError (a ValueError)
        Missing, unreadable, too large or non-depth file (e.g. a color
        image), a depth map without any valid pixel, or one with values
        beyond ``MAX_DEPTH`` (1e15, any unit).
    """
    p = existing_input(path, "depth")
    _check_size(p, "depth", max_pixels)
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
        raise InputFileError(f"depth file {p} is empty (shape {arr.shape}); save the depth map again.")
    _check_size(p, "depth", max_pixels, arr.shape)
    if saturated_invalid and arr.dtype.kind in "ui":
        arr = np.where(arr == np.iinfo(arr.dtype).max, arr.dtype.type(0), arr)
    with np.errstate(invalid="ignore"):
        if not (np.isfinite(arr) & (arr > 0)).any():
            raise InputFileError(no_valid_pixel_message(f"depth file {p}"))
    largest = largest_beyond_limit(arr)
    if largest is not None:
        raise InputFileError(too_deep_message(f"depth file {p}", largest))
    return np.ascontiguousarray(arr)


def depth_to_dtype(depth: np.ndarray, dtype: np.dtype | type) -> np.ndarray:
    """Convert a float depth map (NaN = invalid) to ``dtype`` for writing.

    Integers: rounded, valid pixels clipped to ``[1, max]``; no measurement
    (NaN, inf, 0 or negative) -> 0. Floats: no measurement -> 0 (0 means no
    measurement in a file).

    Examples
    --------
    >>> depth_to_dtype(np.array([np.nan, 0.2, 7.6, 300.0, 0.0], np.float32), np.uint8).tolist()
    [0, 1, 8, 255, 0]
    """
    dtype = np.dtype(dtype)
    depth = np.asarray(depth, dtype=np.float64)
    with np.errstate(invalid="ignore"):
        invalid = ~(np.isfinite(depth) & (depth > 0))
    if dtype.kind in "ui":
        info = np.iinfo(dtype)
        out = np.clip(np.floor(np.where(invalid, 0, depth) + 0.5), max(1, info.min), info.max)
        out[invalid] = 0
        return out.astype(dtype)
    out = np.where(invalid, 0, depth).astype(dtype)
    return out


def scale_to_dtype(depth: np.ndarray, scale: float, dtype: np.dtype | type) -> np.ndarray:
    """``depth * scale`` (float32, NaN = invalid), refused if ``dtype`` cannot store it without clipping.

    For storing a float result in an integer file with an explicit scale,
    e.g. metres x 1000 as uint16 millimetres: a valid value must neither
    exceed the type's maximum nor round to 0 (which means "no measurement"
    in a file), so nothing is clipped silently.

    Raises
    ------
    ValueError
        ``scale`` is not a positive finite number, or a valid value would clip.

    Examples
    --------
    >>> scale_to_dtype(np.array([0.5, np.nan, 2.25], np.float32), 1000, np.uint16).tolist()
    [500.0, nan, 2250.0]
    """
    dtype = np.dtype(dtype)
    if not (isinstance(scale, (int, float)) and math.isfinite(scale) and scale > 0):
        raise ValueError(f"the output scale must be a positive number; got {scale!r}.")
    scaled = np.asarray(depth, dtype=np.float64) * scale
    valid = np.isfinite(scaled)
    if dtype.kind in "ui" and valid.any():
        info = np.iinfo(dtype)
        top, low = float(scaled[valid].max()), float(scaled[valid].min())
        if np.floor(top + 0.5) > info.max:
            raise ValueError(
                f"depth x {scale:g} reaches {top:.6g}, over the {dtype} maximum {info.max}: the values would "
                f"clip; choose a smaller scale (largest that fits: {info.max / (top / scale):.6g}) or a float "
                "output (.tif, .npy)."
            )
        if np.floor(low + 0.5) < max(1, info.min):
            raise ValueError(
                f"depth x {scale:g} goes down to {low:.6g}, which rounds to {np.floor(low + 0.5):g}, but 0 means "
                f"no measurement in a file and {dtype} holds no negative values: the values would clip; "
                "choose a larger scale or a float output (.tif, .npy)."
            )
    return scaled.astype(np.float32)


def output_values(depth: np.ndarray, input_dtype: np.dtype | type, *, scale: float | None = None,
                  dtype: np.dtype | type | str | None = None) -> tuple[np.ndarray, np.dtype]:
    """The depth to write and the dtype to write it in, after an output scale and dtype.

    Without either: ``depth`` itself and ``input_dtype`` (the output keeps the
    input's type). With one of them the conversion is explicit
    (:func:`scale_to_dtype`), so a value the type cannot hold is a
    ``ValueError`` instead of a silent clip.

    Examples
    --------
    >>> values, dtype = output_values(np.array([0.5, 2.25], np.float32), np.float32, scale=1000, dtype="uint16")
    >>> values.tolist(), str(dtype)
    ([500.0, 2250.0], 'uint16')
    """
    out_dtype = np.dtype(dtype or input_dtype)
    if scale is None and dtype is None:
        return depth, out_dtype
    return scale_to_dtype(depth, 1.0 if scale is None else scale, out_dtype), out_dtype


def check_depth_format(path: str | os.PathLike, dtype: np.dtype | type) -> str:
    """The lower-case suffix of ``path`` if it is a depth format that can hold ``dtype``.

    Commands call it before any work, so a wrong output name fails at once.

    Raises
    ------
    InputFileError
        An unknown depth format, or an integer format (PNG, PGM) for a
        float depth map.
    """
    p = Path(path)
    suffix = p.suffix.lower()
    dtype = np.dtype(dtype)
    if suffix not in DEPTH_SUFFIXES:
        raise InputFileError(
            f"output {p}: unknown depth format {suffix!r}; use one of {', '.join(DEPTH_SUFFIXES)}."
        )
    if suffix in _INTEGER_SUFFIXES and dtype not in (np.uint8, np.uint16):
        raise InputFileError(
            f"output {p}: {suffix} holds 8- or 16-bit integers, but the depth is {dtype}; "
            "write .tif or .npy to keep it, or (refine, run) store it as 16-bit PNG with an explicit scale: "
            "--output-scale 1000 --output-dtype uint16 (metres to millimetres)."
        )
    return suffix


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
    dtype = np.dtype(depth.dtype if dtype is None else dtype)
    suffix = check_depth_format(p, dtype)
    return write_array(p, depth_to_dtype(depth, dtype), suffix, overwrite=overwrite)


def encode_depth(depth: np.ndarray, suffix: str, *, dtype: np.dtype | type | None = None) -> bytes:
    """The bytes :func:`write_depth` writes for ``depth`` in a ``suffix`` file (``.png``, ...), in memory.

    ``suffix`` must hold ``dtype`` (default: the array's own; see
    :func:`check_depth_format`). For a worker that makes a file's contents
    and hands them to the process that writes them.

    Examples
    --------
    >>> encode_depth(np.array([[1.5, np.nan]], np.float32), ".npy", dtype=np.uint16)[:6]
    b'\\x93NUMPY'
    """
    dtype = np.dtype(depth.dtype if dtype is None else dtype)
    return encode_array(depth_to_dtype(depth, dtype), check_depth_format(f"depth{suffix}", dtype))


def encode_array(data: np.ndarray, suffix: str) -> bytes:
    """The bytes of a ``suffix`` file holding ``data`` (.npy, .tif/.tiff, else OpenCV's encoder), in memory."""
    if suffix == ".npy":
        buffer = io.BytesIO()
        np.save(buffer, data, allow_pickle=False)
        return buffer.getvalue()
    if suffix in (".tif", ".tiff"):
        buffer = io.BytesIO()
        tifffile.imwrite(buffer, data)
        return buffer.getvalue()
    try:
        ok, encoded = cv2.imencode(suffix, data)
    except cv2.error:
        ok = False
    if not ok:
        raise OSError(f"OpenCV could not encode a {data.dtype} image as {suffix}")
    return encoded.tobytes()


def write_bytes(p: Path, data: bytes, *, overwrite: bool) -> Path:
    """Write ``data`` atomically to the checked path ``p`` (see :func:`check_output`)."""
    return atomic_write(p, lambda tmp: tmp.write_bytes(data), overwrite=overwrite)


def write_array(p: Path, data: np.ndarray, suffix: str, *, overwrite: bool) -> Path:
    """Write ``data`` atomically to the checked path ``p`` as ``suffix`` says (:func:`encode_array`)."""
    return write_bytes(p, encode_array(data, suffix), overwrite=overwrite)


def read_rgb(path: str | os.PathLike, *, max_pixels: int | None = None) -> np.ndarray:
    """Read a color image as RGB (H, W, 3) uint8 or uint16 (float TIFF: float32 in [0, 1]).

    Gray images are repeated to three channels, alpha is dropped. An image
    over ``max_pixels`` or the machine's memory is refused before decoding
    (see :func:`depthrefine._validate.check_pixels`).
    """
    p = existing_input(path, "color")
    _check_size(p, "color", max_pixels)
    arr = _read_any(p, "color")
    if arr.ndim >= 2:
        _check_size(p, "color", max_pixels, arr.shape)
    if arr.ndim == 3 and arr.shape[2] in (3, 4) and p.suffix.lower() not in (".npy", ".tif", ".tiff"):
        arr = cv2.cvtColor(arr, cv2.COLOR_BGRA2RGB if arr.shape[2] == 4 else cv2.COLOR_BGR2RGB)
    if arr.dtype == np.float64:
        arr = arr.astype(np.float32)
    try:
        return np.ascontiguousarray(check_rgb(arr, name=f"color file {p}"))
    except (TypeError, ValueError) as exc:
        raise InputFileError(str(exc)) from None


def write_figure(path: str | os.PathLike, figure, *, overwrite: bool = False) -> Path:
    """Save a matplotlib ``Figure`` (from :mod:`depthrefine.viz`) as PNG, atomically."""
    p = check_output(path, overwrite=overwrite, what="output")
    return atomic_write(p, lambda tmp: figure.savefig(tmp, format="png"), overwrite=overwrite)


def write_rgb(path: str | os.PathLike, rgb: np.ndarray, *, overwrite: bool = False) -> Path:
    """Write an RGB uint8 image (PNG or JPEG by extension), atomically."""
    p = check_output(path, overwrite=overwrite, what="output")
    return write_bytes(p, encode_rgb(rgb, p.suffix.lower()), overwrite=overwrite)


def encode_rgb(rgb: np.ndarray, suffix: str = ".png") -> bytes:
    """The bytes :func:`write_rgb` writes for ``rgb`` in a ``suffix`` file (``.png``, ``.jpg``), in memory."""
    return encode_array(cv2.cvtColor(np.ascontiguousarray(rgb), cv2.COLOR_RGB2BGR), suffix)
