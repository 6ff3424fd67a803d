"""Building the benchmark report: tables, figures and the HTML page (no file access).

Everything here takes :class:`~depthrefine.bench.BenchRow` lists (and, for
figures, one case with the methods' results) and returns text or a
matplotlib ``Figure``; the ``bench`` command writes them:

- :func:`csv_text`: every score, one row per protocol, scene, scale and method;
- :func:`summary_markdown`: per protocol, the mean of each metric per method
  and scale over the test scenes, the median time per image, and the
  published numbers for the same protocol;
- :func:`terminal_table`: the mean RMSE per method and scale, as plain text;
- :func:`scene_figure`: color, ground truth, each method's result and error
  map, with the same zoomed detail on every panel;
- :func:`rmse_scale_figure`: mean RMSE against scale per method;
- :func:`html_page`: all of it on one page.

Means leave out the peers' tuning scenes (``split == "tune"``) unless a
protocol has no other scene.
"""

from __future__ import annotations

import csv
import html
import io
import math
import statistics
from dataclasses import dataclass
from typing import Any, Mapping, Sequence

import cv2
import numpy as np

from .protocols import PROTOCOLS, left_out_reason
from .runner import METRICS, ROW_FIELDS, BenchCase, BenchRow, mean_and_count, mean_or_nan
from .metrics import EDGE_RADIUS, EDGE_THRESHOLD_LEVELS, depth_edges, valid_mask
from ..viz import colorize_depth, depth_limits, to_rgb8

__all__ = [
    "Table",
    "summary_tables",
    "csv_text",
    "summary_markdown",
    "terminal_table",
    "published_table",
    "choose_zoom",
    "error_map",
    "scene_figure",
    "rmse_scale_figure",
    "html_page",
]

_METRIC_TITLES = {
    "rmse": "RMSE",
    "mae": "MAE",
    "edge_rmse": f"edge RMSE (±{EDGE_RADIUS} px)",
    "bad_1": "bad > 1 (%)",
    "bad_3": "bad > 3 (%)",
    "coverage": "coverage (%)",
}

#: Error maps are drawn from 0 to this many levels (larger errors saturate).
ERROR_MAP_MAX = 10.0


@dataclass(frozen=True)
class Table:
    """A table to render as Markdown, HTML or text."""

    title: str
    header: tuple[str, ...]
    body: tuple[tuple[str, ...], ...]
    note: str = ""


# ---------------------------------------------------------------- aggregation

def _methods_in_order(rows: Sequence[BenchRow]) -> list[str]:
    seen: list[str] = []
    for r in rows:
        if r.method not in seen:
            seen.append(r.method)
    return seen


def _protocols_in_order(rows: Sequence[BenchRow]) -> list[str]:
    present = {r.protocol for r in rows}
    return [p for p in PROTOCOLS if p in present] + sorted(present - set(PROTOCOLS))


def _scored_rows(rows: Sequence[BenchRow], protocol: str) -> tuple[list[BenchRow], bool]:
    """The rows a protocol's means use: its test rows, or all rows if it has none."""
    mine = [r for r in rows if r.protocol == protocol]
    test = [r for r in mine if r.split == "test"]
    return (test, False) if test else (mine, True)


def _fmt(value: float, metric: str = "rmse") -> str:
    if value is None or not math.isfinite(value):
        return "–"
    if metric in ("bad_1", "bad_3", "coverage"):
        return f"{100.0 * value:.1f}"
    if metric == "seconds":
        return f"{value:.3f}" if value < 1 else f"{value:.2f}"
    return f"{value:.2f}"


