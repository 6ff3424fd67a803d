"""The benchmark report's section on confidence maps: AUSE tables and sparsification curves (issue 23).

:func:`confidence_tables` gives, per protocol and method, the AUSE of the
method's confidence map and of the steepness baseline on the same output
(both relative to the output's RMSE), and the RMSE ratio of the more to the
less confident half; :func:`sparsification_figure` draws the mean curves.
:mod:`.report` puts both into the Markdown and HTML pages when the rows
carry them (``run_benchmark(..., confidence=True)``).
"""

from __future__ import annotations

import math
from typing import Mapping, Sequence

import numpy as np

from ..methods._names import DEFAULT_METHOD
from .metrics import Sparsification
from .protocols import PROTOCOLS
from .report import Table, _methods_in_order, _protocols_in_order, _scored_rows
from .runner import BenchRow, mean_and_count

__all__ = ["has_confidence", "confidence_tables", "confidence_markdown", "confidence_html", "sparsification_figure",
           "CONFIDENCE_NOTE"]

#: What the tables show, for the page.
CONFIDENCE_NOTE = (
    "Each method's confidence map (depthrefine.refine_with_confidence: gbp's own, the generic map for the "
    "others) is scored by its sparsification curve: the RMSE left after removing the least confident share "
    "of the pixels. AUSE is its area above the oracle curve, which removes the largest true errors first; "
    "it is shown relative to the output's RMSE (0 = a perfect ranking). 'baseline' scores the map "
    "exp(-g / p90(g)), g the 3x3 max-filtered Sobel magnitude of the same output: trust falls where the "
    "output is steep. 'half': RMSE of the more confident half over that of the less confident half. "
    "Lower is better everywhere; test scenes only.")


def has_confidence(rows: Sequence[BenchRow]) -> bool:
    """Whether any row scores a confidence map."""
    return any(math.isfinite(r.ause) for r in rows)


def _ratio(a: float, b: float) -> float:
    return a / b if b > 0 and math.isfinite(a) and math.isfinite(b) else math.nan


def _cell(value: float, n: int, full: int) -> str:
    if not math.isfinite(value):
        return "–"
    return f"{value:.3f}" + (f" (n={n})" if 0 < n < full else "")


def confidence_tables(rows: Sequence[BenchRow]) -> list[Table]:
    """Per protocol: mean relative AUSE of each method's map, of the baseline, and the half ratio, per scale.

    Examples
    --------
    >>> row = BenchRow("park", "art", 4, "gbp", "test", 2.0, 1.0, 4.0, 0.5, 0.1, 1.0, 0.01, 1.5,
    ...                ause=0.2, ause_baseline=0.4, confident_rmse=1.0, doubtful_rmse=4.0)
    >>> table = confidence_tables([row])[0]
    >>> table.header[1:4], table.body[0][1:4]
    (('×4 AUSE', '×4 baseline', '×4 half'), ('0.100', '0.200', '0.250'))
    """
    tables: list[Table] = []
    methods = _methods_in_order(rows)
    for protocol in _protocols_in_order(rows):
        scored, fallback = _scored_rows(rows, protocol)
        scored = [r for r in scored if math.isfinite(r.ause)]
        if not scored:
            continue
        scales = sorted({r.scale for r in scored})
        scenes = sorted({r.scene for r in scored})
        body = []
        for m in methods:
            cells = [m]
            for s in scales:
                sel = [r for r in scored if r.method == m and r.scale == s]
                for values in ([_ratio(r.ause, r.rmse) for r in sel], [_ratio(r.ause_baseline, r.rmse) for r in sel],
                               [_ratio(r.confident_rmse, r.doubtful_rmse) for r in sel]):
                    value, n = mean_and_count(values)
                    cells.append(_cell(value, n, len(sel)))
            body.append(tuple(cells))
        title = PROTOCOLS[protocol].title if protocol in PROTOCOLS else protocol
        tables.append(Table(
            title=f"{protocol}: confidence maps — AUSE / RMSE, the baseline's, and the half ratio ({title})",
            header=("method", *[f"×{s} {k}" for s in scales for k in ("AUSE", "baseline", "half")]),
            body=tuple(body),
            note=f"mean over {len(scenes)} scene(s): {', '.join(scenes)}"
                 + (" (only tuning scenes are present, so they are included)" if fallback else ""),
        ))
    return tables


