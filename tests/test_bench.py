"""The benchmark: protocol cases, run_benchmark, the loaders, and ``depthrefine bench`` end to end."""

from __future__ import annotations

import csv
import math
import shutil
from pathlib import Path

import cv2
import numpy as np
import pytest
from PIL import Image

from depthrefine.bench import (
    LU_BORDER, ROW_FIELDS, BenchCase, bicubic_downsample, lu_case, park_case, parse_scales, run_benchmark, tof_case,
)
from depthrefine.cli import main
from depthrefine.evaluate import score
from depthrefine.bench import load_cases
from depthrefine.io import InputFileError, sample_folder

from conftest import shared_data_path as _shared


def _pil_bicubic_up(depth_lr: np.ndarray, shape) -> np.ndarray:
    img = Image.fromarray(np.asarray(depth_lr, np.float32))
    return np.asarray(img.resize((shape[1], shape[0]), Image.BICUBIC), np.float64)


def test_bicubic_downsample_is_pil_on_the_normalised_map(rng):
    gt = rng.integers(20, 230, (24, 36)).astype(np.uint8)
    lr = bicubic_downsample(gt, 4)
    lo, hi = float(gt.min()), float(gt.max())
    norm = Image.fromarray(((gt - lo) / (hi - lo)).astype(np.float32))
    expected = np.asarray(norm.resize((9, 6), Image.BICUBIC), np.float64) * (hi - lo) + lo
    assert lr.shape == (6, 9) and lr.dtype == np.float32
    np.testing.assert_allclose(lr, expected, rtol=0, atol=1e-3)


def test_lu_case_crops_to_a_multiple_and_scores_inside_the_border(rng):
    gt = rng.integers(1, 255, (37, 50)).astype(np.uint8)
    rgb = rng.integers(0, 256, (37, 50, 3)).astype(np.uint8)
    case = lu_case("middlebury30", "x", 8, rgb, gt)
    assert case.depth_gt.shape == (32, 48) and case.rgb_hr.shape == (32, 48, 3)
    assert case.depth_lr.shape == (4, 6) and case.border == LU_BORDER and case.split == "test"
    assert lu_case("middlebury30", "Middlebury_03", 8, rgb, gt).split == "tune"


def test_park_and_tof_cases(rng):
    gt = rng.integers(30, 200, (32, 48)).astype(np.uint8)
    rgb = np.full((32, 48, 3), 180, np.uint8)
    case = park_case("dolls", 8, gt[::8, ::8].copy(), rgb, gt)
    assert case.split == "tune" and case.border == 0 and case.depth_gt.dtype == np.float32
    tof = tof_case("art", 8, rgb, gt)
    assert tof.depth_lr.shape == (4, 6) and tof.depth_lr.dtype == np.uint8 and tof.split == "test"
    np.testing.assert_array_equal(tof.depth_lr, tof_case("art", 8, rgb, gt).depth_lr)  # fixed seed
    with pytest.raises(ValueError, match="larger than the ground truth"):
        park_case("art", 8, gt, rgb, gt)


def test_parse_scales():
    assert parse_scales("4,8,16") == (4, 8, 16)
    for bad in ("", "4,x", "1", "4;8"):
        with pytest.raises(ValueError, match="--scales"):
            parse_scales(bad)


def test_run_benchmark_rows_times_and_kept_results():
    gt = np.tile(np.repeat(np.array([40, 200], np.uint8), 16), (16, 1))
    case = park_case("toy", 4, gt[1::4, 1::4].copy(), np.zeros((16, 32, 3), np.uint8), gt)
    ticks = iter(range(100))
    seen = []
    result = run_benchmark([case], ["nearest", "bilinear"], keep=lambda c: True,
                           progress=lambda d, t: seen.append((d, t)), clock=lambda: float(next(ticks)))
    assert [r.method for r in result.rows] == ["nearest", "bilinear"]
    assert all(r.seconds == 1.0 for r in result.rows)
    assert seen == [(1, 2), (2, 2)]
    assert set(result.kept[case.key]) == {"nearest", "bilinear"}
    bilinear = result.kept[case.key]["bilinear"]
    assert result.rows[1].rmse == pytest.approx(score(bilinear, case.depth_gt).rmse)
    assert result.rows[0].rmse == 0.0 and result.rows[1].rmse > 0  # nearest is exact on a block-aligned step
    assert tuple(result.rows[0].to_dict()) == ROW_FIELDS
    with pytest.raises(ValueError, match="unknown method"):
        run_benchmark([case], ["nope"])


