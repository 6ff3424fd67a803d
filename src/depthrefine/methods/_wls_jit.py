"""The numba kernels of gbp's solver (:mod:`depthrefine.methods._wls`), compiled on first use and cached on disk.

The reference for the same kernels in C (:mod:`depthrefine._native`, built at
install), which give the same bits; these run where the C library is not
built. Importing this module imports numba. No ``fastmath``.
"""

from __future__ import annotations

import numpy as np

from .._numba import expf32, njit, note_first_compile
from ._wls import MAX_COUPLING

__all__ = ["sweep_columns", "solve_columns", "color_weight_rows", "edge_weight_rows", "depth_weight_rows"]

#: Seconds a first gbp call spends compiling the kernels with an empty numba cache (CPU seconds, cold minus warm,
#: of ``python benchmarks/first_call.py --methods gbp`` on the 2-core machine at 71069c9: 5.6 and 6.0); said in
#: the first-compile note.
FIRST_COMPILE_SECONDS = 6


@njit(error_model="numpy")
def sweep_columns(u, w, lam, j0, j1):
    """Solve ``(I + lam * L_w) v = u`` along axis 0 for columns ``j0:j1`` of ``u``, in place.

    ``w[i, j]`` is the weight between rows ``i`` and ``i + 1`` of column ``j``
    (its last row is unused); ``a_i = min(lam * w[i], MAX_COUPLING)``. Thomas
    algorithm without subtractions of large terms: with ``e_i`` the pivot
    ``d_i`` minus ``a_i`` (``e_0 = 1``), ``r_i = a_i / (e_i + a_i)`` and
    ``e_{i+1} = 1 + r_i * e_i``, all positive; the forward pass keeps the
    weighted mean ``z_i = u_i + q_i * (z_{i-1} - u_i)`` (``q_i = 1 - 1 / e_i``)
    and the backward pass ``v_i = z_i + r_i * (v_{i+1} - z_i)``. A constant
    stays exactly constant and a zero weight exactly separates, for any
    ``lam``. (OpenCV's pivot ``1 + a_{i-1} + a_i - a_{i-1} * r_{i-1}`` cancels
    when the ``a`` are large.) Every divisor is ``>= 1``, so numpy's error
    model (no division-by-zero check, which kept the loops from vectorising)
    changes no result.

    The inner loops run over the block's columns on row views, and the
    previous row's result is carried in a vector of its own (``last``)
    rather than read back from ``u``: with ``u`` both read and written in a
    loop, LLVM's run-time overlap check sent every row to the scalar loop
    (half the speed).
    """
    rows = u.shape[0]
    n = j1 - j0
    ratio = np.empty((rows, n), np.float32)
    e = np.ones(n, np.float32)
    last = u[0, j0:j1].copy()
    one = np.float32(1.0)
    cap = np.float32(MAX_COUPLING)
    if rows > 1:
        w_row, r_row = w[0, j0:j1], ratio[0]
        for k in range(n):
            a = min(lam * w_row[k], cap)
            r_row[k] = a / (one + a)
    for i in range(1, rows - 1):
        u_row, w_row, r_prev, r_row = u[i, j0:j1], w[i, j0:j1], ratio[i - 1], ratio[i]
        for k in range(n):
            g = r_prev[k] * e[k]
            ek = one + g
            f = u_row[k]
            z = f + (g / ek) * (last[k] - f)
            u_row[k] = z
            last[k] = z
            a = min(lam * w_row[k], cap)
            r_row[k] = a / (ek + a)
            e[k] = ek
    if rows > 1:
        u_row, r_prev = u[rows - 1, j0:j1], ratio[rows - 2]
        for k in range(n):
            g = r_prev[k] * e[k]
            f = u_row[k]
            z = f + (g / (one + g)) * (last[k] - f)
            u_row[k] = z
            last[k] = z
    for i in range(rows - 2, -1, -1):
        u_row, r_row = u[i, j0:j1], ratio[i]
        for k in range(n):
            z = u_row[k]
            v = z + r_row[k] * (last[k] - z)
            u_row[k] = v
            last[k] = v


