"""The geodesic nearest seed on a color image (numba): which side of a depth jump a pixel belongs to.

Imported only when gbp runs (it imports numba).
"""

from __future__ import annotations

import numpy as np

from ..._numba import njit

__all__ = ["nearest_seed"]


@njit
def _sweeps(cost_x, cost_y, free, distance, source, sweeps):  # pragma: no cover - compiled
    rows, cols = free.shape
    for _ in range(sweeps):
        for i in range(rows):              # forward: from the top and the left
            for j in range(cols):
                if not free[i, j]:
                    continue
                best, origin = distance[i, j], source[i, j]
                if i > 0:
                    d = distance[i - 1, j] + cost_y[i - 1, j]
                    if d < best:
                        best, origin = d, source[i - 1, j]
                if j > 0:
                    d = distance[i, j - 1] + cost_x[i, j - 1]
                    if d < best:
                        best, origin = d, source[i, j - 1]
                distance[i, j], source[i, j] = best, origin
        for i in range(rows - 1, -1, -1):  # backward: from the bottom and the right
            for j in range(cols - 1, -1, -1):
                if not free[i, j]:
                    continue
                best, origin = distance[i, j], source[i, j]
                if i < rows - 1:
                    d = distance[i + 1, j] + cost_y[i, j]
                    if d < best:
                        best, origin = d, source[i + 1, j]
                if j < cols - 1:
                    d = distance[i, j + 1] + cost_x[i, j]
                    if d < best:
                        best, origin = d, source[i, j + 1]
                distance[i, j], source[i, j] = best, origin


def nearest_seed(cost_x: np.ndarray, cost_y: np.ndarray, free: np.ndarray, sweeps: int = 3) -> np.ndarray:
    """For every pixel, the flat index of the nearest pixel outside ``free`` along the cheapest 4-connected path.

    ``cost_x[i, j]`` is the cost of the step between ``(i, j)`` and
    ``(i, j + 1)``, ``cost_y[i, j]`` between ``(i, j)`` and ``(i + 1, j)``
    (non-negative float32, shape of ``free``). Pixels outside ``free`` are
    their own seed. ``sweeps`` forward and backward raster passes
    (Borgefors-style chamfer propagation); a free pixel no seed reaches
    keeps -1. Deterministic.

    Examples
    --------
    >>> free = np.array([[False, True, True, True, False]])
    >>> cost_x = np.array([[1, 1, 9, 1, 0]], np.float32)     # a strong edge between columns 2 and 3
    >>> nearest_seed(cost_x, np.zeros((1, 5), np.float32), free).tolist()
    [[0, 0, 0, 4, 4]]
    """
    free = np.ascontiguousarray(free, dtype=np.bool_)
    distance = np.where(free, np.float32(np.inf), np.float32(0)).astype(np.float32)
    source = np.where(free, -1, np.arange(free.size, dtype=np.int64).reshape(free.shape))
    _sweeps(np.ascontiguousarray(cost_x, dtype=np.float32), np.ascontiguousarray(cost_y, dtype=np.float32),
            free, distance, source, sweeps)
    return source