def _shipped_park(root: Path, scales=(4,)) -> Path:
    """A data root holding middlebury2005_park/art/ from the Art scene shipped in the package (the same bytes)."""
    art = root / "middlebury2005_park" / "art"
    art.mkdir(parents=True)
    for name in ("color.png", "gt_disp.png", *(f"noisy_x{s}.png" for s in scales)):
        shutil.copy(sample_folder("art") / name, art / name)
    return root


def test_park_protocol_reproduces_the_readme_sanity_baseline(tmp_path):
    # The README gives plain PIL-bicubic numbers computed with each protocol:
    # Park art x4 5.60 (middlebury2005_park/README.md); the shipped Art is the same files.
    cases = load_cases(_shipped_park(tmp_path) / "middlebury2005_park", "park", (4,))
    art = next(c for c in cases if c.scene == "art")
    assert art.depth_lr.dtype == np.uint8 and art.depth_gt.shape == (1088, 1376)
    assert score(_pil_bicubic_up(art.depth_lr, art.depth_gt.shape), art.depth_gt).rmse == pytest.approx(5.60, abs=0.01)


@pytest.mark.shared_data
def test_middlebury30_protocol_reproduces_the_readme_sanity_baselines():
    # middlebury_lu30, 28 shared images: the README's 2.212 / 3.854 / 6.144 are without a border
    # crop; the protocol's 6-px crop gives 2.2257 / 3.8668 / 6.1046 (benchmarks/sanity_baselines.py, docs/bench.md).
    cases = load_cases(_shared("middlebury_lu30"), "middlebury30", (4, 8, 16))
    for scale, readme, cropped in ((4, 2.212, 2.2257), (8, 3.854, 3.8668), (16, 6.144, 6.1046)):
        mine = [c for c in cases if c.scale == scale]
        assert len(mine) == 28 and all(c.border == LU_BORDER == 6 for c in mine)
        ups = [_pil_bicubic_up(c.depth_lr, c.depth_gt.shape) for c in mine]
        no_crop = np.mean([score(u, c.depth_gt, border=0).rmse for u, c in zip(ups, mine)])
        crop = np.mean([score(u, c.depth_gt, border=c.border).rmse for u, c in zip(ups, mine)])
        assert no_crop == pytest.approx(readme, abs=1e-3), scale
        assert crop == pytest.approx(cropped, abs=1e-3), scale


def test_park_tuning_scenes_are_left_out_of_middlebury30_too():
    from depthrefine.bench import TUNING_SCENES, left_out_reason, tuned_on_scenes
    # Park's Dolls and Laundry are Middlebury_14 and _18 (middlebury_lu30 README).
    assert {"Middlebury_14", "Middlebury_18"} <= set(TUNING_SCENES["middlebury30"])
    gt = np.full((32, 32), 100, np.uint8)
    rgb = np.zeros((32, 32, 3), np.uint8)
    assert lu_case("middlebury30", "Middlebury_14", 4, rgb, gt).split == "tune"
    assert lu_case("middlebury30", "Middlebury_18", 4, rgb, gt).split == "tune"
    assert lu_case("middlebury30", "Middlebury_02", 4, rgb, gt).split == "test"
    assert "Dolls" in left_out_reason("middlebury30", "Middlebury_14")
    assert "Middlebury_14" not in tuned_on_scenes("middlebury30")  # left out, but not tuned on