def summary_tables(rows: Sequence[BenchRow]) -> list[Table]:
    """Per protocol: mean RMSE per method x scale, then every metric per method and scale.

    Examples
    --------
    >>> row = BenchRow("park", "art", 4, "bilinear", "test", 2.0, 1.0, 4.0, 0.5, 0.1, 1.0, 0.01, 1.5)
    >>> [t.title.split(":")[0] for t in summary_tables([row])]
    ['park', 'park']
    """
    tables: list[Table] = []
    methods = _methods_in_order(rows)
    for protocol in _protocols_in_order(rows):
        scored, fallback = _scored_rows(rows, protocol)
        scales = sorted({r.scale for r in scored})
        scenes = sorted({r.scene for r in scored})
        note = (f"mean over {len(scenes)} scene(s): {', '.join(scenes)}"
                + (" (only tuning scenes are present, so they are included)" if fallback else ""))
        tuned = sorted({r.scene for r in rows if r.protocol == protocol and r.split == "tune"})
        if tuned and not fallback:
            why = ", ".join(f"{s} ({left_out_reason(protocol, s) or 'tuning scene'})" for s in tuned)
            note += f"; left out: {why}"
        counts = {(m, s): mean_and_count(r.rmse for r in scored if r.method == m and r.scale == s)
                  for m in methods for s in scales}
        full = {s: max((counts[m, s][1] for m in methods), default=0) for s in scales}
        short = sorted({f"{m} ×{s}" for (m, s), (_, n) in counts.items() if 0 < n < full[s] or (n == 0 and full[s])})
        if short:
            note += ("; (n=k): that mean is over only k scene(s) with a finite score, fewer than the other "
                     f"methods' ({', '.join(short)})")
        body = []
        for m in methods:
            cells = [m]
            for s in scales:
                value, n = counts[m, s]
                cells.append(_fmt(value) + (f" (n={n})" if 0 < n < full[s] else ""))
            times = [r.seconds for r in scored if r.method == m]
            cells.append(_fmt(statistics.median(times), "seconds") if times else "–")
            body.append(tuple(cells))
        tables.append(Table(
            title=f"{protocol}: mean RMSE — {PROTOCOLS[protocol].title if protocol in PROTOCOLS else protocol}",
            header=("method", *[f"×{s}" for s in scales], "s / image (median)"),
            body=tuple(body), note=note,
        ))
        body = []
        for m in methods:
            for s in scales:
                sel = [r for r in scored if r.method == m and r.scale == s]
                if not sel:
                    continue
                cells = [m, f"×{s}"]
                for k in METRICS:
                    value, n = mean_and_count(getattr(r, k) for r in sel)
                    cells.append(_fmt(value, k) + (f" (n={n})" if 0 < n < len(sel) else ""))
                cells.append(_fmt(statistics.median(r.seconds for r in sel), "seconds"))
                body.append(tuple(cells))
        mp = mean_or_nan(r.megapixels for r in scored)
        tables.append(Table(
            title=f"{protocol}: all metrics (means per method and scale)",
            header=("method", "scale", *[_METRIC_TITLES[k] for k in METRICS], "s / image"),
            body=tuple(body),
            note=f"{note}; images of {mp:.2f} MP on average; depth edges: jumps of ≥ "
                 f"{EDGE_THRESHOLD_LEVELS:g} levels between 4-neighbours of the ground truth",
        ))
    return tables


