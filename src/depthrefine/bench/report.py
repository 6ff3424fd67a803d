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

The figures live in :mod:`depthrefine.bench.figures` and are re-exported here.

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

from ..methods._names import DEFAULT_METHOD
from .figures import ERROR_PERCENTILE, choose_zoom, error_map, error_scale, scene_figure, zoom_where_methods_differ
from .protocols import PROTOCOLS, left_out_reason
from .runner import METRICS, ROW_FIELDS, BenchRow, mean_and_count, mean_or_nan
from .metrics import EDGE_RADIUS, EDGE_THRESHOLD_LEVELS

__all__ = [
    "Table",
    "summary_tables",
    "OVERVIEW_PEERS",
    "overview_markdown",
    "csv_text",
    "summary_markdown",
    "terminal_table",
    "published_table",
    "ERROR_PERCENTILE",
    "choose_zoom",
    "zoom_where_methods_differ",
    "error_map",
    "error_scale",
    "best_cells",
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


def _row_groups(rows: Sequence[BenchRow]) -> list[tuple[str, str, list[BenchRow]]]:
    """``(label, protocol, rows)`` per protocol; the ``sensor`` protocol's split per sensor model (``<scene>-<model>``)."""
    groups = []
    for protocol in _protocols_in_order(rows):
        mine = [r for r in rows if r.protocol == protocol]
        models = sorted({r.scene.rsplit("-", 1)[-1] for r in mine}) if protocol == "sensor" else []
        groups += ([(f"{protocol} {m}", protocol, [r for r in mine if r.scene.endswith(f"-{m}")]) for m in models]
                   or [(protocol, protocol, mine)])
    return groups


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
    for label, protocol, group in _row_groups(rows):
        scored, fallback = _scored_rows(group, protocol)
        scales = sorted({r.scale for r in scored})
        scenes = sorted({r.scene for r in scored})
        note = (f"mean over {len(scenes)} scene(s): {', '.join(scenes)}"
                + (" (only tuning scenes are present, so they are included)" if fallback else ""))
        tuned = sorted({r.scene for r in group if r.split == "tune"})
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
            title=f"{label}: mean RMSE — {PROTOCOLS[protocol].title if protocol in PROTOCOLS else protocol}",
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
            title=f"{label}: all metrics (means per method and scale)",
            header=("method", "scale", *[_METRIC_TITLES[k] for k in METRICS], "s / image"),
            body=tuple(body),
            note=f"{note}; images of {mp:.2f} MP on average; depth edges: jumps of ≥ "
                 f"{EDGE_THRESHOLD_LEVELS:g} levels between 4-neighbours of the ground truth",
        ))
    return tables


#: The peers the default method is measured against in :func:`overview_markdown`
#: (issue 9: bicubic and the tuned OpenCV filters; nearest and bilinear are shown, not compared).
OVERVIEW_PEERS = ("bicubic", "jbf", "guided", "fgs", "wmf")


