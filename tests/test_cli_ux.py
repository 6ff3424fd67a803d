"""First contact (issue 12): `show`, `refine --preview`, `--output-scale`, one name per option, the demo's panels."""

from __future__ import annotations

import argparse

import cv2
import numpy as np
import pytest
import tifffile

import depthrefine
from depthrefine.bench.synthetic import make_scene
from depthrefine.cli import build_parser, main
from depthrefine.bench.demo import PEERS, demo_panels
from depthrefine.io import read_depth, scale_to_dtype

SCENE = make_scene((48, 64), 4, n_objects=2, seed=11, color_noise_std=3.0)


@pytest.fixture
def files(tmp_path):
    """The scene's depth as 8-bit PNG, 16-bit PNG, float TIFF (metres) and .npy, and its color PNG."""
    depth8 = tmp_path / "d8.png"
    assert cv2.imwrite(str(depth8), SCENE.depth_lr)
    depth16 = tmp_path / "d16.png"
    assert cv2.imwrite(str(depth16), SCENE.depth_lr.astype(np.uint16) * 40)
    metres = SCENE.depth_lr.astype(np.float32) / 100.0
    metres[0, :3] = np.nan
    tif = tmp_path / "m.tif"
    tifffile.imwrite(tif, metres)
    npy = tmp_path / "m.npy"
    np.save(npy, metres)
    color = tmp_path / "color.png"
    assert cv2.imwrite(str(color), cv2.cvtColor(SCENE.rgb_hr, cv2.COLOR_RGB2BGR))
    return {"8": depth8, "16": depth16, "tif": tif, "npy": npy, "color": color}


def _picture(path):
    picture = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    assert picture is not None and picture.ndim == 3 and picture.std() > 5
    return picture


@pytest.mark.parametrize("kind", ["8", "16", "tif", "npy"])
def test_show_any_depth_file(files, tmp_path, kind, capsys):
    out = tmp_path / f"show_{kind}.png"
    assert main(["show", str(files[kind]), str(files["color"]), "-o", str(out), "--units", "m"]) == 0
    _picture(out)
    assert str(out) in capsys.readouterr().err
    alone = tmp_path / f"alone_{kind}.png"
    assert main(["show", str(files[kind]), "-o", str(alone), "--range", "0.5,2"]) == 0
    assert _picture(alone).shape[1] < _picture(out).shape[1]    # one panel instead of two


def test_show_refuses_to_overwrite(files, tmp_path, capsys):
    out = tmp_path / "s.png"
    out.write_bytes(b"mine")
    assert main(["show", str(files["8"]), "-o", str(out)]) == 2
    assert "--overwrite" in capsys.readouterr().err and out.read_bytes() == b"mine"


def test_refine_preview_writes_the_picture_beside_the_result(files, tmp_path, capsys):
    out, preview = tmp_path / "out.png", tmp_path / "preview.png"
    assert main(["refine", str(files["8"]), str(files["color"]), "-o", str(out), "--method", "bilinear",
                 "--preview", str(preview), "--units", "levels"]) == 0
    assert out.is_file() and _picture(preview).shape[1] > SCENE.rgb_hr.shape[1]
    same = tmp_path / "same.png"
    assert main(["refine", str(files["8"]), str(files["color"]), "-o", str(same), "--preview", str(same)]) == 2
    assert "--preview" in capsys.readouterr().err and not same.exists()


def test_float_to_uint16_round_trip_within_half_a_unit(files, tmp_path):
    out = tmp_path / "mm.png"
    assert main(["refine", str(files["tif"]), str(files["color"]), "-o", str(out), "--method", "bilinear",
                 "--output-scale", "1000", "--output-dtype", "uint16"]) == 0
    stored = read_depth(out)
    assert stored.dtype == np.uint16
    metres = depthrefine.refine(tifffile.imread(files["tif"]), SCENE.rgb_hr, method="bilinear")
    valid = np.isfinite(metres)
    assert (stored[~valid] == 0).all()
    assert np.abs(stored[valid] / 1000.0 - metres[valid]).max() <= 0.5 / 1000 + 1e-7
    # The library function: same values, and its refusal to clip.
    np.testing.assert_array_equal(np.floor(scale_to_dtype(metres, 1000, np.uint16)[valid] + 0.5), stored[valid])


