"""The thesis method's kernels in C (``depthrefine._native``) give numba's bits (``methods/thesis/_jit.py``).

Each C kernel runs on the arguments numba's gets and the two results are compared bit for bit, on random
inputs that reach their branches: one-row and one-column patches, values on the binning and class bounds,
clusters that empty or are never used, pixels whose cell is not their cluster's, zero weights (NaN) and
overflowing ones (inf), fallbacks of both dtypes, strided views. The medians are compared with the numba
kernels and with OpenCV. Skipped where the C library is not built (the thesis then runs numba's).
"""

from __future__ import annotations

import subprocess
import sys

import cv2
import numpy as np
import pytest

from depthrefine import _native

lib = _native.library()
needs_c = pytest.mark.skipif(lib is None, reason=f"depthrefine's C kernels: {_native.why_not()}")
SHAPES = [(1, 1), (1, 9), (9, 1), (13, 10), (40, 57)]


def _jit():
    from depthrefine.methods.thesis import _jit

    return _jit


def _c():
    return _native.kernels("depthrefine.methods.thesis._jit")


def _same(a, b) -> bool:
    """Equal bits (NaN included), for arrays and the scalars and tuples the kernels return."""
    if isinstance(a, tuple):
        return isinstance(b, tuple) and len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if isinstance(a, np.ndarray):
        return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()
    return type(a) is type(b) and a == b


def _lab(rng, shape) -> np.ndarray:
    """L*a*b*-like float32 values, a fifth of them on a bound of the binning (x.5) or of the L* classes."""
    lab = np.stack([rng.uniform(0, 100, shape), rng.uniform(-90, 90, shape), rng.uniform(-90, 90, shape)], axis=2)
    on_bounds = rng.random(shape) < 0.2
    lab[..., 0] = np.where(on_bounds, rng.choice([0.0, 20.0, 80.0, 100.0, 19.999998, 80.000008], shape), lab[..., 0])
    lab[..., 1] = np.where(on_bounds, np.round(lab[..., 1]) + 0.5, lab[..., 1])
    lab[..., 2] = np.where(on_bounds, np.round(lab[..., 2]) - 0.5, lab[..., 2])
    return lab.astype(np.float32)


@needs_c
@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("unify", [True, False])
@pytest.mark.parametrize("step", [1.0, 0.5])
def test_quantize_lab_and_feature_codes_are_numbas(shape, unify, step):
    rng = np.random.default_rng(shape[0] * 100 + shape[1])
    lab = _lab(rng, shape)
    results = []
    for kernels in (_jit(), _c()):
        q = [np.full(shape, -7, np.int32) for _ in range(3)]
        ranges = kernels.quantize_lab(lab, np.float32(1 / step), np.float32(0.5), unify, np.float32(20.0),
                                      np.float32(80.0), *q)
        a0, a1, b0, b1, f0, f1 = ranges[:6]
        na, nb = a1 - a0 + 1, b1 - b0 + 1
        f0, nf = (0, 3) if unify else (f0, f1 - f0 + 1)
        code = np.empty(shape, np.int32)
        counts = np.zeros(nf * na * nb, np.intp)
        kernels.feature_codes(*q, a0, na, b0, nb, f0, code, counts)
        sparse = np.empty(shape, np.int32)
        kernels.feature_codes(*q, a0, na, b0, nb, f0, sparse, np.zeros(0, np.intp))
        table = np.random.default_rng(0).integers(-5, 5, counts.size).astype(np.int16)
        labels = np.empty(shape, np.int16)
        kernels.lookup(table, code, labels)
        results.append((ranges, *q, code, counts, sparse, labels))
    assert _same(results[0], results[1])
    assert results[0][-3].sum() == lab.shape[0] * lab.shape[1]