def confidence_markdown(rows: Sequence[BenchRow], *, plot: str | None = None) -> list[str]:
    """The Markdown lines of the confidence section ([] when no row scores a confidence map)."""
    from .report import _markdown_table

    if not has_confidence(rows):
        return []
    out = ["## Confidence maps", "", CONFIDENCE_NOTE, ""]
    out += [_markdown_table(t) for t in confidence_tables(rows)]
    if plot:
        out += [f"![sparsification curves]({plot})", ""]
    return out


def sparsification_figure(curves: Mapping[tuple[str, str, int, str], tuple[Sparsification, Sparsification]],
                          rows: Sequence[BenchRow], *, method: str = DEFAULT_METHOD):
    """Mean sparsification curves (RMSE relative to the full RMSE) per protocol, one line per method.

    The test cases of every scale are pooled. For ``method`` its oracle
    (dashed) and the steepness baseline on its output (dotted) are drawn too.

    Parameters
    ----------
    curves : mapping
        ``{(protocol, scene, scale, method): (its map's, the baseline's)}``
        (:attr:`~depthrefine.bench.runner.BenchResult.curves`).
    rows : sequence of BenchRow
        Say which cases are test cases.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    protocols = [p for p in _protocols_in_order(rows) if any(k[0] == p for k in curves)]
    methods = [m for m in _methods_in_order(rows) if any(k[3] == m for k in curves)]
    fig = Figure(figsize=(4.2 * max(1, len(protocols)) + 1.2, 3.6), dpi=110, layout="constrained")
    axes = fig.subplots(1, max(1, len(protocols)), squeeze=False)[0]
    for ax, protocol in zip(axes, protocols):
        scored, _ = _scored_rows(rows, protocol)
        keys = {(r.protocol, r.scene, r.scale) for r in scored}
        fractions = None
        for m in methods:
            mine = [curves[k + (m,)] for k in sorted(keys) if k + (m,) in curves]
            mine = [pair for pair in mine if pair[0].rmse > 0]
            if not mine:
                continue
            fractions = mine[0][0].fractions
            mean = np.mean([c.curve / c.rmse for c, _ in mine], axis=0)
            line, = ax.plot(100 * fractions, mean, label=m, linewidth=1.6 if m == method else 1.0)
            if m == method:
                ax.plot(100 * fractions, np.mean([b.curve / b.rmse for _, b in mine], axis=0), ":",
                        color=line.get_color(), label=f"{m}: baseline")
                ax.plot(100 * fractions, np.mean([c.oracle / c.rmse for c, _ in mine], axis=0), "--",
                        color=line.get_color(), label=f"{m}: oracle")
        ax.set_xlabel("least confident pixels removed (%)")
        ax.set_ylabel("RMSE of the rest / full RMSE")
        ax.set_title(protocol, fontsize=10)
        ax.set_ylim(bottom=0)
        ax.grid(True, alpha=0.3)
    axes[-1].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    return fig


def confidence_html(rows: Sequence[BenchRow], *, plot: str | None = None) -> list[str]:
    """The HTML parts of the confidence section ([] when no row scores a confidence map)."""
    import html

    from .report import _html_table

    if not has_confidence(rows):
        return []
    parts = ['<h2 id="confidence">Confidence maps</h2>', f'<p class="note">{html.escape(CONFIDENCE_NOTE)}</p>']
    parts += [_html_table(t) for t in confidence_tables(rows)]
    if plot:
        parts.append(f'<figure><a href="{html.escape(plot)}"><img class="plot" src="{html.escape(plot)}" '
                     f'alt="mean sparsification curves per protocol and method"></a></figure>')
    return parts
