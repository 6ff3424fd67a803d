"""The benchmark report (depthrefine.bench.report) and its HTML page, checked in a real headless browser."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from depthrefine.bench import report
from depthrefine.bench import BenchRow, park_case
from depthrefine.cli import main

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


def _row(protocol, scene, scale, method, rmse, split="test", seconds=0.5):
    return BenchRow(protocol, scene, scale, method, split, rmse, rmse / 2, rmse * 2, 0.5, 0.25, 1.0, seconds, 1.5)


def test_summary_means_leave_out_the_tuning_scenes():
    rows = [_row("park", "art", 4, "bilinear", 2.0), _row("park", "books", 4, "bilinear", 4.0),
            _row("park", "dolls", 4, "bilinear", 100.0, split="tune")]
    rmse_table = report.summary_tables(rows)[0]
    assert rmse_table.header[:2] == ("method", "×4")
    assert rmse_table.body == (("bilinear", "3.00", "0.500"),)
    assert "dolls" in rmse_table.note and "left out" in rmse_table.note
    # With only tuning scenes present, they are used (and the note says so).
    only_tune = report.summary_tables([_row("park", "dolls", 4, "bilinear", 7.0, split="tune")])[0]
    assert only_tune.body[0][1] == "7.00" and "only tuning scenes" in only_tune.note


def test_overview_puts_every_protocol_on_one_table_with_the_default_methods_margin():
    rows = [_row("park", "art", 4, "bicubic", 4.0), _row("park", "art", 8, "bicubic", 5.0),
            _row("park", "art", 4, "gbp", 3.0), _row("park", "art", 8, "gbp", 6.0),
            _row("park", "art", 4, "bilinear", 1.0), _row("park", "art", 8, "bilinear", 9.0),
            _row("park", "dolls", 4, "gbp", 100.0, split="tune"),
            _row("lu", "a", 4, "bicubic", 2.0), _row("lu", "a", 4, "gbp", 1.0)]
    lines = report.overview_markdown(rows).splitlines()
    assert lines[0] == "| method | park ×4/×8 | lu ×4 |"
    assert lines[2] == "| bicubic | 4.00 / **5.00** | 2.00 |"
    assert lines[3] == "| gbp (default) | 3.00 / 6.00 | **1.00** |"  # the tuning scene is left out
    assert lines[4] == "| bilinear | **1.00** / 9.00 | – |"
    # bilinear is not a peer of the margin row; above the best peer the margin is negative.
    assert lines[5] == "| gbp below the best peer | 25 % / -20 % | 50 % |"
    assert "### All protocols: mean RMSE" in report.summary_markdown(rows)
    assert report.overview_markdown([]) == ""


def test_published_numbers_sit_beside_ours():
    rows = [_row("park", s, 4, "thesis", v) for s, v in (("art", 3.0), ("books", 2.0), ("moebius", 1.0))]
    (table,) = report.published_table(rows)
    assert table.header == ("method", "art", "books", "moebius", "mean")
    assert table.body[0] == ("TGV (Ferstl et al. 2013) [published]", "4.06", "2.21", "2.03", "2.77")
    assert table.body[1] == ("PIL bicubic (README sanity row) [published]", "5.60", "4.37", "4.31", "4.76")
    assert table.body[2] == ("thesis [this run]", "3.00", "2.00", "1.00", "2.00")
    assert "noisy_ferstl_x4" in table.note and "middlebury2005_park/README.md" in table.note
    assert report.published_table([_row("tof", "art", 4, "thesis", 1.0)]) == []
    md = report.summary_markdown(rows, notes=["a note"], figures=[("cap", "f.png")], plot="p.png")
    assert "4.06" in md and "- a note" in md and "](f.png)" in md and "![RMSE against scale](p.png)" in md


def test_published_means_for_the_bicubic_protocols():
    rows = [_row("middlebury30", "Middlebury_02", s, "thesis", 1.0 * s) for s in (4, 8, 16)]
    rows += [_row("middlebury30", "Middlebury_06", s, "thesis", 3.0 * s) for s in (4, 8, 16)]
    rows += [_row("middlebury30", "Middlebury_14", 4, "thesis", 99.0, split="tune")]
    (table,) = report.published_table(rows)
    assert table.header == ("method", "×4", "×8", "×16", "images")
    body = {r[0]: r[1:] for r in table.body}
    assert body["DCTNet [published]"] == ("1.10", "2.05", "4.19", "30")
    assert body["Bicubic (DKN/JIIF-era tables) [published]"] == ("2.28", "3.98", "6.37", "30")
    assert body["PIL bicubic (README sanity row) [published]"][:3] == ("2.21", "3.85", "6.14")
    assert body["thesis [this run]"] == ("8.00", "16.00", "32.00", "2")
    lu = report.published_table([_row("lu", "RGBD_01", 4, "thesis", 1.0)])[0]
    assert {r[0]: r[1:] for r in lu.body}["DCTNet [published]"] == ("0.88", "1.85", "4.39", "6")


def test_means_over_fewer_scenes_are_marked_and_left_out_scenes_named():
    rows = [_row("middlebury30", "Middlebury_02", 4, "thesis", 2.0), _row("middlebury30", "Middlebury_06", 4, "thesis", 4.0),
            _row("middlebury30", "Middlebury_02", 4, "guided", 1.0),
            _row("middlebury30", "Middlebury_06", 4, "guided", float("nan")),
            _row("middlebury30", "Middlebury_14", 4, "guided", 50.0, split="tune")]
    rmse_table, metrics_table = report.summary_tables(rows)[:2]
    assert rmse_table.body[0][1] == "3.00" and rmse_table.body[1][1] == "1.00 (n=1)"
    assert "guided ×4" in rmse_table.note and "n=k" in rmse_table.note
    assert "Middlebury_14 (Dolls" in rmse_table.note and "left out" in rmse_table.note
    assert metrics_table.body[1][2] == "1.00 (n=1)"


def test_csv_and_terminal_table():
    rows = [_row("lu", "RGBD_01", 8, "nearest", 2.5), _row("lu", "RGBD_01", 8, "guided", float("nan"))]
    lines = report.csv_text(rows).splitlines()
    assert lines[0].split(",")[:4] == ["protocol", "scene", "scale", "method"]
    assert lines[2].split(",")[5] == "nan" and len(lines) == 3
    text = report.terminal_table(rows)
    assert re.search(r"nearest\s+2\.50", text) and re.search(r"guided\s+–", text)


def test_scene_figure_has_both_colorbars_one_depth_range_and_the_rmse_in_titles():
    gt = np.tile(np.repeat(np.array([40, 200], np.uint8), 16), (32, 1))
    case = park_case("toy", 4, gt[1::4, 1::4].copy(), np.zeros((32, 32, 3), np.uint8), gt)
    results = {"nearest": case.depth_gt + 1, "bilinear": case.depth_gt}
    fig = report.scene_figure(case, results, rmse={"nearest": 1.0})
    panels = {ax.get_title(): ax for ax in fig.axes if ax.get_label().startswith("panel:")}
    assert {"ground truth", "color", "nearest: RMSE 1.00", "bilinear", "nearest: |error|"} <= set(panels)
    depth = [ax.get_images()[-1] for ax in fig.axes if ax.get_label().startswith("panel:depth")]
    assert len(depth) == 6 and {im.get_clim() for im in depth} == {(40.0, 200.0)}   # the ground truth's range
    errors = [ax.get_images()[-1] for ax in fig.axes if ax.get_label().startswith("panel:error")]
    assert {im.get_clim() for im in errors} == {(0.0, 0.5)}  # median over methods of the 95th percentiles 1 and 0
    np.testing.assert_array_equal(panels["nearest: |error|"].get_images()[0].get_array(), np.ones((32, 32)))
    bars = {ax.get_label(): ax for ax in fig.axes if ax.get_label().startswith("colorbar:")}
    assert bars["colorbar:depth"].get_xlabel() == "depth (disparity levels)"
    assert bars["colorbar:error"].get_xlabel() == "|error| (disparity levels)"
    assert [t.get_text() for t in fig.legends[0].get_texts()] == ["gray: no measurement"]
    err = report.error_map(case.depth_gt + 20, case.depth_gt, border=2)
    assert err.shape == (32, 32) and np.isnan(err[:2]).all() and (err[2:-2, 2:-2] == 20).all()
    fig = report.rmse_scale_figure([_row("lu", "a", 4, "m", 1.0), _row("lu", "a", 8, "m", 2.0)])
    assert fig.axes[0].lines[0].get_ydata().tolist() == [1.0, 2.0]


def test_best_value_of_each_column_is_marked():
    table = report.Table("t", ("method", "scale", "RMSE", "coverage (%)", "s / image"),
                         (("a", "×4", "2.00", "90.0", "0.5"), ("b", "×4", "1.00 (n=1)", "99.0", "0.5"),
                          ("a", "×8", "3.00", "–", "1.0"), ("b", "×8", "4.00", "95.0", "2.0")))
    # Per scale: RMSE lowest, coverage highest; a lone number, or all equal (0.5, 0.5), is no "best".
    assert report.best_cells(table) == {(1, 2), (1, 3), (2, 2), (2, 4)}
    tie = report.Table("t", ("method", "×4"), (("a", "1.00"), ("b", "1.00"), ("c", "2.00")))
    assert report.best_cells(tie) == {(0, 1), (1, 1)}
    rows = [_row("park", "art", 4, "bilinear", 2.0), _row("park", "art", 4, "thesis", 1.0)]
    html_text = report.html_page(rows, figures=[("cap", "f.png")], plot="p.png")
    assert '<td class="best">1.00</td>' in html_text and "<td>2.00</td>" in html_text
    assert '<a href="f.png"><img src="f.png"' in html_text and "click to enlarge" in html_text
    assert '<a href="p.png"><img class="plot"' in html_text and 'name="viewport"' in html_text
    assert "| thesis | **1.00** |" in report.summary_markdown(rows)


def _synthetic_lu_folder(root: Path, rng) -> Path:
    """Two 96 x 128 RGB-D pairs in the lu6 layout."""
    lu = root / "lu6"
    (lu / "RGB").mkdir(parents=True)
    (lu / "Depth").mkdir()
    for i in (1, 2):
        depth = np.full((96, 128), 60, np.uint8)
        depth[20:70, 30 + 10 * i:90] = 180
        rgb = np.where(depth[..., None] > 100, np.uint8(200), np.uint8(40)) + rng.integers(0, 20, (96, 128, 3))
        Image.fromarray(rgb.astype(np.uint8)).save(lu / "RGB" / f"RGBD_0{i}_ouput_color.png")
        Image.fromarray(depth).save(lu / "Depth" / f"RGBD_0{i}_output_depth.png")
    return root


def test_html_report_in_a_headless_browser(tmp_path, rng, capsys):
    data = _synthetic_lu_folder(tmp_path / "data", rng)
    out = tmp_path / "report"
    status = main(["bench", "--data", str(data), "--protocol", "lu", "--methods", "nearest,bilinear,guided",
                   "--scales", "4,8", "--report", str(out)])
    assert status == 0, capsys.readouterr().err
    page = out / "index.html"
    text = page.read_text()
    # the RMSE table, the all-metrics table, the published means, the confidence maps' AUSE
    assert text.count('<table class="scores">') == 4
    assert text.count('<td class="best">') >= 4
    n_images = text.count("<img ")
    assert n_images == 2 + 2  # the RMSE plot, the sparsification curves and one figure per scene (at x8)
    if CHROMIUM is None:
        pytest.skip("chromium is not installed (CI installs it with apt-get when it can)")
    profile = tmp_path / "chromium-profile"
    cmd = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
           "--disable-background-networking", "--disable-component-update", "--disable-sync",
           f"--user-data-dir={profile}", "--virtual-time-budget=5000", "--dump-dom", page.as_uri()]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    dom = proc.stdout
    assert proc.returncode == 0 and "<html" in dom, proc.stderr[-2000:]
    # The browser parsed the tables and decoded every image (the page counts them on load).
    assert dom.count('<table class="scores">') == 4
    assert re.search(r'<td>bilinear</td><td( class="best")?>[0-9.]+</td><td( class="best")?>[0-9.]+</td>', dom)
    loaded = re.search(r'data-images-loaded="(\d+)"', dom)
    assert loaded and int(loaded.group(1)) == n_images, dom[:500]
    shot = tmp_path / "page.png"
    proc = subprocess.run([*cmd[:-2], f"--screenshot={shot}", "--window-size=1200,900", page.as_uri()],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0 and shot.is_file(), proc.stderr[-2000:]
    pixels = np.asarray(Image.open(shot).convert("L"))
    assert pixels.shape == (900, 1200) and pixels.std() > 5  # something was drawn
