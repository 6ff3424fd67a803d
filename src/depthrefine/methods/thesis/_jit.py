"""Compiled per-pixel kernels of the thesis method (numba).

Every kernel here but :func:`median_rows` also exists in C
(``depthrefine/_native/kernels.c``, built at install): the thesis code takes
them from :func:`depthrefine._native.kernels`, which gives the C ones where
the library is built and this module otherwise. These remain the reference
(``tests/test_native_thesis.py`` compares the two bit for bit) and the
fallback; a change to one must be made to the other.

Imported only where the C kernels are not there, or for arguments they do not
take (never at ``import depthrefine``): importing this module imports numba. Kernels are compiled on first use and
cached on disk (``cache=True``; numba falls back to a per-user cache
directory when the package's own is not writable), and release the GIL
(``nogil=True``) so that patches run in threads.

No ``fastmath``: every float operation is the IEEE operation, in the same
order and precision as the NumPy expressions they replace, so results are
bit for bit those of the NumPy code (``float32`` stays ``float32``; sums run
in the order ``np.bincount`` adds).
"""

from __future__ import annotations

import numpy as np

from ..._numba import njit as _jit, note_first_compile

#: Seconds the thesis method's first run spends compiling its kernels with an empty numba cache
#: (2-core machine, ``python benchmarks/first_call.py``); said in the first-compile note.
FIRST_COMPILE_SECONDS = 13


# ----------------------------------------------------------------------------
# Clustering (segment.cluster_colors, segment.kmeans)
# ----------------------------------------------------------------------------


@_jit
def quantize_lab(lab, inv_step, half, unify, black, white, qa, qb, first):
    """Bin a* and b* (and L* without ``unify``) of one patch; classes and their L* sums.

    ``q = floor(v * inv_step + half)`` in the dtype of ``lab`` (``inv_step`` and
    ``half`` are float32, as in the NumPy expression). With ``unify``,
    ``first`` gets the class of L* (0 black: ``L* <= black``, 2 white:
    ``L* >= white``, else 1) and the L* sums per class are accumulated in
    float64 in row-major order (as ``np.bincount(cls, weights=L*)``);
    without it, ``first`` gets the binned L*.

    Returns ``(a_min, a_max, b_min, b_max, f_min, f_max, n_cls, sum_l)``.
    """
    rows, cols = qa.shape
    a_lo = b_lo = f_lo = np.iinfo(np.int32).max
    a_hi = b_hi = f_hi = np.iinfo(np.int32).min
    # Each class's L* sum in pixel order, as np.bincount adds (x + 0.0 == x).
    c0 = c1 = c2 = 0
    s0 = s1 = s2 = 0.0
    for i in range(rows):
        for j in range(cols):
            light = lab[i, j, 0]
            a = np.int32(np.floor(lab[i, j, 1] * inv_step + half))
            b = np.int32(np.floor(lab[i, j, 2] * inv_step + half))
            if unify:
                f = np.int32(1) - np.int32(light <= black) + np.int32(light >= white)
                wide = np.float64(light)
                s0 += wide if f == 0 else 0.0
                s1 += wide if f == 1 else 0.0
                s2 += wide if f == 2 else 0.0
                c0 += f == 0
                c2 += f == 2
            else:
                f = np.int32(np.floor(light * inv_step + half))
            qa[i, j], qb[i, j], first[i, j] = a, b, f
            a_lo, a_hi = min(a_lo, a), max(a_hi, a)
            b_lo, b_hi = min(b_lo, b), max(b_hi, b)
            f_lo, f_hi = min(f_lo, f), max(f_hi, f)
    c1 = rows * cols - c0 - c2
    return (a_lo, a_hi, b_lo, b_hi, f_lo, f_hi, np.array([c0, c1 if unify else 0, c2], np.int64),
            np.array([s0, s1, s2], np.float64))


@_jit
def lookup(table, index, out):
    """``out[i, j] = table[index[i, j]]``."""
    rows, cols = index.shape
    for i in range(rows):
        for j in range(cols):
            out[i, j] = table[index[i, j]]


