"""``depthrefine refine`` end to end on temporary files."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import cv2
import numpy as np
import pytest
import tifffile

import depthrefine
from depthrefine import METHODS, ThesisParams
from depthrefine.cli import main
from depthrefine.io import depth_to_dtype
from depthrefine.bench.synthetic import make_scene

SCENE = make_scene((64, 96), 4, n_objects=2, seed=5, color_noise_std=4.0, hole_fraction=0.03)


def write_color(path, rgb):
    assert cv2.imwrite(str(path), cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR))
    return path


@pytest.fixture
def files(tmp_path):
    """An 8-bit depth PNG and a color PNG of SCENE."""
    depth = tmp_path / "depth.png"
    assert cv2.imwrite(str(depth), SCENE.depth_lr)
    color = write_color(tmp_path / "color.png", SCENE.rgb_hr)
    return depth, color


def expected(depth_lr, rgb=SCENE.rgb_hr, **kwargs):
    """What the library gives, in the input's dtype as the CLI writes it."""
    return depth_to_dtype(depthrefine.refine(depth_lr, rgb, **kwargs), depth_lr.dtype)


def test_8bit_png_in_8bit_png_out(files, tmp_path, capsys):
    depth, color = files
    out = tmp_path / "out.png"
    assert main(["refine", str(depth), str(color), "-o", str(out)]) == 0
    result = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)
    assert result.dtype == np.uint8 and result.shape == SCENE.rgb_hr.shape[:2]
    np.testing.assert_array_equal(result, expected(SCENE.depth_lr))
    assert f"wrote {out}" in capsys.readouterr().err


def test_16bit_png_in_16bit_png_out(tmp_path):
    scene = make_scene((64, 96), 4, n_objects=2, seed=5, dtype=np.uint16)
    depth = tmp_path / "depth16.png"
    assert cv2.imwrite(str(depth), scene.depth_lr)
    color = write_color(tmp_path / "color.png", scene.rgb_hr)
    out = tmp_path / "out16.png"
    assert main(["refine", str(depth), str(color), "-o", str(out)]) == 0
    result = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)
    assert result.dtype == np.uint16 and result.shape == (64, 96)
    np.testing.assert_array_equal(result, expected(scene.depth_lr, scene.rgb_hr))
    assert result.max() > 255


def test_float32_tiff_in_float32_tiff_out(tmp_path):
    scene = make_scene((64, 96), 4, n_objects=2, seed=5, dtype=np.float32, hole_fraction=0.05)
    depth = tmp_path / "depth.tif"
    tifffile.imwrite(depth, np.nan_to_num(scene.depth_lr, nan=0.0))     # 0 = no measurement in a file
    color = write_color(tmp_path / "color.png", scene.rgb_hr)
    out = tmp_path / "out.tif"
    assert main(["refine", str(depth), str(color), "-o", str(out)]) == 0
    result = tifffile.imread(out)
    assert result.dtype == np.float32 and result.shape == (64, 96)
    np.testing.assert_array_equal(result, depthrefine.refine(scene.depth_lr, scene.rgb_hr))


@pytest.mark.parametrize("dtype", [np.float32, np.uint16])
def test_npy_in_npy_out(tmp_path, dtype):
    scene = make_scene((64, 96), 4, n_objects=2, seed=5, dtype=dtype)
    depth = tmp_path / "depth.npy"
    np.save(depth, scene.depth_lr)
    color = write_color(tmp_path / "color.png", scene.rgb_hr)
    out = tmp_path / "out.npy"
    assert main(["refine", str(depth), str(color), "-o", str(out)]) == 0
    result = np.load(out)
    assert result.dtype == dtype and result.shape == (64, 96)
    np.testing.assert_array_equal(result, expected(scene.depth_lr, scene.rgb_hr))


@pytest.mark.parametrize("method", sorted(METHODS))
def test_every_registered_method(files, tmp_path, method):
    depth, color = files
    out = tmp_path / f"{method}.png"
    assert main(["refine", str(depth), str(color), "-o", str(out), "--method", method]) == 0
    result = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)
    assert result.shape == (64, 96) and result.dtype == np.uint8
    if method in ("thesis", "nearest", "bilinear", "bicubic"):
        np.testing.assert_array_equal(result, expected(SCENE.depth_lr, method=method))


