"""Hole filling shared by the methods and the rig: nearest valid pixel.

It sits below both, so that neither imports the other for it.
"""

from __future__ import annotations

import numpy as np

__all__ = ["fill_invalid_nearest"]


def fill_invalid_nearest(depth: np.ndarray) -> np.ndarray:
    """Replace NaN pixels by the value of the nearest valid pixel (new array).

    Examples
    --------
    >>> fill_invalid_nearest(np.array([[1, np.nan, np.nan, 4]], np.float32)).tolist()
    [[1.0, 1.0, 4.0, 4.0]]
    """
    valid = np.isfinite(depth)
    if valid.all():
        return depth.copy()
    from scipy import ndimage   # only for holes: importing it costs about half a second

    _, (ir, ic) = ndimage.distance_transform_edt(~valid, return_indices=True)
    return depth[ir, ic]