@_jit
def feature_codes(qa, qb, first, a0, na, b0, nb, f0, code, counts):
    """``code = ((first - f0) * na + qa - a0) * nb + qb - b0``; its histogram into ``counts`` (if not empty)."""
    rows, cols = qa.shape
    count = counts.shape[0] > 0
    for i in range(rows):
        for j in range(cols):
            c = ((np.int64(first[i, j]) - f0) * na + (np.int64(qa[i, j]) - a0)) * nb + (np.int64(qb[i, j]) - b0)
            code[i, j] = c
            if count:
                counts[c] += 1


@_jit
def _assign(x, means, labels):
    """Nearest of the float32 ``means`` (first on ties), distances summed in float32 as NumPy does."""
    n, dims = x.shape
    k = means.shape[0]
    for i in range(n):
        best = 0
        best_d = np.float32(0.0)
        for j in range(k):
            d = np.float32(0.0)
            for e in range(dims):
                diff = x[i, e] - means[j, e]
                sq = diff * diff
                d = sq if e == 0 else d + sq
            if j == 0 or d < best_d:
                best, best_d = j, d
        labels[i] = best


@_jit
def lloyd(x, w, means, iterations):
    """``iterations`` rounds of k-means from ``means``; empty clusters dropped, labels renumbered.

    ``x`` (N, D) float32, ``w`` (N,) float64 multiplicities, ``means`` (k, D)
    float64. Counts and sums are accumulated in point order in float64 (as
    ``np.bincount`` with weights); distances in float32.
    """
    n, dims = x.shape
    labels = np.empty(n, np.int32)
    _assign(x, means.astype(np.float32), labels)
    for _ in range(iterations):
        k = means.shape[0]
        counts = np.zeros(k, np.float64)
        sums = np.zeros((k, dims), np.float64)
        for i in range(n):
            c = labels[i]
            counts[c] += w[i]
            for e in range(dims):
                sums[c, e] += w[i] * np.float64(x[i, e])
        kept = 0
        for c in range(k):
            if counts[c] > 0:
                kept += 1
        new = np.empty((kept, dims), np.float64)
        m = 0
        for c in range(k):
            if counts[c] > 0:
                for e in range(dims):
                    new[m, e] = sums[c, e] / counts[c]
                m += 1
        means = new
        _assign(x, means.astype(np.float32), labels)
    k = means.shape[0]
    used = np.zeros(k, np.bool_)
    for i in range(n):
        used[labels[i]] = True
    remap = np.cumsum(used) - 1
    for i in range(n):
        labels[i] = remap[labels[i]]
    return labels, means[used]


# ----------------------------------------------------------------------------
# Interpolation (interpolate._interpolate_clusters)
# ----------------------------------------------------------------------------


#: The eight neighbours in the order the nearest sample is looked for: the four at distance 1, then the four
#: at sqrt(2); among equals, the smaller column offset, then the smaller row offset, the sample that SciPy's exact
#: Euclidean feature transform picks (tests/test_thesis_kernels.py checks both agree).
_NEIGHBOURS = np.array([(0, -1), (-1, 0), (1, 0), (0, 1), (-1, -1), (1, -1), (-1, 1), (1, 1)], np.int64)


@_jit
def grow_samples(masks, corrected, values, grown):
    """Each cluster's samples grown by one pixel (3x3), new pixels taking the value of their nearest sample.

    ``masks[c]`` marks the samples of cluster ``c``; ``grown[c]`` becomes the
    3x3 dilation of ``masks[c]`` and ``values[c]`` the value of
    ``corrected`` at the nearest sample of ``c`` (the pixel itself for a
    sample; 0 off ``grown[c]``). A new pixel's nearest sample is one of its
    eight neighbours, looked for in :data:`_NEIGHBOURS`' order: the result of
    ``scipy.ndimage.binary_dilation`` and of ``distance_transform_edt``'s
    nearest-feature indices, one cluster at a time, for expansion 1.
    """
    k, rows, cols = masks.shape
    for c in range(k):
        mask = masks[c]
        for i in range(rows):
            for j in range(cols):
                if mask[i, j]:
                    grown[c, i, j] = True
                    values[c, i, j] = corrected[i, j]
                    continue
                grown[c, i, j] = False
                values[c, i, j] = 0.0
                for n in range(8):
                    y, x = i + _NEIGHBOURS[n, 0], j + _NEIGHBOURS[n, 1]
                    if 0 <= y < rows and 0 <= x < cols and mask[y, x]:
                        grown[c, i, j] = True
                        values[c, i, j] = corrected[y, x]
                        break


