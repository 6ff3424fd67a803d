"""The weighted least-squares solver of gbp (methods/_wls.py)."""

import numpy as np
import pytest

cv2 = pytest.importorskip("cv2")
_wls = pytest.importorskip("depthrefine.methods._wls")


def _scene(seed=0, shape=(61, 83)):
    rng = np.random.default_rng(seed)
    guide = rng.integers(0, 256, shape + (3,), dtype=np.uint8)
    guide = cv2.GaussianBlur(guide, (5, 5), 1.5)
    src = (rng.normal(0, 5, shape) + np.linspace(0, 40, shape[1])).astype(np.float32)
    return guide, src


@pytest.mark.parametrize("lam, sigma", [(2.0, 4.0), (50.0, 8.0), (800.0, 20.0)])
def test_color_weights_alone_give_opencvs_fast_global_smoother(lam, sigma):
    guide, src = _scene()
    wx, wy = _wls.color_weights(guide, sigma)
    ours = _wls.smooth(src, wx, wy, lam)
    theirs = cv2.ximgproc.fastGlobalSmootherFilter(guide, src, lam, sigma)
    assert np.abs(ours - theirs).max() < 1e-3 * np.abs(src).max()
    assert np.abs(ours - src).max() > 1.0       # it did smooth


def test_smooth_into_out_gives_the_same_bits_without_a_new_array():
    """``out=`` (flat_blend solves its start in a scratch array): the same bits as the copy, in place or elsewhere."""
    guide, src = _scene(3)
    wx, wy = _wls.color_weights(guide, 6.0)
    ref = _wls.smooth(src, wx, wy, 40.0)
    same = src.copy()
    assert _wls.smooth(same, wx, wy, 40.0, out=same) is same
    other = np.empty_like(src)
    assert _wls.smooth(src.astype(np.float64), wx, wy, 40.0, out=other) is other
    np.testing.assert_array_equal(same, ref)
    np.testing.assert_array_equal(other, ref)
    with pytest.raises(ValueError, match="out must have"):
        _wls.smooth(src, wx, wy, 40.0, out=np.empty((3, 4), np.float32))
    with pytest.raises(ValueError, match="out must be a writeable, C-contiguous"):
        _wls.smooth(src, wx, wy, 40.0, out=np.empty(src.shape[::-1], np.float32).T)


def test_guided_smooth_into_out_gives_the_same_bits_without_a_new_array():
    """``out=`` (gbp-fast solves its enlarged result in place): the same bits as the copy, in place or elsewhere."""
    guide, src = _scene(4)
    ref = _wls.guided_smooth(src, guide, 6.0, 3.0, 40.0, iterations=2)
    same = src.copy()
    assert _wls.guided_smooth(same, guide, 6.0, 3.0, 40.0, iterations=2, out=same) is same
    other = np.empty_like(src)
    assert _wls.guided_smooth(src.astype(np.float64), guide, 6.0, 3.0, 40.0, iterations=2, out=other) is other
    np.testing.assert_array_equal(same, ref)
    np.testing.assert_array_equal(other, ref)
    with pytest.raises(ValueError, match="out must have"):
        _wls.guided_smooth(src, guide, 6.0, 3.0, 40.0, out=np.empty((3, 4), np.float32))
    with pytest.raises(ValueError, match="out must be a writeable, C-contiguous"):
        _wls.guided_smooth(src, guide, 6.0, 3.0, 40.0, out=src.astype(np.float64))


