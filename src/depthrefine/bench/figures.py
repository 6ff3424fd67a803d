"""The benchmark report's figures: per scene the methods' results and error maps, and RMSE against scale.

- :func:`scene_figure`: ground truth, color, and per method its result and
  ``|error|`` map, each beside the same zoomed detail;
- :func:`error_scale`: one error-map range per protocol, from the errors
  themselves (the :data:`ERROR_PERCENTILE`-th percentile of the typical
  method, in the figure where it is largest), so that neither a
  millimetre scene nor a disparity scene saturates every map;
- :func:`zoom_where_methods_differ`: the detail window where most methods'
  results disagree (where a reader can tell them apart), with
  :func:`choose_zoom` (the most ground-truth edges) as the fallback;
No file access: the ``bench`` command writes the figures.
"""

from __future__ import annotations

import warnings
from typing import Iterable, Mapping

import numpy as np

from .metrics import EDGE_THRESHOLD_LEVELS, depth_edges, valid_mask
from .protocols import PROTOCOLS
from .runner import BenchCase

__all__ = ["ERROR_PERCENTILE", "choose_zoom", "zoom_where_methods_differ", "error_map", "error_scale",
           "scene_figure"]

#: Error maps run from 0 to this percentile of the typical (median) method's errors (larger errors saturate).
ERROR_PERCENTILE = 95.0


