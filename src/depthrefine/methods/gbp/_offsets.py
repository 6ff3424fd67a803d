"""The per-pixel search of step 1b (numba): how far the color edge lies from each depth jump pixel.

Imported only when gbp runs (it imports numba). One pass over the jump band,
no image-sized temporaries; sequential, so deterministic.
"""

from __future__ import annotations

import math

import numpy as np

from ..._numba import njit

__all__ = ["jump_offsets"]


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
def _search(band, magnitude, gx, gy, edges, reach, peak_ratio, offsets, angles):  # pragma: no cover - compiled
    rows, cols = band.shape
    steps = 2 * reach + 1
    profile = np.empty(steps, np.float64)
    found = 0
    for i in range(rows):
        for j in range(cols):
            here = magnitude[i, j]
            if not band[i, j] or here <= 0.0:
                continue
            nx, ny = gx[i, j] / here, gy[i, j] / here
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
            offsets[found] = peak - reach + shift
            angles[found] = math.atan2(ny, nx)
            found += 1
    return found


def jump_offsets(band: np.ndarray, magnitude: np.ndarray, gx: np.ndarray, gy: np.ndarray, edges: np.ndarray,
                 reach: int, peak_ratio: float) -> tuple[np.ndarray, np.ndarray]:
    """At each pixel of ``band`` on the ridge of the depth gradient, the offset of the strongest color edge along it.

    ``magnitude``, ``gx``, ``gy``: the depth gradient (float32, the grid of
    ``band``); ``edges``: the guide's gradient magnitude. The profile of
    ``edges`` is sampled at ``-reach .. reach`` pixels along the depth
    gradient; its peak counts when it is inside the profile and holds more
    than ``peak_ratio`` times the profile's mean. Returns the offsets (pixels
    of the grid, sub-pixel by a parabola through the peak, positive along
    the gradient) and the gradient's angles (radians), float64.
    """
    count = int(np.count_nonzero(band))
    offsets, angles = np.empty(count), np.empty(count)
    found = _search(band, magnitude, gx, gy, edges, int(reach), float(peak_ratio), offsets, angles)
    return offsets[:found], angles[:found]