@pytest.mark.parametrize(
    "args, params",
    [
        (["--patches", "2x3"], ThesisParams(patches=(2, 3))),
        (["--clusters", "2"], ThesisParams(n_clusters=2)),
        (["--patches", "1x1", "--clusters", "3"], ThesisParams(patches=(1, 1), n_clusters=3)),
    ],
)
def test_patches_and_clusters(files, tmp_path, args, params):
    depth, color = files
    out = tmp_path / "out.png"
    assert main(["refine", str(depth), str(color), "-o", str(out), "--method", "thesis", *args]) == 0
    result = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)
    np.testing.assert_array_equal(result, expected(SCENE.depth_lr, method="thesis", params=params))
    # The options matter: the default parameters give another result.
    assert not np.array_equal(result, expected(SCENE.depth_lr, method="thesis"))


def test_patch_file(files, tmp_path):
    depth, color = files
    layout = [[0, 0, 48, 64], [48, 0, 48, 32], {"x": 48, "y": 32, "width": 48, "height": 32}]
    patch_file = tmp_path / "patches.json"
    patch_file.write_text(json.dumps(layout), encoding="utf-8")
    out = tmp_path / "out.png"
    assert main(["refine", str(depth), str(color), "-o", str(out), "--method", "thesis", "--patch-file", str(patch_file)]) == 0
    params = ThesisParams(patch_layout=((0, 0, 48, 64), (48, 0, 48, 32), (48, 32, 48, 32)))
    np.testing.assert_array_equal(cv2.imread(str(out), cv2.IMREAD_UNCHANGED), expected(SCENE.depth_lr, method="thesis", params=params))


def test_patch_file_that_leaves_a_gap_is_exit_2(files, tmp_path, capsys):
    depth, color = files
    patch_file = tmp_path / "patches.json"
    patch_file.write_text(json.dumps([[0, 0, 48, 64]]), encoding="utf-8")
    out = tmp_path / "out.png"
    assert main(["refine", str(depth), str(color), "-o", str(out), "--method", "thesis", "--patch-file", str(patch_file)]) == 2
    err = capsys.readouterr().err
    assert "uncovered" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_params_toml(files, tmp_path):
    depth, color = files
    toml = tmp_path / "params.toml"
    toml.write_text("patches = [2, 2]\nn_clusters = 3\ncorrect_depth = false\ntolerance_levels = 3.0\n",
                    encoding="utf-8")
    out = tmp_path / "out.png"
    assert main(["refine", str(depth), str(color), "-o", str(out), "--method", "thesis", "--params", str(toml)]) == 0
    params = ThesisParams(patches=(2, 2), n_clusters=3, correct_depth=False, tolerance_levels=3.0)
    np.testing.assert_array_equal(cv2.imread(str(out), cv2.IMREAD_UNCHANGED), expected(SCENE.depth_lr, method="thesis", params=params))


def test_options_override_the_params_file(files, tmp_path):
    depth, color = files
    toml = tmp_path / "params.toml"
    toml.write_text("n_clusters = 3\n", encoding="utf-8")
    out = tmp_path / "out.png"
    assert main(["refine", str(depth), str(color), "-o", str(out), "--method", "thesis", "--params", str(toml), "--clusters", "2"]) == 0
    np.testing.assert_array_equal(cv2.imread(str(out), cv2.IMREAD_UNCHANGED),
                                  expected(SCENE.depth_lr, method="thesis", params=ThesisParams(n_clusters=2)))


@pytest.mark.parametrize("method", ["gbp", "gbp-fast"])
def test_snap_edges_switch_sets_the_parameter(files, tmp_path, method):
    depth, color = files
    out = tmp_path / "out.png"
    assert main(["refine", str(depth), str(color), "-o", str(out), "--method", method, "--snap-edges"]) == 0
    snapped = expected(SCENE.depth_lr, method=method, params=METHODS[method].params_type(snap_edges=True))
    np.testing.assert_array_equal(cv2.imread(str(out), cv2.IMREAD_UNCHANGED), snapped)
    assert np.any(snapped != expected(SCENE.depth_lr, method=method)), "the scene must have a jump that snapping moves"