def published_table(rows: Sequence[BenchRow]) -> list[Table]:
    """Our RMSE beside the published numbers of the same protocol and scale.

    Per scene where the source gives per-scene numbers (``Protocol.published_scenes``),
    else the mean per scale (``Protocol.published_means``; ours over the test
    scenes, with the number of scenes averaged). Each published row names
    its source and how many images it averages over.
    """
    tables = []
    methods = _methods_in_order(rows)
    for protocol, scale, pub in [(p.name, s, pub) for p in PROTOCOLS.values() for s, pub in p.published_scenes.items()]:
        scenes = pub["scenes"]
        ours = {(r.method, r.scene): r.rmse for r in rows if r.protocol == protocol and r.scale == scale}
        if not any(s == scene for _, s in ours for scene in scenes):
            continue
        body = []
        for name, entry in pub["rows"].items():
            values = entry["values"]
            body.append((f"{name} [published]", *[_fmt(values.get(s, float("nan"))) for s in scenes],
                         _fmt(mean_or_nan(values.get(s, float("nan")) for s in scenes))))
        for m in methods:
            vals = [ours.get((m, s), float("nan")) for s in scenes]
            body.append((f"{m} [this run]", *[_fmt(v) for v in vals], _fmt(mean_or_nan(vals))))
        sources = "; ".join(f"{name}: {entry['source']}" for name, entry in pub["rows"].items())
        tables.append(Table(
            title=f"{protocol} ×{scale}: this run beside the published numbers",
            header=("method", *scenes, "mean"), body=tuple(body),
            note=f"Sources: {sources}. Only numbers stated in the issue or the dataset READMEs are quoted; "
                 "the ATGV-Net paper's other rows (bilinear, guided filter, ATGV-Net) are not.",
        ))
    for protocol, entries in [(p.name, p.published_means) for p in PROTOCOLS.values() if p.published_means]:
        scored = [r for r in _scored_rows(rows, protocol)[0]]
        scales = sorted({s for e in entries for s in e["values"]})
        if not scored:
            continue
        body = [(f"{e['name']} [published]", *[_fmt(e["values"].get(s, float("nan"))) for s in scales], e["images"])
                for e in entries]
        for m in methods:
            cells, counts = [], set()
            for s in scales:
                value, n = mean_and_count(r.rmse for r in scored if r.method == m and r.scale == s)
                cells.append(_fmt(value))
                if n:
                    counts.add(n)
            body.append((f"{m} [this run]", *cells, "/".join(map(str, sorted(counts))) or "0"))
        sources = "; ".join(f"{e['name']}: {e['source']}" for e in entries)
        tables.append(Table(
            title=f"{protocol}: this run's means beside the published means",
            header=("method", *[f"×{s}" for s in scales], "images"), body=tuple(body),
            note=f"Sources: {sources}. Published means are over the images stated; ours are over this run's "
                 "test scenes (the held-out and left-out scenes are not in them) with the 6-px border crop, "
                 "so they are not the same average.",
        ))
    return tables


# ---------------------------------------------------------------- text output

def csv_text(rows: Sequence[BenchRow]) -> str:
    """Every row as CSV (header :data:`~depthrefine.bench.ROW_FIELDS`).

    Examples
    --------
    >>> row = BenchRow("park", "art", 4, "bilinear", "test", 2.0, 1.0, 4.0, 0.5, 0.1, 1.0, 0.01, 1.5)
    >>> csv_text([row]).splitlines()[1]
    'park,art,4,bilinear,test,2,1,4,0.5,0.1,1,0.01,1.5'
    """
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(ROW_FIELDS)
    for r in rows:
        writer.writerow([_csv_cell(v) for v in r.to_dict().values()])
    return buf.getvalue()


def _csv_cell(value: Any) -> str:
    if isinstance(value, float):
        return "nan" if not math.isfinite(value) else f"{value:.6g}"
    return str(value)


def _markdown_table(table: Table) -> str:
    lines = [f"### {table.title}", ""]
    if table.note:
        lines += [f"_{table.note}_", ""]
    lines.append("| " + " | ".join(table.header) + " |")
    lines.append("|" + "|".join("---" if i == 0 else "---:" for i in range(len(table.header))) + "|")
    lines += ["| " + " | ".join(row) + " |" for row in table.body]
    return "\n".join(lines) + "\n"


def _text_table(table: Table) -> str:
    widths = [max(len(str(c)) for c in col) for col in zip(table.header, *table.body)]
    fmt = lambda cells: "  ".join(  # noqa: E731
        (c.ljust(w) if i == 0 else c.rjust(w)) for i, (c, w) in enumerate(zip(cells, widths)))
    lines = [table.title, fmt(table.header), fmt(tuple("-" * w for w in widths))]
    lines += [fmt(row) for row in table.body]
    if table.note:
        lines.append(f"({table.note})")
    return "\n".join(lines)