def _best_window(score: np.ndarray, fraction: float) -> tuple[int, int, int, int]:
    """The ``fraction``-sized window with the largest sum of ``score``, on a grid of a quarter window.

    The first best one wins (deterministic).
    """
    rows, cols = score.shape
    wr, wc = max(1, int(rows * fraction)), max(1, int(cols * fraction))
    integral = np.pad(score.astype(np.float64).cumsum(0).cumsum(1), ((1, 0), (1, 0)))
    r0s = np.arange(0, rows - wr + 1, max(1, wr // 4))
    c0s = np.arange(0, cols - wc + 1, max(1, wc // 4))
    R, C = np.meshgrid(r0s, c0s, indexing="ij")
    sums = integral[R + wr, C + wc] - integral[R, C + wc] - integral[R + wr, C] + integral[R, C]
    i, j = np.unravel_index(int(np.argmax(sums)), sums.shape)
    r0, c0 = int(r0s[i]), int(c0s[j])
    return r0, r0 + wr, c0, c0 + wc


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
    return _best_window(depth_edges(gt, threshold=EDGE_THRESHOLD_LEVELS), fraction)


def zoom_where_methods_differ(results: Mapping[str, np.ndarray], depth_gt: np.ndarray, *, border: int = 0,
                              fraction: float = 0.25) -> tuple[int, int, int, int]:
    """The detail window where the methods' results differ most, ``(row0, row1, col0, col1)``.

    A pixel's score is the median over the methods of each result's
    distance to the methods' median there (the median absolute deviation),
    over the scored pixels (ground truth valid, outside ``border``): large
    where most methods disagree, as at depth edges, and not where a single
    method fails on a flat surface. The window of ``fraction`` of each side
    with the largest sum wins. With fewer than two results, or where they
    all agree, :func:`choose_zoom`.

    Examples
    --------
    >>> gt = np.full((40, 40), 5.0); a = gt.copy(); b = gt.copy(); b[2:8, 30:36] = 9.0
    >>> zoom_where_methods_differ({"a": a, "b": b}, gt)
    (0, 10, 26, 36)
    """
    gt = np.asarray(depth_gt, dtype=np.float64)
    maps = [np.asarray(r, dtype=np.float32) for r in results.values()]
    if len(maps) < 2:
        return choose_zoom(gt, fraction=fraction)
    stack = np.stack(maps)
    finite = np.isfinite(stack)
    scored = valid_mask(gt, border=border) & (finite.sum(axis=0) >= 2)
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN pixels: left out by ``scored``
        centre = np.nanmedian(stack, axis=0)
        spread = np.nanmedian(np.abs(stack - centre), axis=0)
    spread = np.where(scored & np.isfinite(spread), spread, 0.0)
    if not (spread > 0).any():
        return choose_zoom(gt, fraction=fraction)
    return _best_window(spread, fraction)


def error_map(depth_pred: np.ndarray, depth_gt: np.ndarray, *, border: int = 0) -> np.ndarray:
    """``|pred - gt|`` as float32, NaN where a pixel is not scored (no ground truth, border, no prediction).

    Examples
    --------
    >>> error_map(np.array([[1.0, 5.0, 2.0]]), np.array([[1.5, np.nan, 2.0]])).tolist()
    [[0.5, nan, 0.0]]
    """
    gt = np.asarray(depth_gt, dtype=np.float64)
    pred = np.asarray(depth_pred, dtype=np.float64)
    scored = valid_mask(gt, border=border) & np.isfinite(pred)
    err = np.full(gt.shape, np.nan, np.float32)
    err[scored] = np.abs(pred[scored] - gt[scored])
    return err


def error_scale(errors: Iterable[Mapping[str, np.ndarray]], *, percentile: float = ERROR_PERCENTILE) -> float:
    """The top of the error maps' range for several figures: the largest over them of the typical method's percentile.

    Parameters
    ----------
    errors : iterable of mapping
        Per figure (case) ``{method: (H, W) |error| map}`` (NaN = not
        scored), e.g. all the figures of one protocol.
    percentile : float

    Returns
    -------
    float
        Per figure, the median over its methods of the ``percentile`` of
        each method's finite errors; the largest of these over the figures
        (1.0 when there are no errors or all are 0). The median method, not
        the worst: one method that fails on a whole region (thesis on the
        Kinect capture: 486 mm against 40-130 mm) would leave every other
        map black; its own map saturates instead, and the colorbar's arrow
        says so. The largest over the figures, so that one scale serves a
        protocol whose scenes differ (the iPhone frame's errors are larger
        than the Kinect capture's) without saturating any figure's typical map.

    Examples
    --------
    >>> a = np.linspace(0, 1, 101)
    >>> error_scale([{"a": a, "b": 2 * a, "c": 100 * a}]), error_scale([{"a": a}, {"a": a + 1}])
    (1.9, 1.95)
    """
    tops = []
    for case in errors:
        per_method = [np.asarray(err, dtype=np.float64).ravel() for err in case.values()]
        per_method = [float(np.percentile(v[np.isfinite(v)], percentile)) for v in per_method if np.isfinite(v).any()]
        if per_method:
            tops.append(float(np.median(per_method)))
    top = max(tops, default=0.0)
    return round(top, 6) if top > 0 else 1.0


def scene_figure(case: BenchCase, results: Mapping[str, np.ndarray], *,
                 rmse: Mapping[str, float] | None = None, zoom: tuple[int, int, int, int] | None = None,
                 units: str | None = None, error_max: float | None = None):
    """Ground truth, color, and per method its result and error map, each beside the same zoomed detail.

    One row per method: result, detail, ``|error|``, detail. Results share
    the ground truth's range and one depth colorbar; error maps go from 0 to
    ``error_max`` (larger errors saturate) with their own colorbar; pixels
    that are not scored are gray (:mod:`depthrefine.viz`).

    Parameters
    ----------
    case : BenchCase
    results : mapping
        ``{method: (H, W) depth}``.
    rmse : mapping, optional
        ``{method: RMSE}``, put in the row titles.
    zoom : (row0, row1, col0, col1), optional
        Default: :func:`zoom_where_methods_differ`.
    units : str, optional
        Default: the protocol's (:attr:`~depthrefine.bench.protocols.Protocol.units`).
    error_max : float, optional
        Top of the error colorbar; default: :func:`error_scale` of this
        figure's errors (the ``bench`` command passes one per protocol).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ..viz import Panel, depth_limits, figure_grid

    zoom = zoom_where_methods_differ(results, case.depth_gt, border=case.border) if zoom is None else zoom
    units = units or (PROTOCOLS[case.protocol].units if case.protocol in PROTOCOLS else "depth units")
    errors = {method: error_map(depth, case.depth_gt, border=case.border) for method, depth in results.items()}
    error_max = error_scale([errors]) if error_max is None else error_max
    rows = [[Panel("ground truth", case.depth_gt), Panel("detail", case.depth_gt, detail=True),
             Panel("color", case.rgb_hr, "color"), Panel("detail", case.rgb_hr, "color", detail=True)]]
    for method, depth in results.items():
        score = "" if rmse is None or method not in rmse else f": RMSE {rmse[method]:.2f}"
        err = errors[method]
        rows.append([Panel(f"{method}{score}", depth), Panel(f"{method}, detail", depth, detail=True),
                     Panel(f"{method}: |error|", err, "error"), Panel(f"{method}: |error|, detail", err, "error",
                                                                        detail=True)])
    r0, r1, c0, c1 = zoom
    return figure_grid(rows, units=units, limits=depth_limits(case.depth_gt), error_max=error_max, zoom=zoom,
                       panel_width=2.2, dpi=140,
                       title=f"{case.protocol} · {case.scene} · ×{case.scale}: results and |error| against the ground "
                             f"truth; |error| from 0 to {error_max:.3g} {units}\n(from the typical method's "
                             f"{ERROR_PERCENTILE:g}th percentile); details: rows {r0}-{r1}, cols {c0}-{c1}, where the "
                             "methods differ most")
