"""gbp's coarse-to-fine rounds and the kernels that keep it fast (methods/gbp/solve.py, methods/_wls.py)."""

import subprocess
import sys

import numpy as np
import pytest

import depthrefine
from depthrefine.bench.synthetic import make_scene
from depthrefine.evaluate import rmse
from depthrefine.methods.gbp import GbpParams, measure, solve, upsample_gbp

cv2 = pytest.importorskip("cv2")
_wls = pytest.importorskip("depthrefine.methods._wls")
_resample = pytest.importorskip("depthrefine.methods._resample")


def _enlarge_reference(x, small, guide, sigma):
    """guided_enlarge's definition, pixel by pixel (float32 operations in the kernel's order)."""
    lut = _wls._color_lut(3, sigma)
    (H, W), (h, w) = guide.shape[:2], x.shape
    out = np.empty((H, W), np.float32)
    tiny = np.float32(1e-30)

    def similar(a, b):
        d = a.astype(np.float32) - b.astype(np.float32)
        return lut[np.int32(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])]

    for i in range(H):
        q = i >> 1
        p = max(q - 1, 0) if i % 2 == 0 else min(q + 1, h - 1)
        for j in range(W):
            r = j >> 1
            f = max(r - 1, 0) if j % 2 == 0 else min(r + 1, w - 1)
            c = guide[i, j]
            w_nn = np.float32(9) * (similar(small[q, r], c) + tiny)
            w_nf = np.float32(3) * (similar(small[q, f], c) + tiny)
            w_fn = np.float32(3) * (similar(small[p, r], c) + tiny)
            w_ff = similar(small[p, f], c) + tiny
            out[i, j] = (w_nn * x[q, r] + w_nf * x[q, f] + w_fn * x[p, r] + w_ff * x[p, f]) / (
                w_nn + w_nf + w_fn + w_ff)
    return out


