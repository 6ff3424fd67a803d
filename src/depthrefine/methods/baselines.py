"""Plain interpolation baselines: nearest, bilinear and bicubic enlargement.

The thesis compares its result with nearest-neighbour enlargement (4.6).
All three resize the depth map straight to the color image's shape with
OpenCV (pixel-area centres aligned), ignoring the color. Invalid depth
pixels are first replaced by their nearest valid neighbour, so an invalid
pixel is never averaged into a result.
"""

from __future__ import annotations

import numpy as np

from .._lazy import cv2
from .._fill import fill_invalid_nearest
from .._validate import as_depth, check_rgb

__all__ = ["upsample_nearest", "upsample_bilinear", "upsample_bicubic", "fill_invalid_nearest", "upsample"]


def upsample(depth_lr: np.ndarray, shape: tuple[int, int], interpolation: int) -> np.ndarray:
    """Resize a NaN-marked depth map to ``shape`` with an OpenCV interpolation flag.

    Holes are filled from the nearest valid pixel first; the result is
    clipped to the input's valid range (bicubic overshoot, float rounding).
    """
    depth = fill_invalid_nearest(as_depth(depth_lr))
    rows, cols = shape
    out = cv2.resize(depth, (cols, rows), interpolation=interpolation)
    # Bicubic overshoots; OpenCV's float32 bilinear weights can leave a
    # constant 1 ulp off. Clipping keeps both within the input's range.
    out = np.clip(out, depth.min(), depth.max())
    return out.astype(np.float32, copy=False)


def upsample_nearest(depth_lr: np.ndarray, rgb_hr: np.ndarray, *, params=None, progress=None) -> np.ndarray:
    """Nearest-neighbour enlargement to the color image's shape (thesis 4.6).

    Examples
    --------
    >>> upsample_nearest(np.array([[1, 2]], np.float32), np.zeros((2, 4, 3), np.uint8)).tolist()
    [[1.0, 1.0, 2.0, 2.0], [1.0, 1.0, 2.0, 2.0]]
    """
    return upsample(depth_lr, check_rgb(rgb_hr).shape[:2], cv2.INTER_NEAREST_EXACT)


def upsample_bilinear(depth_lr: np.ndarray, rgb_hr: np.ndarray, *, params=None, progress=None) -> np.ndarray:
    """Bilinear enlargement to the color image's shape.

    Examples
    --------
    >>> upsample_bilinear(np.array([[0.5, 1.5]], np.float32), np.zeros((1, 4, 3), np.uint8)).tolist()
    [[0.5, 0.75, 1.25, 1.5]]
    """
    return upsample(depth_lr, check_rgb(rgb_hr).shape[:2], cv2.INTER_LINEAR)


def upsample_bicubic(depth_lr: np.ndarray, rgb_hr: np.ndarray, *, params=None, progress=None) -> np.ndarray:
    """Bicubic enlargement to the color image's shape, clipped to the input's range."""
    return upsample(depth_lr, check_rgb(rgb_hr).shape[:2], cv2.INTER_CUBIC)