@pytest.mark.parametrize("method", ["gbp", "gbp-fast"])
def test_sampling_option_sets_the_parameter_and_checks_its_value(files, tmp_path, capsys, method):
    depth, color = files
    out = tmp_path / "out.png"
    # SCENE's depth is point-sampled and measures so: told "mean", the methods model it otherwise
    assert main(["refine", str(depth), str(color), "-o", str(out), "--method", method, "--sampling", "mean"]) == 0
    told = expected(SCENE.depth_lr, method=method, params=METHODS[method].params_type(sampling="mean"))
    np.testing.assert_array_equal(cv2.imread(str(out), cv2.IMREAD_UNCHANGED), told)
    assert np.any(told != expected(SCENE.depth_lr, method=method))
    capsys.readouterr()
    bad = tmp_path / "bad.png"
    assert main(["refine", str(depth), str(color), "-o", str(bad), "--method", method, "--sampling", "points"]) == 2
    err = capsys.readouterr().err
    assert "--sampling" in err and "'point'" in err and len(err.strip().splitlines()) == 1
    assert not bad.exists()


@pytest.mark.parametrize("options, message", [
    (["--snap-edges"], "--snap-edges sets parameters of the gbp and gbp-fast methods; the method is 'bicubic': "
     "add --method gbp (or gbp-fast)."),
    (["--sampling", "mean", "--reprojected"],   # options gbp and gbp-fast share: both named
     "--sampling and --reprojected set parameters of the gbp and gbp-fast methods; the method is 'bicubic': "
     "add --method gbp (or gbp-fast)."),
])
def test_gbp_options_with_another_method_are_exit_2(files, tmp_path, capsys, options, message):
    depth, color = files
    out = tmp_path / "out.png"
    assert main(["refine", str(depth), str(color), "-o", str(out), "--method", "bicubic", *options]) == 2
    err = capsys.readouterr().err
    assert err.strip().endswith(message) and len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_params_toml_with_an_unknown_key_is_exit_2(files, tmp_path, capsys):
    depth, color = files
    toml = tmp_path / "params.toml"
    toml.write_text("n_clusters = 3\nclusterz = 4\n", encoding="utf-8")
    out = tmp_path / "out.png"
    assert main(["refine", str(depth), str(color), "-o", str(out), "--params", str(toml)]) == 2
    err = capsys.readouterr().err
    assert "'clusterz'" in err and "params.toml" in err and "known:" in err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_save_intermediate_writes_the_pictures(files, tmp_path):
    depth, color = files
    out = tmp_path / "out.png"
    folder = tmp_path / "steps"
    assert main(["refine", str(depth), str(color), "-o", str(out), "--method", "thesis", "--save-intermediate", str(folder),
                 "--patches", "2x2"]) == 0
    names = {p.name for p in folder.iterdir()}
    pictures = {"result_colorized.png", "result_blended.png", "cluster_labels.png", "sparse_depth_over_color.png",
                "color_filtered.png", "corrected_depth_over_color.png"}
    assert pictures | {"run.json", "intermediates.npz"} <= names
    assert not [n for n in names if n.startswith(".")], "no temporary files left behind"
    for name in ("cluster_labels.png", "color_filtered.png"):  # images on the color grid
        picture = cv2.imread(str(folder / name), cv2.IMREAD_UNCHANGED)
        assert picture.shape == (64, 96, 3) and picture.dtype == np.uint8, name
    for name in pictures - {"cluster_labels.png", "color_filtered.png"}:  # depth: figures with a colorbar
        picture = cv2.imread(str(folder / name), cv2.IMREAD_UNCHANGED)
        assert picture is not None and picture.shape[1] > 96 and picture.std() > 5, name
    record = json.loads((folder / "run.json").read_text(encoding="utf-8"))
    assert record["method"] == "thesis" and record["params"]["patches"] == [2, 2]
    assert record["depth_shape"] == [16, 24] and record["color_shape"] == [64, 96] and record["dtype"] == "uint8"
    with np.load(folder / "intermediates.npz") as npz:
        assert npz["labels"].shape == (64, 96) and npz["patches"].shape == (4, 4)
    # The result is the same as without --save-intermediate.
    np.testing.assert_array_equal(cv2.imread(str(out), cv2.IMREAD_UNCHANGED),
                                  expected(SCENE.depth_lr, method="thesis", params=ThesisParams(patches=(2, 2))))


