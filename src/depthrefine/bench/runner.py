"""The benchmark: every method on every case of a protocol, scored against ground truth.

A *case* (:class:`BenchCase`) is one scene at one scale under one protocol:
the low-resolution input, the color guide, the ground truth and how to score
it. :func:`run_benchmark` runs methods x cases, times each call and returns
one :class:`BenchRow` per (method, case). The protocols (the data sets'
READMEs say how each is scored):

``park``
    Noisy Middlebury 2005 (Park et al., ICCV 2011): the given noisy
    low-resolution inputs ``noisy_x{4,8,16}.png``, guide ``color.png``, RMSE
    against ``gt_disp.png`` over the whole grid, in disparity levels.
``middlebury30``, ``lu``
    The 30-image Middlebury set and the Lu set (Lu et al., CVPR 2014), as
    in DKN / DCTNet / JIIF: the ground truth cropped to a multiple of the
    scale, min-max normalised, the low-resolution input made by PIL bicubic
    downsampling (:func:`bicubic_downsample`), mapped back to 0..255 units;
    RMSE in those units after a 6-pixel border crop.
``tof``
    Simulated ToF (ours, :mod:`depthrefine.bench.simulate`) from the Park ground
    truth and color, scored like ``park``.

The scenes in :data:`TUNING_SCENES` are the ones the peers' parameters were
tuned on, and the same scenes seen under another protocol (``tof`` shares the
Park scenes; Park's Dolls and Laundry are ``Middlebury_14`` and ``_18`` of the
30-image set); their rows are marked ``split="tune"`` and the summaries leave
them out, saying why (:func:`left_out_reason`).

This module is pure apart from the ``progress`` callback; the files are
read by :mod:`depthrefine.io` (``load_cases``).
"""

from __future__ import annotations

import dataclasses
import math
import time
import zlib
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable, Mapping, Sequence

import numpy as np

from .metrics import score
from ..methods.registry import get_method
from .simulate import ToFModel, simulate_tof

__all__ = [
    "PROTOCOLS",
    "DEFAULT_SCALES",
    "TUNING_SCENES",
    "LEFT_OUT_WHY",
    "left_out_reason",
    "tuned_on_scenes",
    "LU_BORDER",
    "BenchCase",
    "BenchRow",
    "BenchResult",
    "ROW_FIELDS",
    "METRICS",
    "bicubic_downsample",
    "crop_to_multiple",
    "park_case",
    "lu_case",
    "tof_case",
    "tof_seed",
    "run_benchmark",
    "parse_scales",
    "mean_or_nan",
    "mean_and_count",
]

#: Protocol names, in report order.
PROTOCOLS = ("park", "middlebury30", "lu", "tof")
#: The scale factors of the published tables.
DEFAULT_SCALES = (4, 8, 16)
#: Scenes left out of every mean, per protocol (rows marked ``split="tune"``):
#: the scenes the peers were tuned on, and the same scenes under another
#: protocol (:data:`LEFT_OUT_WHY` says why each one is left out).
TUNING_SCENES: dict[str, tuple[str, ...]] = {
    "park": ("dolls", "laundry"),
    "tof": ("dolls", "laundry"),
    "middlebury30": ("Middlebury_03", "Middlebury_10", "Middlebury_14", "Middlebury_18", "Middlebury_19",
                     "Middlebury_25"),
}
#: Why a scene of :data:`TUNING_SCENES` is left out, ``{(protocol, scene): reason}``.
#: Scenes not listed here were tuned on directly.
LEFT_OUT_WHY: dict[tuple[str, str], str] = {
    ("tof", "dolls"): "Park's Dolls, a tuning scene",
    ("tof", "laundry"): "Park's Laundry, a tuning scene",
    ("middlebury30", "Middlebury_14"): "Dolls (middlebury_lu30 README), a Park tuning scene",
    ("middlebury30", "Middlebury_18"): "Laundry (middlebury_lu30 README), a Park tuning scene",
}