def test_bench_cli_on_one_scene_at_one_scale(tmp_path, capsys):
    # One scene laid out as the lu set: the shipped Art's color and ground truth at half size (688x544,
    # about the Lu images' 640x480), named as the set names its files.
    data = tmp_path / "data" / "lu6"
    (data / "RGB").mkdir(parents=True)
    (data / "Depth").mkdir()
    color = cv2.imread(str(sample_folder("art") / "color.png"), cv2.IMREAD_COLOR)
    gt = cv2.imread(str(sample_folder("art") / "gt_disp.png"), cv2.IMREAD_UNCHANGED)
    half = cv2.resize(color, (688, 544), interpolation=cv2.INTER_AREA)
    cv2.imwrite(str(data / "RGB" / "RGBD_01_ouput_color.png"), half)
    cv2.imwrite(str(data / "Depth" / "RGBD_01_output_depth.png"), gt[::2, ::2])
    out = tmp_path / "report"
    status = main(["bench", "--data", str(tmp_path / "data"), "--protocol", "all", "--methods",
                   "thesis,bilinear,guided", "--scales", "16", "--report", str(out)])
    captured = capsys.readouterr()
    assert status == 0, captured.err
    assert "skipping the park protocol" in captured.err
    assert "bilinear" in captured.out and "×16" in captured.out
    with open(out / "scores.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [(r["protocol"], r["scene"], r["scale"], r["method"]) for r in rows] == [
        ("lu", "RGBD_01", "16", m) for m in ("thesis", "bilinear", "guided")]
    assert tuple(rows[0]) == ROW_FIELDS
    # The bilinear row is the library's own score of the protocol's case.
    case = load_cases(tmp_path / "data", "lu", (16,))[0]
    from depthrefine.methods.baselines import upsample_bilinear
    expected = score(upsample_bilinear(case.depth_lr, case.rgb_hr), case.depth_gt, border=LU_BORDER)
    assert float(rows[1]["rmse"]) == pytest.approx(expected.rmse, rel=1e-5)
    assert float(rows[1]["edge_rmse"]) == pytest.approx(expected.edge_rmse, rel=1e-5)
    assert all(math.isfinite(float(r["seconds"])) for r in rows)
    for name in ("summary.md", "index.html", "rmse_vs_scale.png", "fig_lu_RGBD_01_x16.png", "run.json"):
        assert (out / name).is_file(), name
    assert "| bilinear |" in (out / "summary.md").read_text()
    # Never overwrite without --overwrite; the failed run leaves the report as it was.
    before = sorted(p.name for p in out.iterdir())
    status = main(["bench", "--data", str(tmp_path / "data"), "--protocol", "lu", "--methods", "bilinear",
                   "--scales", "16", "--report", str(out)])
    assert status == 2 and "--overwrite" in capsys.readouterr().err
    assert sorted(p.name for p in out.iterdir()) == before


def test_bench_cli_bad_arguments_exit_2(tmp_path, capsys):
    (tmp_path / "empty").mkdir()
    cases = [
        (["--data", str(tmp_path / "missing")], "does not exist"),
        (["--data", str(tmp_path / "empty"), "--protocol", "lu"], "no lu6/ folder"),
        (["--data", str(tmp_path / "empty")], "holds none of the dataset folders"),
        (["--data", str(tmp_path / "empty"), "--methods", "thesis,nope"], "unknown method 'nope'"),
        (["--data", str(tmp_path / "empty"), "--scales", "4,x"], "--scales"),
    ]
    for extra, message in cases:
        status = main(["bench", *extra])
        err = capsys.readouterr().err
        assert status == 2, extra
        assert message in err and "Traceback" not in err and len(err.strip().splitlines()) == 1, err


