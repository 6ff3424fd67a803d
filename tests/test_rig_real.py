"""The rig chain on real captures: ChArUco calibration, factory calibrations, the Azure Kinect mug, printable boards.

Data: the Azure Kinect ChArUco views of ``../shared/data/real_tof/azure_kinect_charuco`` (skipped
without ``../shared``), and the mug and bookshelf captures shipped in the package (byte-exact
copies of ``real_tof/azure_kinect_mug`` and ``real_tof/iphone_lidar_bookshelf``), so the chain
tests run everywhere.

Edge-overlap thresholds (``depthrefine.rig.edges.edge_overlap``, mug outline: nearer than
600 mm next to farther than 1000 mm, against Canny edges of the color image), measured with
the factory calibration: the reprojected depth (on a 1056x594 grid at the depth camera's
resolution, spread over the color grid) has 38 % of its outline within 2 px of a color edge
(median 3.0 px), the refined depth (upsampled x2) a median of 3.0 px. With the extrinsics inverted
(the wrong direction) the reprojected outline has 5 % within 2 px (median 27 px), without
extrinsics 2 % (25 px). The tests ask for at least 25 % and a median of at most 4 px for the
reprojection, at most 8 px for the refined map (whose outline also depends on the method), and
a median over 15 px for the inverted rig.
"""

from __future__ import annotations

import hashlib
import json
import re
from pathlib import Path

import cv2
import numpy as np
import pytest

from conftest import shared_data_path
from depthrefine.cli import main
from depthrefine.io import (DATASETS, file_sha256, load_capture, read_calibration, read_depth, read_ply, read_rgb,
                            read_rig, sample_folder)
from depthrefine.rig import Board, StereoRig, calibrate_from_views, detect_board
from depthrefine.rig.chain import BORDER_BAND, AlignSettings, align_pair, nearest_on_grid
from depthrefine.rig.edges import edge_overlap

CHARUCO = Board.charuco((14, 9), 0.04, 0.03, "DICT_5X5_250")
MUG_FIGURES = {"depth": (504.608, 504.733, 332.781, 348.830), "color": (611.795, 611.927, 639.304, 365.853)}
NEAR, FAR = 600.0, 1000.0


def _intrinsics(camera) -> tuple[float, float, float, float]:
    return camera.K[0, 0], camera.K[1, 1], camera.K[0, 2], camera.K[1, 2]


# ----------------------------------------------------------------------------
# ChArUco calibration on the eight real views
# ----------------------------------------------------------------------------


def test_charuco_calibration_matches_the_upstream_fit_on_30_views():
    folder = shared_data_path("real_tof", "azure_kinect_charuco", "calibration")
    reference, kind = read_calibration(folder / "calib.yml")  # OpenCV FileStorage YAML import
    assert kind == "opencv" and reference.image_size == (4096, 3072) and reference.dist.size == 8
    views = [detect_board(read_rgb(path), CHARUCO) for path in sorted(folder.glob("color-*.jpg"))]
    assert len(views) == 8 and all(v.count >= 60 for v in views)  # partial views: 62..104 of 104 corners
    assert min(v.count for v in views) < 104
    for rational in (False, True):
        camera = calibrate_from_views(views, board=CHARUCO, image_size=(4096, 3072), rational=rational)
        fx, fy, cx, cy = _intrinsics(camera)
        rfx, rfy, rcx, rcy = _intrinsics(reference)
        assert abs(fx / rfx - 1) < 0.005 and abs(fy / rfy - 1) < 0.005, (fx, fy, rational)
        assert abs(cx - rcx) < 5 and abs(cy - rcy) < 5, (cx, cy, rational)
        assert camera.rms < 0.8


def test_calibrate_cli_on_real_charuco_views(tmp_path, capsys):
    folder = shared_data_path("real_tof", "azure_kinect_charuco", "calibration")
    images = [str(p) for p in sorted(folder.glob("color-1*.jpg"))]  # 5 of the 8 views, for speed
    out = tmp_path / "color.json"
    args = ["calibrate", *images, "--board", "charuco:14x9", "--square", "40mm", "--marker", "30mm",
            "--dictionary", "DICT_5X5_250", "-o", str(out)]
    assert main(args) == 0, capsys.readouterr().err
    capsys.readouterr()
    data = json.loads(out.read_text())
    assert data["board"]["dictionary"] == "DICT_5X5_250" and len(data["corners_used"]) == 5
    assert abs(data["K"][0][0] / 1960.95 - 1) < 0.01
    # the board spec does not match the images: the error says what was found, in one line
    wrong = ["calibrate", *images[:3], "--board", "charuco:10x7", "--square", "40mm", "--marker", "30mm",
             "-o", str(tmp_path / "x.json")]
    assert main(wrong) == 2
    err = capsys.readouterr().err
    assert "ChArUco corners found per image: 0, 0, 0" in err and "markers were decoded" in err
    assert len(err.strip().splitlines()) == 1 and not (tmp_path / "x.json").exists()