def overview_markdown(rows: Sequence[BenchRow], *, method: str = DEFAULT_METHOD,
                      peers: Sequence[str] = OVERVIEW_PEERS, metric: str = "rmse") -> str:
    """Every protocol on one table: mean RMSE (or another ``metric``) per method, the scales of a protocol in one cell.

    A cell reads ``×4 / ×8 / ×16``; the best value of each protocol and scale
    is in bold. A last row gives how far ``method`` (the default) is below
    the best of ``peers`` present, in percent of that peer's RMSE (negative:
    above it). Means leave out tuning scenes, as in :func:`summary_tables`.
    This is the table the README quotes. Returns "" when there are no rows.

    Examples
    --------
    >>> rows = [BenchRow("park", "art", s, m, "test", v, 1.0, 1.0, 0.5, 0.1, 1.0, 0.01, 1.5)
    ...         for s, m, v in [(4, "bicubic", 2.0), (8, "bicubic", 4.0), (4, "gbp", 1.5), (8, "gbp", 3.0)]]
    >>> print(overview_markdown(rows).splitlines()[-1])
    | gbp below the best peer | 25 % / 25 % |
    """
    groups = _row_groups(rows)
    if not groups:
        return ""
    protocols = [label for label, _, _ in groups]
    methods = _methods_in_order(rows)
    means: dict[tuple[str, str, int], float] = {}
    scales: dict[str, list[int]] = {}
    for label, protocol, group in groups:
        scored, _ = _scored_rows(group, protocol)
        scales[label] = sorted({r.scale for r in scored})
        for m in methods:
            for s in scales[label]:
                means[label, m, s] = mean_or_nan(getattr(r, metric) for r in scored if r.method == m and r.scale == s)

    def best(protocol: str, s: int, among: Sequence[str]) -> float:
        values = [means[protocol, m, s] for m in among if math.isfinite(means.get((protocol, m, s), math.nan))]
        return min(values) if values else math.nan

    header = ["method"] + [f"{p} " + "/".join(f"×{s}" for s in scales[p]) for p in protocols]
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    for m in methods:
        cells = [f"{m} (default)" if m == method else m]
        for p in protocols:
            parts = []
            for s in scales[p]:
                value = means[p, m, s]
                text = _fmt(value)
                top = best(p, s, methods)
                parts.append(f"**{text}**" if math.isfinite(value) and value == top and len(methods) > 1 else text)
            cells.append(" / ".join(parts))
        lines.append("| " + " | ".join(cells) + " |")
    present = [q for q in peers if q in methods and q != method]
    if method in methods and present:
        cells = [f"{method} below the best peer"]
        for p in protocols:
            parts = []
            for s in scales[p]:
                ours, theirs = means[p, method, s], best(p, s, present)
                parts.append(f"{round(100.0 * (theirs - ours) / theirs)} %"
                             if math.isfinite(ours) and math.isfinite(theirs) and theirs > 0 else "–")
            cells.append(" / ".join(parts))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


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
    'park,art,4,bilinear,test,2,1,4,0.5,0.1,1,0.01,1.5,nan,nan,nan,nan'
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


def _number(cell: str) -> float | None:
    """The number a table cell shows ("5.45", "5.45 (n=2)"), None for "–" and words."""
    head = cell.split(" ", 1)[0]
    try:
        value = float(head)
    except ValueError:
        return None
    return value if math.isfinite(value) else None


#: What the tables' readers need to know about "better".
_BETTER = ("Lower is better, except coverage (higher is better); the best value of each column (per scale in "
           "the all-metrics tables) is in bold on green.")
#: Columns where a larger value is better (everything else: smaller is better).
_HIGHER_IS_BETTER = (_METRIC_TITLES["coverage"],)
#: Columns that are not scores (never highlighted).
_NOT_SCORES = ("method", "scale", "images")


def best_cells(table: Table) -> frozenset[tuple[int, int]]:
    """``(row, column)`` of the best value in each score column of ``table``.

    Smaller is better except in :data:`_HIGHER_IS_BETTER` columns; when the
    table has a ``scale`` column, the best is taken per scale. Ties are all
    marked; a column with fewer than two numbers, or all of them equal, has
    no best.

    Examples
    --------
    >>> t = Table("t", ("method", "×4"), (("a", "2.00"), ("b", "1.00 (n=1)"), ("c", "–")))
    >>> sorted(best_cells(t))
    [(1, 1)]
    """
    header = table.header
    group_col = header.index("scale") if "scale" in header else None
    best: set[tuple[int, int]] = set()
    for col, name in enumerate(header):
        if col == 0 or name in _NOT_SCORES:
            continue
        sign = -1.0 if name in _HIGHER_IS_BETTER else 1.0
        groups: dict[str, list[tuple[float, int]]] = {}
        for row, cells in enumerate(table.body):
            value = _number(cells[col])
            if value is not None:
                key = cells[group_col] if group_col is not None else ""
                groups.setdefault(key, []).append((sign * value, row))
        for values in groups.values():
            if len(values) < 2 or len({v for v, _ in values}) == 1:  # nothing to compare, or all equal
                continue
            top = min(v for v, _ in values)
            best.update((row, col) for v, row in values if v == top)
    return frozenset(best)


