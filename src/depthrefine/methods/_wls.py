"""Weighted least-squares smoothing with any edge weights (numba): the solver of ``gbp``.

The fast global smoother of Min et al. (2014), as OpenCV-contrib's
``ximgproc.fastGlobalSmootherFilter`` implements it, solves
``(I + lambda * L_w) u = f`` approximately by alternating exact 1-D solves
(a tridiagonal system per row, then per column), ``iterations`` times, with
``lambda`` multiplied by ``attenuation`` after each. OpenCV derives the
weights ``w`` of the 1-D Laplacians ``L_w`` from a color guide only
(``exp(-|dc| / sigma_color)``, ``|dc|`` the Euclidean distance of two
neighbours' colors); here they are any non-negative array, so that ``gbp``
can also weight by the current depth's own gradients and vary the smoothing
strength per pixel. With the color weights alone the result equals OpenCV's
up to float rounding (tests/test_wls.py).

Each row (column) is solved on its own and in the same order of operations
whatever the thread count, so the result is bit-identical on any machine
(OpenCV's filter splits its rows into per-thread stripes whose tails take a
scalar path, which changed the last bits with the core count).

Imported only when ``gbp`` runs (never at ``import depthrefine``): importing
this module imports numba. No ``fastmath``.

Reference: D. Min, S. Choi, J. Lu, B. Ham, K. Sohn, M. N. Do, "Fast global
image smoothing based on weighted least squares", IEEE TIP 23(12), 2014.
"""

from __future__ import annotations

import functools

import numba
import numpy as np

from .._numba import njit

__all__ = ["color_weights", "depth_weights", "smooth"]

#: Columns (rows) solved together by one thread (one vectorised sweep).
_BLOCK = 64
#: Images of fewer pixels are solved in the calling thread.
_PARALLEL_PIXELS = 1 << 16


@njit
def _sweep_columns(u, w, lam, j0, j1):
    """Solve ``(I + lam * L_w) v = u`` along axis 0 for columns ``j0:j1`` of ``u``, in place.

    ``w[i, j]`` is the weight between rows ``i`` and ``i + 1`` of column ``j``
    (its last row is unused). Thomas algorithm, as OpenCV's vertical pass.
    """
    rows = u.shape[0]
    n = j1 - j0
    ratio = np.empty((rows, n), np.float32)
    one = np.float32(1.0)
    for k in range(n):
        coef = lam * w[0, j0 + k] if rows > 1 else np.float32(0.0)
        ratio[0, k] = -coef / (one + coef)
        u[0, j0 + k] = u[0, j0 + k] / (one + coef)
    for i in range(1, rows):
        last = i == rows - 1
        for k in range(n):
            prev = lam * w[i - 1, j0 + k]
            cur = np.float32(0.0) if last else lam * w[i, j0 + k]
            denom = (one + prev + cur) + ratio[i - 1, k] * prev
            ratio[i, k] = -cur / denom
            u[i, j0 + k] = (u[i, j0 + k] + u[i - 1, j0 + k] * prev) / denom
    for i in range(rows - 2, -1, -1):
        for k in range(n):
            u[i, j0 + k] = u[i, j0 + k] - ratio[i, k] * u[i + 1, j0 + k]


@njit(parallel=True)
def _solve_columns(u, w, lam):
    """:func:`_sweep_columns` over all columns of ``u``, blocks of columns in parallel."""
    cols = u.shape[1]
    blocks = (cols + _BLOCK - 1) // _BLOCK
    for b in numba.prange(blocks):
        _sweep_columns(u, w, lam, b * _BLOCK, min(cols, (b + 1) * _BLOCK))