# ----------------------------------------------------------------------------
# Factory calibrations in
# ----------------------------------------------------------------------------


def test_shipped_captures_are_the_benchmark_files():
    """The shipped captures have the bytes of the data sets' files (the catalog's SHA-256 of the shared copies)."""
    pairs = [("mug", "depth.png", "azure_kinect_mug", "derived/depth_640x576_mm.png"),
             ("mug", "color.jpg", "azure_kinect_mug", "derived/color_1280x720.jpg"),
             ("mug", "calibration.json", "azure_kinect_mug", "calibration.json"),
             ("mug", "LICENSE", "azure_kinect_mug", "LICENSE.pyk4a-MIT.txt"),
             ("bookshelf", "depth.png", "iphone_lidar_bookshelf", "arkit_depth.png"),
             ("bookshelf", "color.jpg", "iphone_lidar_bookshelf", "image.jpg"),
             ("bookshelf", "LICENSE", "iphone_lidar_bookshelf", "LICENSE.PromptDA-Apache-2.0.txt")]
    for scene, name, dataset, source in pairs:
        assert file_sha256(sample_folder(scene) / name) == DATASETS[dataset].checksums[source], name
    art = DATASETS["middlebury2005_park"].checksums
    for name in ("color.png", "gt_disp.png", "noisy_x4.png", "noisy_x8.png", "noisy_x16.png"):
        assert file_sha256(sample_folder("art") / name) == art[f"art/{name}"], name


def test_shipped_checksums():
    for scene in ("mug", "bookshelf"):
        folder = sample_folder(scene)
        for line in (folder / "SHA256SUMS").read_text().splitlines():
            digest, name = line.split()
            assert hashlib.sha256((folder / name).read_bytes()).hexdigest() == digest, name


def test_rig_import_k4a_gives_the_factory_figures(tmp_path, capsys):
    out = tmp_path / "rig.json"
    code = main(["rig", "import", str(sample_folder("mug") / "calibration.json"), "--depth-mode", "NFOV_UNBINNED",
                 "--color-resolution", "720P", "-o", str(out)])
    assert code == 0, capsys.readouterr().err
    rig = read_rig(out)
    for name, camera in (("depth", rig.depth_camera), ("color", rig.color_camera)):
        assert np.abs(np.array(_intrinsics(camera)) - MUG_FIGURES[name]).max() < 0.01, name
    assert rig.depth_camera.image_size == (640, 576) and rig.color_camera.image_size == (1280, 720)
    assert rig.depth_camera.dist.size == 8
    # depth -> color: the color camera sits 32 mm along the depth camera's +x axis, turned about 5 degrees
    assert np.allclose(rig.t, [-0.032083, -0.002205, 0.003884], atol=1e-6) and 0.031 < rig.color_centre[0] < 0.033
    assert 4.5 < rig.rotation_degrees < 5.5
    data = json.loads(out.read_text())
    assert data["depth_mode"] == "NFOV_UNBINNED" and data["imported_from"] == "calibration.json"
    # the binned mode halves the focal length and follows the SDK's crop
    binned, _ = read_calibration(sample_folder("mug") / "calibration.json", depth_mode="nfov_2x2binned",
                                 color_resolution="3072P")
    assert binned.depth_camera.image_size == (320, 288) and binned.color_camera.image_size == (4096, 3072)
    assert abs(binned.depth_camera.K[0, 0] - 504.608 / 2) < 0.01