def test_a_solve_in_place_refuses_memory_it_reads_and_leaves_out_alone_when_it_refuses():
    """``out`` (or ``x``) may not be the weights a solve makes in this thread's scratch arrays, nor its guide: the
    solve would write over what it reads. A refused call does not touch ``out``."""
    guide, src = _scene(5)
    shape = src.shape
    with pytest.raises(ValueError, match="must not share memory"):
        _wls.guided_smooth(src, guide, 6.0, 3.0, 40.0, out=_wls.scratch(shape)[0])
    raw = np.zeros(4 * src.size, np.uint8)             # out and the guide in the same bytes
    raw[: guide.size] = guide.ravel()
    with pytest.raises(ValueError, match="must not share memory"):
        _wls.guided_smooth(src, raw[: guide.size].reshape(guide.shape), 6.0, 3.0, 40.0,
                           out=raw.view(np.float32).reshape(shape))
    wx, wy = _wls.color_weights(guide, 6.0)
    with pytest.raises(ValueError, match="must not share memory"):
        _wls.smooth_with_gradient(_wls.scratch(shape)[1], wx, wy, 3.0, 40.0)
    with pytest.raises(ValueError, match="must not share memory"):
        _wls.smooth(src, wx, wy, 40.0, out=wy)
    untouched = np.full(shape, -1.0, np.float32)
    for bad in ({"sigma_color": 0.0}, {"lam": -1.0}, {"sigma": float("nan")}):
        arguments = {"sigma_color": 6.0, "sigma": 3.0, "lam": 40.0, **bad}
        with pytest.raises(ValueError):
            _wls.guided_smooth(src, guide, arguments["sigma_color"], arguments["sigma"], arguments["lam"],
                               out=untouched)
    with pytest.raises(ValueError):
        _wls.guided_smooth(src, guide[:-1], 6.0, 3.0, 40.0, out=untouched)
    with pytest.raises(ValueError, match="finite"):
        _wls.smooth(np.where(src > src.mean(), np.nan, src), wx, wy, 40.0, out=untouched)
    with pytest.raises(ValueError, match="finite"):
        _wls.smooth(src.astype(np.float64) * 1e300, wx, wy, 40.0, out=untouched)     # beyond float32
    assert (untouched == -1.0).all()


def test_color_weights_match_the_definition():
    guide, _ = _scene(1, (7, 9))
    wx, wy = _wls.color_weights(guide, 5.0)
    g = guide.astype(np.float64)
    np.testing.assert_allclose(wx[:, :-1], np.exp(-np.sqrt(((g[:, 1:] - g[:, :-1]) ** 2).sum(-1)) / 5.0), rtol=1e-6)
    np.testing.assert_allclose(wy[:-1], np.exp(-np.sqrt(((g[1:] - g[:-1]) ** 2).sum(-1)) / 5.0), rtol=1e-6)
    assert not wx[:, -1].any() and not wy[-1].any()


def test_a_constant_stays_constant_and_zero_weights_change_nothing():
    guide, src = _scene(2)
    wx, wy = _wls.color_weights(guide, 4.0)
    const = np.full(src.shape, 7.25, np.float32)
    np.testing.assert_allclose(_wls.smooth(const, wx, wy, 100.0), 7.25, rtol=1e-5)
    zero = np.zeros_like(wx)
    np.testing.assert_array_equal(_wls.smooth(src, zero, zero, 100.0), src)


def test_depth_weights_keep_a_depth_step_that_the_guide_does_not_show():
    guide = np.full((20, 40, 3), 128, np.uint8)               # a flat guide: color weights 1 everywhere
    step = np.zeros((20, 40), np.float32)
    step[:, 20:] = 50.0
    wx, wy = _wls.color_weights(guide, 4.0)
    blurred = _wls.smooth(step, wx, wy, 50.0)
    kept = _wls.smooth(step, *_wls.depth_weights(step, 2.0, wx, wy), 50.0)
    assert blurred[:, 19].max() > 10 and blurred[:, 20].min() < 40   # color weights alone smooth across it
    assert kept[:, 19].max() < 1e-3 and kept[:, 20].min() > 50 - 1e-3
    dx, _ = _wls.depth_weights(step, 2.0, wx, wy)
    assert dx[0, 19] == pytest.approx(np.exp(-25.0)) and dx[0, 0] == 1.0


def test_the_result_does_not_depend_on_the_thread_count():
    numba = pytest.importorskip("numba")
    guide, src = _scene(3, (150, 170))   # more than two blocks of rows and of columns
    wx, wy = _wls.color_weights(guide, 4.0)
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = _wls.smooth(src, wx, wy, 30.0)
        numba.set_num_threads(before)
        many = _wls.smooth(src, wx, wy, 30.0)
    finally:
        numba.set_num_threads(before)
    assert one.tobytes() == many.tobytes()


def test_single_rows_and_columns():
    for shape in [(1, 30), (30, 1), (1, 1)]:
        guide = np.zeros(shape + (3,), np.uint8)
        src = np.arange(np.prod(shape), dtype=np.float32).reshape(shape)
        out = _wls.smooth(src, *_wls.color_weights(guide, 4.0), 10.0)
        assert out.shape == shape and np.isfinite(out).all()
        assert out.mean() == pytest.approx(src.mean(), rel=1e-4)


