"""The compiled kernels of the thesis method (methods/thesis/_jit.py) against plain NumPy references.

The references are the NumPy formulations the kernels replaced; the kernels must
give the same bits (same float operations in the same order), on many inputs.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from depthrefine.methods.thesis import segment
from depthrefine.methods.thesis.interpolate import _axis_weights, _interpolate_clusters
from depthrefine.methods.thesis.refine import correct_cluster_depths


# ----------------------------------------------------------------------------
# NumPy references
# ----------------------------------------------------------------------------


def _assign_ref(cols, means):
    m = means.astype(np.float32)
    dist = np.square(cols[0][:, None] - m[None, :, 0])
    for d in range(1, len(cols)):
        dist += np.square(cols[d][:, None] - m[None, :, d])
    return dist.argmin(axis=1).astype(np.int32)


def _lloyd_ref(x, w, means, iterations):
    n, dims = x.shape
    wx = (w[:, None] * x).ravel()
    dim_index = np.tile(np.arange(dims), n)
    cols = np.ascontiguousarray(x.T)
    labels = _assign_ref(cols, means)
    for _ in range(iterations):
        k = len(means)
        counts = np.bincount(labels, weights=w, minlength=k)
        sums = np.bincount(np.repeat(labels, dims) * dims + dim_index, weights=wx, minlength=k * dims)
        keep = counts > 0
        means = sums.reshape(k, dims)[keep] / counts[keep, None]
        labels = _assign_ref(cols, means)
    used = np.bincount(labels, minlength=len(means)) > 0
    if not used.all():
        labels = (np.cumsum(used) - 1)[labels].astype(np.int32)
        means = means[used]
    return labels, means


def _cluster_ref(lab, n_clusters=4, iterations=10, unify=True, black_bound=0.2, white_bound=0.8,
                 max_lightness=100.0, lightness_weight=1.0):
    step = segment.AB_STEP
    lightness = lab[..., 0]
    qa = np.floor(lab[..., 1] * np.float32(1.0 / step) + np.float32(0.5)).astype(np.int32)
    qb = np.floor(lab[..., 2] * np.float32(1.0 / step) + np.float32(0.5)).astype(np.int32)
    a0, b0 = int(qa.min()), int(qb.min())
    na, nb = int(qa.max()) - a0 + 1, int(qb.max()) - b0 + 1
    if unify:
        cls = segment.lightness_classes(lightness, black_bound=black_bound, white_bound=white_bound,
                                        max_lightness=max_lightness)
        n_cls = np.bincount(cls.ravel(), minlength=3)
        sum_l = np.bincount(cls.ravel(), weights=lightness.ravel(), minlength=3)
        class_l = np.divide(sum_l, n_cls, out=np.zeros(3), where=n_cls > 0)
        first = cls.astype(np.int32)
        lightness_of = lambda index: class_l[index]  # noqa: E731
    else:
        first = np.floor(lightness * np.float32(1.0 / step) + np.float32(0.5)).astype(np.int32)
        l0 = int(first.min())
        first -= l0
        lightness_of = lambda index: (index + l0) * step  # noqa: E731
    code = (first * na + (qa - a0)) * nb + (qb - b0)
    bins, inverse, weights = np.unique(code.ravel(), return_inverse=True, return_counts=True)
    feats = np.stack([lightness_of(bins // (na * nb)) * lightness_weight, ((bins // nb) % na + a0) * step,
                      (bins % nb + b0) * step], axis=1).astype(np.float32)
    x = feats.astype(np.float32)
    bin_labels, _ = _lloyd_ref(x, weights.astype(np.float64), segment.initial_means(x, n_clusters), iterations)
    return bin_labels.astype(np.int16)[inverse].reshape(code.shape)


def _correct_ref(values, *, origin, level_size, n_bins, dominant_fraction=0.5, tolerance_levels=5.0,
                 bin_width=None):
    values = np.asarray(values, dtype=np.float64)
    valid = np.isfinite(values)
    if not valid.any():
        return np.full(values.shape, np.nan)
    bin_width = level_size if bin_width is None else bin_width
    bins = np.clip(np.floor((values[valid] - origin) / bin_width + 0.5).astype(np.int64), 0, n_bins - 1)
    counts = np.bincount(bins, minlength=n_bins)
    peak = counts.max()
    dominant = origin + np.flatnonzero((counts == peak) | (counts > dominant_fraction * peak)) * bin_width
    out = np.empty_like(values)
    out[~valid] = origin + float(np.argmax(counts)) * bin_width
    v = values[valid]
    dist = np.abs(v[:, None] - dominant[None, :])
    nearest = np.argmin(dist, axis=1)
    rare = dist[np.arange(len(v)), nearest] > tolerance_levels * level_size
    out[valid] = np.where(rare, dominant[nearest], v)
    return out


def _interpolate_ref(corrected, lab_samples, labels, k, s, expansion):
    """Per cluster: expansion, then normalised bilinear interpolation; each pixel from its own cluster."""
    hp, wp = corrected.shape
    valid = np.isfinite(corrected)
    values = np.zeros((k, hp, wp))
    weights = np.zeros((k, hp, wp))
    for c in range(k):
        mask = valid & (lab_samples == c)
        if not mask.any():
            continue
        if expansion > 0 and not mask.all():
            _, (ir, ic) = ndimage.distance_transform_edt(~mask, return_indices=True)
            grown = ndimage.binary_dilation(mask, structure=np.ones((3, 3), bool), iterations=expansion)
            values[c] = np.where(grown, corrected[ir, ic], 0.0)
            weights[c] = grown
        else:
            values[c] = np.where(mask, corrected, 0.0)
            weights[c] = mask
    i0, i1, fr = _axis_weights(labels.shape[0], s, hp)
    j0, j1, fc = _axis_weights(labels.shape[1], s, wp)
    filled = np.where(valid, corrected, 0.0).astype(np.float32)
    left = filled[:, j0]
    along = left + fc.astype(np.float32) * (filled[:, j1] - left)
    top = along[i0]
    result = top + fr.astype(np.float32)[:, None] * (along[i1] - top)
    below, right = np.minimum(np.arange(hp) + 1, hp - 1), np.minimum(np.arange(wp) + 1, wp - 1)
    lab_valid = np.where(valid, lab_samples, -1)
    uniform = ((lab_valid == lab_valid[below]) & (lab_valid == lab_valid[:, right])
               & (lab_valid == lab_valid[below][:, right]))
    cell_label = np.where(uniform, lab_valid, -1).astype(np.int16)
    rr, cc = np.nonzero(cell_label[i0][:, j0] != labels)
    p, q = values * weights, weights

    def lerp2(a):
        lab_ = labels[rr, cc]
        top = a[lab_, i0[rr], j0[cc]] + fc[cc] * (a[lab_, i0[rr], j1[cc]] - a[lab_, i0[rr], j0[cc]])
        bottom = a[lab_, i1[rr], j0[cc]] + fc[cc] * (a[lab_, i1[rr], j1[cc]] - a[lab_, i1[rr], j0[cc]])
        return top + fr[rr] * (bottom - top)

    num, den = lerp2(p), lerp2(q)
    with np.errstate(invalid="ignore", divide="ignore"):
        result[rr, cc] = np.where(den > 0, num / den, np.nan)
    return result


# ----------------------------------------------------------------------------
# Tests
# ----------------------------------------------------------------------------


@pytest.mark.parametrize("seed", range(12))
def test_lloyd_equals_the_numpy_reference(seed):
    rng = np.random.default_rng(seed)
    n, k = int(rng.integers(1, 400)), int(rng.integers(1, 7))
    x = (rng.normal(0, 30, (n, 3)) * rng.choice([1.0, 0.01], 3)).astype(np.float32)
    if seed % 3 == 0:
        x = np.round(x)  # ties between means
    w = rng.integers(1, 50, n).astype(np.float64)
    means = segment.initial_means(x, k)
    iterations = int(rng.integers(0, 12))
    got = segment._lloyd(x, w, means, iterations)
    want = _lloyd_ref(x, w, means, iterations)
    np.testing.assert_array_equal(got[0], want[0])
    assert got[0].dtype == np.int32
    np.testing.assert_array_equal(got[1], want[1])


@pytest.mark.parametrize("unify", [True, False])
@pytest.mark.parametrize("seed", range(6))
def test_cluster_colors_equals_the_numpy_reference(seed, unify):
    rng = np.random.default_rng(seed)
    shape = (int(rng.integers(1, 60)), int(rng.integers(1, 60)))
    rgb = rng.integers(0, 256, shape + (3,)).astype(np.uint8)
    if seed % 2:  # a few flat colors, L* on the class bounds
        rgb = rng.choice(np.array([[0, 0, 0], [255, 255, 255], [119, 119, 119], [200, 30, 30], [48, 48, 48]],
                                  np.uint8), shape)
    lab = segment.rgb_to_lab(rgb)
    view = np.pad(lab, ((1, 1), (2, 2), (0, 0)))[1:-1, 2:-2]  # a strided view, as the patches are
    k = int(rng.integers(1, 6))
    got = segment.cluster_colors(view, unify=unify, n_clusters=k)
    want = _cluster_ref(lab, unify=unify, n_clusters=k)
    np.testing.assert_array_equal(got, want)
    assert got.dtype == np.int16


def test_lightness_bounds_compare_in_float32_like_numpy():
    # 80.0 as float32 is white: NumPy compares float32 L* with the bound cast to float32
    # (0.8 * 100 = 80.00000000000001 in float64).
    lab = np.array([[[80.0, 0, 0], [20.0, 0, 0], [50.0, 0, 0]]], np.float32)
    _, features = segment.cluster_colors(lab, n_clusters=3, return_features=True)
    classes = segment.lightness_classes(lab[..., 0])
    assert classes.tolist() == [[2, 0, 1]]
    assert features[0, :, 0].tolist() == [80.0, 20.0, 50.0]


@pytest.mark.parametrize("seed", range(20))
def test_correct_cluster_depths_equals_the_numpy_reference(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 300))
    values = rng.choice([10.0, 11.0, 40.0, 41.5, 90.0], n) + rng.normal(0, 3, n) * (seed % 2)
    values[rng.random(n) < 0.1] = np.nan
    if seed == 0:
        values[:] = np.nan
    kwargs = dict(origin=float(rng.uniform(0, 5)), level_size=float(rng.choice([1.0, 0.37])),
                  n_bins=int(rng.integers(2, 300)), dominant_fraction=float(rng.uniform(0.2, 0.9)),
                  tolerance_levels=float(rng.choice([0.0, 2.0, 5.0])), bin_width=float(rng.choice([1.0, 0.5])))
    np.testing.assert_array_equal(correct_cluster_depths(values, **kwargs), _correct_ref(values, **kwargs))


@pytest.mark.parametrize("expansion", [0, 1, 2])
@pytest.mark.parametrize("seed", range(8))
def test_interpolate_clusters_equals_the_per_cluster_numpy_reference(seed, expansion):
    rng = np.random.default_rng(seed)
    hp, wp, s, k = int(rng.integers(1, 14)), int(rng.integers(1, 14)), int(rng.integers(1, 6)), int(rng.integers(1, 5))
    corrected = rng.choice([3.0, 7.5, 20.0], (hp, wp)) + np.round(rng.normal(0, 1, (hp, wp)), 1)
    corrected[rng.random((hp, wp)) < 0.2] = np.nan
    lab_samples = rng.integers(0, k, (hp, wp)).astype(np.int16)
    labels = np.repeat(np.repeat(lab_samples, s, axis=0), s, axis=1)
    labels[rng.random(labels.shape) < 0.15] = rng.integers(0, k)
    result, _, n_missing = _interpolate_clusters(corrected, lab_samples, labels, k, s, expansion, False)
    want = _interpolate_ref(corrected, lab_samples, labels, k, s, expansion)
    np.testing.assert_array_equal(result, want)
    assert n_missing == int((~np.isfinite(want)).sum())


def test_kmeans_rejects_features_that_are_not_finite():
    x = np.array([[0.0, 1.0], [np.nan, 2.0]])
    with pytest.raises(ValueError, match="finite"):
        segment.kmeans(x, 2)


def test_without_a_cache_directory_the_kernels_compile_in_memory_with_one_warning(monkeypatch):
    import warnings

    import types

    from depthrefine import _numba

    real_numba = _numba.numba
    real = real_numba.njit

    def njit(*args, **options):
        if options.get("cache"):
            raise RuntimeError("cannot cache function: no locator available")
        return real(*args, **options)

    monkeypatch.setattr(_numba, "numba", types.SimpleNamespace(njit=njit))   # numba itself untouched
    monkeypatch.setattr(_numba, "_warned_no_cache", False)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        double = _numba.njit(lambda x: 2 * x)
        triple = _numba.njit(parallel=True)(lambda x: 3 * x)
    with warnings.catch_warnings():   # parallel=True on a scalar lambda: numba says there is nothing to parallelize
        warnings.simplefilter("ignore", real_numba.NumbaPerformanceWarning)
        assert (double(4), triple(4)) == (8, 12)
    assert [str(w.message).split(":")[0] for w in caught] == ["numba found no writable cache directory"]


def test_grow_samples_is_scipys_dilation_and_nearest_sample(rng):
    """The expansion of one pixel (the default) by a compiled kernel: SciPy's result bit for bit, ties included."""
    from scipy import ndimage

    from depthrefine.methods.thesis import _jit

    for _ in range(200):
        k, h, w = rng.integers(1, 5), rng.integers(1, 12), rng.integers(1, 12)
        masks = rng.random((k, h, w)) < rng.uniform(0, 0.7)
        corrected = rng.normal(size=(h, w))
        values, grown = np.where(masks, corrected[None], 0.0), masks
        if masks.any():
            grown = ndimage.binary_dilation(masks, structure=np.ones((1, 3, 3), bool), iterations=1)
            for c in range(k):
                if masks[c].any() and not masks[c].all():
                    ir, ic = ndimage.distance_transform_edt(~masks[c], return_distances=False, return_indices=True)
                    values[c] = np.where(grown[c], corrected[ir, ic], 0.0)
        ours_values, ours_grown = np.empty(masks.shape), np.empty(masks.shape, bool)
        _jit.grow_samples(masks, corrected, ours_values, ours_grown)
        np.testing.assert_array_equal(ours_grown, grown)
        np.testing.assert_array_equal(ours_values, values)


@pytest.mark.parametrize("bin_width", [0.0, -1.0, float("nan"), float("inf")])
def test_correct_cluster_depths_refuses_a_bin_width_that_is_not_positive(bin_width):
    """numba divided by zero where C gave a value: neither is asked any more."""
    from depthrefine.methods.thesis.refine import correct_cluster_depths

    with pytest.raises(ValueError, match="bin_width"):
        correct_cluster_depths(np.array([1.0, 2.0, 50.0]), origin=0, level_size=1, n_bins=8, bin_width=bin_width)