def _markdown_table(table: Table) -> str:
    lines = [f"### {table.title}", ""]
    if table.note:
        lines += [f"_{table.note}_", ""]
    lines.append("| " + " | ".join(table.header) + " |")
    lines.append("|" + "|".join("---" if i == 0 else "---:" for i in range(len(table.header))) + "|")
    best = best_cells(table)
    lines += ["| " + " | ".join(f"**{c}**" if (i, j) in best else c for j, c in enumerate(row)) + " |"
              for i, row in enumerate(table.body)]
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
    confidence_plot: str | None = None,
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
    confidence_plot : str, optional
        File name of the sparsification curves (:mod:`.confidence_report`).
    """
    from .confidence_report import confidence_markdown

    out = ["# depthrefine benchmark", ""]
    n_cases = len({(r.protocol, r.scene, r.scale) for r in rows})
    out.append(f"{len(rows)} runs: {len(_methods_in_order(rows))} methods on {n_cases} cases "
               f"(protocol, scene, scale). Every score is in `scores.csv`. {_BETTER.replace('in bold on green', 'in bold')}")
    out.append("")
    for note in notes:
        out.append(f"- {note}")
    if notes:
        out.append("")
    out.append("## Results")
    out.append("")
    for metric in ("rmse", "edge_rmse"):
        overview = overview_markdown(rows, metric=metric)
        if overview:
            present = [q for q in OVERVIEW_PEERS if q in _methods_in_order(rows)]
            out += [f"### All protocols: mean {_METRIC_TITLES[metric]}, ×4 / ×8 / ×16", "",
                    f"_Test scenes only; best of each protocol and scale in bold; the last row: how far the default "
                    f"method ({DEFAULT_METHOD}) is below the best of {', '.join(present) or 'the peers'}._", "",
                    overview]
    for t in summary_tables(rows):
        out.append(_markdown_table(t))
    for t in published_table(rows):
        out.append(_markdown_table(t))
    out += confidence_markdown(rows, plot=confidence_plot)
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

def rmse_scale_figure(rows: Sequence[BenchRow]):
    """Mean RMSE (test scenes) against scale, one line per method, one panel per protocol."""
    from matplotlib.figure import Figure

    groups = _row_groups(rows)
    methods = _methods_in_order(rows)
    fig = Figure(figsize=(4.2 * max(1, len(groups)), 3.6), dpi=110, layout="constrained")
    axes = fig.subplots(1, max(1, len(groups)), squeeze=False)[0]
    markers = "os^vDP*Xhd<>"
    for ax, (label, protocol, group) in zip(axes, groups):
        scored, _ = _scored_rows(group, protocol)
        scales = sorted({r.scale for r in scored})
        for i, m in enumerate(methods):
            ys = [mean_or_nan(r.rmse for r in scored if r.method == m and r.scale == s) for s in scales]
            ax.plot(scales, ys, marker=markers[i % len(markers)], label=m, linewidth=1.2, markersize=4)
        ax.set_xscale("log", base=2)
        ax.set_xticks(scales, [f"×{s}" for s in scales])
        ax.minorticks_off()
        ax.set_xlabel("scale factor")
        ax.set_ylabel("mean RMSE")
        ax.set_title(label, fontsize=10)
        ax.grid(True, alpha=0.3)
    axes[-1].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    return fig


# ---------------------------------------------------------------- HTML

def _html_table(table: Table) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in table.header)
    best = best_cells(table)
    body = "\n".join(
        "<tr>" + "".join(f'<td class="best">{html.escape(c)}</td>' if (i, j) in best else f"<td>{html.escape(c)}</td>"
                         for j, c in enumerate(row)) + "</tr>"
        for i, row in enumerate(table.body))
    note = f'<p class="note">{html.escape(table.note)}</p>' if table.note else ""
    return (f'<h3>{html.escape(table.title)}</h3>{note}\n<div class="wide"><table class="scores">\n'
            f"<thead><tr>{head}</tr></thead>\n<tbody>\n{body}\n</tbody></table></div>")


def html_page(
    rows: Sequence[BenchRow],
    *,
    params_used: Mapping[str, Mapping[str, Any]] | None = None,
    notes: Sequence[str] = (),
    figures: Sequence[tuple[str, str]] = (),
    plot: str | None = None,
    csv_name: str = "scores.csv",
    markdown_name: str = "summary.md",
    confidence_plot: str | None = None,
) -> str:
    """One self-contained HTML page (images by relative file name) showing the whole report.

    After loading, ``<body data-images-loaded="N">`` holds the number of
    images that decoded, so a headless browser can check them.
    """
    from .confidence_report import confidence_html

    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8"><title>depthrefine benchmark</title>',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        "<style>body{font-family:sans-serif;margin:1.5em;max-width:1600px}"
        ".wide{overflow-x:auto;max-width:100%}"
        "table.scores{border-collapse:collapse;margin:.5em 0 1.5em}"
        "table.scores td,table.scores th{border:1px solid #bbb;padding:2px 8px;text-align:right;white-space:nowrap}"
        "table.scores td:first-child,table.scores th:first-child{text-align:left}"
        "table.scores td.best{font-weight:bold;background:#d9f2d9}"
        ".note{color:#555;font-size:90%}figure{margin:1em 0}figure img{max-width:100%;height:auto}"
        "figure a{display:inline-block;cursor:zoom-in}"
        "figcaption{font-size:90%;color:#333}"
        "@media (max-width:600px){body{margin:.6em}h1{font-size:1.4em}}</style>",
        "<script>window.addEventListener('load',function(){var n=0;for(var i=0;i<document.images.length;i++)"
        "{var im=document.images[i];if(im.complete&&im.naturalWidth>0){n++;}}"
        "document.body.setAttribute('data-images-loaded',String(n));});</script>",
        "</head><body>",
        "<h1>depthrefine benchmark</h1>",
        f'<p>Every score: <a href="{html.escape(csv_name)}">{html.escape(csv_name)}</a>; '
        f'the same summary as Markdown: <a href="{html.escape(markdown_name)}">{html.escape(markdown_name)}</a>. '
        f"{_BETTER}</p>",
    ]
    if notes:
        parts.append("<ul>" + "".join(f"<li>{html.escape(n)}</li>" for n in notes) + "</ul>")
    parts.append('<h2 id="results">Results</h2>')
    parts += [_html_table(t) for t in summary_tables(rows)]
    parts += [_html_table(t) for t in published_table(rows)]
    parts += confidence_html(rows, plot=confidence_plot)
    if params_used:
        parts.append("<h2>Parameters</h2><ul>")
        for method, fields in params_used.items():
            text = ", ".join(f"{k} = {v}" for k, v in fields.items()) if fields else "(none)"
            parts.append(f"<li><code>{html.escape(method)}</code>: {html.escape(text)}</li>")
        parts.append("</ul>")
    if plot:
        parts.append(f'<h2>RMSE against scale</h2><figure><a href="{html.escape(plot)}"><img class="plot" '
                     f'src="{html.escape(plot)}" alt="mean RMSE against scale per method"></a></figure>')
    if figures:
        parts.append('<h2 id="figures">Figures</h2><p class="note">Click a figure to open it at full size.</p>')
        for caption, name in figures:
            parts.append(f'<figure class="scene"><a href="{html.escape(name)}"><img src="{html.escape(name)}" '
                         f'alt="{html.escape(caption)}"></a>'
                         f"<figcaption>{html.escape(caption)} (click to enlarge)</figcaption></figure>")
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"