def test_save_intermediate_for_a_baseline_writes_the_result_pictures(files, tmp_path):
    depth, color = files
    folder = tmp_path / "steps"
    assert main(["refine", str(depth), str(color), "-o", str(tmp_path / "o.png"), "--method", "bilinear",
                 "--save-intermediate", str(folder)]) == 0
    names = {p.name for p in folder.iterdir()}
    assert {"result_colorized.png", "result_blended.png", "run.json"} <= names


def test_existing_output_needs_overwrite(files, tmp_path, capsys):
    depth, color = files
    out = tmp_path / "out.png"
    out.write_bytes(b"keep me")
    before = os.stat(out).st_mtime_ns
    assert main(["refine", str(depth), str(color), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "exists" in err and "--overwrite" in err and "Traceback" not in err
    assert out.read_bytes() == b"keep me" and os.stat(out).st_mtime_ns == before
    assert main(["refine", str(depth), str(color), "-o", str(out), "--overwrite"]) == 0
    np.testing.assert_array_equal(cv2.imread(str(out), cv2.IMREAD_UNCHANGED), expected(SCENE.depth_lr))


def test_non_integer_ratio_applies_the_scale_step_and_says_so(tmp_path, capsys):
    depth = tmp_path / "depth.png"
    assert cv2.imwrite(str(depth), SCENE.depth_lr)                       # 24 x 16
    rgb = cv2.resize(SCENE.rgb_hr, (106, 71), interpolation=cv2.INTER_NEAREST)   # ratio 4.42
    color = write_color(tmp_path / "color.png", rgb)
    out = tmp_path / "out.png"
    assert main(["refine", str(depth), str(color), "-o", str(out), "--method", "thesis"]) == 0
    result = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)
    assert result.shape == (71, 106)
    err = capsys.readouterr().err
    assert "note:" in err and "scale step" in err and "non-integer ratio" in err
    with pytest.warns(depthrefine.ScaleWarning):
        np.testing.assert_array_equal(result, expected(SCENE.depth_lr, rgb, method="thesis"))


def test_python_dash_m(files, tmp_path):
    depth, color = files
    out = tmp_path / "out.png"
    proc = subprocess.run([sys.executable, "-m", "depthrefine", "refine", str(depth), str(color), "-o", str(out),
                           "--method", "nearest"], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    result = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)
    np.testing.assert_array_equal(result, expected(SCENE.depth_lr, method="nearest"))
    # And the error path: an unknown parameter key, exit 2, one line, no output.
    toml = tmp_path / "bad.toml"
    toml.write_text("k = 3\n", encoding="utf-8")
    out2 = tmp_path / "out2.png"
    proc = subprocess.run([sys.executable, "-m", "depthrefine", "refine", str(depth), str(color), "-o", str(out2),
                           "--params", str(toml)], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2 and "'k'" in proc.stderr and "Traceback" not in proc.stderr
    assert not out2.exists()


def test_output_and_save_intermediate_on_one_path_is_exit_2(files, tmp_path, capsys):
    depth, color = files
    out = tmp_path / "same.png"
    assert main(["refine", str(depth), str(color), "-o", str(out), "--save-intermediate", str(out)]) == 2
    err = capsys.readouterr().err
    assert "same path" in err and len(err.strip().splitlines()) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["color.png", "depth.png"]


def test_patches_conflicting_with_a_patch_layout_in_the_params_file_is_exit_2(files, tmp_path, capsys):
    depth, color = files
    toml = tmp_path / "params.toml"
    toml.write_text("patch_layout = [[0, 0, 64, 64]]\n", encoding="utf-8")
    out = tmp_path / "out.png"
    assert main(["refine", str(depth), str(color), "-o", str(out), "--method", "thesis", "--params", str(toml), "--patches", "2x2"]) == 2
    err = capsys.readouterr().err
    assert "conflicts with patch_layout" in err and not out.exists()