def test_rig_import_opencv_and_ros_yaml(tmp_path, capsys):
    ros = tmp_path / "camera_info.yaml"
    ros.write_text("image_width: 640\nimage_height: 480\ncamera_name: tof\ncamera_matrix:\n  rows: 3\n  cols: 3\n"
                   "  data: [504.6, 0, 332.8, 0, 504.7, 348.8, 0, 0, 1]\ndistortion_model: plumb_bob\n"
                   "distortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [0.1, -0.2, 0.001, 0.002, 0]\n")
    message = tmp_path / "info_msg.yaml"  # `ros2 topic echo --once` output
    message.write_text("header:\n  stamp:\n    sec: 1\n    nanosec: 2\n  frame_id: tof\nheight: 480\nwidth: 640\n"
                       "distortion_model: rational_polynomial\nd: [0.1, -0.2, 0.001, 0.002, 0.0, 0.01, 0.0, 0.0]\n"
                       "k: [504.6, 0.0, 332.8, 0.0, 504.7, 348.8, 0.0, 0.0, 1.0]\n---\n")
    for path, n_dist in ((ros, 5), (message, 8)):
        out = tmp_path / f"{path.stem}.json"
        assert main(["rig", "import", str(path), "-o", str(out)]) == 0, capsys.readouterr().err
        data = json.loads(out.read_text())
        assert data["K"][0] == [504.6, 0.0, 332.8] and data["image_size"] == [640, 480]
        assert len(data["dist"]) == n_dist and "ROS" in data["format"]
    assert "wrote camera file" in capsys.readouterr().err
    opencv = tmp_path / "calib.yml"
    opencv.write_text("%YAML:1.0\n---\nK: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                      "   data: [ 1960.9, 0., 2053.1, 0., 1960.9, 1556.2, 0., 0., 1. ]\n"
                      "dist: !!opencv-matrix\n   rows: 5\n   cols: 1\n   dt: d\n   data: [ 0.1, 0., 0., 0., 0. ]\n"
                      "img_size: !!opencv-matrix\n   rows: 2\n   cols: 1\n   dt: i\n   data: [ 4096, 3072 ]\n")
    camera, kind = read_calibration(opencv)
    assert kind == "opencv" and camera.image_size == (4096, 3072) and camera.K[1, 2] == 1556.2


def _k4a(tmp_path: Path, edit) -> Path:
    data = json.loads((sample_folder("mug") / "calibration.json").read_text())
    edit(data["CalibrationInformation"]["Cameras"])
    path = tmp_path / "calibration.json"
    path.write_text(json.dumps(data))
    return path