@njit
def _sweep_rows(u, w, lam, i0, i1):
    """:func:`_sweep_columns` along axis 1 for rows ``i0:i1``: on a transposed copy of the block, written back."""
    n = i1 - i0
    cols = u.shape[1]
    tile = np.empty((cols, n), np.float32)
    weights = np.empty((cols, n), np.float32)
    for k in range(n):
        for j in range(cols):
            tile[j, k] = u[i0 + k, j]
            weights[j, k] = w[i0 + k, j]
    _sweep_columns(tile, weights, lam, 0, n)
    for k in range(n):
        for j in range(cols):
            u[i0 + k, j] = tile[j, k]


@njit(parallel=True)
def _solve_rows(u, w, lam):
    """:func:`_sweep_rows` over all rows of ``u``, blocks of rows in parallel."""
    rows = u.shape[0]
    blocks = (rows + _BLOCK - 1) // _BLOCK
    for b in numba.prange(blocks):
        _sweep_rows(u, w, lam, b * _BLOCK, min(rows, (b + 1) * _BLOCK))


@njit(parallel=True)
def _color_weights(guide, lut, wx, wy):
    """:func:`_color_weight_rows` over blocks of rows in parallel."""
    rows = guide.shape[0]
    blocks = (rows + _BLOCK - 1) // _BLOCK
    for b in numba.prange(blocks):
        _color_weight_rows(guide, lut, wx, wy, b * _BLOCK, min(rows, (b + 1) * _BLOCK))


@njit(parallel=True)
def _depth_weights(x, inv_sigma, wx, wy, out_x, out_y):
    """:func:`_depth_weight_rows` over blocks of rows in parallel."""
    rows = x.shape[0]
    blocks = (rows + _BLOCK - 1) // _BLOCK
    for b in numba.prange(blocks):
        _depth_weight_rows(x, inv_sigma, wx, wy, out_x, out_y, b * _BLOCK, min(rows, (b + 1) * _BLOCK))


def _parallel(shape: tuple[int, ...]) -> bool:
    """Threads pay off only on larger images (starting them costs more than a small image's whole solve)."""
    return shape[0] * shape[1] >= _PARALLEL_PIXELS


@functools.lru_cache(maxsize=8)
def _color_lut(channels: int, sigma_color: float) -> np.ndarray:
    """``exp(-sqrt(d2) / sigma_color)`` for every squared color distance ``d2`` of 8-bit channels."""
    levels = np.arange(channels * 255 * 255 + 1, dtype=np.float32)
    lut = np.exp(-np.sqrt(levels) / np.float32(sigma_color)).astype(np.float32)
    lut.flags.writeable = False
    return lut


@njit
def _color_weight_rows(guide, lut, wx, wy, i0, i1):
    """``lut[|dc|**2]`` between horizontal (``wx``) and vertical (``wy``) neighbours, rows ``i0:i1``."""
    rows, cols, channels = guide.shape
    for i in range(i0, i1):
        for j in range(cols):
            if j + 1 < cols:
                d2 = 0
                for c in range(channels):
                    d = np.int32(guide[i, j + 1, c]) - np.int32(guide[i, j, c])
                    d2 += d * d
                wx[i, j] = lut[d2]
            else:
                wx[i, j] = 0.0
            if i + 1 < rows:
                d2 = 0
                for c in range(channels):
                    d = np.int32(guide[i + 1, j, c]) - np.int32(guide[i, j, c])
                    d2 += d * d
                wy[i, j] = lut[d2]
            else:
                wy[i, j] = 0.0


@njit
def _depth_weight_rows(x, inv_sigma, wx, wy, out_x, out_y, i0, i1):
    """``w * exp(-|dx| * inv_sigma)`` for horizontal and vertical neighbours of ``x``, rows ``i0:i1``."""
    rows, cols = x.shape
    for i in range(i0, i1):
        for j in range(cols):
            if j + 1 < cols:
                out_x[i, j] = wx[i, j] * np.exp(-abs(x[i, j + 1] - x[i, j]) * inv_sigma)
            else:
                out_x[i, j] = 0.0
            if i + 1 < rows:
                out_y[i, j] = wy[i, j] * np.exp(-abs(x[i + 1, j] - x[i, j]) * inv_sigma)
            else:
                out_y[i, j] = 0.0


