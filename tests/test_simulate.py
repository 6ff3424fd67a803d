"""The simulated ToF sensor (depthrefine.bench.simulate): each part of the model, seeds, errors."""

from __future__ import annotations

import numpy as np
import pytest

from depthrefine.bench.simulate import ToFModel, footprint_mean, linear_luminance, simulate_tof

QUIET = ToFModel(noise_near=0.0, noise_far=0.0, dark_low=0.0, dark_high=0.0)
BRIGHT = np.full((32, 32, 3), 200, np.uint8)


def test_shape_dtype_and_flat_scene_is_exact():
    gt = np.full((32, 48), 120, np.uint8)
    rgb = np.full((32, 48, 3), 200, np.uint8)
    lr = simulate_tof(gt, rgb, scale=8, model=QUIET)
    assert lr.shape == (4, 6) and lr.dtype == np.uint8
    assert (lr == 120).all()


def test_footprint_integration_mixes_values_at_a_depth_edge():
    gt = np.full((16, 16), 40, np.uint8)
    gt[:, 6:] = 200  # edge inside the second 4-pixel footprint (cols 4..7: two of each)
    lr = simulate_tof(gt, BRIGHT[:16, :16], scale=4, model=QUIET)
    assert lr[:, 0].tolist() == [40] * 4
    assert lr[:, 1].tolist() == [120] * 4  # the "flying" mixed value, (2*40 + 2*200) / 4
    assert (lr[:, 2:] == 200).all()


def test_footprint_mean_ignores_invalid_ground_truth():
    values = np.array([[10.0, np.nan, 0.0, 0.0], [30.0, np.nan, 0.0, 0.0]])
    out = footprint_mean(values, 2, valid=values > 0)
    assert out[0, 0] == pytest.approx(20.0) and np.isnan(out[0, 1])
    gt = np.zeros((8, 8), np.uint8)
    gt[:4, :4] = 90
    lr = simulate_tof(gt, BRIGHT[:8, :8], scale=4, model=QUIET)
    assert lr.tolist() == [[90, 0], [0, 0]]  # no valid ground truth: no measurement


def test_dark_surfaces_drop_out_and_bright_ones_do_not():
    gt = np.full((64, 64), 150, np.uint8)
    rgb = np.full((64, 64, 3), 220, np.uint8)
    rgb[:, :32] = 5  # black cloth: linear luminance ~ 0.0015 < dark_low
    lr = simulate_tof(gt, rgb, scale=4, model=ToFModel(noise_near=0, noise_far=0), seed=1)
    assert (lr[:, :8] == 0).all()
    assert (lr[:, 8:] == 150).all()


def test_dropout_probability_falls_linearly_between_the_bounds():
    gt = np.full((400, 400), 150, np.uint8)
    level = round(255 * 1.055 * 0.02 ** (1 / 2.4) - 0.055 * 255)  # sRGB value of linear 0.02
    rgb = np.full((400, 400, 3), level, np.uint8)
    model = ToFModel(noise_near=0, noise_far=0, dark_low=0.01, dark_high=0.03)
    lum = float(linear_luminance(rgb[:1, :1])[0, 0])
    expected = (0.03 - lum) / 0.02
    lr = simulate_tof(gt, rgb, scale=4, model=model, seed=5)
    assert (lr == 0).mean() == pytest.approx(expected, abs=0.03)
    assert 0.3 < expected < 0.7


def test_noise_grows_with_distance():
    gt = np.full((400, 400), 250, np.uint8)
    gt[200:] = 50  # far half
    rgb = np.full((400, 400, 3), 200, np.uint8)
    model = ToFModel(noise_near=1.0, noise_far=4.0, dark_low=0.0, dark_high=0.0)
    lr = simulate_tof(gt, rgb, scale=4, model=model, seed=2).astype(float)
    near, far = lr[:49], lr[51:]
    assert np.std(near) == pytest.approx(1.0, abs=0.15)
    assert np.std(far) == pytest.approx(4.0, abs=0.3)
    assert abs(near.mean() - 250) < 0.3 and abs(far.mean() - 50) < 0.5


def test_seeded_and_deterministic(rng):
    gt = rng.integers(30, 220, (64, 64)).astype(np.uint8)
    rgb = rng.integers(0, 256, (64, 64, 3)).astype(np.uint8)
    gt0, rgb0 = gt.copy(), rgb.copy()
    a = simulate_tof(gt, rgb, scale=4, seed=7)
    b = simulate_tof(gt, rgb, scale=4, seed=7)
    c = simulate_tof(gt, rgb, scale=4, seed=8)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)
    np.testing.assert_array_equal(gt, gt0)
    np.testing.assert_array_equal(rgb, rgb0)


def test_quantised_to_whole_levels_in_range():
    gt = np.full((40, 40), 254, np.uint8)
    lr = simulate_tof(gt, np.full((40, 40, 3), 200, np.uint8), scale=2,
                      model=ToFModel(noise_near=5, noise_far=5, dark_low=0, dark_high=0), seed=0)
    assert lr.dtype == np.uint8 and lr.min() >= 1 and lr.max() == 255  # clipped, never 0 by noise


def test_bad_inputs():
    gt = np.full((8, 8), 100, np.uint8)
    with pytest.raises(ValueError, match="8-bit"):
        simulate_tof(np.full((8, 8), 1000.0), BRIGHT[:8, :8], scale=2)
    with pytest.raises(ValueError, match="same grid"):
        simulate_tof(gt, BRIGHT[:8, :6], scale=2)
    with pytest.raises(ValueError, match="block"):
        simulate_tof(gt, BRIGHT[:8, :8], scale=16)
    with pytest.raises(ValueError, match="dark_high"):
        ToFModel(dark_low=0.5, dark_high=0.1)
    with pytest.raises(TypeError, match="ToFModel"):
        simulate_tof(gt, BRIGHT[:8, :8], scale=2, model={"noise_near": 1})
