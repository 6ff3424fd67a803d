"""The numba kernels of :mod:`depthrefine.methods._resample`, compiled on first use and cached on disk.

The reference for the same kernels in C (:mod:`depthrefine._native`, built at
install), which give the same bits; these run where the C library is not
built. Importing this module imports numba (the first-compile note of
:mod:`._wls_jit` covers these kernels too: they compile in the same first run).
"""

from __future__ import annotations

import numpy as np

from .._numba import njit

__all__ = ["enlarge_rows", "clip_rows", "clip_toward_rows"]


@njit(inline="always")
def _similar(lut, a0, a1, a2, b0, b1, b2, k):
    """``lut[|dc|**2]`` of the colors at ``k`` of the color planes ``a0, a1, a2`` and ``b0, b1, b2``."""
    d0 = np.float32(a0[k]) - np.float32(b0[k])   # float32, not numba's int64: exact, and half the width
    d1 = np.float32(a1[k]) - np.float32(b1[k])
    d2 = np.float32(a2[k]) - np.float32(b2[k])
    return lut[np.int32(d0 * d0 + d1 * d1 + d2 * d2)]


@njit
def _blend_row(lut, colors, near, near_far, far, far_far, x_near, x_near_far, x_far, x_far_far, out, n):
    """``out[k]``, ``k < n``: the mean of the small pixels ``near`` (bilinear weight 9/16), ``near_far``
    (3/16), ``far`` (3/16) and ``far_far`` (1/16), each weighted also by its color's likeness to ``colors``
    (tuples of three color rows); every array is indexed by ``k`` alone (the caller shifts them)."""
    tiny = np.float32(1e-30)   # all four colors far off: the bilinear weights
    b0, b1, b2 = colors
    n0, n1, n2 = near
    nf0, nf1, nf2 = near_far
    f0, f1, f2 = far
    ff0, ff1, ff2 = far_far
    for k in range(n):
        w_nn = np.float32(9.0) * (_similar(lut, n0, n1, n2, b0, b1, b2, k) + tiny)
        w_nf = np.float32(3.0) * (_similar(lut, nf0, nf1, nf2, b0, b1, b2, k) + tiny)
        w_fn = np.float32(3.0) * (_similar(lut, f0, f1, f2, b0, b1, b2, k) + tiny)
        w_ff = _similar(lut, ff0, ff1, ff2, b0, b1, b2, k) + tiny
        out[k] = (w_nn * x_near[k] + w_nf * x_near_far[k] + w_fn * x_far[k] + w_ff * x_far_far[k]) / (
            w_nn + w_nf + w_fn + w_ff)


@njit(inline="always")
def _shift(planes, start, stop):
    """The rows of ``planes`` (a tuple of three) from ``start`` to ``stop``."""
    return planes[0][start:stop], planes[1][start:stop], planes[2][start:stop]


@njit
def enlarge_rows(x, s0, s1, s2, guide, lut, out, i0, i1):
    """:func:`guided_enlarge` for the rows ``i0:i1`` of ``out``; ``s*`` the small guide's color planes,
    ``guide`` the (H, W, 3) one.

    Output row ``2q`` lies between small rows ``q`` (bilinear weight 3/4)
    and ``q - 1`` (1/4), row ``2q + 1`` between ``q`` and ``q + 1``, and so
    along the columns (clamped at the borders). The even and the odd
    output columns are made apart, each from its own color row (the guide's
    row split into its even and odd pixels), then interleaved.
    """
    h, w = x.shape
    cols = out.shape[1]
    odd_cols = cols // 2                      # output columns 2k + 1
    even_colors = np.empty((3, w), np.uint8)
    odd_colors = np.empty((3, w), np.uint8)
    even_out = np.empty(w, np.float32)
    odd_out = np.empty(w, np.float32)
    for i in range(i0, i1):
        q = i >> 1
        p = max(q - 1, 0) if i % 2 == 0 else min(q + 1, h - 1)
        near, far = (s0[q], s1[q], s2[q]), (s0[p], s1[p], s2[p])
        x_near, x_far = x[q], x[p]
        row = guide[i]
        for c in range(3):
            even_c, odd_c = even_colors[c], odd_colors[c]
            for k in range(odd_cols):
                even_c[k] = row[2 * k, c]
                odd_c[k] = row[2 * k + 1, c]
            if w > odd_cols:
                even_c[w - 1] = row[2 * w - 2, c]
        even = (even_colors[0], even_colors[1], even_colors[2])
        odd = (odd_colors[0], odd_colors[1], odd_colors[2])
        # column 0: small column 0 on both sides; columns 2k, k >= 1: small columns k and k - 1
        _blend_row(lut, even, near, near, far, far, x_near, x_near, x_far, x_far, even_out, 1)
        _blend_row(lut, _shift(even, 1, w), _shift(near, 1, w), _shift(near, 0, w - 1), _shift(far, 1, w),
                   _shift(far, 0, w - 1), x_near[1:], x_near[:-1], x_far[1:], x_far[:-1], even_out[1:], w - 1)
        # columns 2k + 1: small columns k and k + 1 (the last column: k on both sides)
        last = min(odd_cols, w - 1)
        _blend_row(lut, odd, near, _shift(near, 1, w), far, _shift(far, 1, w), x_near, x_near[1:], x_far,
                   x_far[1:], odd_out, last)
        if odd_cols > last:
            _blend_row(lut, _shift(odd, last, w), _shift(near, last, w), _shift(near, last, w),
                       _shift(far, last, w), _shift(far, last, w), x_near[last:], x_near[last:],
                       x_far[last:], x_far[last:], odd_out[last:], 1)
        out_row = out[i]
        for k in range(odd_cols):
            out_row[2 * k] = even_out[k]
            out_row[2 * k + 1] = odd_out[k]
        if w > odd_cols:
            out_row[2 * w - 2] = even_out[w - 1]


@njit
def clip_rows(x, low, high, lower, upper, rows, cols, i0, i1):
    """:func:`clip_nearest` for the rows ``i0:i1`` of ``x``."""
    for i in range(i0, i1):
        x_row, lower_row, upper_row = x[i], lower[rows[i]], upper[rows[i]]
        for j in range(x_row.shape[0]):
            v = min(max(x_row[j], low), high)
            x_row[j] = min(max(v, lower_row[cols[j]]), upper_row[cols[j]])


@njit
def clip_toward_rows(x, weight, lower, upper, rows, cols, i0, i1):
    """:func:`clip_toward` for the rows ``i0:i1`` of ``x``."""
    for i in range(i0, i1):
        x_row, w_row, lower_row, upper_row = x[i], weight[i], lower[rows[i]], upper[rows[i]]
        for j in range(x_row.shape[0]):
            v = x_row[j]
            clipped = min(max(v, lower_row[cols[j]]), upper_row[cols[j]])
            x_row[j] = v + (clipped - v) * w_row[j]
