"""``gbp-fast``: gbp on a reduced grid and one full-resolution solve (methods/gbp/fast.py)."""

from __future__ import annotations

import numpy as np
import pytest

import depthrefine
from depthrefine.bench.synthetic import make_scene
from depthrefine.evaluate import rmse
from depthrefine.methods.gbp import GbpParams
from depthrefine.methods.gbp.fast import GbpFastParams, restore_smooth_surfaces, upsample_gbp_fast, work_shape

from test_gbp import _area, _step

cv2 = pytest.importorskip("cv2")


def test_it_is_registered_with_its_parameters():
    entry = depthrefine.get_method("gbp-fast")
    assert entry.func is upsample_gbp_fast and entry.params_type is GbpFastParams
    assert entry.guided and entry.interpolating and entry.deterministic
    assert "gbp-fast" in depthrefine.methods._names.BUILTIN_METHODS


@pytest.mark.parametrize("edge_col", [29, 31])
def test_a_step_edge_lands_on_the_color_edge(edge_col):
    """Crossed where the color edge is; sharper than bicubic, though not as sharp as gbp (band RMSE 19.8, gbp 1.6,
    bicubic 30.3): the single full-resolution pass smooths the enlarged work-grid edge but does not pull it."""
    gt, rgb, depth_lr = _step(edge_col=edge_col)
    out = depthrefine.refine(depth_lr, rgb, method="gbp-fast")
    assert (out[:, :edge_col] < 120).all() and (out[:, edge_col:] > 120).all()
    band = slice(edge_col - 6, edge_col + 6)
    bicubic = depthrefine.refine(depth_lr, rgb, method="bicubic")
    assert rmse(out[:, band], gt[:, band]) < 0.75 * rmse(bicubic[:, band], gt[:, band])


def test_a_constant_stays_constant_and_holes_never_leak(rng):
    texture = rng.integers(0, 256, (64, 80, 3)).astype(np.uint8)
    for value, dtype in ((77, np.uint8), (1234, np.uint16), (2.5, np.float32)):
        out = depthrefine.refine(np.full((16, 20), value, dtype), texture, method="gbp-fast")
        assert out.dtype == np.float32 and (out == np.float32(value)).all()
    gt, rgb, depth_lr = _step()
    holes = depth_lr.copy()
    holes[4:8, 2:6] = np.nan
    holes[:, 12] = 0
    out = depthrefine.refine(holes, rgb, method="gbp-fast")
    assert np.isfinite(out).all() and out.min() >= 40 and out.max() <= 200
    assert np.abs(out[:, :16] - 40).max() < 1.0


def test_a_scene_improves_on_bicubic_clean_and_noisy(rng):
    scene = make_scene((96, 128), 4, n_objects=3, seed=5, shading=0.1, color_noise_std=3.0)
    gt = scene.depth_hr_gt
    clean = _area(gt, 4)
    noisy = (clean + rng.normal(0, 3.0, clean.shape)).astype(np.float32)
    for depth_lr in (clean, noisy):
        ours = rmse(depthrefine.refine(depth_lr, scene.rgb_hr, method="gbp-fast"), gt)
        bicubic = rmse(depthrefine.refine(depth_lr, scene.rgb_hr, method="bicubic"), gt)
        assert ours < 0.8 * bicubic, (ours, bicubic)


def test_with_trust_a_textured_guide_over_a_smooth_depth_does_no_harm(rng):
    """Without the trust check gbp-fast copies texture edges (stripes: 0.77 against bicubic's 0.16); with it, no."""
    rows, cols, s = 96, 128, 4
    yy, xx = np.mgrid[0:rows, 0:cols].astype(np.float32)
    smooth = 120 + 30 * np.sin(xx / 23.0) * np.cos(yy / 31.0)
    stripes = np.where((np.sin(xx / 3.0) > 0)[..., None], 200, 40).astype(np.uint8).repeat(3, 2)
    depth_lr = _area(smooth, s)
    bicubic = rmse(depthrefine.refine(depth_lr, stripes, method="bicubic"), smooth)
    trusted = rmse(upsample_gbp_fast(depth_lr, stripes, params=GbpFastParams(trust=True)), smooth)
    untrusted = rmse(upsample_gbp_fast(depth_lr, stripes), smooth)
    assert trusted <= 1.02 * bicubic and untrusted > 2 * bicubic, (trusted, untrusted, bicubic)