def left_out_reason(protocol: str, scene: str) -> str:
    """Why ``scene`` is left out of ``protocol``'s means ("" if it is not).

    Examples
    --------
    >>> left_out_reason("middlebury30", "Middlebury_14")
    'Dolls (middlebury_lu30 README), a Park tuning scene'
    >>> left_out_reason("park", "dolls"), left_out_reason("park", "art")
    ('tuned on', '')
    """
    if scene not in TUNING_SCENES.get(protocol, ()):
        return ""
    return LEFT_OUT_WHY.get((protocol, scene), "tuned on")


def tuned_on_scenes(protocol: str) -> tuple[str, ...]:
    """The scenes of ``protocol`` the peers' parameters were tuned on (not those left out as duplicates).

    Examples
    --------
    >>> tuned_on_scenes("middlebury30")
    ('Middlebury_03', 'Middlebury_10', 'Middlebury_19', 'Middlebury_25')
    """
    return tuple(s for s in TUNING_SCENES.get(protocol, ()) if (protocol, s) not in LEFT_OUT_WHY)
#: Border crop of the middlebury30 / lu protocols, pixels.
LU_BORDER = 6
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
    """The scores and the time of one method on one case (one CSV row)."""

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

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)


#: Column names of a row, in CSV order.
ROW_FIELDS = tuple(f.name for f in dataclasses.fields(BenchRow))


@dataclass
class BenchResult:
    """Rows of a run, and the predictions it was asked to keep.

    ``kept[(protocol, scene, scale)][method]`` is the (H, W) float32 result.
    """

    rows: list[BenchRow] = field(default_factory=list)
    kept: dict[tuple[str, str, int], dict[str, np.ndarray]] = field(default_factory=dict)


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


