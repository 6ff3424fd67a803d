"""The numba kernel of step 1b's search (:mod:`depthrefine.methods.gbp._offsets`), compiled on first use.

The reference for the same kernel in C (:mod:`depthrefine._native`, built at
install), which gives the same bits; it runs where the C library is not
built. Importing this module imports numba.
"""

from __future__ import annotations

import math

import numpy as np

from ..._numba import njit

__all__ = ["search"]


@njit
def _bilinear(image, x, y):  # pragma: no cover - compiled
    """``image`` at ``(x, y)``, bilinear, the border replicated."""
    rows, cols = image.shape
    x = min(max(x, 0.0), cols - 1.0)
    y = min(max(y, 0.0), rows - 1.0)
    x0, y0 = int(math.floor(x)), int(math.floor(y))
    x1, y1 = min(x0 + 1, cols - 1), min(y0 + 1, rows - 1)
    fx, fy = x - x0, y - y0
    top = image[y0, x0] + fx * (image[y0, x1] - image[y0, x0])
    bottom = image[y1, x0] + fx * (image[y1, x1] - image[y1, x0])
    return top + fy * (bottom - top)


@njit
def search(band, magnitude, gx, gy, edges, reach, peak_ratio, row_start, offsets, angles, found,
           i0, i1):  # pragma: no cover - compiled
    """Rows ``i0:i1``: row ``i``'s results go to ``offsets[row_start[i]:]`` in column order, their count to ``found[i]``."""
    cols = band.shape[1]
    steps = 2 * reach + 1
    profile = np.empty(steps, np.float64)
    for i in range(i0, i1):
        n = row_start[i]
        for j in range(cols):
            here = magnitude[i, j]
            if not band[i, j] or here <= 0.0:
                continue
            nx, ny = gx[i, j] / here, gy[i, j] / here
            if not (math.isfinite(nx) and math.isfinite(ny)):
                continue                                   # no direction (a gradient that overflowed float32)
            if here < _bilinear(magnitude, j + nx, i + ny) or here < _bilinear(magnitude, j - nx, i - ny):
                continue                                   # not on the ridge of the depth gradient
            total = 0.0
            peak = 0
            for k in range(steps):
                t = k - reach
                profile[k] = _bilinear(edges, j + t * nx, i + t * ny)
                total += profile[k]
                if profile[k] > profile[peak]:
                    peak = k
            if peak == 0 or peak == steps - 1 or profile[peak] <= peak_ratio / steps * (total + 1e-6):
                continue                                   # no clear color edge within reach
            before, top, after = profile[peak - 1], profile[peak], profile[peak + 1]
            curvature = before - 2.0 * top + after
            shift = 0.5 * (before - after) / curvature if curvature < 0.0 else 0.0
            offsets[n] = peak - reach + shift
            angles[n] = math.atan2(ny, nx)
            n += 1
        found[i] = n - row_start[i]