def terminal_table(rows: Sequence[BenchRow]) -> str:
    """The mean-RMSE tables as aligned plain text, for the terminal."""
    return "\n\n".join(_text_table(t) for t in summary_tables(rows)[::2]) + "\n"


def summary_markdown(
    rows: Sequence[BenchRow],
    *,
    params_used: Mapping[str, Mapping[str, Any]] | None = None,
    notes: Sequence[str] = (),
    figures: Sequence[tuple[str, str]] = (),
    plot: str | None = None,
) -> str:
    """The Markdown summary: tables, published numbers, parameters, notes and figure links.

    Parameters
    ----------
    rows : sequence of BenchRow
    params_used : mapping, optional
        ``{method: {field: value}}`` of the parameters each method ran with.
    notes : sequence of str
        Extra lines (e.g. that the fast bilateral solver is unavailable).
    figures : sequence of (caption, file name)
    plot : str, optional
        File name of the RMSE-vs-scale plot.
    """
    out = ["# depthrefine benchmark", ""]
    n_cases = len({(r.protocol, r.scene, r.scale) for r in rows})
    out.append(f"{len(rows)} runs: {len(_methods_in_order(rows))} methods on {n_cases} cases "
               f"(protocol, scene, scale). Every score is in `scores.csv`. Lower is better everywhere.")
    out.append("")
    for note in notes:
        out.append(f"- {note}")
    if notes:
        out.append("")
    out.append("## Results")
    out.append("")
    for t in summary_tables(rows):
        out.append(_markdown_table(t))
    for t in published_table(rows):
        out.append(_markdown_table(t))
    if params_used:
        out.append("## Parameters")
        out.append("")
        for method, fields in params_used.items():
            text = ", ".join(f"{k} = {v}" for k, v in fields.items()) if fields else "(none)"
            out.append(f"- `{method}`: {text}")
        out.append("")
    if plot:
        out += ["## RMSE against scale", "", f"![RMSE against scale]({plot})", ""]
    if figures:
        out += ["## Figures", ""]
        out += [f"- [{caption}]({name})" for caption, name in figures]
        out.append("")
    return "\n".join(out)


# ---------------------------------------------------------------- figures