def test_output_scale_that_would_clip_is_an_error_and_writes_nothing(files, tmp_path, capsys):
    out = tmp_path / "clip.png"
    assert main(["refine", str(files["tif"]), str(files["color"]), "-o", str(out), "--method", "bilinear",
                 "--output-scale", "1e6", "--output-dtype", "uint16"]) == 2
    err = capsys.readouterr().err
    assert "--output-scale 1e+06" in err and "clip" in err and "65535" in err and not out.exists()
    assert main(["refine", str(files["tif"]), str(files["color"]), "-o", str(out), "--method", "bilinear",
                 "--output-dtype", "uint8"]) == 2        # metres below 0.5 would round to 0, "no measurement"
    assert "rounds to 0" in capsys.readouterr().err and not out.exists()
    with pytest.raises(ValueError, match="positive"):
        scale_to_dtype(np.ones((2, 2), np.float32), -1.0, np.uint16)


def test_float_png_error_names_the_option(files, tmp_path, capsys):
    assert main(["refine", str(files["tif"]), str(files["color"]), "-o", str(tmp_path / "f.png")]) == 2
    err = capsys.readouterr().err
    assert "--output-scale 1000 --output-dtype uint16" in err and ".tif" in err


def _parse(argv):
    return build_parser().parse_args(argv)


RUN = ["run", "d.png", "c.png", "--rig", "rig.json", "-o", "o.png"]


def test_run_method_is_the_alignment_method_and_refine_method_the_refinement(capsys):
    args = _parse(RUN + ["--method", "shift", "--refine-method", "bilinear", "--stride", "3"])
    assert (args.align_method, args.method, args.stride) == ("shift", "bilinear", 3)
    assert capsys.readouterr().err == ""
    args = _parse(RUN)
    assert (args.align_method, args.method, args.stride) == (None, None, 1)   # the settings file decides
    text = build_parser()._subparsers._group_actions[0].choices["run"].format_help()
    assert "--refine-method" in text and "alignment method" in text and "--stride" in text
    assert "--align " not in text and "--ply-stride" not in text            # old spellings are hidden


@pytest.mark.parametrize("old, new, field, value", [
    (["--align", "shift"], "--method", "align_method", "shift"),
    (["--ply-stride", "4"], "--stride", "stride", 4),
    (["--method", "bilinear"], "--refine-method", "method", "bilinear"),    # run --method NAME, the old meaning
])
def test_old_run_spellings_still_work_with_a_note(capsys, old, new, field, value):
    args = _parse(RUN + old)
    assert getattr(args, field) == value
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "deprecated" in err[0] and new in err[0]


def test_run_method_rejects_other_names(capsys):
    with pytest.raises(SystemExit):
        _parse(RUN + ["--method", "magic"])
    err = capsys.readouterr().err
    assert "'magic'" in err and "reproject" in err and "--refine-method" in err


def test_patches_are_columns_first_in_every_command():
    for command in (["refine", "d.png", "c.png", "-o", "o.png"], RUN):
        args = _parse(command + ["--patches", "6x4"])
        assert args.patches == (6, 4)
    params = depthrefine.ThesisParams(patches=(6, 4))
    assert params.patches == (6, 4)    # (across, down), as --board
    text = build_parser()._subparsers._group_actions[0].choices["refine"].format_help()
    assert "COLSxROWS" in text and "columns first" in text
    with pytest.raises(argparse.ArgumentTypeError, match="COLSxROWS"):
        from depthrefine.cli._common import parse_grid
        parse_grid("4by4")


def test_demo_panels_pick_the_best_peer_and_name_the_default():
    depth = np.zeros((4, 4), np.float32)
    results = {name: depth for name in ("nearest", "bilinear", *PEERS, "thesis", "other", "ground truth")}
    scores = {"nearest": 9.0, "bilinear": 7.0, "jbf": 5.6, "guided": 6.5, "fgs": 5.0, "wmf": 5.4, "thesis": 15.0,
              "other": 4.0}
    panels, best = demo_panels(results, scores, scale=8, default="thesis")
    assert best == "fgs"
    assert [t for t, _ in panels] == ["input ×8 (nearest)\nRMSE 9.00", "bilinear\nRMSE 7.00",
                                      "best peer: fgs\nRMSE 5.00", "thesis method (the default)\nRMSE 15.00",
                                      "ground truth"]
    panels, _ = demo_panels(results, scores, scale=8, default="other")
    assert [t for t, _ in panels][3:5] == ["thesis method\nRMSE 15.00", "other (the default method)\nRMSE 4.00"]
    assert depthrefine.refine.__kwdefaults__["method"] == depthrefine.methods.registry.DEFAULT_METHOD


# ----------------------------------------------------------------------------
# Issue 24: pictures at a chosen crop and scale; DEPTH and COLOR must differ
# ----------------------------------------------------------------------------