@needs_c
def test_the_histogram_of_many_bins_and_a_float64_patch_are_numbas():
    rng = np.random.default_rng(4)
    lab = _lab(rng, (60, 70))
    q = [np.empty((60, 70), np.int32) for _ in range(3)]
    ranges = _c().quantize_lab(lab, np.float32(4.0), np.float32(0.5), False, np.float32(20.0), np.float32(80.0), *q)
    a0, a1, b0, b1, f0, f1 = ranges[:6]
    na, nb, nf = a1 - a0 + 1, b1 - b0 + 1, f1 - f0 + 1
    assert nf * na * nb > 1 << 14         # past the partial histograms: one histogram
    outs = []
    for kernels in (_jit(), _c()):
        code, counts = np.empty((60, 70), np.int32), np.zeros(nf * na * nb, np.intp)
        kernels.feature_codes(*q, a0, na, b0, nb, f0, code, counts)
        outs.append((code, counts))
    assert _same(outs[0], outs[1])
    wide = lab.astype(np.float64)          # numba's float64 kernel, through the C namespace
    bounds = (np.float64(20.0), np.float64(80.0))
    q_jit, q_c = [np.empty((60, 70), np.int32) for _ in range(3)], [np.empty((60, 70), np.int32) for _ in range(3)]
    assert _same(_jit().quantize_lab(wide, np.float32(1), np.float32(0.5), True, *bounds, *q_jit),
                 _c().quantize_lab(wide, np.float32(1), np.float32(0.5), True, *bounds, *q_c))
    assert _same(tuple(q_jit), tuple(q_c))


@needs_c
@pytest.mark.parametrize("n", [1, 5, 63, 64, 65, 700])
@pytest.mark.parametrize("dims", [3, 2])
@pytest.mark.parametrize("iterations", [0, 1, 10])
def test_lloyd_is_numbas(n, dims, iterations):
    rng = np.random.default_rng(n * dims + iterations)
    x = rng.integers(-3, 4, (n, dims)).astype(np.float32) * np.float32(1.5)   # many equal distances (ties)
    w = rng.integers(0, 4, n).astype(np.float64)
    w[0] = 1.0
    means = np.concatenate([x[rng.integers(0, n, 3)].astype(np.float64), [[100.0] * dims], x[:1]])  # one unused
    labels_jit, means_jit = _jit().lloyd(x, w, means, iterations)
    labels_c, means_c = _c().lloyd(x, w, means, iterations)
    assert _same(labels_jit, labels_c) and _same(np.ascontiguousarray(means_jit), np.ascontiguousarray(means_c))
    assert labels_c.max() == len(means_c) - 1 < len(means)


@needs_c
@pytest.mark.parametrize("shape", SHAPES)
def test_grow_samples_is_numbas(shape):
    rng = np.random.default_rng(sum(shape))
    masks = rng.random((3,) + shape) < 0.3
    masks[2] = False
    corrected = rng.normal(50, 10, shape)
    outs = []
    for kernels in (_jit(), _c()):
        values, grown = np.full(masks.shape, 7.0), np.zeros(masks.shape, bool)
        kernels.grow_samples(masks, corrected, values, grown)
        outs.append((values, grown))
    assert _same(outs[0], outs[1])


@needs_c
@pytest.mark.parametrize("lr_shape", [(1, 1), (1, 6), (5, 1), (9, 12)])
@pytest.mark.parametrize("s", [1, 4, 7])
def test_interpolate_patch_is_numbas(lr_shape, s):
    from depthrefine.methods.thesis.interpolate import _axis_weights

    rng = np.random.default_rng(lr_shape[0] * 10 + lr_shape[1] + s)
    k = 3
    shape = (lr_shape[0] * s, lr_shape[1] * s)
    filled = rng.normal(50, 20, lr_shape).astype(np.float32)
    cell_label = rng.integers(-1, k, lr_shape).astype(np.int16)
    labels = rng.integers(0, k, shape).astype(np.int16)
    present = rng.integers(0, 2, (k,) + lr_shape).astype(np.float64)         # zero weights: NaN
    weighted = present * rng.normal(50, 20, (k,) + lr_shape)
    weighted[0, 0, 0] = 1e308                                                  # overflow: inf
    present[0, 0, 0] = 1e-300
    i0, i1, fr = _axis_weights(shape[0], s, lr_shape[0])
    j0, j1, fc = _axis_weights(shape[1], s, lr_shape[1])
    outs = []
    for kernels in (_jit(), _c()):
        out = np.full(shape, 3.0, np.float32)
        bad = kernels.interpolate_patch(filled, cell_label, labels, weighted, present, i0, i1, fr, j0, j1, fc, out)
        outs.append((int(bad), out))
    assert outs[0][0] == outs[1][0] and _same(outs[0][1], outs[1][1])