@_jit
def interpolate_patch(filled, cell_label, labels, weighted, present, i0, i1, fr, j0, j1, fc, out):
    """Each pixel of one patch from the samples of its own cluster; returns the count of non-finite results.

    A pixel whose cell (its four neighbouring samples) is all valid and of
    the pixel's cluster (``cell_label[i0, j0] == label``) is plain bilinear
    interpolation of ``filled`` in float32: along columns first, then rows,
    each ``a + f * (b - a)``. Any other pixel is the bilinear interpolation of
    ``weighted`` (value x weight of its cluster) divided by that of
    ``present`` (weight), in float64; NaN where the weight is 0.
    """
    rows, cols = labels.shape
    n_lr = filled.shape[0]
    fr32 = fr.astype(np.float32)
    fc32 = fc.astype(np.float32)
    # Along columns, once per sample row; the cell label seen by each column.
    along = np.empty((n_lr, cols), np.float32)
    cell = np.empty((n_lr, cols), np.int16)
    for i in range(n_lr):
        for c in range(cols):
            left = filled[i, j0[c]]
            along[i, c] = left + fc32[c] * (filled[i, j1[c]] - left)
            cell[i, c] = cell_label[i, j0[c]]
    bad = 0
    for r in range(rows):
        a0, a1, f = i0[r], i1[r], fr32[r]
        top, bottom, own, row = along[a0], along[a1], cell[a0], out[r]
        for c in range(cols):
            row[c] = top[c] + f * (bottom[c] - top[c])
        for c in range(cols):
            label = labels[r, c]
            if own[c] == label:
                continue
            b0, b1 = j0[c], j1[c]
            p, q = weighted[label], present[label]
            t = p[a0, b0] + fc[c] * (p[a0, b1] - p[a0, b0])
            u = p[a1, b0] + fc[c] * (p[a1, b1] - p[a1, b0])
            num = t + fr[r] * (u - t)
            t = q[a0, b0] + fc[c] * (q[a0, b1] - q[a0, b0])
            u = q[a1, b0] + fc[c] * (q[a1, b1] - q[a1, b0])
            den = t + fr[r] * (u - t)
            if den > 0:
                row[c] = np.float32(num / den)
                if not np.isfinite(row[c]):
                    bad += 1
            else:
                row[c] = np.nan
                bad += 1
    return bad


@_jit
def fill_missing(result, fallback, near_rows, near_cols):
    """Non-finite pixels of ``result`` take ``fallback[near_rows[r], near_cols[c]]``."""
    rows, cols = result.shape
    for r in range(rows):
        for c in range(cols):
            if not np.isfinite(result[r, c]):
                result[r, c] = fallback[near_rows[r], near_cols[c]]


# ----------------------------------------------------------------------------
# Histogram correction (refine.correct_cluster_depths)
# ----------------------------------------------------------------------------


@_jit
def correct_values(values, origin, level_size, bin_width, n_bins, dominant_fraction, tolerance, out):
    """:func:`refine.correct_cluster_depths` on float64 ``values`` into ``out`` (``tolerance`` in depth units)."""
    n = values.shape[0]
    counts = np.zeros(n_bins, np.int64)
    n_valid = 0
    for i in range(n):
        v = values[i]
        if np.isfinite(v):
            n_valid += 1
            b = np.int64(np.floor((v - origin) / bin_width + 0.5))
            counts[min(max(b, 0), n_bins - 1)] += 1
    if n_valid == 0:
        out[:] = np.nan
        return
    peak = counts.max()
    fullest = origin + np.float64(np.argmax(counts)) * bin_width
    n_dom = 0
    for b in range(n_bins):
        if counts[b] == peak or counts[b] > dominant_fraction * peak:
            n_dom += 1
    dominant = np.empty(n_dom, np.float64)
    n_dom = 0
    for b in range(n_bins):
        if counts[b] == peak or counts[b] > dominant_fraction * peak:
            dominant[n_dom] = origin + np.float64(b) * bin_width
            n_dom += 1
    for i in range(n):
        v = values[i]
        if not np.isfinite(v):
            out[i] = fullest
            continue
        best = dominant[0]
        best_d = abs(v - best)
        for j in range(1, n_dom):
            d = abs(v - dominant[j])
            if d < best_d:
                best, best_d = dominant[j], d
        out[i] = best if best_d > tolerance else v


