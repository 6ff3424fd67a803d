"""Shared validators: one place for the checks and messages of array inputs.

Every public function checks its arrays here, once, and raises ``TypeError``
(wrong kind of thing) or ``ValueError`` (right kind, wrong value) with a
message that names the argument, says what was received and what to do.
"""

from __future__ import annotations

import numpy as np

__all__ = ["as_depth", "as_rgb", "check_depth", "check_rgb", "check_positive_int", "valid_range"]

_DEPTH_DTYPES = (np.uint8, np.uint16, np.int16, np.int32, np.float32, np.float64)


def check_depth(depth: object, name: str = "depth_lr") -> np.ndarray:
    """Check that ``depth`` is a 2-D numeric array with at least one valid pixel."""
    if not isinstance(depth, np.ndarray):
        raise TypeError(f"{name} must be a numpy array; got {type(depth).__name__}.")
    if depth.ndim == 3 and depth.shape[2] == 1:
        depth = depth[:, :, 0]
    if depth.ndim != 2:
        raise ValueError(
            f"{name} must be 2-D (rows, cols); got shape {depth.shape}. "
            "Pass a single-channel depth map (squeeze or select the channel first)."
        )
    if depth.dtype.type not in _DEPTH_DTYPES:
        raise TypeError(
            f"{name} has dtype {depth.dtype}; expected uint8, uint16, int16, int32, float32 or float64."
        )
    if depth.shape[0] < 1 or depth.shape[1] < 1:
        raise ValueError(f"{name} is empty (shape {depth.shape}).")
    return depth


def as_depth(depth: object, name: str = "depth_lr") -> np.ndarray:
    """Return a new float32 copy of ``depth`` with every invalid pixel as NaN.

    Invalid: 0 (no measurement, any dtype), NaN, +-inf and negative values.
    The input is never modified. Raises ``ValueError`` if no pixel is valid.
    """
    depth = check_depth(depth, name)
    out = depth.astype(np.float32, copy=True)
    with np.errstate(invalid="ignore"):
        out[~(np.isfinite(out) & (out > 0))] = np.nan
    if not np.isfinite(out).any():
        raise ValueError(
            f"{name} has no valid pixel (all are 0, NaN, inf or negative); "
            "there is no depth to refine. Check the depth file or its units."
        )
    return out


def valid_range(depth: np.ndarray) -> tuple[float, float]:
    """Min and max of the valid (finite) pixels of a float depth map."""
    return float(np.nanmin(depth)), float(np.nanmax(depth))


def check_rgb(rgb: object, name: str = "rgb_hr") -> np.ndarray:
    """Check a color image: (H, W, 3) uint8/uint16/float, RGB order.

    A single-channel (H, W) or (H, W, 1) guide is accepted and repeated to
    three channels; an alpha channel (H, W, 4) is dropped. Float images must
    lie in [0, 1].
    """
    if not isinstance(rgb, np.ndarray):
        raise TypeError(f"{name} must be a numpy array; got {type(rgb).__name__}.")
    if rgb.ndim == 2:
        rgb = np.repeat(rgb[:, :, None], 3, axis=2)
    elif rgb.ndim == 3 and rgb.shape[2] == 1:
        rgb = np.repeat(rgb, 3, axis=2)
    elif rgb.ndim == 3 and rgb.shape[2] == 4:
        rgb = rgb[:, :, :3]
    if rgb.ndim != 3 or rgb.shape[2] != 3:
        raise ValueError(
            f"{name} must be a color image of shape (rows, cols, 3); got shape {rgb.shape}."
        )
    if rgb.shape[0] < 1 or rgb.shape[1] < 1:
        raise ValueError(f"{name} is empty (shape {rgb.shape}).")
    if rgb.dtype == np.uint8 or rgb.dtype == np.uint16:
        return rgb
    if rgb.dtype in (np.float32, np.float64):
        if not np.isfinite(rgb).all():
            raise ValueError(f"{name} holds NaN or inf; color values must be finite.")
        lo, hi = float(rgb.min()), float(rgb.max())
        if lo < 0.0 or hi > 1.0:
            raise ValueError(
                f"{name} is floating point with values in [{lo:g}, {hi:g}]; float color must lie in "
                "[0, 1]. Divide by 255 (8-bit) or 65535 (16-bit), or pass the integer image."
            )
        return rgb
    raise TypeError(f"{name} has dtype {rgb.dtype}; expected uint8, uint16, float32 or float64.")


def as_rgb_float(rgb: np.ndarray) -> np.ndarray:
    """float32 RGB in [0, 1] from a checked uint8/uint16/float image (new array)."""
    if rgb.dtype == np.uint8:
        return rgb.astype(np.float32) / np.float32(255.0)
    if rgb.dtype == np.uint16:
        return rgb.astype(np.float32) / np.float32(65535.0)
    return rgb.astype(np.float32, copy=True)


def as_rgb(rgb: object, name: str = "rgb_hr") -> np.ndarray:
    """Checked color image as float32 RGB in [0, 1]."""
    return as_rgb_float(check_rgb(rgb, name))


def check_positive_int(value: object, name: str) -> int:
    """An integer >= 1 (bools rejected)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer; got {value!r}.")
    if value < 1:
        raise ValueError(f"{name} must be >= 1; got {value}.")
    return int(value)