@needs_c
@pytest.mark.parametrize("dtype", [np.float64, np.float32, np.int32])
def test_fill_missing_is_numbas(dtype):
    rng = np.random.default_rng(3)
    result = rng.normal(0, 1, (11, 14)).astype(np.float32)
    result[rng.random(result.shape) < 0.2] = np.nan
    result[3, 4], result[5, 0], result[7, :] = np.inf, -np.inf, np.nan
    wide = (rng.normal(0, 100, (6, 9)) * (1e36 if dtype != np.int32 else 1)).astype(dtype)
    fallback = wide[1:5, 2:8]                                                 # a strided view
    near_rows, near_cols = rng.integers(0, 4, 11), rng.integers(0, 6, 14)
    outs = []
    for kernels in (_jit(), _c()):
        out = result.copy()
        kernels.fill_missing(out, fallback, near_rows, near_cols)
        outs.append(out)
    assert _same(outs[0], outs[1]) and np.isfinite(outs[1]).all()


@needs_c
@pytest.mark.parametrize("correct", [True, False])
@pytest.mark.parametrize("seed", range(6))
def test_correct_patch_and_values_are_numbas(correct, seed):
    rng = np.random.default_rng(seed)
    depth = rng.choice([10.0, 10.5, 11.0, 30.0, 31.0, 55.25, np.nan, 255.0, -3.0], (20, 24)).astype(np.float32)
    depth += rng.normal(0, 0.3, depth.shape).astype(np.float32) * (seed % 2)
    labels = rng.integers(0, 4, (40, 48)).astype(np.int16)
    labels[labels == 3] = 2                                                    # cluster 3 has no sample
    d_view, s_view = depth[2:17, 3:20], labels[1::2, 1::2][2:17, 3:20]         # strided, as the patches are
    args = (4, correct, 0.0, 1.0, 2.0, 64, 0.5, 1.5)
    outs = []
    for kernels in (_jit(), _c()):
        out = np.full(d_view.shape, np.nan)
        kernels.correct_patch(d_view, s_view, *args, out)
        values = np.concatenate([d_view.ravel().astype(np.float64), [np.nan] * 3])
        fixed, all_missing = np.empty_like(values), np.empty(3)
        kernels.correct_values(values, 0.0, 1.0, 2.0, 64, 0.5, 1.5, fixed)
        kernels.correct_values(np.full(3, np.nan), 0.0, 1.0, 2.0, 64, 0.5, 1.5, all_missing)
        outs.append((out, fixed, all_missing))
    assert _same(outs[0], outs[1])