def test_small_images_solved_in_the_calling_thread_give_the_same_bits(monkeypatch):
    guide, src = _scene(4, (260, 270))   # above the size where threads start
    assert _wls._parallel(src.shape)

    def run():
        wx, wy = _wls.color_weights(guide, 4.0)
        return _wls.smooth(src, *_wls.depth_weights(src, 3.0, wx, wy), 25.0)

    from depthrefine import _threads

    threaded = run()
    monkeypatch.setattr(_threads, "PARALLEL_PIXELS", 10**12)
    assert not _wls._parallel(src.shape)
    assert run().tobytes() == threaded.tobytes()


@pytest.mark.parametrize("lam", [1e3, 1e8, 1e20, 1e30, 1e38, np.inf])
def test_large_lambdas_keep_a_constant_and_a_separated_step_exact(lam):
    """No cancellation in the elimination: huge couplings give no NaN/inf and tie or separate exactly."""
    shape = (40, 300)
    ones = np.ones(shape, np.float32)
    const = np.full(shape, 7.25, np.float32)
    np.testing.assert_array_equal(_wls.smooth(const, ones, ones, lam), const)
    step = np.zeros(shape, np.float32)
    step[:, 150:] = 50.3
    wx = ones.copy()
    wx[:, 149] = 0.0                       # no link across the step
    np.testing.assert_array_equal(_wls.smooth(step, wx, ones, lam), step)
    _, src = _scene(5, shape)
    out = _wls.smooth(src, ones, ones, lam)
    assert np.isfinite(out).all() and src.min() <= out.min() and out.max() <= src.max()


@pytest.mark.parametrize("lam", [0.5, 30.0, 1e4, 1e6, 1e9])
def test_one_row_is_the_exact_tridiagonal_solve(lam):
    """One row, one iteration: the float64 banded solve of ``(I + lam * L_w) v = f``, to float32 precision."""
    linalg = pytest.importorskip("scipy.linalg")
    rng = np.random.default_rng(6)
    n = 500
    f = (rng.normal(0, 5, n) + np.linspace(0, 40, n)).astype(np.float32)
    w = rng.uniform(0.0, 1.0, n).astype(np.float32)
    w[rng.random(n) < 0.05] = 0.0
    w[-1] = 0.0
    a = lam * w[:-1].astype(np.float64)                     # coupling of i and i + 1
    band = np.zeros((3, n))
    band[0, 1:] = -a
    band[2, :-1] = -a
    band[1] = 1.0
    band[1, :-1] += a
    band[1, 1:] += a
    exact = linalg.solve_banded((1, 1), band, f.astype(np.float64))
    ours = _wls.smooth(f[None], w[None], np.zeros((1, n), np.float32), lam, iterations=1)[0]
    assert np.abs(ours - exact).max() < 1e-5 * np.abs(f).max()


def _bad(**changes):
    src = np.ones((5, 6), np.float32)
    args = dict(src=src, wx=np.ones_like(src), wy=np.ones_like(src), lam=10.0, iterations=3, attenuation=0.25)
    args.update(changes)
    return args


@pytest.mark.parametrize("changes, name", [
    (dict(lam=float("nan")), "lam"), (dict(lam=-1.0), "lam"), (dict(iterations=0), "iterations"),
    (dict(attenuation=-0.5), "attenuation"), (dict(attenuation=float("nan")), "attenuation"),
    (dict(src=np.ones((5, 6, 2), np.float32)), "src"), (dict(src=np.ones(5, np.float32)), "src"),
    (dict(wx=np.ones((5, 7), np.float32)), "wx"), (dict(wy=np.ones((6, 5), np.float32)), "wy"),
    (dict(wx=np.full((5, 6), -1.0, np.float32)), "wx"), (dict(wy=np.full((5, 6), np.nan, np.float32)), "wy"),
    (dict(src=np.full((5, 6), np.nan, np.float32)), "src"), (dict(src=np.full((5, 6), np.inf, np.float32)), "src"),
])
def test_bad_arguments_raise_a_value_error_naming_them(changes, name):
    args = _bad(**changes)
    with pytest.raises(ValueError, match=name):
        _wls.smooth(args.pop("src"), args.pop("wx"), args.pop("wy"), args.pop("lam"), **args)


