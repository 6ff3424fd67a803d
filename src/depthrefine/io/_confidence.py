"""Confidence map files: float TIFF, ``.npy``, or 16-bit PNG scaled to 0..65535.

A confidence map (:func:`depthrefine.refine_with_confidence`) is float32 in
[0, 1] on the color grid, 1 = most trusted, 0 = no depth. TIFF and ``.npy``
keep it as float32; a PNG stores ``round(confidence * 65535)`` as uint16 (an
8-bit PNG read back is divided by 255).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .._lazy import cv2, tifffile
from ._files import InputFileError, check_output
from ._images import encode_array, write_bytes

__all__ = ["CONFIDENCE_SUFFIXES", "CONFIDENCE_PNG_MAX", "check_confidence_format", "confidence_to_png",
           "encode_confidence", "write_confidence", "read_confidence"]

#: The formats a confidence map is written in.
CONFIDENCE_SUFFIXES = (".tif", ".tiff", ".npy", ".png")
#: A PNG stores confidence 1 as this value (16 bits).
CONFIDENCE_PNG_MAX = 65535


def check_confidence_format(path: str | os.PathLike, *, what: str = "confidence file") -> str:
    """The lower-case suffix of ``path`` if a confidence map can be written there (``InputFileError`` if not)."""
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in CONFIDENCE_SUFFIXES:
        raise InputFileError(f"{what} {p}: unknown format {suffix!r}; use .tif (float32), .npy (float32) or .png "
                             "(16-bit, confidence x 65535).")
    return suffix


def confidence_to_png(confidence: np.ndarray) -> np.ndarray:
    """``round(confidence * 65535)`` as uint16, NaN as 0.

    Examples
    --------
    >>> confidence_to_png(np.array([0.0, 0.5, 1.0, np.nan], np.float32)).tolist()
    [0, 32768, 65535, 0]
    """
    c = np.nan_to_num(np.asarray(confidence, dtype=np.float64), nan=0.0)
    return np.floor(np.clip(c, 0.0, 1.0) * CONFIDENCE_PNG_MAX + 0.5).astype(np.uint16)


def write_confidence(path: str | os.PathLike, confidence: np.ndarray, *, overwrite: bool = False) -> Path:
    """Write a confidence map atomically: float32 TIFF or ``.npy``, or 16-bit PNG (x 65535) by ``path``'s suffix.

    Raises
    ------
    InputFileError
        Unknown format, the file exists (without ``overwrite``), or its folder is missing.
    """
    p = check_output(path, overwrite=overwrite, what="confidence file")
    return write_bytes(p, encode_confidence(confidence, check_confidence_format(p)), overwrite=overwrite)


def encode_confidence(confidence: np.ndarray, suffix: str) -> bytes:
    """The bytes :func:`write_confidence` writes for ``confidence`` in a ``suffix`` file, in memory."""
    suffix = check_confidence_format(f"confidence{suffix}")
    if suffix == ".png":
        data = confidence_to_png(confidence)
    else:
        data = np.clip(np.nan_to_num(np.asarray(confidence, dtype=np.float32), nan=0.0), 0.0, 1.0)
    return encode_array(data, suffix)


def read_confidence(path: str | os.PathLike) -> np.ndarray:
    """Read a confidence map as float32 in [0, 1] (16-bit PNG / 65535, 8-bit / 255, float as stored).

    Raises
    ------
    InputFileError
        A missing or unreadable file, not 2-D, or float values outside [0, 1].
    """
    p = Path(path)
    if not p.is_file():
        raise InputFileError(f"confidence file {p} does not exist; give the file written by --confidence.")
    suffix = check_confidence_format(p)
    try:
        if suffix == ".npy":
            data = np.load(p, allow_pickle=False)
        elif suffix in (".tif", ".tiff"):
            data = tifffile.imread(p)
        else:
            data = cv2.imread(str(p), cv2.IMREAD_UNCHANGED)
    except (OSError, ValueError) as exc:
        raise InputFileError(f"confidence file {p} cannot be read ({exc}).") from None
    if data is None or data.ndim != 2:
        shape = None if data is None else data.shape
        raise InputFileError(f"confidence file {p}: expected a single-channel map; got shape {shape}.")
    if data.dtype.kind in "ui":
        top = CONFIDENCE_PNG_MAX if data.dtype.itemsize > 1 else 255
        return (data.astype(np.float32) / np.float32(top)).clip(0.0, 1.0)
    data = np.nan_to_num(data.astype(np.float32), nan=0.0)
    if data.size and (data.min() < 0.0 or data.max() > 1.0):
        raise InputFileError(f"confidence file {p} holds values from {data.min():g} to {data.max():g}; a "
                             "confidence map lies in [0, 1].")
    return data