def choose_zoom(depth_gt: np.ndarray, *, fraction: float = 0.25) -> tuple[int, int, int, int]:
    """The detail window with the most ground-truth depth edges, ``(row0, row1, col0, col1)``.

    The window is ``fraction`` of the image's height and width; candidates
    lie on a grid of a quarter window, the first best one wins (deterministic).

    Examples
    --------
    >>> gt = np.full((40, 40), 50.0); gt[30:, 30:] = 200.0
    >>> choose_zoom(gt)
    (28, 38, 28, 38)
    """
    gt = np.asarray(depth_gt, dtype=np.float64)
    rows, cols = gt.shape
    wr, wc = max(1, int(rows * fraction)), max(1, int(cols * fraction))
    edges = depth_edges(gt, threshold=EDGE_THRESHOLD_LEVELS).astype(np.float64)
    integral = np.pad(edges.cumsum(0).cumsum(1), ((1, 0), (1, 0)))
    r0s = np.arange(0, rows - wr + 1, max(1, wr // 4))
    c0s = np.arange(0, cols - wc + 1, max(1, wc // 4))
    R, C = np.meshgrid(r0s, c0s, indexing="ij")
    counts = integral[R + wr, C + wc] - integral[R, C + wc] - integral[R + wr, C] + integral[R, C]
    i, j = np.unravel_index(int(np.argmax(counts)), counts.shape)
    r0, c0 = int(r0s[i]), int(c0s[j])
    return r0, r0 + wr, c0, c0 + wc


def error_map(depth_pred: np.ndarray, depth_gt: np.ndarray, *, vmax: float = ERROR_MAP_MAX,
              border: int = 0) -> np.ndarray:
    """``|pred - gt|`` as RGB uint8 (inferno, 0..``vmax``); unscored pixels black.

    Examples
    --------
    >>> error_map(np.array([[1.0, 5.0]]), np.array([[1.0, np.nan]])).tolist()
    [[[0, 0, 4], [0, 0, 0]]]
    """
    gt = np.asarray(depth_gt, dtype=np.float64)
    pred = np.asarray(depth_pred, dtype=np.float64)
    scored = valid_mask(gt, border=border) & np.isfinite(pred)
    err = np.zeros(gt.shape, np.uint8)
    err[scored] = np.clip(np.abs(pred[scored] - gt[scored]) / vmax * 255.0 + 0.5, 0, 255).astype(np.uint8)
    rgb = cv2.cvtColor(cv2.applyColorMap(err, cv2.COLORMAP_INFERNO), cv2.COLOR_BGR2RGB)
    rgb[~scored] = 0
    return rgb


def scene_figure(case: BenchCase, results: Mapping[str, np.ndarray], *,
                 rmse: Mapping[str, float] | None = None, zoom: tuple[int, int, int, int] | None = None):
    """Color, ground truth, each method's result and its error map, each with the same detail.

    Rows: full depth, full error map, zoomed depth, zoomed error. Depth maps
    share the ground truth's color scale; error maps go from 0 (black) to
    :data:`ERROR_MAP_MAX` levels (yellow).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    zoom = choose_zoom(case.depth_gt) if zoom is None else zoom
    r0, r1, c0, c1 = zoom
    limits = depth_limits(case.depth_gt)
    columns = [("color", to_rgb8(case.rgb_hr), None),
               ("ground truth", colorize_depth(case.depth_gt, limits=limits), None)]
    for method, depth in results.items():
        caption = method if rmse is None or method not in rmse else f"{method}\nRMSE {rmse[method]:.2f}"
        columns.append((caption, colorize_depth(depth, limits=limits),
                        error_map(depth, case.depth_gt, border=case.border)))
    n = len(columns)
    h, w = case.depth_gt.shape
    panel = 1.7
    fig = Figure(figsize=(panel * n, panel * (h / w * 2 + (r1 - r0) / (c1 - c0) * 2) + 0.9), dpi=100,
                 layout="constrained")
    axes = fig.subplots(4, n, squeeze=False)
    for col, (caption, image, err) in enumerate(columns):
        panels = (image, err, image[r0:r1, c0:c1], None if err is None else err[r0:r1, c0:c1])
        for row, img in enumerate(panels):
            ax = axes[row, col]
            ax.set_axis_off()
            if img is None:
                continue
            ax.imshow(img, interpolation="nearest" if row >= 2 else "antialiased")
            if row < 2:
                ax.add_patch(Rectangle((c0, r0), c1 - c0, r1 - r0, fill=False, edgecolor="white", linewidth=0.8))
        axes[0, col].set_title(caption, fontsize=7)
    axes[1, 0].text(0.5, 0.5, f"error maps:\nblack 0 → yellow\n≥ {ERROR_MAP_MAX:g} levels",
                    ha="center", va="center", fontsize=7, transform=axes[1, 0].transAxes)
    fig.suptitle(f"{case.protocol} · {case.scene} · ×{case.scale}: results (rows 1, 3) and |error| (rows 2, 4); "
                 f"rows 3-4 zoom on rows {r0}-{r1}, cols {c0}-{c1}", fontsize=8)
    return fig


def rmse_scale_figure(rows: Sequence[BenchRow]):
    """Mean RMSE (test scenes) against scale, one line per method, one panel per protocol."""
    from matplotlib.figure import Figure

    protocols = _protocols_in_order(rows)
    methods = _methods_in_order(rows)
    fig = Figure(figsize=(4.2 * max(1, len(protocols)), 3.6), dpi=110, layout="constrained")
    axes = fig.subplots(1, max(1, len(protocols)), squeeze=False)[0]
    markers = "os^vDP*Xhd<>"
    for ax, protocol in zip(axes, protocols):
        scored, _ = _scored_rows(rows, protocol)
        scales = sorted({r.scale for r in scored})
        for i, m in enumerate(methods):
            ys = [mean_or_nan(r.rmse for r in scored if r.method == m and r.scale == s) for s in scales]
            ax.plot(scales, ys, marker=markers[i % len(markers)], label=m, linewidth=1.2, markersize=4)
        ax.set_xscale("log", base=2)
        ax.set_xticks(scales, [f"×{s}" for s in scales])
        ax.minorticks_off()
        ax.set_xlabel("scale factor")
        ax.set_ylabel("mean RMSE")
        ax.set_title(protocol, fontsize=10)
        ax.grid(True, alpha=0.3)
    axes[-1].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    return fig


# ---------------------------------------------------------------- HTML

def _html_table(table: Table) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in table.header)
    body = "\n".join("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in row) + "</tr>" for row in table.body)
    note = f'<p class="note">{html.escape(table.note)}</p>' if table.note else ""
    return (f'<h3>{html.escape(table.title)}</h3>{note}\n<table class="scores">\n<thead><tr>{head}</tr></thead>\n'
            f"<tbody>\n{body}\n</tbody></table>")


def html_page(
    rows: Sequence[BenchRow],
    *,
    params_used: Mapping[str, Mapping[str, Any]] | None = None,
    notes: Sequence[str] = (),
    figures: Sequence[tuple[str, str]] = (),
    plot: str | None = None,
    csv_name: str = "scores.csv",
    markdown_name: str = "summary.md",
) -> str:
    """One self-contained HTML page (images by relative file name) showing the whole report.

    After loading, ``<body data-images-loaded="N">`` holds the number of
    images that decoded, so a headless browser can check them.
    """
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8"><title>depthrefine benchmark</title>',
        "<style>body{font-family:sans-serif;margin:1.5em;max-width:1600px}"
        "table.scores{border-collapse:collapse;margin:.5em 0 1.5em}"
        "table.scores td,table.scores th{border:1px solid #bbb;padding:2px 8px;text-align:right}"
        "table.scores td:first-child,table.scores th:first-child{text-align:left}"
        ".note{color:#555;font-size:90%}figure{margin:1em 0}figure img{max-width:100%}"
        "figcaption{font-size:90%;color:#333}</style>",
        "<script>window.addEventListener('load',function(){var n=0;for(var i=0;i<document.images.length;i++)"
        "{var im=document.images[i];if(im.complete&&im.naturalWidth>0){n++;}}"
        "document.body.setAttribute('data-images-loaded',String(n));});</script>",
        "</head><body>",
        "<h1>depthrefine benchmark</h1>",
        f'<p>Every score: <a href="{html.escape(csv_name)}">{html.escape(csv_name)}</a>; '
        f'the same summary as Markdown: <a href="{html.escape(markdown_name)}">{html.escape(markdown_name)}</a>. '
        "Lower is better everywhere.</p>",
    ]
    if notes:
        parts.append("<ul>" + "".join(f"<li>{html.escape(n)}</li>" for n in notes) + "</ul>")
    parts.append('<h2 id="results">Results</h2>')
    parts += [_html_table(t) for t in summary_tables(rows)]
    parts += [_html_table(t) for t in published_table(rows)]
    if params_used:
        parts.append("<h2>Parameters</h2><ul>")
        for method, fields in params_used.items():
            text = ", ".join(f"{k} = {v}" for k, v in fields.items()) if fields else "(none)"
            parts.append(f"<li><code>{html.escape(method)}</code>: {html.escape(text)}</li>")
        parts.append("</ul>")
    if plot:
        parts.append(f'<h2>RMSE against scale</h2><figure><img class="plot" src="{html.escape(plot)}" '
                     'alt="mean RMSE against scale per method"></figure>')
    if figures:
        parts.append('<h2 id="figures">Figures</h2>')
        for caption, name in figures:
            parts.append(f'<figure class="scene"><img src="{html.escape(name)}" alt="{html.escape(caption)}">'
                         f"<figcaption>{html.escape(caption)}</figcaption></figure>")
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"
