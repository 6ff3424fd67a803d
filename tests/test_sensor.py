"""The simulated real sensors of the ``sensor`` protocol (``depthrefine.bench.sensor``) on small scenes."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from PIL import Image

from depthrefine.bench.sensor import (SENSOR_MODELS, SENSOR_PEER_PARAMS, SENSOR_TUNING_SCENES, SensorModel,
                                      mix_footprints, simulate_sensor, warp_horizontal)

ITOF, DTOF = SENSOR_MODELS["itof"], SENSOR_MODELS["dtof"]
#: An ideal camera: no noise, no dropouts, no calibration error, the footprint of its pixel.
IDEAL = dataclasses.replace(ITOF, name="ideal", footprint=1.0, noise_mm_at_1m=0.0, misregistration=0.0,
                            dark_low=0.0, dark_high=0.0)


def _scene(rows=64, cols=192, near=120.0, far=40.0):
    """A near box (columns 64-127) in front of a far wall, on a bright color image."""
    gt = np.full((rows, cols), far)
    gt[:, 64:128] = near
    return gt, np.full((rows, cols, 3), 200, np.uint8)


def test_warp_moves_nearer_points_further_and_keeps_the_nearest():
    gt, _ = _scene()
    warped, source = warp_horizontal(gt, 0.2, surface_gap=4)
    # the box moves 24 columns, the wall 8: the box now covers 88..151 and hides the wall there
    assert (warped[:, 88:152] == 120).all() and (warped[:, 152:] == 40).all()
    assert (source[:, 88:152] >= 64).all() and (source[:, 88:152] < 128).all()
    # what the color camera could not see (left of the moved box) is the wall continuing
    assert (warped[:, 8:88] == 40).all()


def test_mixing_flying_pixels_against_fattening():
    values = np.array([[100.0, 100.0, 100.0, 20.0], [100.0, 20.0, 20.0, 20.0], [50.0, 51.0, 52.0, 53.0]])
    weights = np.ones_like(values)
    assert mix_footprints(values, weights, ITOF).tolist() == [80.0, 40.0, 51.5]       # coverage-weighted means
    assert mix_footprints(values, weights, DTOF).tolist() == [100.0, 100.0, 51.5]     # the near quarter wins
    strict = dataclasses.replace(ITOF, mixed_invalid=0.25)
    assert np.isnan(mix_footprints(values, weights, strict)[:2]).all()                # mixed pixels dropped
    assert mix_footprints(values, weights, strict)[2] == 51.5                         # one slanted surface
    few = dataclasses.replace(DTOF, near_wins=0.5)
    assert mix_footprints(values, weights, few)[1] == 20.0                            # a quarter is too little


def test_ideal_sensor_sees_the_truth_with_occlusion_holes_beside_the_near_edge():
    gt, rgb = _scene()
    out = simulate_sensor(gt, rgb, scale=4, model=IDEAL)
    assert out.shape == (16, 48) and out.dtype == np.float32
    row = out[8]
    assert np.allclose(row[17:31], 120, atol=0.1) and np.allclose(row[2:15], 40, atol=0.1)
    # The depth camera, 32 mm to the left, cannot see the wall just right of the box: (120-40)*0.2/4 = 4 px.
    assert np.isnan(row[32:36]).all() and np.allclose(row[37:44], 40, atol=0.1)
    assert not np.isnan(row[:32]).any()


def test_dtof_fattens_the_near_box_and_itof_leaves_flying_pixels():
    gt, rgb = _scene()
    clean = {"noise_mm_at_1m": 0.0, "misregistration": 0.0}
    dtof = simulate_sensor(gt, rgb, scale=4, model=dataclasses.replace(DTOF, **clean))[8]
    itof = simulate_sensor(gt, rgb, scale=4, model=dataclasses.replace(ITOF, **clean))[8]
    near_d = np.flatnonzero(np.isfinite(dtof) & (dtof > 110))
    near_i = np.flatnonzero(np.isfinite(itof) & (itof > 110))
    assert near_d[0] < 16 and near_d[0] < near_i[0]  # the box (columns 16-31) grows to the left
    flying = np.isfinite(itof) & (itof > 45) & (itof < 115)
    assert flying.any() and not (np.isfinite(dtof) & (dtof > 45) & (dtof < 115)).any()


def test_dark_surfaces_drop_out_and_noise_grows_with_distance():
    gt, rgb = _scene(rows=128, cols=256)
    rgb[:64] = 10  # very dark (linear luminance 0.003) in the top half
    out = simulate_sensor(gt, rgb, scale=4, model=ITOF, seed=1)
    assert np.isnan(out[2:14]).all() and np.isfinite(out[20:30, :14]).all()
    flat = np.full((128, 256), 200.0)
    far = simulate_sensor(np.full((128, 256), 20.0), np.full((128, 256, 3), 200, np.uint8), scale=4, model=DTOF)
    near = simulate_sensor(flat, np.full((128, 256, 3), 200, np.uint8), scale=4, model=DTOF)
    # sigma_Z grows as Z^2.7 and a level spans Z^2 / (f B) mm, so in levels as Z^0.7: 0.38 at 2.7 m against
    # 0.26 at 1.5 m (there mostly the 1-mm rounding, 0.27 levels)
    assert np.nanstd(far[:, :20]) > 1.3 * np.nanstd(near[:, :20]) > 0


def test_simulation_is_deterministic_and_the_seed_moves_the_calibration_error():
    gt, rgb = _scene()
    a = simulate_sensor(gt, rgb, scale=4, model=DTOF, seed=5)
    assert np.array_equal(a, simulate_sensor(gt, rgb, scale=4, model=DTOF, seed=5), equal_nan=True)
    assert not np.array_equal(a, simulate_sensor(gt, rgb, scale=4, model=DTOF, seed=6), equal_nan=True)


def test_bad_models_and_inputs_are_refused():
    with pytest.raises(ValueError, match="mixing"):
        dataclasses.replace(ITOF, mixing="phase")
    with pytest.raises(ValueError, match="footprint"):
        dataclasses.replace(ITOF, footprint=0.5)
    with pytest.raises(ValueError, match="near_wins"):
        dataclasses.replace(DTOF, near_wins=1.5)
    with pytest.raises(ValueError, match="without '-'"):
        dataclasses.replace(DTOF, name="d-tof")
    gt, rgb = _scene()
    with pytest.raises(ValueError, match="multiple of the scale"):
        simulate_sensor(gt[:, :190], rgb[:, :190], scale=4, model=ITOF)
    with pytest.raises(TypeError, match="SensorModel"):
        simulate_sensor(gt, rgb, scale=4, model="itof")
    assert isinstance(ITOF, SensorModel)


def test_sensor_protocol_cases_and_report_columns(tmp_path):
    from depthrefine.bench import load_cases, run_benchmark
    from depthrefine.bench.report import overview_markdown, summary_tables
    from depthrefine.bench.suite import protocol_params, report_notes

    gt, rgb = _scene(rows=64, cols=128)
    rgb[:, 40:80] = (30, 160, 90)
    for scene in ("art", "dolls"):
        folder = tmp_path / "middlebury2005_park" / scene
        folder.mkdir(parents=True)
        Image.fromarray(gt.astype(np.uint8)).save(folder / "gt_disp.png")
        Image.fromarray(rgb).save(folder / "color.png")
    cases = load_cases(tmp_path, "sensor", (4,))
    assert [(c.scene, c.split) for c in cases] == [("art-itof", "test"), ("art-dtof", "test"),
                                                   ("dolls-itof", "tune"), ("dolls-dtof", "tune")]
    assert set(SENSOR_TUNING_SCENES) == {"dolls-itof", "dolls-dtof", "laundry-itof", "laundry-dtof"}
    rows = run_benchmark(cases, ["nearest", "bilinear"]).rows
    titles = [t.title.split(":")[0] for t in summary_tables(rows)]
    assert titles == ["sensor dtof", "sensor dtof", "sensor itof", "sensor itof"]
    header = overview_markdown(rows, metric="edge_rmse").splitlines()[0]
    assert "sensor dtof ×4" in header and "sensor itof ×4" in header
    params = protocol_params("sensor")
    assert set(SENSOR_PEER_PARAMS) == {"jbf", "guided", "fgs", "wmf"}
    assert set(params) == set(SENSOR_PEER_PARAMS) | {"gbp", "gbp-fast"}     # the reprojected inputs' methods are told
    assert params["gbp"].reprojected and params["gbp-fast"].reprojected
    assert params["gbp"] == type(params["gbp"])(reprojected=True)            # otherwise gbp's defaults
    assert protocol_params("park") == {}
    notes = report_notes(rows, ["gbp", "bilinear"])
    assert any("sensor protocol's inputs come through the rig chain's reprojection, so gbp is told so" in n
               for n in notes)