def test_an_infinite_lambda_or_weight_is_capped_not_nan():
    _, src = _scene(7, (20, 30))
    ones = np.ones(src.shape, np.float32)
    capped = _wls.smooth(src, ones, ones, _wls.MAX_COUPLING)
    np.testing.assert_array_equal(_wls.smooth(src, ones, ones, np.inf), capped)
    np.testing.assert_array_equal(_wls.smooth(src, np.full_like(ones, np.inf), np.full_like(ones, np.inf), 1.0), capped)
    np.testing.assert_array_equal(_wls.smooth(src, ones, ones, 0.0), src)   # no smoothing


def test_weight_functions_check_their_shapes():
    with pytest.raises(ValueError, match="guide"):
        _wls.color_weights(np.zeros((2, 3, 4, 5), np.uint8), 4.0)
    with pytest.raises(ValueError, match="guide must be uint8"):
        _wls.color_weights(np.full((5, 6, 3), 300, np.uint16), 4.0)   # a cast would give 44, not a scaled 255
    wx, wy = _wls.color_weights(np.zeros((5, 6, 3), np.uint8), 4.0)
    with pytest.raises(ValueError, match="x must be a 2-D"):
        _wls.depth_weights(np.zeros((5, 6, 1), np.float32), 2.0, wx, wy)
    with pytest.raises(ValueError, match="wy"):
        _wls.depth_weights(np.zeros((5, 6), np.float32), 2.0, wx, wy[:, :5])


def test_the_split_over_threads_gives_the_same_bits_for_any_thread_count(monkeypatch):
    """The rows (columns) are cut into one run of blocks per thread: 1, 2, 3 or 7 threads give the same bits."""
    from depthrefine import _numba

    guide, src = _scene(8, (300, 260))   # above the size where threads start
    assert _wls._parallel(src.shape)

    def run():
        wx, wy = _wls.color_weights(guide, 4.0)
        return _wls.smooth(src, *_wls.depth_weights(src, 3.0, wx, wy), 25.0).tobytes()

    results = set()
    for count in (1, 2, 3, 7):
        monkeypatch.setattr(_numba, "threads", lambda count=count: count)
        results.add(run())
    assert len(results) == 1


def test_run_split_covers_the_range_once_and_raises_a_kernel_error():
    from depthrefine import _numba

    seen = np.zeros(101, np.int64)

    def kernel(out, k0, k1):
        out[k0:k1] += 1

    _numba.run_split(kernel, 101, seen)
    assert (seen == 1).all()
    _numba.run_split(kernel, 101, seen, parallel=False)
    assert (seen == 2).all()

    def failing(k0, k1):
        if k0 > 0:
            raise ValueError("part failed")

    if _numba.threads() > 1:
        with pytest.raises(ValueError, match="part failed"):
            _numba.run_split(failing, 10)


def test_expf32_is_exp_to_the_last_bit_of_float32_and_keeps_its_special_cases():
    from depthrefine._numba import expf32

    rng = np.random.default_rng(3)
    xs = np.concatenate([rng.uniform(-103, 88.7, 2000), rng.normal(0, 1, 500)]).astype(np.float32)
    ours = np.array([expf32(x) for x in xs], np.float32)
    exact = np.exp(xs.astype(np.float64))
    ulp = np.spacing(exact.astype(np.float32)).astype(np.float64)
    assert (np.abs(ours - exact) <= ulp).all()           # within one float32 step of the exact value
    special = np.array([0.0, -np.inf, np.inf, 89.0, -104.0, -103.5], np.float32)
    assert [float(expf32(x)) for x in special] == [1.0, 0.0, np.inf, np.inf, 0.0, float(np.float32(2.0 ** -149))]
    assert np.isnan(expf32(np.float32(np.nan)))


@pytest.mark.parametrize("shape", [(37, 37), (23, 41)])
def test_guided_smooth_is_smooth_with_the_edge_weights_bit_for_bit(shape):
    """On a square image too, whose transposed scratch arrays have the shape of the weights'."""
    guide, src = _scene(4, shape)
    for iterations in (1, 3):
        fused = _wls.guided_smooth(src, guide, 6.0, 3.0, 40.0, iterations=iterations)
        apart = _wls.smooth(src, *_wls.edge_weights(guide, 6.0, src, 3.0), 40.0, iterations=iterations)
        assert fused.tobytes() == apart.tobytes()
    wx, wy = _wls.edge_weights(guide, 6.0, src, 3.0)
    ref = _wls.depth_weights(src, 3.0, *_wls.color_weights(guide, 6.0))
    assert wx.tobytes() == ref[0].tobytes() and wy.tobytes() == ref[1].tobytes()