@_jit
def correct_patch(depth, samples, k, correct, origin, level_size, bin_width, n_bins, dominant_fraction, tolerance,
                  out):
    """Per cluster ``c < k``: the samples of ``depth`` labelled ``c`` corrected (:func:`correct_values`) into ``out``.

    Without ``correct`` they are copied; pixels of no cluster stay as they are in ``out``.
    """
    rows, cols = depth.shape
    values = np.empty(rows * cols, np.float64)
    fixed = np.empty(rows * cols, np.float64)
    for c in range(k):
        n = 0
        for i in range(rows):
            for j in range(cols):
                if samples[i, j] == c:
                    values[n] = depth[i, j]
                    n += 1
        if n == 0:
            continue
        if correct:
            correct_values(values[:n], origin, level_size, bin_width, n_bins, dominant_fraction, tolerance,
                           fixed[:n])
        else:
            fixed[:n] = values[:n]
        n = 0
        for i in range(rows):
            for j in range(cols):
                if samples[i, j] == c:
                    out[i, j] = fixed[n]
                    n += 1


# ----------------------------------------------------------------------------
# Median (median.median_filter)
# ----------------------------------------------------------------------------

#: Lanes rounded up to this many (one AVX2 register of bytes) so that every
#: min/max loop vectorises without a scalar tail; the extra lanes are garbage
#: that no output depends on.
_VEC = 32


@_jit
def median_rows(image, out, table, n_slots, out0, out1, size, y0, y1, chunk):
    """Rows ``y0 .. y1-1`` of the ``size`` x ``size`` median of ``image`` (edges replicated) into ``out``.

    ``image`` and ``out`` are (rows, width, channels) C-contiguous; ``y1 - y0``
    is even or ``y1`` is the last row. The program ``table`` (of
    :func:`median.median_network`) runs on lanes of one row pair: lane
    ``x * channels + c`` is channel ``c`` of the window whose leftmost column
    is ``x``, so a column offset is ``channels`` lanes. Lanes go by in chunks
    of ``chunk`` so that the ``n_slots`` rows of the program stay in cache.
    """
    rows, width, ch = image.shape
    half = size // 2
    lanes = width * ch
    pad = half * ch
    span = (size - 1) * ch
    buf = np.zeros((n_slots, chunk + span + 2 * _VEC), image.dtype)
    flat = image.reshape(rows, lanes)
    oflat = out.reshape(rows, lanes)
    ops = table.astype(np.int64)
    for i in range(ops.shape[0]):
        ops[i, 3] *= ch
        ops[i, 5] *= ch
        ops[i, 6] *= ch
    for y in range(y0, y1, 2):
        for c0 in range(0, lanes, chunk):
            m = min(chunk, lanes - c0)  # output lanes of this chunk
            n_in = m + span  # edge-padded input lanes c0 .. c0 + n_in
            for r in range(size + 1):
                src = min(max(y + r - half, 0), rows - 1)
                row = buf[r]
                lo = max(0, pad - c0)
                hi = min(n_in, pad + lanes - c0)
                row[lo:hi] = flat[src, c0 + lo - pad:c0 + hi - pad]
                for j in range(lo):
                    row[j] = flat[src, (c0 + j) % ch]
                for j in range(hi, n_in):
                    row[j] = flat[src, lanes - ch + (c0 + j) % ch]
            for i in range(ops.shape[0]):
                d = buf[ops[i, 1]]
                a = buf[ops[i, 2]][ops[i, 3]:]
                b = buf[ops[i, 4]][ops[i, 5]:]
                n = (m + ops[i, 6] + _VEC - 1) // _VEC * _VEC
                if ops[i, 0] == 0:
                    for x in range(n):
                        d[x] = min(a[x], b[x])
                else:
                    for x in range(n):
                        d[x] = max(a[x], b[x])
            oflat[y, c0:c0 + m] = buf[out0][:m]
            if y + 1 < rows:
                oflat[y + 1, c0:c0 + m] = buf[out1][:m]


# With a cold numba cache the thesis method's first run compiles these kernels (and the median
# kernels): say so, once, before it starts.
note_first_compile(__name__, what="the thesis method's kernels", seconds=FIRST_COMPILE_SECONDS)