@pytest.mark.parametrize("shape", [(7, 9), (8, 10), (1, 1), (2, 3), (5, 2), (6, 1), (1, 6)])
def test_guided_enlarge_is_its_definition_bit_for_bit_at_odd_and_tiny_sizes(rng, shape):
    guide = rng.integers(0, 256, shape + (3,)).astype(np.uint8)
    small = rng.integers(0, 256, (-(-shape[0] // 2), -(-shape[1] // 2), 3)).astype(np.uint8)
    x = (rng.random(small.shape[:2]) * 100).astype(np.float32)
    assert np.array_equal(_resample.guided_enlarge(x, small, guide, 40.0), _enlarge_reference(x, small, guide, 40.0))
    with pytest.raises(ValueError, match="halved"):
        _resample.guided_enlarge(x[:, :0], small, guide, 40.0)


def test_a_clean_step_stays_sharp_through_the_reduced_rounds():
    """A 40 | 200 step at x4 and x8 whose color edge is inside a reduced pixel: the enlargement takes each pixel
    from the reduced pixels of its own color. Band RMSE (12 px around the edge) measured 0.91 at x4 and 0.48-0.83
    at x8 (bicubic 30.3, 39-47); a bicubic enlargement instead left 12-21."""
    for s, rows, cols, edge in ((4, 48, 64, 29), (8, 48, 128, 61), (8, 48, 128, 65)):
        gt = np.where(np.arange(cols)[None, :] < edge, 40.0, 200.0).repeat(rows, axis=0).astype(np.float32)
        rgb = np.zeros((rows, cols, 3), np.uint8)
        rgb[:, edge:] = 255
        depth = gt.reshape(rows // s, s, cols // s, s).mean(axis=(1, 3)).astype(np.float32)
        band = slice(edge - 6, edge + 6)
        assert rmse(upsample_gbp(depth, rgb)[:, band], gt[:, band]) < 2.0


def test_the_reduced_grid_is_taken_for_footprint_means_at_x4_and_up_only():
    guide = np.zeros((64, 64, 3), np.uint8)
    p = GbpParams()
    for s, expected in ((4, (32, 32)), (8, (32, 32)), (2, None)):
        m = measure.measure_input(np.full((64 // s, 64 // s), 5.0, np.float32), guide)
        solver = solve.make_solver(guide, m, p, solve.GUIDE_NOISE)
        assert (None if solver.reduced is None else solver.reduced.shape) == expected
        assert solve.make_solver(guide, m, p, solve.GUIDE_NOISE, coarse=False).reduced is None
    assert solver.reduced is None or solver.reduced.scale == pytest.approx(solver.scale / 2)



def test_the_filtered_guide_is_kept_only_where_it_is_read_later():
    """x4 and up: the reduced grid and the guided enlargement read it; x2: it goes once the weights are made
    (peak memory), unless asked for (step 6, ``snap_edges``)."""
    guide = np.zeros((64, 64, 3), np.uint8)
    p = GbpParams()
    for s, kept in ((2, False), (4, True), (8, True)):
        m = measure.measure_input(np.full((64 // s, 64 // s), 5.0, np.float32), guide)
        assert (solve.make_solver(guide, m, p, solve.GUIDE_NOISE).guide is not None) == kept
        assert solve.make_solver(guide, m, p, solve.GUIDE_NOISE, coarse=False).guide is None
        assert solve.make_solver(guide, m, p, solve.GUIDE_NOISE, coarse=False, keep_guide=True).guide is not None

def test_point_samples_stay_on_the_full_grid():
    """Flat-colored point-sampled scenes: the reduced rounds raised the RMSE 9 -> 156 there, so they are skipped."""
    scene = make_scene((64, 96), 4, n_objects=3, seed=3, color_noise_std=6.0)
    m = measure.measure_input(np.asarray(scene.depth_lr, np.float32), scene.rgb_hr)
    assert m.footprint < solve.COARSE_MIN_FOOTPRINT
    solver = solve.make_solver(scene.rgb_hr, m, GbpParams(), solve.GUIDE_NOISE)
    assert solver.reduced is not None and solve._coarse(solver, m) is None


@pytest.mark.parametrize("shape", [(144, 176, 1008, 1232), (68, 86, 1088, 1376), (5, 7, 17, 23), (1, 1, 5, 5),
                                   (3, 4, 3, 4), (100, 100, 150, 150), (37, 53, 61, 299)])
def test_bounds_are_opencvs_nearest_enlargement_and_clip_the_same_bits(rng, shape):
    h, w, H, W = shape
    depth = (rng.random((h, w)) * 100).astype(np.float32)
    depth[rng.random((h, w)) < 0.1] = np.nan
    bounds = solve.local_bounds(depth, (H, W))
    low, high = bounds.full()
    padded = np.pad(depth, 1, mode="reflect", reflect_type="odd")
    valid = np.isfinite(padded)
    kernel = np.ones((3, 3), np.uint8)
    ref_low = cv2.erode(np.where(valid, padded, np.inf).astype(np.float32), kernel)[1:-1, 1:-1]
    ref_low[~valid[1:-1, 1:-1]] = -np.inf
    assert np.array_equal(low, cv2.resize(ref_low, (W, H), interpolation=cv2.INTER_NEAREST))
    x = (rng.random((H, W)) * 140 - 20).astype(np.float32)
    ours, theirs = x.copy(), np.clip(x, 3.0, 95.0)
    solve.clip_to_bounds(ours, bounds, 3.0, 95.0)
    np.minimum(np.maximum(theirs, low), high, out=theirs)
    assert np.array_equal(ours, theirs)


def test_clamped_bicubic_is_the_clip_of_the_bicubic_enlargement_blended_by_the_jump(rng):
    depth = (rng.random((23, 31)) * 50).astype(np.float32)
    depth[8:, 12:] += 100
    jump = measure.near_jump(depth, 0.5, 150.0)
    shape = (92, 124)
    up = cv2.resize(depth, shape[::-1], interpolation=cv2.INTER_CUBIC)
    kernel = np.ones((3, 3), np.uint8)
    lo = cv2.resize(cv2.erode(depth, kernel), shape[::-1], interpolation=cv2.INTER_NEAREST)
    hi = cv2.resize(cv2.dilate(depth, kernel), shape[::-1], interpolation=cv2.INTER_NEAREST)
    step = np.minimum(np.maximum(up, lo), hi) - up
    step *= cv2.resize(jump, shape[::-1], interpolation=cv2.INTER_LINEAR)
    assert np.array_equal(solve.clamped_bicubic(depth, shape, jump), up + step)


def test_smooth_with_gradient_is_smooth_of_the_depth_weights_in_place(rng):
    guide = cv2.GaussianBlur(rng.integers(0, 256, (70, 90, 3), dtype=np.uint8), (5, 5), 1.5)
    x = (rng.normal(0, 5, (70, 90)) + np.linspace(0, 80, 90)).astype(np.float32)
    wx, wy = _wls.color_weights(guide, 6.0)
    ref = _wls.smooth(x, *_wls.depth_weights(x, 4.0, wx, wy), 30.0, iterations=2)
    assert _wls.smooth_with_gradient(x, wx, wy, 4.0, 30.0, iterations=2) is x
    assert np.array_equal(x, ref)
    with pytest.raises(ValueError, match="in place"):
        _wls.smooth_with_gradient(x[:, ::2], wx, wy, 4.0, 30.0)


def test_the_guide_noise_band_counts_every_2x2_block_once(rng):
    """The row-pair differences in strips give the histogram of the band a - b - c + d of every 2x2 block."""
    for shape in ((7, 9, 3), (300, 41, 3), (129, 33), (2, 1, 3), (257, 20, 4)):
        guide = rng.integers(0, 256, shape).astype(np.uint8)
        h, w = shape[0] // 2 * 2, shape[1] // 2 * 2
        g = guide[:h, :w].astype(np.int64)
        band = g[0::2, 0::2] - g[0::2, 1::2] - g[1::2, 0::2] + g[1::2, 1::2]
        counts = np.bincount((band + 510).ravel(), minlength=1021).astype(np.float64)
        expected = measure._clipped_rms((np.arange(1021) - 510) * 0.5, counts) if band.size else 0.0
        assert measure.estimate_guide_noise(guide) == expected
        assert measure.estimate_guide_noise(np.asfortranarray(guide)) == expected


def test_gbp_fast_keeps_its_own_rounds():
    """gbp-fast solves on its work grid as before: no reduced rounds (coarse=False), three iterations per round."""
    from depthrefine.methods.gbp import fast

    assert fast.WORK_ITERATIONS == 3
    scene = make_scene((48, 64), 4, n_objects=2, seed=5)
    out = depthrefine.refine(scene.depth_lr, scene.rgb_hr, method="gbp-fast")
    assert out.shape == scene.rgb_hr.shape[:2] and np.isfinite(out).all()


def test_the_command_lines_warm_up_skips_numbas_blas_check_and_kernels_still_run():
    code = ("import sys; from depthrefine import _numba; _numba.warm_up(skip_blas_check=True); "
            "import numpy as np; from depthrefine.methods import _wls; "
            "x = np.ones((4, 4), np.float32); _wls.smooth(x, x, x, 1.0); "
            "print('scipy.linalg' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "False"