@njit
def solve_columns(u, w, lam, block, b0, b1):
    """:func:`sweep_columns` over the blocks ``b0:b1`` of ``block`` columns of ``u``, one after the other."""
    cols = u.shape[1]
    for b in range(b0, b1):
        sweep_columns(u, w, lam, b * block, min(cols, (b + 1) * block))


@njit(inline="always")
def _color_distance2(a, b, j_a, j_b):
    """Squared Euclidean distance of the colors ``a[j_a]`` and ``b[j_b]`` (rows of a uint8 guide), as int32."""
    if a.shape[1] == 3:   # unrolled: the loop over the columns then vectorises
        d0 = np.int32(a[j_a, 0]) - np.int32(b[j_b, 0])
        d1 = np.int32(a[j_a, 1]) - np.int32(b[j_b, 1])
        d2 = np.int32(a[j_a, 2]) - np.int32(b[j_b, 2])
        return d0 * d0 + d1 * d1 + d2 * d2
    total = np.int32(0)
    for c in range(a.shape[1]):
        d = np.int32(a[j_a, c]) - np.int32(b[j_b, c])
        total += d * d
    return total


@njit
def color_weight_rows(guide, lut, wx, wy, i0, i1):
    """``lut[|dc|**2]`` between horizontal (``wx``) and vertical (``wy``) neighbours, rows ``i0:i1``."""
    rows, cols = guide.shape[:2]
    for i in range(i0, i1):
        row, out = guide[i], wx[i]
        for j in range(cols - 1):
            out[j] = lut[_color_distance2(row, row, j + 1, j)]
        out[cols - 1] = 0.0
        out = wy[i]
        if i + 1 < rows:
            below = guide[i + 1]
            for j in range(cols):
                out[j] = lut[_color_distance2(below, row, j, j)]
        else:
            out[:] = 0.0


@njit
def edge_weight_rows(guide, lut, x, inv_sigma, wx, wy, i0, i1):
    """:func:`color_weight_rows` times :func:`depth_weight_rows`' factor, rows ``i0:i1``.

    Each row is made in two loops (the color weights, then the factor), which
    vectorise; one loop doing both did not, and took twice their time.
    """
    rows, cols = x.shape
    for i in range(i0, i1):
        color_weight_rows(guide, lut, wx, wy, i, i + 1)
        x_row, out = x[i], wx[i]
        for j in range(cols - 1):
            out[j] *= expf32(-abs(x_row[j + 1] - x_row[j]) * inv_sigma)
        if i + 1 < rows:
            below, out = x[i + 1], wy[i]
            for j in range(cols):
                out[j] *= expf32(-abs(below[j] - x_row[j]) * inv_sigma)


@njit
def depth_weight_rows(x, inv_sigma, wx, wy, out_x, out_y, i0, i1):
    """``w * exp(-|dx| * inv_sigma)`` for horizontal and vertical neighbours of ``x``, rows ``i0:i1``.

    ``exp`` is :func:`~depthrefine._numba.expf32` (glibc's ``expf``, bit for
    bit, but vectorised); each loop runs over a row's columns.
    """
    rows, cols = x.shape
    for i in range(i0, i1):
        x_row, w_row, out_row = x[i], wx[i], out_x[i]
        for j in range(cols - 1):
            out_row[j] = w_row[j] * expf32(-abs(x_row[j + 1] - x_row[j]) * inv_sigma)
        out_row[cols - 1] = 0.0
        out_row = out_y[i]
        if i + 1 < rows:
            below, w_row = x[i + 1], wy[i]
            for j in range(cols):
                out_row[j] = w_row[j] * expf32(-abs(below[j] - x_row[j]) * inv_sigma)
        else:
            out_row[:] = 0.0



# With a cold numba cache the first solve compiles the kernels above: say so, once, before it starts.
note_first_compile(__name__, what="gbp's solver", seconds=FIRST_COMPILE_SECONDS)