def _size(path) -> tuple[int, int]:
    rows, cols = _picture(path).shape[:2]
    return cols, rows


def test_show_crop_and_scale_place_the_pixels_exactly(files, tmp_path, capsys):
    """--crop X,Y,W,H at --scale F: each panel is W*F x H*F pixels holding the window's pixels (nearest)."""
    out = tmp_path / "crop.png"
    assert main(["show", str(files["16"]), "-o", str(out), "--crop", "2,3,8,5", "--scale", "10",
                 "--range", "0,20000"]) == 0, capsys.readouterr().err
    picture = cv2.cvtColor(_picture(out), cv2.COLOR_BGR2RGB)
    from depthrefine.viz import colorize_depth

    window = read_depth(files["16"]).astype(np.float32)[3:8, 2:10]
    colors = colorize_depth(window, limits=(0, 20000))
    # find the 80 x 50 panel: its top-left pixel block has the window's first color
    rows, cols = np.nonzero(np.all(np.abs(picture.astype(int) - colors[0, 0]) <= 2, axis=2))
    top, left = rows.min(), cols.min()
    panel = picture[top:top + 50, left:left + 80].astype(int)
    assert panel.shape == (50, 80, 3)
    block_means = panel.reshape(5, 10, 8, 10, 3).mean(axis=(1, 3))
    assert np.abs(block_means - colors).max() <= 2  # matplotlib's viridis vs OpenCV's: within 2 levels
    full = tmp_path / "full.png"
    assert main(["show", str(files["16"]), str(files["color"]), "-o", str(full), "--full"]) == 0
    cropped = tmp_path / "cropped.png"
    assert main(["show", str(files["16"]), str(files["color"]), "-o", str(cropped), "--crop", "0,0,8,6"]) == 0
    # --full: the color grid (64x48) at its own resolution, twice (color and depth) plus margins
    assert 2 * 64 < _size(full)[0] < 2 * 64 + 200 and 48 < _size(full)[1] < 48 + 100
    # --crop alone enlarges a 32x24 color window (8x6 depth pixels) by a whole factor, at most 16
    assert 2 * 32 * 16 < _size(cropped)[0] < 2 * 32 * 16 + 200


def test_picture_options_errors_are_one_line(files, tmp_path, capsys):
    out = tmp_path / "x.png"
    cases = [
        (["show", str(files["8"]), "-o", str(out), "--crop", "60,0,10,10"], "must lie inside the 16x12 depth map"),
        (["show", str(files["8"]), "-o", str(out), "--crop", "1,2,3"], "X,Y,WIDTH,HEIGHT"),
        (["show", str(files["8"]), "-o", str(out), "--scale", "0"], "0 < F <= 64"),
        (["show", str(files["8"]), "-o", str(out), "--scale", "2", "--full"], "not allowed with argument"),
        (["refine", str(files["8"]), str(files["color"]), "-o", str(tmp_path / "r.png"), "--full"],
         "add --preview PNG"),
        (["refine", str(files["8"]), str(files["color"]), "-o", str(tmp_path / "r.png"), "--preview", str(out),
          "--crop", "0,0,100,10"], "--crop 0,0,100,10"),
    ]
    for args, message in cases:
        assert main(args) == 2, args
        err = capsys.readouterr().err
        assert message in err and len(err.strip().splitlines()) == 1, err
    assert not out.exists() and not (tmp_path / "r.png").exists()


def test_refine_preview_crop(files, tmp_path, capsys):
    out, preview = tmp_path / "r.png", tmp_path / "p.png"
    assert main(["refine", str(files["8"]), str(files["color"]), "-o", str(out), "--preview", str(preview),
                 "--crop", "16,8,32,24", "--scale", "4"]) == 0, capsys.readouterr().err
    cols, rows = _size(preview)
    assert 2 * 128 < cols < 2 * 128 + 200 and 96 < rows < 96 + 100


def test_the_same_file_as_depth_and_color_is_refused(files, tmp_path, capsys):
    copy = tmp_path / "copy.png"
    copy.write_bytes(files["color"].read_bytes())
    for depth, color, message in ((files["color"], files["color"], "are the same file"),
                                  (copy, files["color"], "identical bytes")):
        for command in (["refine", str(depth), str(color), "-o", str(tmp_path / "r.png")],
                        ["show", str(depth), str(color), "-o", str(tmp_path / "s.png")]):
            assert main(command) == 2
            err = capsys.readouterr().err
            assert message in err and len(err.strip().splitlines()) == 1, err
    assert not (tmp_path / "r.png").exists() and not (tmp_path / "s.png").exists()
