"""The rig commands end to end on tmp_path: calibrate, calibrate-stereo, undistort, align, run, export-ply.

The captures are synthetic (see test_calibrate.py and test_align.py): boards
rendered through known lenses, and a two-plane scene seen by a depth camera
with barrel distortion and a color camera 6 cm to its right, turned 1.8
degrees. ``run`` on the raw captures must give the depth rendered directly in
the color camera's (undistorted) view.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import cv2
import numpy as np
import pytest

from depthrefine.rig import align_reproject, undistort_image
from depthrefine.cli import main
from depthrefine.io import read_camera, read_depth, read_ply, read_rgb, read_rig, write_rig
from test_align import COLOR_CAM, DEPTH_CAM, RIG, RIG_R, RIG_T, _shift_rig, edge_zone, render_depth
from test_calibrate import COLOR_K, DEPTH_K, RIG_T as BOARD_RIG_T, color_views, depth_views

SQUARE_ARG = "30mm"


def _write_images(folder: Path, images, stem: str) -> list[str]:
    folder.mkdir(exist_ok=True)
    paths = []
    for i, image in enumerate(images):
        path = folder / f"{stem}_{i:02d}.png"
        cv2.imwrite(str(path), image)
        paths.append(str(path))
    return paths


@pytest.fixture(scope="module")
def captures(tmp_path_factory) -> dict[str, Path]:
    """Raw captures of the scene: uint16 mm depth (distorted), color (distorted), rig file, ground truth."""
    folder = tmp_path_factory.mktemp("rig")
    z_raw, _ = render_depth(DEPTH_CAM, distorted=True)
    depth = np.floor(z_raw * 1000 + 0.5).astype(np.uint16)
    depth[5:9, 5:9] = 0  # a patch without measurement
    cv2.imwrite(str(folder / "depth.png"), depth)
    _, front = render_depth(COLOR_CAM, RIG_R, RIG_T, distorted=True)
    rgb = np.where(front[..., None], np.array([210, 40, 30], np.uint8), np.array([40, 90, 200], np.uint8))
    cv2.imwrite(str(folder / "color.png"), cv2.cvtColor(rgb.astype(np.uint8), cv2.COLOR_RGB2BGR))
    write_rig(folder / "rig.json", RIG)
    (folder / "capture.toml").write_text(
        'rig = "rig.json"\n\n[align]\nmethod = "reproject"\ndepth_units = 0.001\n\n'
        '[refine]\nmethod = "thesis"\n\n[refine.params]\npatches = [2, 2]\n'
    )
    return {"folder": folder, "depth": folder / "depth.png", "color": folder / "color.png",
            "rig": folder / "rig.json", "settings": folder / "capture.toml"}


def _truth_mm() -> tuple[np.ndarray, np.ndarray]:
    z, front = render_depth(COLOR_CAM.without_distortion(), RIG_R, RIG_T, distorted=False)
    return z * 1000, front


# ----------------------------------------------------------------------------
# calibrate, calibrate-stereo
# ----------------------------------------------------------------------------


def test_calibrate_writes_the_camera_and_reports_skipped_images(tmp_path, capsys):
    paths = _write_images(tmp_path / "ir", depth_views(), "ir")
    blank = tmp_path / "ir" / "blank.png"
    cv2.imwrite(str(blank), np.full((180, 240), 128, np.uint8))
    out = tmp_path / "camera.json"
    code = main(["calibrate", *paths, str(blank), "--board", "8x6", "--square", SQUARE_ARG, "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 0, err
    assert f"not found in {blank}; skipped" in err
    data = json.loads(out.read_text())
    assert {"K", "dist", "image_size", "rms"} <= set(data)
    assert data["image_size"] == [240, 180] and len(data["dist"]) == 5
    K = np.array(data["K"])
    assert abs(K[0, 0] / DEPTH_K[0, 0] - 1) < 0.01 and abs(K[1, 1] / DEPTH_K[1, 1] - 1) < 0.01
    assert abs(K[0, 2] - DEPTH_K[0, 2]) < 2 and abs(K[1, 2] - DEPTH_K[1, 2]) < 2
    assert data["images_skipped"] == [str(blank)] and 0 < data["rms"] < 0.3
    # never overwrite without --overwrite
    assert main(["calibrate", *paths, "--board", "8x6", "--square", "0.03", "-o", str(out)]) == 2
    assert "exists; pass --overwrite" in capsys.readouterr().err


def test_calibrate_with_too_few_boards_fails_cleanly(tmp_path, capsys):
    paths = _write_images(tmp_path / "ir", depth_views()[:2], "ir")
    blank = tmp_path / "ir" / "blank.png"
    cv2.imwrite(str(blank), np.full((180, 240), 128, np.uint8))
    out = tmp_path / "camera.json"
    assert main(["calibrate", *paths, str(blank), "--board", "8x6", "--square", "30mm", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "found in 2 of 3 images; calibration needs at least 3" in err and "Traceback" not in err
    assert f"board not found in {blank}." in err and len(err.strip().splitlines()) == 1  # names it, one line
    assert not out.exists()
    # calibrate-stereo names the images of the pairs it could not use
    color = _write_images(tmp_path / "rgb", color_views()[:3], "rgb")
    stereo = ["calibrate-stereo", "--depth-images", *paths, str(blank), "--color-images", *color,
              "--board", "8x6", "--square", "30mm", "-o", str(out)]
    assert main(stereo) == 2
    err = capsys.readouterr().err
    assert "found in both images of 2 of 3 pairs" in err and f"board not found in {blank}" in err
    assert len(err.strip().splitlines()) == 1 and not out.exists()
    assert main(["calibrate", *paths, "--board", "8", "--square", "30mm", "-o", str(out)]) == 2
    assert "COLSxROWS" in capsys.readouterr().err


def test_calibrate_stereo_writes_the_rig(tmp_path, capsys):
    depth_paths = _write_images(tmp_path / "ir", depth_views(), "ir")
    color_paths = _write_images(tmp_path / "rgb", color_views(), "rgb")
    out = tmp_path / "rig.json"
    args = ["calibrate-stereo", "--depth-images", *depth_paths, "--color-images", *color_paths,
            "--board", "8x6", "-o", str(out)]
    assert main(args + ["--square", "0.03"]) == 0, capsys.readouterr().err  # a bare number is metres
    err = capsys.readouterr().err
    assert "pair skipped" in err  # one color view misses the board
    rig = read_rig(out)
    assert np.abs(rig.t - BOARD_RIG_T).max() < 0.003
    assert abs(rig.color_camera.focal[0] / COLOR_K[0, 0] - 1) < 0.01
    data = json.loads(out.read_text())
    assert {"depth_camera", "color_camera", "R", "t", "rms"} <= set(data)
    # a bare square size of 30 would make t 1000 times too large: refused
    assert main(args + ["--square", "30", "--overwrite"]) == 2
    assert "give it, e.g. --square 25mm" in capsys.readouterr().err
    assert main(args[:3] + args[4:] + ["--square", "30mm", "--overwrite"]) == 2  # 9 depth, 10 color
    assert "in pairs" in capsys.readouterr().err


# ----------------------------------------------------------------------------
# undistort, align
# ----------------------------------------------------------------------------


def test_undistort_depth_and_intensity(captures, tmp_path, capsys):
    out = tmp_path / "und.png"
    assert main(["undistort", str(captures["depth"]), "--camera", str(captures["rig"]), "-o", str(out)]) == 0
    und = read_depth(out)
    assert und.dtype == np.uint16 and und.shape == (72, 96)
    ideal, _ = render_depth(DEPTH_CAM, distorted=False)
    assert set(np.unique(und)) <= {0, 1000, 2000}
    assert (und == np.floor(ideal * 1000 + 0.5)).mean() > 0.9
    out_rgb = tmp_path / "color_und.png"
    assert main(["undistort", str(captures["color"]), "--camera", str(captures["rig"]), "--color", "--intensity",
                 "-o", str(out_rgb)]) == 0
    assert cv2.imread(str(out_rgb)).shape == (504, 672, 3)


def test_align_reproject_and_shift(captures, tmp_path, capsys):
    out = tmp_path / "aligned.png"
    base = ["align", str(captures["depth"]), "--rig", str(captures["rig"])]
    assert main(base + ["-o", str(out), "--depth-units", "0.001"]) == 0, capsys.readouterr().err
    aligned = read_depth(out)
    assert aligned.dtype == np.uint16 and aligned.shape == (72, 96)  # the 672 x 504 color grid / 7
    err = capsys.readouterr().err
    assert "reprojected" in err
    # the color lens has distortion: the note says the output lines up with the undistorted color image
    assert "aligned to the undistorted color image" in err
    assert f"depthrefine undistort COLOR --camera {captures['rig']} --color --intensity" in err
    # the shift on this rig (turned 1.8 degrees, other intrinsics) would misplace the depth: refused
    out_shift = tmp_path / "shift.png"
    assert main(base + ["-o", str(out_shift), "--method", "shift", "--depth-units", "0.001"]) == 2
    err = capsys.readouterr().err
    assert "misplace the depth" in err and "--method reproject" in err and "Traceback" not in err
    assert not out_shift.exists()
    # on a parallel rig whose color image shows the depth camera's view it runs
    rig_file = tmp_path / "parallel.json"
    write_rig(rig_file, _shift_rig())
    assert main(["align", str(captures["depth"]), "--rig", str(rig_file), "-o", str(out_shift),
                 "--method", "shift", "--depth-units", "0.001"]) == 0
    err = capsys.readouterr().err
    assert "shifted" in err and "undistorted color image" not in err  # that color lens has no distortion
    assert read_depth(out_shift).shape == (72, 96)
    # --no-undistort: both images already undistorted, the depth aligned to the undistorted color camera
    z, _ = render_depth(DEPTH_CAM, distorted=False)
    undistorted = tmp_path / "depth_undistorted.png"
    cv2.imwrite(str(undistorted), np.floor(z * 1000 + 0.5).astype(np.uint16))
    out_nu = tmp_path / "no_undistort.png"
    assert main(["align", str(undistorted), "--rig", str(captures["rig"]), "-o", str(out_nu), "--depth-units",
                 "0.001", "--no-undistort"]) == 0
    assert "undistorted color image" not in capsys.readouterr().err
    expected = align_reproject(read_depth(undistorted), RIG, depth_units=0.001, depth_distorted=False)
    assert np.array_equal(read_depth(out_nu), np.nan_to_num(np.floor(expected + 0.5)).astype(np.uint16))
    # the settings file's [align] gives the units
    out_file = tmp_path / "from_settings.png"
    assert main(["align", str(captures["depth"]), "--rig", str(captures["settings"]), "-o", str(out_file)]) == 0
    assert np.array_equal(read_depth(out_file), aligned)
    # reprojection without units: a clear error, no output
    out_bad = tmp_path / "bad.png"
    assert main(base + ["-o", str(out_bad)]) == 2
    err = capsys.readouterr().err
    assert "needs the depth's units" in err and not out_bad.exists()


# ----------------------------------------------------------------------------
# run, export-ply
# ----------------------------------------------------------------------------


def test_run_on_raw_captures_matches_the_color_view(captures, tmp_path, capsys):
    out = tmp_path / "refined.png"
    cloud = tmp_path / "cloud.ply"
    used = tmp_path / "used.json"
    code = main(["run", str(captures["depth"]), str(captures["color"]), "--rig", str(captures["settings"]),
                 "-o", str(out), "--ply", str(cloud), "--save-settings", str(used)])
    err = capsys.readouterr().err
    assert code == 0, err
    refined = read_depth(out)
    assert refined.dtype == np.uint16 and refined.shape == (504, 672)
    truth, front = _truth_mm()
    # away from the rectangle's edge (one depth pixel = 7 color pixels) the depth is right
    close = np.abs(refined.astype(np.float64) - truth) < 0.01 * truth
    far_from_edge = ~edge_zone(front, 7)
    assert close[far_from_edge].mean() > 0.99  # without the alignment: 0.53
    # the edge follows the color edge: within 1 px almost everywhere. No depth reached the 2-3 depth pixels beside
    # the rectangle that the depth camera could not see (38 of the aligned map's pixels); a strip that narrow
    # between two surfaces is given to them by the color (`rig.chain.BORDER_BAND`): here all to the wall, whose
    # color it has, at the wall's depth
    measured = refined > 0
    assert measured.all()
    assert close[~edge_zone(front, 1)].mean() > 0.99
    refined_front = refined < 1500
    assert (refined_front == front)[~edge_zone(front, 1) & measured].mean() > 0.999  # without: 0.979
    # the point cloud: one point per valid pixel, in metres, colored
    points, colors = read_ply(cloud)
    assert points.shape[0] == np.count_nonzero(refined) and colors is not None
    assert 0.9 < points[:, 2].min() and points[:, 2].max() < 2.2
    # the settings written can be run again and give the same bytes
    settings = json.loads(used.read_text())
    assert settings["align"]["depth_units"] == 0.001 and settings["refine"]["params"]["patches"] == [2, 2]
    again = tmp_path / "again.png"
    assert main(["run", str(captures["depth"]), str(captures["color"]), "--rig", str(used), "-o", str(again)]) == 0
    assert again.read_bytes() == out.read_bytes()
    # --output-scale / --output-dtype: the same result stored as float metres
    metres = tmp_path / "refined_m.tif"
    assert main(["run", str(captures["depth"]), str(captures["color"]), "--rig", str(used), "-o", str(metres),
                 "--output-scale", "0.001", "--output-dtype", "float32"]) == 0
    stored = read_depth(metres)
    assert stored.dtype == np.float32
    np.testing.assert_allclose(stored[refined > 0] * 1000, refined[refined > 0], atol=0.5)


def test_run_with_the_thesis_shift_and_options(captures, tmp_path, capsys):
    out = tmp_path / "refined.tif"
    aligned = tmp_path / "aligned.png"
    # the captures' rig does not fit the shift (before: exit 0 and the rectangle 3.5 depth pixels off)
    code = main(["run", str(captures["depth"]), str(captures["color"]), "--rig", str(captures["rig"]),
                 "--method", "shift", "--depth-units", "0.001", "--refine-method", "nearest", "-o", str(out),
                 "--save-aligned", str(aligned)])
    err = capsys.readouterr().err
    assert code == 2 and "misplace the depth" in err and "--method reproject" in err
    assert not out.exists() and not aligned.exists()
    # a parallel rig whose color image shows the depth camera's view: the shift puts the depth in place
    rig = _shift_rig()
    rig_file = tmp_path / "parallel.json"
    write_rig(rig_file, rig)
    truth, front = render_depth(rig.color_camera, np.eye(3), rig.t, distorted=False)
    color = tmp_path / "color_parallel.png"
    cv2.imwrite(str(color), np.where(front[..., None], 60, 200).astype(np.uint8).repeat(3, axis=2))
    code = main(["run", str(captures["depth"]), str(color), "--rig", str(rig_file),
                 "--method", "shift", "--depth-units", "0.001", "--refine-method", "nearest", "-o", str(out),
                 "--save-aligned", str(aligned)])
    err = capsys.readouterr().err
    assert code == 0, err
    assert "shifted" in err
    refined = read_depth(out).astype(np.float64)
    assert refined.shape == (504, 672) and read_depth(aligned).shape == (72, 96)
    close = np.abs(refined - truth * 1000) < 0.01 * truth * 1000
    assert close[~edge_zone(front, 7) & (refined > 0)].mean() > 0.99
    assert not ((refined < 1500) != front)[~edge_zone(front, 7) & (refined > 0)].any()  # edges within 1 depth px


def test_run_errors_leave_no_output(captures, tmp_path, capsys):
    out = tmp_path / "refined.png"
    cloud = tmp_path / "cloud.ply"
    # 8-bit depth intensity cannot be reprojected without a conversion
    intensity = tmp_path / "intensity.png"
    cv2.imwrite(str(intensity), np.full((72, 96), 120, np.uint8))
    assert main(["run", str(intensity), str(captures["color"]), "--rig", str(captures["rig"]), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "inverse_scale" in err and "Traceback" not in err
    # --ply without units
    assert main(["run", str(captures["depth"]), str(captures["color"]), "--rig", str(captures["rig"]),
                 "--method", "shift", "--slope", "0.5", "-o", str(out), "--ply", str(cloud)]) == 2
    assert "--ply needs the depth's units" in capsys.readouterr().err
    # a color image of the wrong size
    small = tmp_path / "small.png"
    cv2.imwrite(str(small), np.zeros((50, 60, 3), np.uint8))
    assert main(["run", str(captures["depth"]), str(small), "--rig", str(captures["settings"]), "-o", str(out)]) == 2
    assert "color image is 60x50" in capsys.readouterr().err
    # an unknown key in the settings file
    bad = tmp_path / "bad.toml"
    bad.write_text(f'rig = "{captures["rig"]}"\n[align]\ndepth_unit = 0.001\n')
    assert main(["run", str(captures["depth"]), str(captures["color"]), "--rig", str(bad), "-o", str(out)]) == 2
    assert "unknown parameter(s) 'depth_unit'" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml", "intensity.png", "small.png"]


def test_export_ply(captures, tmp_path, capsys):
    truth, _ = _truth_mm()
    depth = tmp_path / "depth_color_grid.png"
    cv2.imwrite(str(depth), np.floor(truth + 0.5).astype(np.uint16))
    out = tmp_path / "cloud.ply"
    assert main(["export-ply", str(depth), str(captures["color"]), "--rig", str(captures["settings"]),
                 "-o", str(out), "--stride", "4"]) == 0, capsys.readouterr().err
    points, colors = read_ply(out)
    assert points.shape == (126 * 168, 3) and colors.shape == points.shape
    # back in the depth camera's frame the points lie on the two planes Z = 1 and Z = 2
    in_depth_frame = (points.astype(np.float64) - RIG_T) @ RIG_R
    assert np.all(np.minimum(np.abs(in_depth_frame[:, 2] - 1.0), np.abs(in_depth_frame[:, 2] - 2.0)) < 0.01)
    assert main(["export-ply", str(depth), str(captures["color"]), "--rig", str(captures["rig"]),
                 "-o", str(tmp_path / "x.ply")]) == 2
    assert "units are unknown" in capsys.readouterr().err


def test_export_ply_no_undistort_takes_color_as_already_undistorted(captures, tmp_path, capsys):
    """--no-undistort means the same as in align and run: COLOR is already undistorted."""
    truth, _ = _truth_mm()
    depth = tmp_path / "depth_color_grid.png"
    cv2.imwrite(str(depth), np.floor(truth + 0.5).astype(np.uint16))
    camera = read_camera(captures["rig"], which="color")
    assert camera.has_distortion
    color_und = tmp_path / "color_undistorted.png"
    cv2.imwrite(str(color_und), cv2.cvtColor(undistort_image(read_rgb(captures["color"]), camera), cv2.COLOR_RGB2BGR))
    default, given = tmp_path / "a.ply", tmp_path / "b.ply"
    args = ["--rig", str(captures["settings"]), "--stride", "4"]
    assert main(["export-ply", str(depth), str(captures["color"]), "-o", str(default)] + args) == 0
    assert main(["export-ply", str(depth), str(color_und), "-o", str(given), "--no-undistort"] + args) == 0
    (p_default, c_default), (p_given, c_given) = read_ply(default), read_ply(given)
    np.testing.assert_array_equal(p_default, p_given)
    np.testing.assert_array_equal(c_default, c_given)
    # --distorted-grid back-projects through the lens model instead: other points
    raw = tmp_path / "c.ply"
    assert main(["export-ply", str(depth), str(captures["color"]), "-o", str(raw), "--distorted-grid"] + args) == 0
    assert not np.array_equal(read_ply(raw)[0], p_default)


def test_run_with_a_non_integer_ratio_applies_the_scale_step(captures, tmp_path, capsys):
    """Thesis 3.2.2: color 7.4 times the depth -> depth x7, color x0.95 (bilinear), result back to the color size."""
    rig = _shift_rig(size=(710, 533))  # 72 x 96 depth pixels * 7.4, parallel: the shift applies
    rig_file = tmp_path / "rig74.json"
    write_rig(rig_file, rig)
    _, front = render_depth(rig.color_camera, np.eye(3), rig.t, distorted=False)
    color = tmp_path / "color74.png"
    cv2.imwrite(str(color), np.where(front[..., None], 60, 200).astype(np.uint8).repeat(3, axis=2))
    out = tmp_path / "refined.png"
    code = main(["run", str(captures["depth"]), str(color), "--rig", str(rig_file), "--method", "shift",
                 "--depth-units", "0.001", "--refine-method", "thesis", "--patches", "2x2", "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 0, err
    assert "non-integer ratio 7.39" in err and "depth enlarged x7, color resized x0.946" in err
    assert read_depth(out).shape == (533, 710)


# ----------------------------------------------------------------------------
# Issue 24: calibration quality gates, plausible units, run --preview
# ----------------------------------------------------------------------------


def test_calibrate_prints_view_errors_warns_on_few_views_and_writes_the_report(tmp_path, capsys):
    paths = _write_images(tmp_path / "ir", depth_views()[:6], "ir")
    out, report = tmp_path / "camera.json", tmp_path / "report"
    assert main(["calibrate", *paths, "--board", "8x6", "--square", SQUARE_ARG, "-o", str(out),
                 "--report", str(report)]) == 0
    err = capsys.readouterr().err
    assert "warning: only 6 views for the plain lens model" in err and "about 15" in err
    for path in paths:  # one line per view: its RMS error and corners
        assert re.search(rf"{re.escape(path)}\s+0\.\d{{3}} px  \(48 corners\)", err), err
    data = json.loads(out.read_text())
    assert len(data["view_rms"]) == 6 and data["lens_model"] == "plain"
    assert max(data["view_rms"]) < 0.3 and data["rms"] <= max(data["view_rms"])
    views = (report / "views.csv").read_text().splitlines()
    assert views[0] == "image,rms_px,corners" and len(views) == 7 and views[1].startswith(paths[0])
    picture = read_rgb(report / "coverage.png")
    assert picture.shape[1] > 800 and picture.std() > 10
    # the k3 model too (it needs about 20)
    assert main(["calibrate", *paths, "--board", "8x6", "--square", SQUARE_ARG, "-o", str(out), "--overwrite",
                 "--k3"]) == 0
    err = capsys.readouterr().err
    assert "only 6 views for the k3 lens model (k1, k2, p1, p2, k3); a stable fit needs about 20" in err


def test_calibration_over_max_rms_is_refused_in_one_line_and_writes_nothing(tmp_path, capsys):
    paths = _write_images(tmp_path / "ir", depth_views()[:4], "ir")
    out, report = tmp_path / "camera.json", tmp_path / "report"
    assert main(["calibrate", *paths, "--board", "8x6", "--square", SQUARE_ARG, "-o", str(out),
                 "--report", str(report), "--max-rms", "0.01"]) == 2
    err = capsys.readouterr().err
    assert "calibration refused: RMS reprojection error 0.1" in err and "over --max-rms 0.01 px" in err
    assert re.search(r"worst views: \S+ir_\d\d\.png 0\.\d\d px", err), err
    assert len(err.strip().splitlines()) == 1 and not out.exists() and not report.exists()
    # an image without the board: the line says how many had it (a wrong --board finds the board in few)
    blank = _write_images(tmp_path / "blank", [np.full_like(depth_views()[0], 128)], "blank")
    assert main(["calibrate", *paths, *blank, "--board", "8x6", "--square", SQUARE_ARG, "-o", str(out),
                 "--max-rms", "0.01"]) == 2
    err = capsys.readouterr().err
    assert "(the board found in 4 of 5 images, plain lens model; worst views: " in err
    assert len(err.strip().splitlines()) == 1 and not out.exists()
    color = _write_images(tmp_path / "rgb", color_views()[:4], "rgb")
    stereo = ["calibrate-stereo", "--depth-images", *paths, "--color-images", *color, "--board", "8x6",
              "--square", SQUARE_ARG, "-o", str(out)]
    assert main(stereo + ["--max-rms", "0.01"]) == 2
    err = capsys.readouterr().err
    assert "the depth camera's calibration refused" in err and len(err.strip().splitlines()) == 1
    depth_camera, color_camera = tmp_path / "d.json", tmp_path / "c.json"
    assert main(["calibrate", *paths, "--board", "8x6", "--square", SQUARE_ARG, "-o", str(depth_camera)]) == 0
    all_color = _write_images(tmp_path / "rgb_all", color_views(), "rgb")
    assert main(["calibrate", *all_color, "--board", "8x6", "--square", SQUARE_ARG, "-o", str(color_camera)]) == 0
    capsys.readouterr()
    # both cameras known: only the pair's own fit is checked
    known = ["--depth-camera", str(depth_camera), "--color-camera", str(color_camera)]
    assert main(stereo + known + ["--max-rms", "0.01"]) == 2
    err = capsys.readouterr().err
    assert "stereo calibration refused" in err and "worst pairs: ir_" in err and len(err.strip().splitlines()) == 1
    assert not out.exists()
    assert main(stereo + known) == 0
    err = capsys.readouterr().err
    assert re.search(r"ir_00\.png \+ rgb_00\.png  depth  0\.\d{3} px, color  0\.\d{3} px", err), err
    assert len(json.loads(out.read_text())["pair_rms"]) >= 3


def test_implausible_depth_units_are_a_warning_naming_the_units_and_the_median(captures, tmp_path, capsys):
    out = tmp_path / "r.png"
    assert main(["run", str(captures["depth"]), str(captures["color"]), "--rig", str(captures["rig"]),
                 "--depth-units", "1", "-o", str(out), "--refine-method", "bilinear"]) == 0
    err = capsys.readouterr().err
    # the background plane is 2000 mm away
    assert "depthrefine run: warning: depth units 1 m per stored value give a median depth of 2 km, outside the " \
        "5 cm .. 50 m" in err and "give --depth-units 0.001" in err, err
    aligned = tmp_path / "a.png"
    assert main(["align", str(captures["depth"]), "--rig", str(captures["rig"]), "--depth-units", "1e-6",
                 "-o", str(aligned)]) == 0
    err = capsys.readouterr().err
    assert "depthrefine align: warning: depth units 1e-06 m per stored value give a median depth of 2 mm, " in err
    assert main(["run", str(captures["depth"]), str(captures["color"]), "--rig", str(captures["rig"]),
                 "--depth-units", "0.001", "-o", str(out), "--overwrite", "--refine-method", "bilinear"]) == 0
    assert "warning" not in capsys.readouterr().err


def test_run_preview_and_same_file_refused(captures, tmp_path, capsys):
    out, preview = tmp_path / "r.png", tmp_path / "p.png"
    assert main(["run", str(captures["depth"]), str(captures["color"]), "--rig", str(captures["settings"]),
                 "-o", str(out), "--preview", str(preview), "--crop", "300,200,100,80", "--scale", "3",
                 "--refine-method", "bilinear"]) == 0
    assert f"wrote {preview}" in capsys.readouterr().err
    picture = read_rgb(preview)
    assert 600 < picture.shape[1] < 800 and 240 < picture.shape[0] < 360
    for command in (["run", str(captures["depth"]), str(captures["depth"]), "--rig", str(captures["settings"]),
                     "-o", str(tmp_path / "x.png")],
                    ["export-ply", str(captures["color"]), str(captures["color"]), "--rig",
                     str(captures["settings"]), "-o", str(tmp_path / "x.ply")]):
        assert main(command) == 2
        err = capsys.readouterr().err
        assert "DEPTH and COLOR are the same file" in err and len(err.strip().splitlines()) == 1


def test_run_save_color_and_factor_options(captures, tmp_path, capsys):
    common = ["run", str(captures["depth"]), str(captures["color"]), "--rig", str(captures["settings"]),
              "--refine-method", "bilinear"]
    out, color = tmp_path / "refined.png", tmp_path / "color.png"
    assert main([*common, "-o", str(out), "--save-color", str(color), "--factor", "7.5"]) == 0, capsys.readouterr().err
    err = capsys.readouterr().err
    assert "s = 7.5" in err and "90x67 grid" in err
    assert read_depth(out).shape == (504, 672) and cv2.imread(str(color)).shape == (504, 672, 3)
    for bad, message in ((["--save-color", str(tmp_path / "c.bmp")], "unknown format '.bmp'"),
                         (["--factor", "0.5"], "expected a number >= 1")):
        assert main([*common, "-o", str(tmp_path / "x.png"), *bad]) == 2
        assert message in capsys.readouterr().err and not (tmp_path / "x.png").exists()


def test_run_tells_gbp_its_input_is_reprojected_unless_the_params_say_not(captures, tmp_path):
    """run makes gbp's unsaid ``reprojected`` True (GbpParams.reprojected), and records it; ``reprojected = false``
    in a parameter file stays false."""
    common = [str(captures["depth"]), str(captures["color"]), "--rig", str(captures["rig"]), "--depth-units", "0.001"]
    assert main(["run", *common, "-o", str(tmp_path / "told.npy"), "--save-settings", str(tmp_path / "told.json")]) == 0
    (tmp_path / "p.toml").write_text("reprojected = false\n")
    assert main(["run", *common, "-o", str(tmp_path / "not.npy"), "--params", str(tmp_path / "p.toml"),
                 "--save-settings", str(tmp_path / "not.json")]) == 0
    told, kept = (json.loads((tmp_path / f"{n}.json").read_text())["refine"]["params"] for n in ("told", "not"))
    assert told["reprojected"] is True and kept["reprojected"] is False
    assert not np.array_equal(np.load(tmp_path / "told.npy"), np.load(tmp_path / "not.npy"), equal_nan=True)
