"""The numba kernel of :mod:`depthrefine._geodesic`, compiled on first use and cached on disk.

The reference for the same kernel in C (:mod:`depthrefine._native`, built at
install), which gives the same bits; it runs where the C library is not
built. Importing this module imports numba.
"""

from __future__ import annotations

from ._numba import njit

__all__ = ["sweeps"]


@njit
def sweeps(cost_x, cost_y, free, distance, source, passes):  # pragma: no cover - compiled
    rows, cols = free.shape
    for _ in range(passes):
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
