"""Calibration boards: 3-D corner coordinates, and finding the corners in an image."""

from __future__ import annotations

import math
from typing import Any

import cv2
import numpy as np

from .._validate import is_int

__all__ = ["board_points", "to_gray8", "find_board_corners"]

_SUBPIX_CRITERIA = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 50, 1e-4)


def board_points(board: tuple[int, int], square_size: float) -> np.ndarray:
    """The inner corners of a checkerboard in its own plane (Z = 0), in OpenCV's order.

    Parameters
    ----------
    board : (int, int)
        Inner corners ``(cols, rows)``.
    square_size : float
        Side of a square, metres.

    Returns
    -------
    (cols * rows, 3) float32 ndarray
        Row by row, ``cols`` corners each: ``(col * size, row * size, 0)``.

    Examples
    --------
    >>> board_points((3, 2), 0.5)[:4].tolist()
    [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.5, 0.0]]
    """
    cols, rows = _check_board(board)
    size = _check_square(square_size)
    grid = np.mgrid[0:rows, 0:cols].astype(np.float32)
    pts = np.zeros((rows * cols, 3), np.float32)
    pts[:, 0] = grid[1].ravel() * size
    pts[:, 1] = grid[0].ravel() * size
    return pts


def to_gray8(image: np.ndarray) -> np.ndarray:
    """An 8-bit gray version of an intensity or color image, for corner detection.

    8-bit images are only converted to gray. 16-bit and float images (ToF
    amplitude) are stretched so that the 0.5th-99.5th percentiles of their
    finite values span 0..255.

    Examples
    --------
    >>> to_gray8(np.array([[0, 1000], [2000, 4000]], np.uint16)).tolist()
    [[0, 64], [128, 255]]
    """
    if not isinstance(image, np.ndarray):
        raise TypeError(f"image must be a numpy array; got {type(image).__name__}.")
    if image.ndim == 3 and image.shape[2] in (3, 4):
        if image.dtype == np.uint8 or image.dtype == np.uint16 or image.dtype == np.float32:
            image = cv2.cvtColor(np.ascontiguousarray(image[:, :, :3]), cv2.COLOR_RGB2GRAY)
        else:
            image = image[:, :, :3].astype(np.float64) @ np.array([0.299, 0.587, 0.114])
    elif image.ndim == 3 and image.shape[2] == 1:
        image = image[:, :, 0]
    if image.ndim != 2:
        raise ValueError(f"image must be (rows, cols) or (rows, cols, 3); got shape {image.shape}.")
    if image.dtype == np.uint8:
        return np.ascontiguousarray(image)
    values = image.astype(np.float64)
    finite = np.isfinite(values)
    if not finite.any():
        raise ValueError("image has no finite pixel.")
    lo, hi = np.percentile(values[finite], [0.5, 99.5])
    if hi <= lo:
        hi = lo + 1.0
    out = np.clip((np.where(finite, values, lo) - lo) * (255.0 / (hi - lo)), 0, 255)
    return np.floor(out + 0.5).astype(np.uint8)


def find_board_corners(image: np.ndarray, board: tuple[int, int]) -> np.ndarray | None:
    """Find a checkerboard's inner corners to sub-pixel accuracy.

    Parameters
    ----------
    image : (rows, cols) or (rows, cols, 3) ndarray
        Intensity (any dtype) or RGB image.
    board : (int, int)
        Inner corners ``(cols, rows)``.

    Returns
    -------
    (cols * rows, 2) float32 ndarray or None
        Corner positions ``(x, y)`` = (column, row) in pixels, in
        :func:`board_points` order, the first corner being the one nearest
        the image's top-left; ``None`` if the board is not found.
    """
    cols, rows = _check_board(board)
    gray = to_gray8(image)
    flags = cv2.CALIB_CB_ADAPTIVE_THRESH | cv2.CALIB_CB_NORMALIZE_IMAGE
    found, corners = cv2.findChessboardCorners(gray, (cols, rows), flags=flags)
    if found:
        corners = corners.reshape(-1, 2).astype(np.float32)
        step = _corner_spacing(corners, cols, rows)
        half = int(np.clip(np.floor(step * 0.4), 2, 11))
        refined = cv2.cornerSubPix(gray, corners.reshape(-1, 1, 2).copy(), (half, half), (-1, -1),
                                   _SUBPIX_CRITERIA)
        corners = refined.reshape(-1, 2)
    else:
        found, corners = cv2.findChessboardCornersSB(gray, (cols, rows), flags=cv2.CALIB_CB_ACCURACY)
        if not found:
            return None
        corners = corners.reshape(-1, 2).astype(np.float32)
    # OpenCV's order is defined up to a half turn of the board: put the first
    # corner top-left so that two cameras of an upright rig agree.
    if corners[0].sum() > corners[-1].sum():
        corners = corners[::-1].copy()
    return np.ascontiguousarray(corners, dtype=np.float32)



def _check_board(board: Any) -> tuple[int, int]:
    if (isinstance(board, (str, bytes)) or not hasattr(board, "__len__") or len(board) != 2
            or not all(is_int(v) for v in board)):
        raise TypeError(f"board must be two integers (cols, rows) of inner corners; got {board!r}.")
    cols, rows = int(board[0]), int(board[1])
    if cols < 2 or rows < 2:
        raise ValueError(f"board must have at least 2x2 inner corners; got {cols}x{rows}.")
    return cols, rows


def _check_square(square_size: Any) -> float:
    if isinstance(square_size, bool) or not isinstance(square_size, (int, float, np.floating)):
        raise TypeError(f"square_size must be a number (metres); got {square_size!r}.")
    if not (math.isfinite(square_size) and square_size > 0):
        raise ValueError(f"square_size must be > 0 metres; got {square_size}.")
    return float(square_size)


def _corner_spacing(corners: np.ndarray, cols: int, rows: int) -> float:
    """Smallest distance between neighbouring corners, pixels."""
    grid = corners.reshape(rows, cols, 2)
    across = np.linalg.norm(np.diff(grid, axis=1), axis=2)
    down = np.linalg.norm(np.diff(grid, axis=0), axis=2)
    return float(min(across.min(), down.min()))