def test_bench_cli_default_data_missing_is_a_clear_error(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("DEPTHREFINE_DATA", raising=False)
    monkeypatch.setattr("depthrefine.bench.suite.checkout_data_dir", lambda: tmp_path / "shared" / "data")
    assert main(["bench", "--protocol", "lu"]) == 2
    err = capsys.readouterr().err
    assert "pass --data DIR" in err and "DEPTHREFINE_DATA" in err and str(tmp_path / "shared" / "data") in err
    monkeypatch.setenv("DEPTHREFINE_DATA", str(tmp_path / "missing"))
    assert main(["bench", "--protocol", "lu"]) == 2
    assert "$DEPTHREFINE_DATA is " in capsys.readouterr().err


def test_bench_cli_default_data_order(tmp_path, monkeypatch):
    """--data, else $DEPTHREFINE_DATA, else ../shared/data beside the source checkout."""
    from depthrefine.bench.suite import checkout_data_dir, find_data_folder as _data_dir

    import depthrefine

    checkout = Path(depthrefine.__file__).resolve().parents[2]          # <checkout>/src/depthrefine/__init__.py
    assert checkout_data_dir() == checkout.parent / "shared" / "data"   # tests run from a source checkout
    monkeypatch.setenv("DEPTHREFINE_DATA", str(tmp_path))
    assert _data_dir(None) == tmp_path
    assert _data_dir(str(tmp_path / ".")) == tmp_path / "."
    monkeypatch.delenv("DEPTHREFINE_DATA")
    monkeypatch.setattr("depthrefine.bench.suite.checkout_data_dir", lambda: tmp_path)
    assert _data_dir(None) == tmp_path


def _park_scene(root: Path, name: str, *, gt_dtype=np.uint8, noisy=(8,)) -> None:
    scene = root / "middlebury2005_park" / name
    scene.mkdir(parents=True)
    Image.fromarray(np.full((32, 32, 3), 100, np.uint8)).save(scene / "color.png")
    Image.fromarray(np.full((32, 32), 100 if gt_dtype == np.uint8 else 3000, gt_dtype)).save(scene / "gt_disp.png")
    for s in noisy:
        Image.fromarray(np.full((32 // s, 32 // s), 100, np.uint8)).save(scene / f"noisy_x{s}.png")


def test_loader_skips_what_is_missing_or_unusable_with_a_note(tmp_path):
    _park_scene(tmp_path, "art", noisy=(4,))
    _park_scene(tmp_path, "books", noisy=(4, 8))
    (tmp_path / "middlebury2005_park" / "empty").mkdir()
    notes: list[str] = []
    cases = load_cases(tmp_path, "park", (4, 8), notes=notes)
    assert [c.key for c in cases] == [("park", "art", 4), ("park", "books", 4), ("park", "books", 8)]
    assert any("art x8" in n and "noisy_x8.png is missing" in n for n in notes), notes
    assert any("empty" in n and "color.png" in n for n in notes), notes
    # Only missing scales: a clear error naming the expected files.
    with pytest.raises(InputFileError, match="no usable case.*noisy_x<s>.png"):
        load_cases(tmp_path, "park", (16,))
    assert [c.key for c in load_cases(tmp_path, "tof", (8,))] == [("tof", "art", 8), ("tof", "books", 8)]
    with pytest.raises(ValueError, match="unknown protocol"):
        load_cases(tmp_path, "nyu", (8,))
    assert isinstance(load_cases(tmp_path / "middlebury2005_park", "tof", (4,))[0], BenchCase)


def test_a_16_bit_ground_truth_skips_tof_only(tmp_path, capsys):
    _park_scene(tmp_path, "art", noisy=(8,))
    _park_scene(tmp_path, "deep", gt_dtype=np.uint16, noisy=(8,))
    notes: list[str] = []
    assert [c.scene for c in load_cases(tmp_path, "tof", (8,), notes=notes)] == ["art"]
    assert len(notes) == 1 and notes[0].startswith("tof: skipped deep x8") and "8-bit" in notes[0]
    out = tmp_path / "report"
    status = main(["bench", "--data", str(tmp_path), "--methods", "nearest", "--scales", "8", "--report", str(out)])
    err = capsys.readouterr().err
    assert status == 0, err
    assert "note: tof: skipped deep x8" in err
    with open(out / "scores.csv", newline="") as fh:
        keys = [(r["protocol"], r["scene"]) for r in csv.DictReader(fh)]
    assert ("park", "deep") in keys and ("tof", "art") in keys and ("tof", "deep") not in keys
    assert "tof: skipped deep x8" in (out / "summary.md").read_text()


def test_a_lu_folder_with_no_usable_pair_names_the_expected_files(tmp_path):
    lu = tmp_path / "lu6"
    (lu / "RGB").mkdir(parents=True)
    (lu / "Depth").mkdir()
    Image.fromarray(np.zeros((16, 16, 3), np.uint8)).save(lu / "RGB" / "scene_color.png")
    with pytest.raises(InputFileError, match=r"_output_color.png.*_output_depth.png"):
        load_cases(tmp_path, "lu", (4,))
    Image.fromarray(np.zeros((16, 16, 3), np.uint8)).save(lu / "RGB" / "a_output_color.png")
    with pytest.raises(InputFileError, match="no usable"):
        load_cases(tmp_path, "lu", (4,))  # the only pair lacks its depth file
    with pytest.raises(InputFileError, match=r"middlebury_lu30/RGB/<name>_output_color.png"):
        load_cases(tmp_path, "middlebury30", (4,))


def _triplets(root: Path, rng) -> Path:
    """Three triplets (x4, two with holes, one in uint16 with 65535 as 'no measurement') paired by stem."""
    for sub in ("color", "input", "gt"):
        (root / sub).mkdir(parents=True)
    for i, stem in enumerate(("a", "b", "c")):
        gt = np.full((40, 48), 1500 + 100 * i, np.uint16)
        gt[10:30, 12 + 4 * i:36] = 2600
        gt[0, :5] = 65535                                    # no measurement, by --invalid 65535
        rgb = np.where(gt[..., None] > 2000, np.uint8(210), np.uint8(50)) + rng.integers(0, 30, (40, 48, 3))
        low = gt[1::4, 1::4].astype(np.int32) + rng.integers(-40, 40, (10, 12))
        low = np.clip(low, 1, 65534).astype(np.uint16)
        low[2, 3] = 65535
        Image.fromarray(rgb.astype(np.uint8)).save(root / "color" / f"{stem}.png")
        cv2.imwrite(str(root / "input" / f"{stem}.png"), low)
        cv2.imwrite(str(root / "gt" / f"{stem}.png"), gt)
    (root / "gt" / "extra.png").write_bytes((root / "gt" / "a.png").read_bytes())   # no color, no input: skipped
    return root


def test_bench_pairs_gives_the_rmse_of_evaluate_on_the_same_arrays(tmp_path, rng, capsys):
    import depthrefine
    from depthrefine.evaluate import rmse
    from depthrefine.io import read_depth, read_rgb

    folder = _triplets(tmp_path / "mine", rng)
    out = tmp_path / "report"
    assert main(["bench", "--pairs", str(folder), "--units", "mm", "--invalid", "65535", "--crop", "2",
                 "--methods", "bilinear,guided", "--report", str(out)]) == 0
    captured = capsys.readouterr()
    assert "skipped extra" in captured.err
    with open(out / "scores.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert {(r["protocol"], r["scene"], r["scale"], r["method"]) for r in rows} == {
        ("pairs", s, "4", m) for s in "abc" for m in ("bilinear", "guided")}
    for r in rows:
        low = read_depth(folder / "input" / f"{r['scene']}.png")
        low = np.where(low == 65535, 0, low).astype(np.uint16)
        gt = read_depth(folder / "gt" / f"{r['scene']}.png").astype(np.float32)
        gt[(gt == 65535) | (gt == 0)] = np.nan
        valid = np.zeros(gt.shape, bool)
        valid[2:-2, 2:-2] = True
        pred = depthrefine.refine(low, read_rgb(folder / "color" / f"{r['scene']}.png"), method=r["method"])
        assert float(r["rmse"]) == pytest.approx(rmse(pred, gt, valid=valid), rel=1e-5)
    page = (out / "index.html").read_text()
    assert "pairs: mean RMSE" in page and "mm" in page and page.count('<figure class="scene">') == 3
    assert "pairs" in captured.out and "×4" in captured.out


def test_bench_pairs_bad_uses_are_clear_errors(tmp_path, rng, capsys):
    folder = _triplets(tmp_path / "mine", rng)
    assert main(["bench", "--pairs", str(folder), "--protocol", "lu"]) == 2
    assert "--pairs DIR takes neither --protocol nor --scales" in capsys.readouterr().err
    assert main(["bench", "--pairs", str(folder), "--data", str(tmp_path)]) == 2
    assert "not allowed with argument" in capsys.readouterr().err
    assert main(["bench", "--data", str(tmp_path), "--units", "mm"]) == 2
    assert "--units is for --pairs" in capsys.readouterr().err
    shutil.rmtree(folder / "input")
    assert main(["bench", "--pairs", str(folder)]) == 2
    err = capsys.readouterr().err
    assert "input/" in err and "paired by stem" in err