@pytest.mark.parametrize("s", [4, 8])
def test_smooth_curved_surfaces_under_a_featureless_guide_are_no_worse_than_bicubic(s):
    """The full-resolution solve lowers a curved surface by about its smoothness times the Laplacian; the input's
    residual put back (``restore_smooth_surfaces``) undoes it. Before it, gbp-fast / bicubic here: wave 4.0x / 13x,
    bowl 1.5x / 1.5x (x4 / x8); after 0.70 / 0.99 and 0.82 / 0.93."""
    y, x = np.mgrid[:96, :128].astype(np.float64)
    guide = np.full((96, 128, 3), 100, np.uint8)
    for truth in (1000 + 300 * np.sin(x / 12) * np.cos(y / 15), 1000 + 0.05 * ((x - 64) ** 2 + (y - 48) ** 2)):
        truth = truth.astype(np.float32)
        depth_lr = cv2.resize(truth, (128 // s, 96 // s), interpolation=cv2.INTER_AREA)
        ours = rmse(depthrefine.refine(depth_lr, guide, method="gbp-fast"), truth)
        assert ours <= 1.02 * rmse(depthrefine.refine(depth_lr, guide, method="bicubic"), truth)


def _restored(truth: np.ndarray, depth_lr: np.ndarray, bias: float = 3.0) -> tuple[np.ndarray, object]:
    """``restore_smooth_surfaces`` of ``truth - bias`` (a solve's bias: the whole surface lower), and the measures."""
    from depthrefine.methods.gbp.measure import measure_input

    m = measure_input(np.asarray(depth_lr, np.float32), np.full((*truth.shape, 3), 100, np.uint8))
    out = (truth - bias).astype(np.float32)
    restore_smooth_surfaces(out, m)
    return out, m


def test_the_residual_is_put_back_on_a_noise_free_input_and_not_on_a_noisy_one(rng):
    from depthrefine.methods.gbp.solve import reduce

    y, x = np.mgrid[:96, :128].astype(np.float32)
    bowl = 1000 + 0.05 * ((x - 64) ** 2 + (y - 48) ** 2)
    depth_lr = cv2.resize(bowl, (32, 24), interpolation=cv2.INTER_AREA)
    out, m = _restored(bowl, depth_lr)
    assert np.abs(reduce(out, (24, 32), 1.0) - m.filled).max() < 0.3   # 3 before
    noisy, _ = _restored(bowl, depth_lr + rng.normal(0, 40, depth_lr.shape))
    np.testing.assert_array_equal(noisy, bowl - 3.0)


def test_the_residual_is_not_put_back_at_the_inputs_jumps_nor_from_its_holes():
    y, x = np.mgrid[:96, :128].astype(np.float32)
    step = np.where(x < 62, 1000.0, 1400.0).astype(np.float32) + 0.5 * y
    depth_lr = cv2.resize(step, (32, 24), interpolation=cv2.INTER_AREA)
    out, m = _restored(step, depth_lr)
    assert m.jump[:, 15].min() == 1.0                              # the jump map covers the step's columns
    np.testing.assert_array_equal(out[:, 60:64], step[:, 60:64] - 3.0)   # where the step is, nothing moves
    assert np.abs(out[:, :40] - step[:, :40]).max() < 0.5          # away from it the bias is undone
    holed = cv2.resize(0.5 * y + 1000, (32, 24), interpolation=cv2.INTER_AREA)
    holed[4:20, 8:24] = np.nan                                     # a hole 16 depth pixels wide
    out, _ = _restored(0.5 * y + 1000, holed)
    # at least 3 depth pixels inside the hole no residual reaches (the bicubic kernel spans 2)
    np.testing.assert_array_equal(out[7 * 4:17 * 4, 11 * 4:21 * 4], (0.5 * y + 1000 - 3.0)[7 * 4:17 * 4, 11 * 4:21 * 4])


def test_deterministic_input_untouched_and_progress_reaches_its_total(small_scene):
    depth = small_scene.depth_lr.copy()
    calls = []
    a = upsample_gbp_fast(depth, small_scene.rgb_hr, progress=lambda d, t: calls.append((d, t)))
    b = depthrefine.refine(depth, small_scene.rgb_hr, method="gbp-fast")
    assert a.tobytes() == b.tobytes()
    np.testing.assert_array_equal(depth, small_scene.depth_lr)
    assert calls[-1][0] == calls[-1][1] == GbpFastParams().rounds + 2


def test_the_work_grid_is_an_integer_reduction_and_small_factors_are_not_reduced(small_scene):
    assert work_shape((144, 176), (1008, 1232), 4.0) == (504, 616)         # x7: half
    assert work_shape((68, 86), (1088, 1376), 4.0) == (272, 344)           # x16: a quarter
    assert work_shape((50, 50), (75, 75), 4.0) == (75, 75)                  # x1.5: the color grid itself
    rgb = cv2.resize(small_scene.rgb_hr, (70, 70), interpolation=cv2.INTER_AREA)   # ratio 4.375
    out = upsample_gbp_fast(small_scene.depth_lr, rgb)
    assert out.shape == (70, 70) and np.isfinite(out).all()


@pytest.mark.parametrize("bad, error", [(dict(rounds=0), ValueError), (dict(work_scale=0), ValueError),
                                        (dict(lambda_lr=-1), ValueError), (dict(trust="yes"), TypeError)])
def test_params_are_checked(bad, error):
    with pytest.raises(error):
        GbpFastParams(**bad)


def test_sampling_sets_the_model_of_the_work_grid_rounds(small_scene):
    """small_scene's depth is point-sampled and measures so: told footprint means, gbp-fast's result changes."""
    depth_lr, rgb = small_scene.depth_lr, small_scene.rgb_hr
    auto = upsample_gbp_fast(depth_lr, rgb)
    np.testing.assert_array_equal(upsample_gbp_fast(depth_lr, rgb, params=GbpFastParams(sampling="point")), auto)
    assert not np.array_equal(upsample_gbp_fast(depth_lr, rgb, params=GbpFastParams(sampling="mean")), auto)


def test_the_shared_knobs_are_gbps():
    p = GbpFastParams(rounds=3, sigma_color=6.0, trust=True)
    assert p.gbp_params() == GbpParams(iterations=3, sigma_color=6.0, trust=True)
    with pytest.raises(TypeError, match="GbpFastParams"):
        depthrefine.refine(np.ones((4, 4), np.float32), np.zeros((16, 16, 3), np.uint8), method="gbp-fast",
                           params=GbpParams())


def test_reprojected_smooths_away_the_misplacement_of_the_samples():
    """As gbp's ``reprojected``, for the work-grid rounds (the full-resolution solve keeps its strength): on
    samples misplaced by up to half a depth pixel the RMSE falls from 7.1 to 4.9."""
    from test_gbp import misplaced_samples

    gt, rgb, depth_lr = misplaced_samples(0)
    plain = upsample_gbp_fast(depth_lr, rgb)
    told = upsample_gbp_fast(depth_lr, rgb, params=GbpFastParams(reprojected=True))
    # not lambda_lr = 2 throughout: that raises the full-resolution solve too
    assert not np.array_equal(told, upsample_gbp_fast(depth_lr, rgb, params=GbpFastParams(lambda_lr=2.0)))
    assert rmse(told, gt) < 0.75 * rmse(plain, gt)


def test_cli_reprojected_sets_the_knob_of_gbp_and_gbp_fast_and_no_other(tmp_path, capsys):
    from depthrefine.cli import main
    from depthrefine.io import read_depth
    from test_gbp import misplaced_samples

    _, rgb, depth_lr = misplaced_samples()
    depth, color = tmp_path / "d.npy", tmp_path / "c.png"
    np.save(depth, depth_lr)
    cv2.imwrite(str(color), rgb[..., ::-1])
    for method, params in (("gbp", GbpParams(reprojected=True)), ("gbp-fast", GbpFastParams(reprojected=True))):
        out = tmp_path / f"{method}.npy"
        assert main(["refine", str(depth), str(color), "-o", str(out), "--method", method, "--reprojected"]) == 0
        np.testing.assert_array_equal(read_depth(out), depthrefine.refine(depth_lr, rgb, method=method, params=params))
    assert main(["refine", str(depth), str(color), "-o", str(tmp_path / "b.npy"), "--method", "bicubic",
                 "--reprojected"]) == 2
    assert "add --method gbp" in capsys.readouterr().err and not (tmp_path / "b.npy").exists()
