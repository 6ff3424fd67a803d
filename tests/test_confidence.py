"""Confidence maps (issue 23): the library call, the generic and gbp maps, the metric, files, CLI, batch, bench."""

from __future__ import annotations

import json

import numpy as np
import pytest

import depthrefine
from depthrefine._validate import as_depth
from depthrefine.bench.metrics import sparsification, sparsification_curve
from depthrefine.bench.synthetic import make_scene
from depthrefine.cli import main
from depthrefine.io import read_confidence, read_depth, write_confidence, write_depth, write_rgb
from depthrefine.methods.confidence import generic_confidence, steepness_confidence
from depthrefine.methods.registry import METHODS, refine

from conftest import shared_data_path

from test_cli_rig import captures  # noqa: F401  (the rig fixture for `run`)


def hard_scene(seed: int, scale: int):
    """A generated scene with the errors a confidence map must find.

    Beside noise, one object has the wall's color (a depth edge the guide
    does not show) and a block of the input is missing (depth invented
    across a hole). Returns (depth_lr, rgb_hr, depth_gt).
    """
    scene = make_scene((96, 128), scale, n_objects=3, seed=seed, color_noise_std=3.0, shading=0.1)
    rgb = scene.rgb_hr.copy()
    rgb[scene.labels_hr == 1] = np.median(rgb[scene.labels_hr == 0], axis=0).astype(np.uint8)
    depth = scene.depth_lr.copy()
    h, w = depth.shape
    depth[h // 3: h // 3 + max(2, h // 6), w // 2: w // 2 + max(2, w // 5)] = 0
    return depth, rgb, scene.depth_hr_gt


# ---------------------------------------------------------------- the library call

@pytest.mark.parametrize("method", sorted(METHODS))
def test_every_method_gets_a_confidence_map_and_the_same_depth_as_refine(method, small_scene):
    depth_lr, rgb = small_scene.depth_lr.copy(), small_scene.rgb_hr
    depth_lr[3:5, 6:9] = 0
    kwargs = {"params": depthrefine.ThesisParams(patches=(2, 2))} if method == "thesis" else {}
    depth_hr, confidence = depthrefine.refine_with_confidence(depth_lr, rgb, method=method, **kwargs)
    assert confidence.dtype == np.float32 and confidence.shape == rgb.shape[:2] == depth_hr.shape
    assert np.isfinite(confidence).all() and confidence.min() >= 0.0 and confidence.max() <= 1.0
    labels = small_scene.labels_hr
    edge = np.zeros(labels.shape, bool)
    edge[:, 1:] |= labels[:, 1:] != labels[:, :-1]
    edge[1:, :] |= labels[1:, :] != labels[:-1, :]
    assert confidence[edge].mean() < 0.5 * confidence[~edge].mean()  # depth edges are trusted less
    if METHODS[method].deterministic:
        assert np.array_equal(depth_hr, refine(depth_lr, rgb, method=method, **kwargs))


def test_gbp_uses_its_own_map_and_the_default_method_is_gbp(small_scene):
    from depthrefine.methods.gbp import upsample_gbp_with_confidence

    assert METHODS["gbp"].confidence is upsample_gbp_with_confidence
    assert all(METHODS[m].confidence is None for m in METHODS if m != "gbp")
    depth_hr, confidence = depthrefine.refine_with_confidence(small_scene.depth_lr, small_scene.rgb_hr)
    again = upsample_gbp_with_confidence(small_scene.depth_lr, small_scene.rgb_hr)
    assert np.array_equal(depth_hr, again[0]) and np.array_equal(confidence, again[1])  # deterministic
    generic = generic_confidence(small_scene.depth_lr, depth_hr)
    assert not np.array_equal(confidence, generic)  # gbp's internals change the map


def test_confidence_is_zero_where_there_is_no_depth():
    depth_lr = np.array([[10, 10, 50, 50]] * 4, np.float32)
    depth_hr = np.repeat(np.repeat(depth_lr, 4, 0), 4, 1)
    depth_hr[0, :3] = np.nan
    confidence = generic_confidence(depth_lr, depth_hr)
    assert (confidence[0, :3] == 0).all() and (confidence[1:, :3] > 0.9).all()
    assert steepness_confidence(depth_hr)[0, 0] == 0.0


def test_a_filled_hole_is_trusted_less_the_further_it_is_from_a_measurement():
    depth_lr = np.full((16, 16), 100, np.uint8)
    depth_lr[4:12, 4:12] = 0
    rgb = np.zeros((64, 64, 3), np.uint8)
    depth_hr, confidence = depthrefine.refine_with_confidence(depth_lr, rgb, method="bilinear")
    assert np.isfinite(depth_hr).all()
    assert confidence[32, 32] < confidence[20, 32] < confidence[2, 32] == 1.0


def test_refine_with_confidence_checks_like_refine():
    with pytest.raises(ValueError, match="unknown method"):
        depthrefine.refine_with_confidence(np.ones((4, 4)), np.zeros((16, 16, 3)), method="nope")
    with pytest.raises(TypeError, match="takes no parameters"):
        depthrefine.refine_with_confidence(np.ones((4, 4)), np.zeros((16, 16, 3)), method="bilinear",
                                           params=depthrefine.GbpParams())


@pytest.mark.parametrize("method", ["gbp", "bilinear", "guided"])
@pytest.mark.parametrize("seed, scale", [(0, 4), (1, 8), (2, 4), (3, 8)])
def test_high_confidence_means_low_error_on_generated_scenes(method, seed, scale):
    depth_lr, rgb, gt = hard_scene(seed, scale)
    depth_hr, confidence = depthrefine.refine_with_confidence(depth_lr, rgb, method=method)
    mine = sparsification(depth_hr, gt, confidence)
    blind = sparsification(depth_hr, gt, np.ones_like(confidence))  # a constant map ranks nothing
    assert mine.confident_rmse <= 0.5 * mine.doubtful_rmse
    assert mine.ause <= 0.5 * blind.ause
    assert np.allclose(blind.curve, blind.rmse)  # ties are removed evenly: a flat curve


# ---------------------------------------------------------------- the metric

def test_sparsification_of_a_perfect_and_a_reversed_ranking():
    gt = np.ones((4, 25))
    pred = gt + np.arange(100, dtype=np.float64).reshape(4, 25) / 10
    err = np.abs(pred - gt)
    perfect = sparsification(pred, gt, -err)
    reversed_ = sparsification(pred, gt, err)
    assert perfect.ause == pytest.approx(0.0, abs=1e-12) and np.allclose(perfect.curve, perfect.oracle)
    assert reversed_.ause > 1.0 and reversed_.half_ratio > 1 > perfect.half_ratio
    assert perfect.rmse == pytest.approx(float(np.sqrt(np.mean(err ** 2))))
    # the more confident half holds the 50 smallest errors
    assert perfect.confident_rmse == pytest.approx(float(np.sqrt(np.mean(np.sort(err.ravel())[:50] ** 2))))
    assert perfect.fractions[0] == 0 and perfect.fractions[-1] == 0.99 and perfect.curve.shape == (100,)


def test_sparsification_scores_the_pixels_score_does():
    gt = np.full((6, 6), 5.0)
    gt[0] = 0          # no ground truth: not scored
    pred = gt + 1.0
    pred[2, 2] = np.nan  # no prediction: not scored
    s = sparsification(pred, gt, np.ones((6, 6)), border=1)
    assert s.n_pixels == 4 * 4 - 1 and s.rmse == 1.0
    with pytest.raises(ValueError, match="confidence has shape"):
        sparsification(pred, gt, np.ones((5, 6)))


def test_curve_with_ties_interpolates_within_the_tied_group():
    # two tied pixels (errors 3 and 1) removed first; removing one of them removes half their squares
    curve = sparsification_curve(np.array([3.0, 1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0, 1.0]),
                                 np.array([0.0, 0.25, 0.5]))
    assert curve.tolist() == pytest.approx([np.sqrt(10 / 4), np.sqrt(5 / 3), 0.0])


# ---------------------------------------------------------------- files

@pytest.mark.parametrize("suffix", [".tif", ".npy", ".png"])
def test_confidence_files_round_trip(tmp_path, suffix):
    confidence = np.linspace(0, 1, 48, dtype=np.float32).reshape(6, 8)
    path = write_confidence(tmp_path / f"c{suffix}", confidence)
    back = read_confidence(path)
    assert back.dtype == np.float32 and back.shape == (6, 8)
    if suffix == ".png":
        import cv2

        raw = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
        assert raw.dtype == np.uint16 and raw.max() == 65535 and raw.min() == 0
        assert np.abs(back - confidence).max() <= 0.5 / 65535 + 1e-7
    else:
        assert np.array_equal(back, confidence)


def test_confidence_files_refuse_what_they_cannot_hold(tmp_path):
    from depthrefine.io import InputFileError

    with pytest.raises(InputFileError, match="unknown format '.jpg'"):
        write_confidence(tmp_path / "c.jpg", np.zeros((2, 2), np.float32))
    np.save(tmp_path / "bad.npy", np.full((2, 2), 2.0, np.float32))
    with pytest.raises(InputFileError, match="lies in \\[0, 1\\]"):
        read_confidence(tmp_path / "bad.npy")


# ---------------------------------------------------------------- the command line

@pytest.fixture
def pair(tmp_path):
    depth_lr, rgb, _ = hard_scene(0, 4)
    write_depth(tmp_path / "d.png", as_depth(depth_lr), dtype=np.uint8)  # float NaN: holes are written as 0
    write_rgb(tmp_path / "c.png", rgb)
    return tmp_path, depth_lr, rgb


def test_refine_writes_the_confidence_and_min_confidence_drops_doubtful_depth(pair, capsys):
    folder, depth_lr, rgb = pair
    base = ["refine", str(folder / "d.png"), str(folder / "c.png"), "--method", "bilinear"]
    assert main([*base, "-o", str(folder / "o.png"), "--confidence", str(folder / "conf.tif")]) == 0
    expected_depth, expected = depthrefine.refine_with_confidence(depth_lr, rgb, method="bilinear")
    assert np.array_equal(read_confidence(folder / "conf.tif"), expected)
    assert "median confidence" in capsys.readouterr().err
    assert main([*base, "-o", str(folder / "m.png"), "--min-confidence", "0.5", "--confidence",
                 str(folder / "conf.png"), "--preview", str(folder / "p.png")]) == 0
    written = read_depth(folder / "m.png")
    full = read_depth(folder / "o.png")
    low = expected < 0.5
    assert low.any() and (written[low] == 0).all() and np.array_equal(written[~low], full[~low])
    assert (read_confidence(folder / "conf.png")[low] == 0).all()  # no depth, no confidence
    assert "below --min-confidence 0.5 written as 0" in capsys.readouterr().err
    assert (folder / "p.png").stat().st_size > 0


def test_refine_confidence_option_errors_are_one_line_before_any_work(pair, capsys):
    folder, _, _ = pair
    base = ["refine", str(folder / "d.png"), str(folder / "c.png"), "-o", str(folder / "o.png")]
    assert main([*base, "--confidence", str(folder / "conf.jpg")]) == 2
    err = capsys.readouterr().err
    assert "unknown format '.jpg'" in err and len(err.strip().splitlines()) == 1
    (folder / "conf.npy").write_bytes(b"")
    assert main([*base, "--confidence", str(folder / "conf.npy")]) == 2
    assert "exists; pass --overwrite" in capsys.readouterr().err
    assert main([*base, "--confidence", str(folder / "o.png")]) == 2
    assert "its own name" in capsys.readouterr().err
    assert main([*base, "--min-confidence", "1.5"]) == 2
    assert "between 0 and 1" in capsys.readouterr().err
    assert not (folder / "o.png").exists()


def test_show_draws_a_confidence_map_beside_the_depth(pair, capsys):
    folder, depth_lr, rgb = pair
    assert main(["refine", str(folder / "d.png"), str(folder / "c.png"), "-o", str(folder / "o.png"),
                 "--method", "bilinear", "--confidence", str(folder / "conf.npy")]) == 0
    assert main(["show", str(folder / "o.png"), "--confidence", str(folder / "conf.npy"), "-o",
                 str(folder / "s.png")]) == 0
    assert (folder / "s.png").stat().st_size > 0
    assert main(["show", str(folder / "d.png"), "--confidence", str(folder / "conf.npy"), "-o",
                 str(folder / "s2.png")]) == 2
    assert "give the confidence map written with this depth" in capsys.readouterr().err


def test_depth_figure_has_a_confidence_panel_and_colorbar():
    from depthrefine import viz

    fig = viz.depth_figure(np.ones((8, 8), np.float32), units="m", confidence=np.full((8, 8), 0.25, np.float32))
    labels = [ax.get_label() for ax in fig.axes]
    assert "panel:confidence" in labels and "colorbar:confidence" in labels
    panel = fig.axes[labels.index("panel:confidence")]
    assert panel.get_images()[0].get_clim() == (0.0, 1.0)


def test_pixel_exact_picture_draws_the_same_window_of_the_confidence_map():
    from depthrefine import viz

    depth = np.arange(64, dtype=np.float32).reshape(8, 8)
    confidence = np.zeros((8, 8), np.float32)
    confidence[:, 4:] = 1.0
    fig = viz.depth_figure(depth, units="m", crop=(2, 2, 4, 3), scale=10, confidence=confidence)
    labels = [ax.get_label() for ax in fig.axes]
    assert labels == ["colorbar:depth", "colorbar:confidence"]
    depth_image, confidence_image = (im.get_array() for im in fig.images)
    assert depth_image.shape == confidence_image.shape == (30, 40, 3)
    # The window's columns 2-3 have confidence 0, columns 4-5 have 1: two colors, split in the middle.
    assert (confidence_image[:, :20] == confidence_image[0, 0]).all()
    assert (confidence_image[:, 20:] == confidence_image[0, -1]).all()
    assert not np.array_equal(confidence_image[0, 0], confidence_image[0, -1])


def test_batch_options_check_the_confidence_settings():
    from depthrefine.batch import BatchOptions, FramePlan
    from depthrefine.methods.registry import get_method

    with pytest.raises(ValueError, match="tif, npy, png"):
        BatchOptions(confidence="jpg")
    with pytest.raises(ValueError, match="between 0 and 1"):
        BatchOptions(min_confidence=1.5)
    with pytest.raises(ValueError, match="confidence=True"):
        FramePlan(get_method("bilinear"), min_confidence=0.5)


def test_run_writes_a_confidence_map_zero_where_unmeasured(captures, tmp_path, capsys):  # noqa: F811
    out, conf = tmp_path / "out.png", tmp_path / "conf.tif"
    assert main(["run", str(captures["depth"]), str(captures["color"]), "-o", str(out), "--rig",
                 str(captures["settings"]), "--refine-method", "bilinear", "--confidence", str(conf)]) == 0, \
        capsys.readouterr().err
    depth = read_depth(out)
    confidence = read_confidence(conf)
    assert confidence.shape == depth.shape
    assert (confidence[depth == 0] == 0).all() and (confidence[depth > 0] > 0).all()


# ---------------------------------------------------------------- batch

def test_batch_writes_confidence_maps_like_refine_with_confidence(tmp_path, capsys):
    pytest.importorskip("distributed")
    from distributed import Client, LocalCluster

    from depthrefine.batch import refine_many

    frames = [hard_scene(seed, 4)[:2] for seed in range(2)]
    src = tmp_path / "seq"
    (src / "depth").mkdir(parents=True)
    (src / "color").mkdir()
    for i, (depth, rgb) in enumerate(frames):
        write_depth(src / "depth" / f"{i:02d}.png", as_depth(depth), dtype=np.uint8)
        write_rgb(src / "color" / f"{i:02d}.png", rgb)
    out = tmp_path / "out"
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        assert main(["batch", str(src), "-o", str(out), "--method", "gbp", "--confidence", "png",
                     "--min-confidence", "0.2", "--scheduler", cluster.scheduler_address]) == 0, \
            capsys.readouterr().err
        got = list(refine_many({i: f for i, f in enumerate(frames)}, client=client, confidence=True))
    record = json.loads((out / "batch.json").read_text())
    assert record["confidence"] == "png" and record["frames"][0]["confidence_output"] == "confidence/00.png"
    for i, (depth, rgb) in enumerate(frames):
        depth_hr, confidence = depthrefine.refine_with_confidence(depth, rgb)
        key, batch_depth, batch_confidence = got[i]
        assert key == i and np.array_equal(batch_depth, depth_hr) and np.array_equal(batch_confidence, confidence)
        written = read_confidence(out / "confidence" / f"{i:02d}.png")
        kept = confidence >= 0.2
        assert np.abs(written[kept] - confidence[kept]).max() <= 1 / 65535 and (written[~kept] == 0).all()
        assert (read_depth(out / f"{i:02d}.png")[~kept] == 0).all()


# ---------------------------------------------------------------- the bench

def test_bench_scores_the_confidence_maps_and_reports_them():
    from depthrefine.bench import report
    from depthrefine.bench.confidence_report import confidence_tables, sparsification_figure
    from depthrefine.bench.runner import BenchCase, run_benchmark

    depth_lr, rgb, gt = hard_scene(1, 4)
    case = BenchCase("toy", "hard", 4, depth_lr, rgb, gt)
    result = run_benchmark([case], ["bilinear", "gbp"], confidence=True)
    for row in result.rows:
        assert 0 < row.ause < row.rmse and row.ause_baseline > 0 and row.confident_rmse < row.doubtful_rmse
    mine, base = result.curves[("toy", "hard", 4, "gbp")]
    assert mine.ause == result.rows[1].ause and base.ause == result.rows[1].ause_baseline
    assert np.isnan(run_benchmark([case], ["bilinear"]).rows[0].ause)  # only when asked
    [table] = confidence_tables(result.rows)
    assert table.header[1:4] == ("×4 AUSE", "×4 baseline", "×4 half") and [r[0] for r in table.body] == \
        ["bilinear", "gbp"]
    assert "## Confidence maps" in report.summary_markdown(result.rows, confidence_plot="s.png")
    assert 'id="confidence"' in report.html_page(result.rows)
    fig = sparsification_figure(result.curves, result.rows)
    assert len(fig.axes[0].lines) == 4  # two methods, gbp's baseline and oracle


@pytest.mark.shared_data
def test_gbp_confidence_beats_the_baseline_on_park_x16():
    from depthrefine.bench.protocols import load_cases

    data = shared_data_path("middlebury2005_park").parent      # skips without the Park data
    case = next(c for c in load_cases(data, "park", (16,)) if c.scene == "art")
    depth_hr, confidence = depthrefine.refine_with_confidence(case.depth_lr, case.rgb_hr)
    mine = sparsification(depth_hr, case.depth_gt, confidence)
    base = sparsification(depth_hr, case.depth_gt, steepness_confidence(depth_hr))
    assert mine.ause < 0.85 * base.ause and mine.half_ratio < 0.5


def test_confidence_is_bit_identical_from_call_to_call_and_thread_to_thread():
    # cv2.magnitude and numpy's ``**`` were not: their vector and scalar paths round differently
    from concurrent.futures import ThreadPoolExecutor

    depth_lr, rgb, _ = hard_scene(1, 4)
    first = depthrefine.refine_with_confidence(depth_lr, rgb)[1]
    with ThreadPoolExecutor(2) as pool:
        runs = [f.result()[1] for f in [pool.submit(depthrefine.refine_with_confidence, depth_lr, rgb)
                                        for _ in range(4)]]
    assert all(np.array_equal(first, again) for again in runs)


def test_temporal_batch_confidence_is_the_frames_own_map_or_the_generic_map_of_the_warm_result():
    pytest.importorskip("distributed")
    from distributed import Client, LocalCluster

    from depthrefine.batch import refine_many
    from depthrefine.bench.synthetic import make_sequence

    frames = [(f.depth_lr, f.rgb_hr) for f in make_sequence(3, (48, 64), 4, seed=5)]
    params = depthrefine.ThesisParams(patches=(2, 2))
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        pairs = dict(enumerate(frames))
        gbp = list(refine_many(pairs, client=client, temporal=True, confidence=True))
        thesis = list(refine_many(pairs, method="thesis", params=params, client=client, temporal=True,
                                  confidence=True))
    for (depth_lr, rgb), (_, _, confidence) in zip(frames, gbp):
        assert np.array_equal(confidence, depthrefine.refine_with_confidence(depth_lr, rgb)[1])
    for (depth_lr, _), (_, depth_hr, confidence) in zip(frames, thesis):
        assert np.array_equal(confidence, generic_confidence(depth_lr, depth_hr))


def test_the_reach_term_looks_a_whole_input_pixel_from_an_edge_on_a_reprojected_input():
    from depthrefine.methods.confidence import error_terms

    depth_lr = np.full((12, 12), 100.0, np.float32)
    depth_lr[:, 6:] = 200.0
    depth_hr = np.full((96, 96), 100.0, np.float32)
    depth_hr[:, 48:] = 200.0                                  # the edge between color columns 47 and 48, x8
    valid = np.ones(depth_lr.shape, bool)
    half, whole = (error_terms(depth_hr, valid, depth_lr, 1.0, reach=r)["reach"] for r in (0.5, 1.0))
    columns = lambda t: np.flatnonzero(t[48] > 0)             # noqa: E731
    assert columns(half).tolist() == list(range(43, 53))      # 4 color pixels each side of the Sobel's two columns
    assert columns(whole).tolist() == list(range(39, 57))     # 8


def test_gbp_gives_a_reprojected_input_the_wider_reach():
    from depthrefine import GbpParams
    from depthrefine.methods.gbp import confidence as gbp_confidence

    depth = np.array([[10, 10, 10, 50, 50, 50]] * 6, np.float32)
    rgb = np.zeros((48, 48, 3), np.uint8)
    rgb[:, 24:] = 200
    _, registered = gbp_confidence.upsample_gbp_with_confidence(depth, rgb)
    _, reprojected = gbp_confidence.upsample_gbp_with_confidence(depth, rgb, params=GbpParams(reprojected=True))
    doubtful = lambda c: int((c < c.max() - 0.05).sum())       # noqa: E731
    assert doubtful(reprojected) > doubtful(registered)