def color_weights(guide: np.ndarray, sigma_color: float) -> tuple[np.ndarray, np.ndarray]:
    """Edge weights ``exp(-|dc| / sigma_color)`` of an (H, W, C) uint8 guide, as OpenCV's fast global smoother.

    Returns ``(wx, wy)``, two (H, W) float32 arrays: ``wx[i, j]`` links pixel
    ``(i, j)`` to ``(i, j + 1)``, ``wy[i, j]`` to ``(i + 1, j)`` (0 in the last
    column / row). ``|dc|`` is the Euclidean distance of the two colors.
    """
    guide = np.ascontiguousarray(guide if guide.ndim == 3 else guide[:, :, None], dtype=np.uint8)
    lut = _color_lut(guide.shape[2], float(sigma_color))
    wx = np.empty(guide.shape[:2], np.float32)
    wy = np.empty(guide.shape[:2], np.float32)
    if _parallel(guide.shape):
        _color_weights(guide, lut, wx, wy)
    else:
        _color_weight_rows(guide, lut, wx, wy, 0, guide.shape[0])
    return wx, wy


def depth_weights(x: np.ndarray, sigma: float, wx: np.ndarray, wy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(wx, wy)`` multiplied by ``exp(-|dx| / sigma)``, the current depth's own gradients (``sigma > 0``)."""
    x = np.ascontiguousarray(x, dtype=np.float32)
    out_x = np.empty_like(wx)
    out_y = np.empty_like(wy)
    if _parallel(x.shape):
        _depth_weights(x, np.float32(1.0 / sigma), wx, wy, out_x, out_y)
    else:
        _depth_weight_rows(x, np.float32(1.0 / sigma), wx, wy, out_x, out_y, 0, x.shape[0])
    return out_x, out_y


def smooth(src: np.ndarray, wx: np.ndarray, wy: np.ndarray, lam: float, *, iterations: int = 3,
           attenuation: float = 0.25) -> np.ndarray:
    """Weighted least-squares smoothing of ``src`` with edge weights ``wx``, ``wy`` (see the module docstring).

    Parameters
    ----------
    src : (H, W) ndarray
        Values to smooth (converted to float32).
    wx, wy : (H, W) float32 ndarray
        Non-negative weights between horizontal / vertical neighbours
        (:func:`color_weights`; their last column / row is not used).
    lam : float
        Smoothing strength of the first iteration.
    iterations, attenuation : int, float
        As OpenCV's ``num_iter`` (3) and ``lambda_attenuation`` (0.25).

    Returns
    -------
    (H, W) float32 ndarray

    Examples
    --------
    >>> guide = np.zeros((4, 6, 3), np.uint8); guide[:, 3:] = 255
    >>> wx, wy = color_weights(guide, 4.0)
    >>> src = np.tile(np.array([0, 1, 0, 10, 11, 10], np.float32), (4, 1))
    >>> out = smooth(src, wx, wy, 100.0)
    >>> bool(out[:, :3].max() < 1 and out[:, 3:].min() > 10)
    True
    """
    u = np.array(src, dtype=np.float32, order="C")
    wx = np.ascontiguousarray(wx, dtype=np.float32)
    wy = np.ascontiguousarray(wy, dtype=np.float32)
    lam32 = np.float32(lam)
    parallel = _parallel(u.shape)
    for _ in range(iterations):
        if parallel:
            _solve_rows(u, wx, lam32)
            _solve_columns(u, wy, lam32)
        else:
            _sweep_rows(u, wx, lam32, 0, u.shape[0])
            _sweep_columns(u, wy, lam32, 0, u.shape[1])
        lam32 = np.float32(lam32 * np.float32(attenuation))
    return u
