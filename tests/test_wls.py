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

    threaded = run()
    monkeypatch.setattr(_wls, "_PARALLEL_PIXELS", 10**12)
    assert not _wls._parallel(src.shape)
    assert run().tobytes() == threaded.tobytes()