@pytest.mark.parametrize("case, args, message", [
    ("no mode", [], "give --depth-mode"),
    ("unknown mode", ["--depth-mode", "NFOV", "--color-resolution", "720P"], "unknown depth mode 'NFOV'"),
    ("unknown resolution", ["--depth-mode", "NFOV_UNBINNED", "--color-resolution", "480P"],
     "unknown color resolution '480P'"),
    ("no color camera", ["--depth-mode", "NFOV_UNBINNED", "--color-resolution", "720P"], "has no color camera"),
    ("depth sensor not 1024", ["--depth-mode", "WFOV_UNBINNED", "--color-resolution", "720P"],
     "not the 1024x1024 the Azure Kinect SDK needs for depth mode WFOV_UNBINNED"),
    ("color not 4:3", ["--depth-mode", "NFOV_UNBINNED", "--color-resolution", "1080P"], "neither 4:3 nor 16:9"),
])
def test_rig_import_k4a_errors(tmp_path, capsys, case, args, message):
    edits = {
        "no color camera": lambda cams: cams.pop(1),
        "depth sensor not 1024": lambda cams: cams[0].update(SensorWidth=512, SensorHeight=512),
        "color not 4:3": lambda cams: cams[1].update(SensorWidth=4096, SensorHeight=4096),
    }
    path = _k4a(tmp_path, edits.get(case, lambda cams: None))
    out = tmp_path / "rig.json"
    assert main(["rig", "import", str(path), "-o", str(out), *args]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert not out.exists()


def test_rig_import_refuses_files_of_the_wrong_kind(tmp_path, capsys):
    rig_file = tmp_path / "mine.json"
    assert main(["rig", "import", str(sample_folder("mug") / "calibration.json"), "--depth-mode", "NFOV_UNBINNED",
                 "--color-resolution", "720P", "-o", str(rig_file)]) == 0
    capsys.readouterr()
    fisheye = tmp_path / "fisheye.yaml"
    fisheye.write_text("width: 640\nheight: 480\ndistortion_model: equidistant\nd: [0.1, 0, 0, 0]\n"
                       "k: [500, 0, 320, 0, 500, 240, 0, 0, 1]\n")
    for path, message in ((rig_file, "depthrefine rig or camera file already"),
                          (sample_folder("mug") / "depth.png", "is not a text file"),
                          (fisheye, "distortion_model 'equidistant' is not supported")):
        assert main(["rig", "import", str(path), "-o", str(tmp_path / "out.json")]) == 2
        err = capsys.readouterr().err
        assert message in err and len(err.strip().splitlines()) == 1, err
    assert main(["rig", "import", str(sample_folder("mug") / "calibration.json"), "--depth-mode", "NFOV_UNBINNED",
                 "--color-resolution", "720P", "-o", str(rig_file)]) == 2  # no --overwrite
    assert "exists; pass --overwrite" in capsys.readouterr().err


# ----------------------------------------------------------------------------
# The chain on the real Azure Kinect capture
# ----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def mug_run(tmp_path_factory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("mug")
    scene = sample_folder("mug")
    rig = folder / "rig.json"
    assert main(["rig", "import", str(scene / "calibration.json"), "--depth-mode", "NFOV_UNBINNED",
                 "--color-resolution", "720P", "-o", str(rig)]) == 0
    out = {"rig": rig, "refined": folder / "refined.png", "aligned": folder / "aligned.png",
           "ply": folder / "cloud.ply", "filled": folder / "filled.png", "color": folder / "color.png",
           "float": folder / "refined.npy"}
    assert main(["run", str(scene / "depth.png"), str(scene / "color.jpg"), "--rig", str(rig), "--depth-units",
                 "0.001", "-o", str(out["refined"]), "--ply", str(out["ply"]), "--save-aligned",
                 str(out["aligned"]), "--save-color", str(out["color"])]) == 0
    settings = folder / "settings.json"
    assert main(["run", str(scene / "depth.png"), str(scene / "color.jpg"), "--rig", str(rig), "--depth-units",
                 "0.001", "-o", str(out["filled"]), "--fill-holes", "--save-settings", str(settings)]) == 0
    assert json.loads(settings.read_text())["refine"]["fill_holes"] is True
    out["settings"] = settings
    return out


def test_mug_chain_gives_a_1280x720_millimetre_map_lined_up_with_the_color(mug_run):
    capture = load_capture("mug")
    refined = read_depth(mug_run["refined"])
    aligned = read_depth(mug_run["aligned"])
    # the depth camera's resolution (focal ratio 1.21: 1280x720 / 1.21), upsampled by the method
    assert refined.shape == (720, 1280) and refined.dtype == np.uint16 and aligned.shape == (594, 1056)
    mug = refined[450:600, 300:450]  # the mug's body, at about 256 mm
    assert 220 < np.median(mug[mug > 0]) < 300
    rgb = align_pair(capture.depth, capture.rgb, read_rig(mug_run["rig"]),
                     settings=AlignSettings(depth_units=0.001)).rgb_hr
    assert np.array_equal(read_rgb(mug_run["color"]), rgb)  # --save-color: the grid the result lies on
    fit = edge_overlap(nearest_on_grid(aligned, rgb.shape[:2]), rgb, near=NEAR, far=FAR)
    assert fit.pixels > 200 and fit.fraction >= 0.25 and fit.median_px <= 4.0, fit
    fit_refined = edge_overlap(refined.astype(np.float32), rgb, near=NEAR, far=FAR)
    assert fit_refined.median_px <= 8.0, fit_refined


def test_mug_extrinsics_direction(mug_run):
    """The factory Rt maps depth to color: used the other way round, the outline misses the color edges."""
    capture = load_capture("mug")
    rig = read_rig(mug_run["rig"])
    inverted = StereoRig(rig.depth_camera, rig.color_camera, rig.R.T, -rig.R.T @ rig.t)
    pair = align_pair(capture.depth, capture.rgb, inverted, settings=AlignSettings(depth_units=0.001))
    fit = edge_overlap(nearest_on_grid(pair.depth_lr, pair.rgb_hr.shape[:2]), pair.rgb_hr, near=NEAR, far=FAR)
    assert fit.median_px > 15, fit


def test_mug_unmeasured_pixels_stay_invalid_unless_fill_holes(mug_run):
    refined = read_depth(mug_run["refined"])
    aligned = read_depth(mug_run["aligned"])
    filled = read_depth(mug_run["filled"])
    # outside the NFOV hexagon (the color image's corners and left/right edges) nothing was measured
    for corner in (refined[:40, :40], refined[:40, -40:], refined[-40:, -40:], refined[300:400, :60]):
        assert (corner == 0).all()
    # the aligned depth's holes, their border moved onto the color edges by at most BORDER_BAND depth pixels
    grid_holes = nearest_on_grid(aligned, refined.shape) == 0
    moved = (refined == 0) != grid_holes
    border = cv2.distanceTransform((~grid_holes).astype(np.uint8), cv2.DIST_L2, 5)
    border = np.where(grid_holes, cv2.distanceTransform(grid_holes.astype(np.uint8), cv2.DIST_L2, 5), border)
    per_pixel = refined.shape[1] / aligned.shape[1]
    assert moved.any() and (border[moved] <= BORDER_BAND * per_pixel + 1).all()
    assert moved.mean() < 0.02
    assert 0.40 < (refined == 0).mean() < 0.50
    # --fill-holes: the holes inside a measured surface get the refinement's depth, what lies beyond any
    # measurement (outside the hexagon) stays unmeasured
    assert (filled == 0).mean() < (refined == 0).mean() - 0.01
    for corner in (filled[:40, :40], filled[:40, -40:], filled[-40:, -40:], filled[300:400, :60]):
        assert (corner == 0).all()
    again = mug_run["filled"].with_name("again.png")  # fill_holes = true read back from the settings file
    scene = sample_folder("mug")
    assert main(["run", str(scene / "depth.png"), str(scene / "color.jpg"), "--rig", str(mug_run["settings"]),
                 "-o", str(again)]) == 0
    assert again.read_bytes() == mug_run["filled"].read_bytes()
    both = (refined > 0)
    # the same depth where both are measured, but where the border took a pixel: its depth is copied from the
    # measured pixel the color joins it to, and with --fill-holes that may be a filled one
    on_grid = both & ~grid_holes & (filled > 0)
    assert np.array_equal(filled[on_grid], refined[on_grid])
    assert np.mean(filled[both] == refined[both]) > 0.99
    # --fill-holes adds depth; the border's side of a pixel depends on the pixels around it, which it changes too
    # (on the mug, 1-2 pixels of about 510 000 are measured without it and not with it)
    assert np.count_nonzero(filled[both] == 0) <= 1e-4 * both.sum()
    points, colors = read_ply(mug_run["ply"])
    assert points.shape[0] == int(both.sum()) and colors.shape == (points.shape[0], 3)
    assert 0.2 < np.median(points[:, 2]) < 2.5  # metres
    # The point cloud is made from the float result: no 1 mm terraces (depths between whole millimetres).
    assert np.mean(np.abs(points[:, 2] * 1000 - np.round(points[:, 2] * 1000)) > 0.01) > 0.5


def test_mug_run_writes_float_or_finer_integer_depth(mug_run, tmp_path):
    """The refined depth keeps its fractions of a millimetre as float32 (.npy/.tif) or as 0.1 mm uint16."""
    scene = sample_folder("mug")
    common = [str(scene / "depth.png"), str(scene / "color.jpg"), "--rig", str(mug_run["rig"]), "--depth-units",
              "0.001", "--refine-method", "bilinear"]
    tenth = tmp_path / "tenth.png"
    assert main(["run", *common, "-o", str(mug_run["float"]), "--output-dtype", "float32"]) == 0
    assert main(["run", *common, "-o", str(tenth), "--output-scale", "10", "--output-dtype", "uint16"]) == 0
    depth = np.load(mug_run["float"])
    assert depth.dtype == np.float32 and depth.shape == (720, 1280)
    valid = depth > 0
    assert np.mean(np.abs(depth[valid] - np.round(depth[valid])) > 0.01) > 0.5  # not whole millimetres
    tenths = read_depth(tenth)
    assert tenths.dtype == np.uint16 and np.array_equal(tenths > 0, valid)
    assert np.abs(tenths[valid] - depth[valid].astype(np.float64) * 10).max() <= 0.5 + 1e-3  # 0.1 mm steps


# ----------------------------------------------------------------------------
# Printable boards, demos
# ----------------------------------------------------------------------------


def test_board_png_is_detected_at_its_dpi(tmp_path, capsys):
    out = tmp_path / "board.png"
    assert main(["board", "--board", "charuco:5x7", "--square", "30mm", "--marker", "22mm", "--dpi", "100",
                 "-o", str(out)]) == 0
    assert "one square prints 29.97 mm" in capsys.readouterr().err  # 30 mm at 100 dpi: 118 px = 29.97 mm
    from PIL import Image

    with Image.open(out) as img:
        assert tuple(round(v) for v in img.info["dpi"]) == (100, 100)
    image = read_rgb(out)
    found = detect_board(image, Board.charuco((5, 7), 0.03, 0.022))
    assert found.count == 24
    checker = tmp_path / "checker.png"
    assert main(["board", "--board", "9x6", "--square", "25mm", "--dpi", "150", "-o", str(checker)]) == 0
    assert detect_board(read_rgb(checker), Board.checkerboard((9, 6), 0.025)).count == 54


def test_board_pdf_true_size_on_a4_and_letter(tmp_path, capsys):
    out = tmp_path / "board.pdf"
    assert main(["board", "--board", "9x6", "--square", "25mm", "-o", str(out)]) == 0
    box = [float(v) for v in re.search(rb"MediaBox \[ *([\d. ]+)\]", out.read_bytes()).group(1).split()]
    assert np.allclose(box[2:], [297 / 25.4 * 72, 210 / 25.4 * 72], atol=0.5)  # A4 landscape, in points
    letter = tmp_path / "letter.pdf"
    assert main(["board", "--board", "charuco:5x7", "--square", "30mm", "--marker", "22mm", "--paper", "Letter",
                 "-o", str(letter)]) == 0
    box = [float(v) for v in re.search(rb"MediaBox \[ *([\d. ]+)\]", letter.read_bytes()).group(1).split()]
    assert np.allclose(box[2:], [612, 792], atol=0.5)  # Letter portrait
    capsys.readouterr()
    too_big = tmp_path / "big.pdf"
    assert main(["board", "--board", "charuco:14x9", "--square", "40mm", "--marker", "30mm", "-o", str(too_big)]) == 2
    err = capsys.readouterr().err
    assert "560 x 360 mm; it does not fit on A4" in err and not too_big.exists()
    for args, message in ((["--board", "9x6", "--square", "25mm", "-o", str(tmp_path / "b.jpg")], "write the board as .pdf"),
                          (["--board", "charuco:5x7", "--square", "30mm", "-o", str(tmp_path / "b.pdf")], "needs --marker"),
                          (["--board", "charuco:5x7", "--square", "30mm", "--marker", "22mm", "--dictionary", "DICT_9X9",
                            "-o", str(tmp_path / "b.pdf")], "unknown ArUco dictionary 'DICT_9X9'")):
        assert main(["board", *args]) == 2
        assert message in capsys.readouterr().err


def test_demo_mug(tmp_path, capsys):
    out = tmp_path / "demo"
    assert main(["demo", "--scene", "mug", "-o", str(out)]) == 0, capsys.readouterr().err
    record = json.loads((out / "demo.json").read_text())
    assert record["scene"] == "mug" and "pyk4a" in record["citation"]
    assert record["edge_overlap"]["aligned"]["fraction_within_2px"] >= 0.25
    assert 40 < record["unmeasured_percent"] < 50
    for name in ("demo_figure.png", "edges.png", "refined.png", "aligned.png", "rig.json", "cloud.ply"):
        assert (out / name).stat().st_size > 0, name
    assert read_depth(out / "refined.png").shape == (720, 1280)


def test_demo_bookshelf(tmp_path, capsys):
    out = tmp_path / "demo"
    assert main(["demo", "--scene", "bookshelf", "-o", str(out)]) == 0, capsys.readouterr().err
    record = json.loads((out / "demo.json").read_text())
    scores = record["self_benchmark"]["rmse_mm"]
    assert set(scores) >= {"nearest", "bilinear"} and all(0 < v < 500 for v in scores.values())
    # point samples at the library's place, gbp told so (issue 20): ahead of interpolation (32.2 / 35.6 mm)
    assert scores["gbp"] < 0.95 * scores["bilinear"] < scores["nearest"], scores
    assert read_depth(out / "refined.png").shape == (1440, 1920)
