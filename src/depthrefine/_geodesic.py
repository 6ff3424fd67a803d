"""The geodesic nearest seed on a color image (a compiled kernel): which side of an edge a pixel belongs to.

Shared by gbp's edge snapping (:mod:`depthrefine.methods.gbp.edges`) and the
chain's unmeasured pixels (:mod:`depthrefine.rig.chain`), which sit in
different domains. The kernel is depthrefine's C one when built
(:mod:`depthrefine._native`), else numba's (:mod:`._geodesic_jit`).
"""

from __future__ import annotations

import numpy as np

from ._native import kernels

__all__ = ["nearest_seed", "color_step_costs"]


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
    kernels(__package__ + "._geodesic_jit").sweeps(
        np.ascontiguousarray(cost_x, dtype=np.float32), np.ascontiguousarray(cost_y, dtype=np.float32), free,
        distance, source, int(sweeps))
    return source


def color_step_costs(color: np.ndarray, *, blur: float, step_levels: float) -> tuple[np.ndarray, np.ndarray]:
    """The costs ``(cost_x, cost_y)`` of :func:`nearest_seed` on a color image: a path crosses its edges dearly.

    A step costs the Euclidean distance of the two pixels' colors (levels of
    ``color``, (H, W, 3), after a Gaussian blur of sigma ``blur`` pixels, so
    that fine texture makes no path) plus ``step_levels``, so that where the
    color is flat the nearest seed is the nearest in distance. float32, the
    last column of ``cost_x`` and the last row of ``cost_y`` are 0 (unused).

    Examples
    --------
    >>> color = np.zeros((1, 4, 3), np.uint8); color[:, 2:] = 100
    >>> cost_x, _ = color_step_costs(color, blur=0, step_levels=2)
    >>> cost_x.astype(np.float64).round(1).tolist()
    [[2.0, 175.2, 2.0, 0.0]]
    """
    import cv2

    c = np.asarray(color, np.float32)
    if blur > 0:
        c = cv2.GaussianBlur(c, (0, 0), blur)
    rows, cols = c.shape[:2]
    planes = cv2.split(c)        # contiguous channels: the differences below run along rows
    cost_x = np.zeros((rows, cols), np.float32)
    cost_y = np.zeros((rows, cols), np.float32)
    _squared_distance([p[:, 1:] for p in planes], [p[:, :-1] for p in planes], cost_x[:, :-1])
    _squared_distance([p[1:] for p in planes], [p[:-1] for p in planes], cost_y[:-1])
    for cost in (cost_x[:, :-1], cost_y[:-1]):
        np.sqrt(cost, out=cost)
        cost += np.float32(step_levels)
    return cost_x, cost_y


def _squared_distance(a: list[np.ndarray], b: list[np.ndarray], out: np.ndarray) -> None:
    """``out = sum over the channels of (a - b)**2``, channel by channel in order (the bits of ``np.sum(axis=2)``)."""
    diff = np.empty(out.shape, np.float32)
    for channel, (plane_a, plane_b) in enumerate(zip(a, b)):
        np.subtract(plane_a, plane_b, out=diff)
        np.multiply(diff, diff, out=diff)
        if channel == 0:
            out[...] = diff
        else:
            out += diff
