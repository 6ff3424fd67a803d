"""gbp's compiled kernels between two grids: the guided x2 enlargement, clips to bounds on the input's grid.

- :func:`guided_enlarge`: joint bilateral x2 enlargement of the reduced
  rounds' estimate (:func:`depthrefine.methods.gbp.solve.back_project`);
- :func:`clip_nearest`, :func:`clip_toward`: a clip to per-pixel bounds
  that live on the input's grid (their nearest-neighbour enlargement,
  without its image-sized arrays).

Imported only when gbp runs (it imports numba, like :mod:`._wls`, whose
first-compile note covers these kernels too: they compile in the same first
run).
"""

from __future__ import annotations

import numpy as np

from .._numba import njit, run_split
from .._validate import check_number
from ._wls import _check_in_place, _color_lut, _guide, _parallel

__all__ = ["guided_enlarge", "clip_nearest", "clip_toward"]


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
def _enlarge_rows(x, s0, s1, s2, guide, lut, out, i0, i1):
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


def guided_enlarge(x: np.ndarray, small_guide: np.ndarray, guide: np.ndarray, sigma_color: float) -> np.ndarray:
    """Enlarge ``x`` x2 to ``guide``'s grid, each pixel from the small pixels whose color is like its own.

    Joint bilateral upsampling (Kopf et al. 2007) on the bilinear footprint:
    each output pixel is the mean of its four nearest ``x`` pixels weighted
    by their bilinear weights (9, 3, 3, 1 sixteenths) times
    ``exp(-|dc| / sigma_color)``, ``|dc|`` the distance of the output
    pixel's color in ``guide`` to the small pixel's color in ``small_guide``
    (its 2x2 block's mean, say); where all four are far off, the bilinear
    enlargement. ``x`` and ``small_guide`` are on the grid of
    ``ceil(H / 2) x ceil(W / 2)`` pixels, small pixel ``q`` centred between
    output pixels ``2q`` and ``2q + 1``; the guides are (H, W, 3) uint8.

    Examples
    --------
    >>> guide = np.zeros((4, 8, 3), np.uint8); guide[:, 3:] = 255       # the edge inside small column 1
    >>> small = np.zeros((2, 4, 3), np.uint8); small[:, 1] = 128; small[:, 2:] = 255
    >>> x = np.array([[0, 50, 100, 100]] * 2, np.float32)
    >>> guided_enlarge(x, small, guide, 16.0)[0].round(1).tolist()
    [0.0, 0.0, 0.0, 100.0, 100.0, 100.0, 100.0, 100.0]
    """
    import cv2

    small_guide, guide = _guide(small_guide), _guide(guide)
    x = np.ascontiguousarray(x, dtype=np.float32)
    (H, W), (h, w) = guide.shape[:2], x.shape
    if small_guide.shape[:2] != (h, w) or (h, w) != (-(-H // 2), -(-W // 2)) or guide.shape[2] != 3 \
            or small_guide.shape[2] != 3:
        raise ValueError(f"x and small_guide must be of the guide's grid halved, {(-(-H // 2), -(-W // 2))}, "
                         f"the guides of 3 channels; got {x.shape}, {small_guide.shape} and {guide.shape}.")
    lut = _color_lut(3, check_number("sigma_color", sigma_color, positive=True))
    out = np.empty((H, W), np.float32)
    run_split(_enlarge_rows, H, x, *cv2.split(small_guide), guide, lut, out, parallel=_parallel(out.shape))
    return out


@njit
def _clip_rows(x, low, high, lower, upper, rows, cols, i0, i1):
    """:func:`clip_nearest` for the rows ``i0:i1`` of ``x``."""
    for i in range(i0, i1):
        x_row, lower_row, upper_row = x[i], lower[rows[i]], upper[rows[i]]
        for j in range(x_row.shape[0]):
            v = min(max(x_row[j], low), high)
            x_row[j] = min(max(v, lower_row[cols[j]]), upper_row[cols[j]])


def clip_nearest(x: np.ndarray, low: float, high: float, lower: np.ndarray, upper: np.ndarray, rows: np.ndarray,
                 cols: np.ndarray) -> None:
    """Clip ``x`` in place to ``[low, high]``, then pixel ``(i, j)`` to ``[lower[rows[i], cols[j]], upper[...]]``.

    One pass: the bounds ``lower``, ``upper`` stay on their own (small)
    grid, ``rows`` and ``cols`` (int32) map ``x``'s rows and columns to
    theirs. ``x`` is a C-contiguous float32 array without NaN.

    Examples
    --------
    >>> x = np.arange(6, dtype=np.float32).reshape(2, 3)
    >>> clip_nearest(x, 0.5, 4.5, np.full((1, 2), 1, np.float32), np.array([[3, 9]], np.float32),
    ...              np.zeros(2, np.int32), np.array([0, 0, 1], np.int32)); x.tolist()
    [[1.0, 1.0, 2.0], [3.0, 3.0, 4.5]]
    """
    _check_in_place(x, "clipped")
    if x.shape != (len(rows), len(cols)):
        raise ValueError(f"rows and cols must map x's {x.shape} rows and columns; got {len(rows)} and {len(cols)}.")
    lower = np.ascontiguousarray(lower, dtype=np.float32)
    upper = np.ascontiguousarray(upper, dtype=np.float32)
    rows = np.ascontiguousarray(rows, dtype=np.int32)
    cols = np.ascontiguousarray(cols, dtype=np.int32)
    run_split(_clip_rows, x.shape[0], x, np.float32(low), np.float32(high), lower, upper, rows, cols,
              parallel=_parallel(x.shape))


@njit
def _clip_toward_rows(x, weight, lower, upper, rows, cols, i0, i1):
    """:func:`clip_toward` for the rows ``i0:i1`` of ``x``."""
    for i in range(i0, i1):
        x_row, w_row, lower_row, upper_row = x[i], weight[i], lower[rows[i]], upper[rows[i]]
        for j in range(x_row.shape[0]):
            v = x_row[j]
            clipped = min(max(v, lower_row[cols[j]]), upper_row[cols[j]])
            x_row[j] = v + (clipped - v) * w_row[j]


def clip_toward(x: np.ndarray, weight: np.ndarray, lower: np.ndarray, upper: np.ndarray, rows: np.ndarray,
                cols: np.ndarray) -> None:
    """Move ``x`` in place toward its clip to the bounds of :func:`clip_nearest` by ``weight`` (0: stay, 1: clip).

    ``x <- x + weight * (clip(x) - x)`` with float32 operations in that
    order; ``weight`` is an array of ``x``'s shape.

    Examples
    --------
    >>> x = np.array([[0.0, 5.0, 10.0]], np.float32)
    >>> clip_toward(x, np.array([[1.0, 1.0, 0.5]], np.float32), np.full((1, 1), 2, np.float32),
    ...             np.full((1, 1), 6, np.float32), np.zeros(1, np.int32), np.zeros(3, np.int32)); x.tolist()
    [[2.0, 5.0, 8.0]]
    """
    _check_in_place(x, "changed")
    if x.shape != (len(rows), len(cols)) or weight.shape != x.shape:
        raise ValueError(f"weight must be of x's shape {x.shape} and rows, cols map its rows and columns; got "
                         f"{weight.shape}, {len(rows)} and {len(cols)}.")
    run_split(_clip_toward_rows, x.shape[0], x, np.ascontiguousarray(weight, dtype=np.float32),
              np.ascontiguousarray(lower, dtype=np.float32), np.ascontiguousarray(upper, dtype=np.float32),
              np.ascontiguousarray(rows, dtype=np.int32), np.ascontiguousarray(cols, dtype=np.int32),
              parallel=_parallel(x.shape))
