"""The benchmark runner: every method on every case, scored against ground truth.

A *case* (:class:`BenchCase`) is one scene at one scale under one protocol:
the low-resolution input, the color guide, the ground truth and how to score
it. :func:`run_benchmark` runs methods x cases, times each call and returns
one :class:`BenchRow` per (method, case). The protocols that make the cases
are in :mod:`depthrefine.bench.protocols`.

This module is pure apart from the ``progress`` callback.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable, Mapping, Sequence

import numpy as np

from ..methods.registry import get_method
from .metrics import Sparsification, score, sparsification

__all__ = [
    "DEFAULT_SCALES",
    "BenchCase",
    "BenchRow",
    "BenchResult",
    "ROW_FIELDS",
    "METRICS",
    "run_benchmark",
    "parse_scales",
    "mean_or_nan",
    "mean_and_count",
]

#: The scale factors of the published tables.
DEFAULT_SCALES = (4, 8, 16)
#: The metric columns of a row, in report order.
METRICS = ("rmse", "mae", "edge_rmse", "bad_1", "bad_3", "coverage")


@dataclass(frozen=True, eq=False)
class BenchCase:
    """One scene at one scale under one protocol.

    Attributes
    ----------
    protocol, scene : str
    scale : int
        The upsampling factor.
    depth_lr : (h, w) ndarray
        The method's input (uint8 for ``park`` / ``tof``, float32 for the
        bicubic protocols), 0 = no measurement.
    rgb_hr : (H, W, 3) uint8 ndarray
        The color guide, on the ground truth's grid.
    depth_gt : (H, W) float32 ndarray
        Ground truth, NaN = no measurement.
    border : int
        Pixels left out on each side when scoring.
    split : str
        ``"tune"`` for the peers' tuning scenes, else ``"test"``.
    """

    protocol: str
    scene: str
    scale: int
    depth_lr: np.ndarray
    rgb_hr: np.ndarray
    depth_gt: np.ndarray
    border: int = 0
    split: str = "test"

    @property
    def key(self) -> tuple[str, str, int]:
        """``(protocol, scene, scale)``."""
        return self.protocol, self.scene, self.scale


@dataclass(frozen=True)
class BenchRow:
    """The scores and the time of one method on one case (one CSV row).

    With ``run_benchmark(..., confidence=True)`` the last four fields score
    the method's confidence map (:func:`depthrefine.refine_with_confidence`)
    by :func:`~depthrefine.bench.metrics.sparsification`: ``ause`` and,
    for the same output, ``ause_baseline`` of the steepness baseline
    (:func:`~depthrefine.methods.confidence.steepness_confidence`), and the
    RMSE of the more and the less confident half; NaN without it.
    """

    protocol: str
    scene: str
    scale: int
    method: str
    split: str
    rmse: float
    mae: float
    edge_rmse: float
    bad_1: float
    bad_3: float
    coverage: float
    seconds: float
    megapixels: float
    ause: float = math.nan
    ause_baseline: float = math.nan
    confident_rmse: float = math.nan
    doubtful_rmse: float = math.nan

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)


#: Column names of a row, in CSV order.
ROW_FIELDS = tuple(f.name for f in dataclasses.fields(BenchRow))


@dataclass
class BenchResult:
    """Rows of a run, and the predictions it was asked to keep.

    ``kept[(protocol, scene, scale)][method]`` is the (H, W) float32 result.
    ``curves[(protocol, scene, scale, method)]`` holds, with
    ``confidence=True``, the :class:`~depthrefine.bench.metrics.Sparsification`
    of the method's confidence map and of the steepness baseline.
    """

    rows: list[BenchRow] = field(default_factory=list)
    kept: dict[tuple[str, str, int], dict[str, np.ndarray]] = field(default_factory=dict)
    curves: dict[tuple[str, str, int, str], tuple[Sparsification, Sparsification]] = field(default_factory=dict)


def parse_scales(text: str) -> tuple[int, ...]:
    """``"4,8,16"`` -> ``(4, 8, 16)``; each an integer >= 2.

    Examples
    --------
    >>> parse_scales("16, 4")
    (16, 4)
    """
    parts = [p.strip() for p in str(text).split(",") if p.strip()]
    if not parts:
        raise ValueError(f"--scales must list integer factors such as 4,8,16; got {text!r}.")
    scales = []
    for p in parts:
        if not p.isdigit() or int(p) < 2:
            raise ValueError(f"--scales must list integer factors >= 2 such as 4,8,16; got {p!r} in {text!r}.")
        if int(p) not in scales:
            scales.append(int(p))
    return tuple(scales)


def run_benchmark(
    cases: Sequence[BenchCase],
    methods: Sequence[str],
    *,
    params: Mapping[str, Any] | None = None,
    keep: Callable[[BenchCase], bool] | None = None,
    progress: Callable[[int, int], None] | None = None,
    clock: Callable[[], float] = time.perf_counter,
    confidence: bool = False,
) -> BenchResult:
    """Run every method on every case and score it.

    Parameters
    ----------
    cases : sequence of BenchCase
    methods : sequence of str
        Registered method names (:data:`depthrefine.METHODS`).
    params : mapping, optional
        ``{method: params}`` for methods that should not use their defaults.
    keep : callable, optional
        ``keep(case) -> bool``: keep the results on that case (for figures).
    progress : callable, optional
        ``progress(done, total)`` after each (method, case).
    clock : callable
        Seconds, for timing each call.
    confidence : bool
        Also score each method's confidence map and the steepness baseline
        on its output (untimed; a method with its own map runs again, and its
        depth must come out bit-identical).

    Returns
    -------
    BenchResult
        One row per (case, method), in case order then method order.

    Raises
    ------
    ValueError
        An unknown method name (before anything runs).

    Examples
    --------
    >>> gt = np.tile(np.repeat(np.array([40, 200], np.float32), 8), (16, 1))
    >>> case = BenchCase("toy", "toy", 4, gt[::4, ::4].copy(), np.zeros((16, 16, 3), np.uint8), gt)
    >>> [round(r.rmse, 2) for r in run_benchmark([case], ["nearest"]).rows]
    [0.0]
    """
    entries = [get_method(m) for m in methods]
    params = dict(params or {})
    result = BenchResult()
    total = len(cases) * len(entries)
    done = 0
    for case in cases:
        megapixels = case.depth_gt.size / 1e6
        for entry in entries:
            start = clock()
            depth_hr = entry.func(case.depth_lr, case.rgb_hr, params=params.get(entry.name), progress=None)
            seconds = clock() - start
            if depth_hr.shape != case.depth_gt.shape:
                raise ValueError(
                    f"method {entry.name!r} returned shape {depth_hr.shape} on {case.scene} x{case.scale}; "
                    f"expected the ground truth's {case.depth_gt.shape}."
                )
            s = score(depth_hr, case.depth_gt, border=case.border)
            sparse: dict[str, float] = {}
            if confidence:
                mine, base = _confidence_curves(entry, case, depth_hr, params.get(entry.name))
                result.curves[case.key + (entry.name,)] = (mine, base)
                sparse = dict(ause=mine.ause, ause_baseline=base.ause, confident_rmse=mine.confident_rmse,
                              doubtful_rmse=mine.doubtful_rmse)
            result.rows.append(BenchRow(
                protocol=case.protocol, scene=case.scene, scale=case.scale, method=entry.name,
                split=case.split, rmse=s.rmse, mae=s.mae, edge_rmse=s.edge_rmse, bad_1=s.bad_1,
                bad_3=s.bad_3, coverage=s.coverage, seconds=float(seconds), megapixels=megapixels, **sparse,
            ))
            if keep is not None and keep(case):
                result.kept.setdefault(case.key, {})[entry.name] = depth_hr
            done += 1
            if progress is not None:
                progress(done, total)
    return result


def _confidence_curves(entry, case: BenchCase, depth_hr: np.ndarray, params: Any
                       ) -> tuple[Sparsification, Sparsification]:
    """The sparsification of ``entry``'s confidence map on ``depth_hr`` and of the steepness baseline."""
    from ..methods.confidence import generic_confidence, steepness_confidence

    if entry.confidence is not None:
        again, conf = entry.confidence(case.depth_lr, case.rgb_hr, params=params, progress=None)
        if entry.deterministic and not np.array_equal(again, depth_hr, equal_nan=True):
            raise RuntimeError(f"method {entry.name!r}: its confidence hook's depth differs from its output on "
                               f"{case.scene} x{case.scale}; they must be bit-identical.")
    else:
        conf = generic_confidence(case.depth_lr, depth_hr)
    return (sparsification(depth_hr, case.depth_gt, conf, border=case.border),
            sparsification(depth_hr, case.depth_gt, steepness_confidence(depth_hr), border=case.border))


def mean_and_count(values: Iterable[float]) -> tuple[float, int]:
    """Mean of the finite values (NaN if none) and how many there were.

    Examples
    --------
    >>> mean_and_count([1.0, float("nan"), 3.0])
    (2.0, 2)
    """
    vals = [v for v in values if isinstance(v, (int, float)) and math.isfinite(v)]
    return (sum(vals) / len(vals) if vals else float("nan")), len(vals)


def mean_or_nan(values: Iterable[float]) -> float:
    """Mean of the finite values (NaN if none); :func:`mean_and_count` also says over how many.

    Examples
    --------
    >>> mean_or_nan([1.0, float("nan"), 3.0])
    2.0
    """
    return mean_and_count(values)[0]