@needs_c
@pytest.mark.parametrize("size", [3, 5, 7])
@pytest.mark.parametrize("channels", [1, 3])
@pytest.mark.parametrize("dtype", [np.uint8, np.uint16])
@pytest.mark.parametrize("shape", [(1, 1), (2, 3), (7, 700), (33, 90)])
def test_the_c_medians_are_numbas_and_opencvs(size, channels, dtype, shape):
    from depthrefine.methods.thesis import _median_kernels

    rng = np.random.default_rng(size * channels + shape[1])
    image = rng.integers(0, np.iinfo(dtype).max, shape + (channels,), endpoint=True).astype(dtype)
    image[:, ::5] = image[:, :1]                                               # ties
    flat = image.reshape(shape[0], -1)
    c_out, jit_out = np.zeros_like(flat), np.zeros_like(flat)
    getattr(_median_kernels, f"median{size}_c{channels}")(flat, jit_out, 0, shape[0])
    middle = 2 * ((shape[0] + 1) // 4)                                          # in two bands, as two threads run it
    assert _c().median_rows(flat, c_out, size, channels, 0, middle)
    assert _c().median_rows(flat, c_out, size, channels, middle, shape[0])
    assert _same(c_out, jit_out)
    if dtype == np.uint8:
        expected = cv2.medianBlur(np.ascontiguousarray(image if channels == 3 else image[..., 0]), size)
        assert _same(c_out, expected.reshape(flat.shape))


@needs_c
def test_the_c_kmeans_refuses_weights_that_keep_no_cluster():
    """numba's kernel indexes empty arrays there (garbage labels); the C one says what is wrong."""
    x = np.arange(18, dtype=np.float32).reshape(6, 3)
    with pytest.raises(ValueError, match="kept no cluster"):
        _c().lloyd(x, np.zeros(6), np.zeros((3, 3)), 10)


@needs_c
def test_the_c_medians_refuse_rows_outside_the_image():
    flat = np.zeros((4, 12), np.uint8)
    for y0, y1 in ((0, 8), (-2, 2), (3, 1)):
        with pytest.raises(ValueError, match="outside the image"):
            _c().median_rows(flat, flat.copy(), 3, 3, y0, y1)


@needs_c
def test_the_c_medians_leave_other_sizes_and_dtypes_to_numba():
    flat = np.zeros((4, 12), np.uint8)
    assert not _c().median_rows(flat, flat.copy(), 9, 3, 0, 4)
    assert not _c().median_rows(flat.astype(np.int16), flat.astype(np.int16), 7, 3, 0, 4)


_THESIS = ("import hashlib, sys, numpy as np, depthrefine; "
           "from depthrefine.bench.synthetic import make_scene; "
           "s = make_scene((384, 512), 4, n_objects=4, seed=5, color_noise_std=3.0, shading=0.2); "
           "out = depthrefine.refine(s.depth_lr, s.rgb_hr, method='thesis'); "
           "print('numba' in sys.modules, hashlib.sha256(out.tobytes()).hexdigest())")


@needs_c
def test_the_thesis_in_a_fresh_process_runs_without_numba_and_gives_numbas_result():
    import os

    def fresh(**env):
        out = subprocess.run([sys.executable, "-c", _THESIS], capture_output=True, text=True,
                             env={**os.environ, **env}, timeout=300)
        assert out.returncode == 0, out.stderr
        return out.stdout.split()

    native, forced = fresh(), fresh(DEPTHREFINE_KERNELS="numba")
    assert native[0] == "False" and forced[0] == "True"
    assert native[1] == forced[1]


@needs_c
def test_the_thesis_methods_first_call_imports_no_numpy_ma():
    """np.unique's first call in a process imports numpy.ma (37 ms); the thesis method's patch grid does without."""
    code = ("import sys, numpy as np, depthrefine; "
            "rgb = np.zeros((64, 80, 3), np.uint8); rgb[:, 40:] = 200; depth = np.full((16, 20), 5.0, np.float32); "
            "depth[:, 10:] = 9.0; depthrefine.refine(depth, rgb, method='thesis'); print('numpy.ma' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["False"]


def test_the_command_line_builds_opencvs_lab_tables_while_it_reads_for_the_thesis_method():
    from depthrefine.cli.refine import _warm_up_lab

    assert _warm_up_lab("gbp") is None and _warm_up_lab("bicubic") is None
    thread = _warm_up_lab("thesis")
    thread.join(timeout=60)
    assert thread.name == "depthrefine-lab-warm-up" and not thread.is_alive()