def crop_to_multiple(array: np.ndarray, scale: int) -> np.ndarray:
    """The top-left part of ``array`` whose rows and columns are multiples of ``scale`` (a view).

    Examples
    --------
    >>> crop_to_multiple(np.zeros((10, 13)), 4).shape
    (8, 12)
    """
    rows, cols = (array.shape[0] // scale) * scale, (array.shape[1] // scale) * scale
    if rows < scale or cols < scale:
        raise ValueError(f"an image of shape {array.shape[:2]} is smaller than one {scale}x{scale} block.")
    return array[:rows, :cols]


def _gt_float(depth_gt: np.ndarray) -> np.ndarray:
    gt = np.asarray(depth_gt).astype(np.float32)
    with np.errstate(invalid="ignore"):
        gt[~(np.isfinite(gt) & (gt > 0))] = np.nan
    return gt


def bicubic_downsample(depth_gt: np.ndarray, scale: int) -> np.ndarray:
    """Low-resolution input of the DKN / DCTNet / JIIF protocol, in the ground truth's units.

    The map is min-max normalised to [0, 1] (over all its pixels, as the
    published code does), resized to ``(W // scale, H // scale)`` with PIL's
    bicubic filter on a float ``'F'`` image, and mapped back with the same
    min and max. ``depth_gt`` should already be cropped to a multiple of
    ``scale``.

    Parameters
    ----------
    depth_gt : (H, W) ndarray
        Ground truth as stored (uint8 here).
    scale : int

    Returns
    -------
    (H // scale, W // scale) float32 ndarray

    Examples
    --------
    >>> bicubic_downsample(np.full((8, 8), 50, np.uint8), 4).tolist()
    [[50.0, 50.0], [50.0, 50.0]]
    """
    from PIL import Image

    raw = np.asarray(depth_gt, dtype=np.float64)
    lo, hi = float(raw.min()), float(raw.max())
    span = hi - lo if hi > lo else 1.0
    norm = ((raw - lo) / span).astype(np.float32)
    rows, cols = raw.shape[0] // scale, raw.shape[1] // scale
    small = Image.fromarray(norm).resize((cols, rows), Image.BICUBIC)
    return (np.asarray(small, dtype=np.float64) * span + lo).astype(np.float32)


def park_case(scene: str, scale: int, depth_lr: np.ndarray, rgb_hr: np.ndarray, depth_gt: np.ndarray,
              *, protocol: str = "park") -> BenchCase:
    """A case of the ``park`` protocol: the given noisy input, the whole ground-truth grid."""
    h, w = depth_lr.shape[:2]
    rows, cols = h * scale, w * scale
    if rows > depth_gt.shape[0] or cols > depth_gt.shape[1]:
        raise ValueError(
            f"{scene} x{scale}: the input ({w}x{h}) times {scale} is larger than the ground truth "
            f"({depth_gt.shape[1]}x{depth_gt.shape[0]})."
        )
    return BenchCase(protocol, scene, scale, depth_lr, rgb_hr[:rows, :cols], _gt_float(depth_gt[:rows, :cols]),
                     border=0, split=_split(protocol, scene))


def lu_case(protocol: str, scene: str, scale: int, rgb_hr: np.ndarray, depth_gt: np.ndarray) -> BenchCase:
    """A case of the ``middlebury30`` / ``lu`` protocol (crop, PIL bicubic input, 6-pixel border)."""
    gt = crop_to_multiple(depth_gt, scale)
    rgb = rgb_hr[: gt.shape[0], : gt.shape[1]]
    return BenchCase(protocol, scene, scale, bicubic_downsample(gt, scale), rgb, _gt_float(gt),
                     border=LU_BORDER, split=_split(protocol, scene))


def tof_seed(scene: str, scale: int) -> int:
    """The fixed seed of the simulated ToF input of a scene and scale.

    Examples
    --------
    >>> tof_seed("art", 8) == tof_seed("art", 8) != tof_seed("art", 4)
    True
    """
    return zlib.crc32(f"tof/{scene}/x{scale}".encode())


def tof_case(scene: str, scale: int, rgb_hr: np.ndarray, depth_gt: np.ndarray,
             *, model: ToFModel | None = None) -> BenchCase:
    """A case of the ``tof`` protocol: simulated ToF input (:func:`simulate_tof`), whole grid."""
    gt = crop_to_multiple(depth_gt, scale)
    rgb = rgb_hr[: gt.shape[0], : gt.shape[1]]
    depth_lr = simulate_tof(gt, rgb, scale=scale, model=model, seed=tof_seed(scene, scale))
    return BenchCase("tof", scene, scale, depth_lr, rgb, _gt_float(gt), border=0, split=_split("tof", scene))


def _split(protocol: str, scene: str) -> str:
    return "tune" if scene in TUNING_SCENES.get(protocol, ()) else "test"


def run_benchmark(
    cases: Sequence[BenchCase],
    methods: Sequence[str],
    *,
    params: Mapping[str, Any] | None = None,
    keep: Callable[[BenchCase], bool] | None = None,
    progress: Callable[[int, int], None] | None = None,
    clock: Callable[[], float] = time.perf_counter,
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
    >>> gt = np.tile(np.repeat(np.array([40, 200], np.uint8), 8), (16, 1))
    >>> case = park_case("toy", 4, gt[::4, ::4].copy(), np.zeros((16, 16, 3), np.uint8), gt)
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
            result.rows.append(BenchRow(
                protocol=case.protocol, scene=case.scene, scale=case.scale, method=entry.name,
                split=case.split, rmse=s.rmse, mae=s.mae, edge_rmse=s.edge_rmse, bad_1=s.bad_1,
                bad_3=s.bad_3, coverage=s.coverage, seconds=float(seconds), megapixels=megapixels,
            ))
            if keep is not None and keep(case):
                result.kept.setdefault(case.key, {})[entry.name] = depth_hr
            done += 1
            if progress is not None:
                progress(done, total)
    return result


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
