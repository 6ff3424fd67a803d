"""Helpers shared by the rig's geometry modules (``pointcloud``, ``shift``, ``reproject``), private to ``rig``.

- :func:`depth_conversion`: which of the two depth-to-metres conversions is given, checked
- :func:`metres64`: depth in metres as float64, for geometry that must not lose precision
- :func:`zbuffer`: for each target pixel, the source that wins (nearest first)
"""

from __future__ import annotations

import math

import numpy as np

from .._validate import as_depth

__all__ = ["depth_conversion", "metres64", "zbuffer"]


def depth_conversion(depth_units: float | None, inverse_scale: float | None) -> tuple[str, float]:
    """Check that exactly one conversion is given; return ``(kind, value)``, kind ``"distance"`` or ``"inverse"``.

    Examples
    --------
    >>> depth_conversion(0.001, None), depth_conversion(None, 255.0)
    (('distance', 0.001), ('inverse', 255.0))
    """
    if depth_units is None and inverse_scale is None:
        raise ValueError(
            "the depth's units are unknown: give depth_units (metres per unit, e.g. 0.001 for uint16 "
            "millimetres) or, for 8-bit depth intensity / disparity (larger = nearer), inverse_scale "
            "with metres = inverse_scale / value. 8-bit depth intensity cannot be placed in 3-D without it."
        )
    if depth_units is not None and inverse_scale is not None:
        raise ValueError("give either depth_units or inverse_scale, not both.")
    name, value = ("depth_units", depth_units) if depth_units is not None else ("inverse_scale", inverse_scale)
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating)):
        raise TypeError(f"{name} must be a number; got {value!r}.")
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be > 0; got {value}.")
    return ("distance" if name == "depth_units" else "inverse"), float(value)


def metres64(depth: np.ndarray, depth_units: float | None, inverse_scale: float | None) -> np.ndarray:
    """Depth in metres as float64 (NaN stays NaN), for geometry that must not lose precision."""
    kind, value = depth_conversion(depth_units, inverse_scale)
    d = as_depth(depth, "depth").astype(np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        return d * value if kind == "distance" else value / d


def zbuffer(target: np.ndarray, priority: np.ndarray, source: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each distinct target, the source with the highest priority (ties: the lowest source index).

    Examples
    --------
    >>> t, s = zbuffer(np.array([5, 5, 2]), np.array([1.0, 3.0, 0.0]), np.array([0, 1, 2]))
    >>> t.tolist(), s.tolist()
    ([2, 5], [2, 1])
    """
    order = np.lexsort((source, -priority, target))
    target_sorted = target[order]
    first = np.ones(target_sorted.size, dtype=bool)
    first[1:] = target_sorted[1:] != target_sorted[:-1]
    return target_sorted[first], source[order][first]
