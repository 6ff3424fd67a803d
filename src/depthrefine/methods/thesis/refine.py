"""The thesis refinement, steps 4-8 of the design note ``docs/algorithm.md`` (thesis chapter 4).

For each patch of the color image and the matching patch of the depth map:
cluster the colors (4.3), classify the depth samples by the cluster of the
color pixel they land on and correct rare depths per cluster (4.4), then
interpolate each cluster's samples on its own and keep only its own pixels
(4.5). The patches together make the high-resolution depth map (4.1).

Symbols follow the thesis: ``s`` is the integer scale factor, ``k`` the
number of clusters. Arrays are indexed ``(rows, cols)``; the only ``(x, y)``
are the manual patch rectangles, in color-image pixels.
"""

from __future__ import annotations

import functools
import math
import threading
import time
import warnings
from concurrent.futures import ThreadPoolExecutor
from contextlib import closing, contextmanager
from dataclasses import dataclass
from typing import Any, Callable, Iterator

import numpy as np

from ..._validate import as_depth, check_pixels, check_rgb, valid_range
from ..._fill import fill_invalid_nearest
from .params import ThesisParams
from ..scale import ScaleStep, ScaleWarning, plan_scale, resize_color, resize_depth_nearest
from .interpolate import _interpolate_clusters, _nearest_samples, _spread
from .patches import _manual_patches, patch_grid
from .segment import cluster_colors, median_rgb, rgb_to_lab

__all__ = [
    "refine_thesis_stateful",
    "Refinement",
    "refine_thesis",
    "refine_with_intermediates",
    "patch_grid",
    "correct_cluster_depths",
    "ScaleWarning",
    "step_times",
]

#: ``progress(done, total)``: called after each patch.
Progress = Callable[[int, int], None]


#: Threads for the patch loop (patches are independent), and the smallest
#: image (pixels) worth starting them for.
_MAX_THREADS = 8
_PARALLEL_MIN_PIXELS = 200_000


@dataclass(frozen=True)
class Refinement:
    """The result of the thesis refinement with every intermediate (for debugging).

    Arrays marked *work grid* have shape ``scale.work_shape`` (= the color
    image's shape unless the ratio was not an integer, see :mod:`.scale`).

    Attributes
    ----------
    depth_hr : (H, W) float32
        The refined depth on the color image's grid (NaN only if a patch had
        no valid depth anywhere in reach, which cannot happen for a depth map
        with one valid pixel).
    scale : ScaleStep
        The scale step applied.
    patches : list of (row0, row1, col0, col1)
        Patches on the work grid, in processing order.
    rgb_filtered : (Hw, Ww, 3)
        Median-filtered color (work grid, input dtype) (4.3.1).
    lab_unified : (Hw, Ww, 3) float32
        L*a*b* of the filtered color with L* unified per patch (before the L*
        weight) (4.3.2). k-means clusters these with a* and b* binned at
        :data:`depthrefine.methods.thesis.segment.AB_STEP` units.
    labels : (Hw, Ww) int16
        Cluster label of each pixel, local to its patch, ``0 .. k'-1`` (4.3.3).
    patch_index : (Hw, Ww) int32
        Which patch each pixel belongs to.
    labels_lr : (h, w) int16
        The labels sampled at the depth pixels (Fig. 39a) (4.4.2).
    sparse_depth : (Hw, Ww) float32
        The spread depth: each depth pixel at its color pixel, NaN elsewhere (4.4.1).
    corrected_lr : (h, w) float32
        The depth after the histogram correction (4.4.4); NaN where a depth
        pixel stayed invalid (its cluster had no valid depth).
    corrected_sparse : (Hw, Ww) float32
        ``corrected_lr`` spread on the work grid, NaN elsewhere.
    cluster_pieces : (k, Hw, Ww) float32
        Per cluster index ``c``: the expanded, interpolated depth of cluster
        ``c`` of every patch, before reshaping (NaN out of reach) (4.5.1-4.5.3).
    level_size : float
        Depth units per level, the unit of the +-``tolerance_levels`` test
        (1 for uint8 input, else ``(max - min) / 255`` of the valid depths,
        unless set in the parameters).
    """

    depth_hr: np.ndarray
    scale: ScaleStep
    patches: list[tuple[int, int, int, int]]
    rgb_filtered: np.ndarray
    lab_unified: np.ndarray
    labels: np.ndarray
    patch_index: np.ndarray
    labels_lr: np.ndarray
    sparse_depth: np.ndarray
    corrected_lr: np.ndarray
    corrected_sparse: np.ndarray
    cluster_pieces: np.ndarray
    level_size: float


def refine_thesis(
    depth_lr: np.ndarray,
    rgb_hr: np.ndarray,
    *,
    params: ThesisParams | None = None,
    progress: Progress | None = None,
) -> np.ndarray:
    """Refine ``depth_lr`` to the resolution of ``rgb_hr`` with the thesis method.

    Parameters
    ----------
    depth_lr : (h, w) ndarray
        Low-resolution depth, any units; 0, NaN, inf and negative values mean
        "no measurement". uint8 input counts one histogram bin per level.
    rgb_hr : (H, W, 3) uint8, uint16 or float ndarray in [0, 1]
        Registered color image (RGB order). Gray (H, W) is repeated to three
        channels; an alpha channel is dropped.
    params : ThesisParams, optional
        Thesis defaults when omitted.
    progress : callable, optional
        ``progress(done, total)`` after each patch.

    Returns
    -------
    (H, W) float32 ndarray
        Refined depth in the units of ``depth_lr``.

    Raises
    ------
    TypeError, ValueError
        For arrays of the wrong kind, shape or content (see messages).

    References
    ----------
    Chen Ching-Kun, "TOF-Sensor Captured Depth Map Refinement Using
    High-Resolution Color Images", M.S. thesis, NCTU, 2014, chapter 4.

    Examples
    --------
    >>> depth = np.array([[10, 10, 50, 50]] * 4, np.uint8)
    >>> rgb = np.zeros((8, 8, 3), np.uint8); rgb[:, 4:] = 200
    >>> out = refine_thesis(depth, rgb, params=ThesisParams(patches=(1, 1), n_clusters=2))
    >>> out.shape, out.dtype, out[0].tolist()
    ((8, 8), dtype('float32'), [10.0, 10.0, 10.0, 10.0, 50.0, 50.0, 50.0, 50.0])
    """
    return _run(depth_lr, rgb_hr, params, progress, keep=False).depth_hr


def refine_thesis_stateful(
    depth_lr: np.ndarray,
    rgb_hr: np.ndarray,
    *,
    params: ThesisParams | None = None,
    state: Any = None,
    progress: Progress | None = None,
) -> tuple[np.ndarray, Any]:
    """:func:`refine_thesis` for a video: each patch's k-means starts from the previous frame's means.

    With ``state=None`` (the first frame) the result is :func:`refine_thesis`'s,
    bit for bit. The returned state holds each patch's cluster means; give it
    with the next frame so that its k-means starts there instead of at the
    default means: on a static or slowly moving camera, pixels keep their
    clusters from frame to frame and the result does not flicker. A state
    from a frame of another size or patch layout is ignored (a cold start).

    Returns
    -------
    depth_hr : (H, W) float32 ndarray
    state : object
        Opaque; pass it with the next frame.

    Examples
    --------
    >>> depth = np.array([[10, 10, 50, 50]] * 4, np.uint8)
    >>> rgb = np.zeros((8, 8, 3), np.uint8); rgb[:, 4:] = 200
    >>> out, state = refine_thesis_stateful(depth, rgb)
    >>> out2, state = refine_thesis_stateful(depth, rgb, state=state)
    >>> bool((out == refine_thesis(depth, rgb)).all()), bool((out2 == out).all())
    (True, True)
    """
    result, means = _run(depth_lr, rgb_hr, params, progress, keep=False, warm=state)
    return result.depth_hr, means


def refine_with_intermediates(
    depth_lr: np.ndarray,
    rgb_hr: np.ndarray,
    *,
    params: ThesisParams | None = None,
    progress: Progress | None = None,
) -> Refinement:
    """Like :func:`refine_thesis`, but return every intermediate result too.

    Returns
    -------
    Refinement
        ``.depth_hr`` is identical to :func:`refine_thesis`'s output.

    Examples
    --------
    >>> depth = np.full((4, 4), 30, np.uint8)
    >>> rgb = np.zeros((8, 8, 3), np.uint8)
    >>> r = refine_with_intermediates(depth, rgb, params=ThesisParams(patches=(2, 2)))
    >>> r.labels.shape, len(r.patches), r.scale.factor
    ((8, 8), 4, 2)
    """
    return _run(depth_lr, rgb_hr, params, progress, keep=True)


def correct_cluster_depths(
    values: np.ndarray,
    *,
    origin: float,
    level_size: float,
    n_bins: int,
    dominant_fraction: float = 0.5,
    tolerance_levels: float = 5.0,
    bin_width: float | None = None,
) -> np.ndarray:
    """Correct the depth samples of one cluster (thesis 4.4.3-4.4.4).

    Bin ``b`` of the histogram holds the values nearest to
    ``origin + b * bin_width`` (default ``bin_width = level_size``: one bin
    per level). The fullest bin is dominant, and so is every bin whose count
    exceeds ``dominant_fraction`` of it; a dominant value is its bin's center.
    A value within ``tolerance_levels * level_size`` of a dominant value is
    kept; any other is rare and becomes the nearest dominant value (ties: the
    lower). NaN (invalid) samples are not counted and become the fullest
    bin's value.

    Parameters
    ----------
    values : (n,) float ndarray
        The cluster's depth samples (NaN = invalid).

    Returns
    -------
    (n,) float64 ndarray
        Corrected values; all NaN if the cluster has no valid sample.

    Examples
    --------
    >>> v = np.array([100, 100, 100, 101, 97, 60, np.nan])
    >>> correct_cluster_depths(v, origin=0, level_size=1, n_bins=256).tolist()
    [100.0, 100.0, 100.0, 101.0, 97.0, 100.0, 100.0]
    """
    from .segment import _kernels

    values = np.ascontiguousarray(values, dtype=np.float64).ravel()
    out = np.empty_like(values)
    bin_width = level_size if bin_width is None else bin_width
    if not (bin_width > 0 and math.isfinite(bin_width)) or int(n_bins) < 1:
        raise ValueError(f"bin_width (or level_size) must be finite and > 0 and n_bins >= 1; got {bin_width!r}, "
                         f"{n_bins!r}.")
    _kernels().correct_values(values, float(origin), float(level_size), float(bin_width), int(n_bins),
                              float(dominant_fraction), float(tolerance_levels * level_size), out)
    return out


# ----------------------------------------------------------------------------
# The pipeline: prepare the run, solve each patch, paste it back, build the result
# ----------------------------------------------------------------------------


@dataclass(frozen=True)
class _Levels:
    """The depth scale of one run (spec conventions).

    The +-``tolerance_levels`` test counts in levels of ``level_size`` depth
    units: 1 for 8-bit input, else ``(max - min) / 255`` of the valid depths,
    unless ``params.level_size`` is set. The histogram has one bin per level
    for 8-bit input, else ``params.histogram_bins`` bins over the valid range,
    starting at ``origin`` (the smallest valid depth).
    """

    origin: float
    level_size: float
    bin_width: float
    n_bins: int


def _levels(depth: np.ndarray, is_8bit: bool, params: ThesisParams) -> _Levels:
    lo, hi = valid_range(depth)
    if params.level_size is not None:
        level_size = float(params.level_size)
    else:
        level_size = 1.0 if is_8bit or hi == lo else (hi - lo) / 255.0
    if is_8bit:
        bin_width, n_bins = 1.0, int(hi - lo) + 1
    else:
        n_bins = params.histogram_bins
        bin_width = (hi - lo) / (n_bins - 1) if hi > lo else 1.0
    return _Levels(origin=lo, level_size=level_size, bin_width=bin_width, n_bins=n_bins)


@dataclass(frozen=True)
class _Context:
    """What every patch reads (shared, never written while patches are solved)."""

    depth: np.ndarray          # (h, w) float32, NaN = no measurement
    color: np.ndarray          # (Hw, Ww, 3): the median-filtered color (each patch makes its own L*a*b*)
    nearest: np.ndarray        # (h, w): nearest valid depth anywhere (for patches without any)
    s: int                     # the integer scale factor
    levels: _Levels
    params: ThesisParams
    keep: bool                 # also return the intermediates
    init_means: list | None = None  # per patch: the previous frame's cluster means (warm start)
    want_means: bool = False   # return each patch's cluster means (for the next frame)


@dataclass
class _PatchResult:
    depth: np.ndarray                      # (Hp, Wp) float32
    corrected: np.ndarray                  # (hp, wp) float64
    lab_samples: np.ndarray                # (hp, wp) int16
    labels: np.ndarray | None = None       # (Hp, Wp) int16, with keep
    features: np.ndarray | None = None     # (Hp, Wp, 3) float32, with keep
    per_cluster: np.ndarray | None = None  # (k, Hp, Wp) float32, with keep
    means: np.ndarray | None = None        # (k, 3) cluster means in k-means features, with want_means


@dataclass(frozen=True)
class _WarmState:
    """What :func:`refine_thesis_stateful` carries from frame to frame."""

    patches: list
    params: ThesisParams
    means: list


@dataclass
class _Canvas:
    """The run's output arrays, filled patch by patch."""

    depth: np.ndarray                      # (Hw, Ww) float32
    corrected_lr: np.ndarray               # (h, w) float32
    labels_lr: np.ndarray                  # (h, w) int16
    lab: np.ndarray | None = None          # the rest only with keep
    labels: np.ndarray | None = None
    patch_index: np.ndarray | None = None
    pieces: np.ndarray | None = None

    @classmethod
    def empty(cls, work_shape: tuple[int, int], depth_shape: tuple[int, int], n_clusters: int,
              keep: bool) -> _Canvas:
        canvas = cls(depth=np.full(work_shape, np.nan, dtype=np.float32),
                     corrected_lr=np.full(depth_shape, np.nan, dtype=np.float32),
                     labels_lr=np.zeros(depth_shape, dtype=np.int16))
        if keep:
            canvas.lab = np.zeros(work_shape + (3,), dtype=np.float32)
            canvas.labels = np.zeros(work_shape, dtype=np.int16)
            canvas.patch_index = np.zeros(work_shape, dtype=np.int32)
            canvas.pieces = np.full((n_clusters,) + work_shape, np.nan, dtype=np.float32)
        return canvas

    def paste(self, index: int, rect: tuple[int, int, int, int], res: _PatchResult, s: int,
              owner: np.ndarray | None) -> None:
        """Write patch ``index`` back: all of it for a grid, only the pixels it owns for a manual layout."""
        r0, r1, c0, c1 = rect
        own = slice(r0 * s, r1 * s), slice(c0 * s, c1 * s)
        lr = slice(r0, r1), slice(c0, c1)
        if owner is None:
            self.depth[own] = res.depth
            self.corrected_lr[lr] = res.corrected
            self.labels_lr[lr] = res.lab_samples
            mine = (slice(None), slice(None))
        else:
            mine_lr = owner[lr] == index
            mine = np.repeat(np.repeat(mine_lr, s, axis=0), s, axis=1)
            self.depth[own][mine] = res.depth[mine]
            self.corrected_lr[lr][mine_lr] = res.corrected[mine_lr]
            self.labels_lr[lr][mine_lr] = res.lab_samples[mine_lr]
        if self.lab is not None:
            self.lab[own][mine] = res.features[mine]
            self.labels[own][mine] = res.labels[mine]
            self.patch_index[own][mine] = index
            for c in range(len(res.per_cluster)):
                self.pieces[c][own][mine] = res.per_cluster[c][mine]


def _run(depth_lr, rgb_hr, params, progress, *, keep: bool, warm: Any = False):
    """The thesis driver: check the inputs, plan the scale step and the depth levels, make the
    color features once for the whole image, then solve each patch and paste it back in order.

    With ``warm`` (``None`` or a previous state) also return the new state: each patch's
    k-means starts from the previous frame's means when that frame had the same patches.
    """
    params = ThesisParams() if params is None else params
    if not isinstance(params, ThesisParams):
        raise TypeError(f"params must be a ThesisParams; got {type(params).__name__}.")
    depth = as_depth(depth_lr)
    rgb = check_rgb(rgb_hr)
    check_pixels(rgb.shape, name="rgb_hr")
    step = plan_scale(depth.shape, rgb.shape)
    if step.resizes_color:
        warnings.warn(f"thesis scale step applied: {step.describe()}", ScaleWarning, stacklevel=3)
    levels = _levels(depth, np.asarray(depth_lr).dtype == np.uint8, params)
    lr_patches, owner = _lr_patches(params, depth.shape, step)  # a bad patch layout fails before any work
    filtered = _color_features(rgb, step, params)
    with _timed("nearest fill"):
        nearest = fill_invalid_nearest(depth)
    stateful = warm is not False
    previous = warm if stateful and isinstance(warm, _WarmState) and warm.patches == lr_patches \
        and warm.params == params and len(warm.means) == len(lr_patches) else None
    ctx = _Context(depth=depth, color=filtered, nearest=nearest, s=step.factor, levels=levels, params=params, keep=keep,
                   init_means=None if previous is None else previous.means, want_means=stateful)
    canvas = _Canvas.empty(step.work_shape, depth.shape, params.n_clusters, keep)
    means = []
    with closing(_solve_patches(ctx, lr_patches)) as solved:  # closing: stop the threads on an error
        for index, (rect, res) in enumerate(zip(lr_patches, solved)):
            with _timed("paste"):
                canvas.paste(index, rect, res, ctx.s, owner)
            means.append(res.means)
            if progress is not None:
                progress(index + 1, len(lr_patches))
    result = _result(canvas, ctx, step, lr_patches, filtered)
    return (result, _WarmState(lr_patches, params, means)) if stateful else result


def _color_features(rgb: np.ndarray, step: ScaleStep, params: ThesisParams) -> np.ndarray:
    """4.3.1 on the whole work grid: the median-filtered color.

    The median runs on the whole image at once (at a patch border the window
    sees the neighbouring patch, not a mirrored edge). Its L*a*b* (4.3.2),
    per pixel, is made by each patch in its own thread (:func:`_solve_patch`):
    OpenCV's conversion gives each pixel the same value whatever the image
    around it (checked on whole images, patches, single pixels and shuffled
    pixels), and a whole-image pass was a step of its own between the median
    and the patches.
    """
    with _timed("scale step"):
        rgb_work = resize_color(rgb, step)
    with _timed("median"):
        return median_rgb(rgb_work, params.median_size)


def _lr_patches(params: ThesisParams, depth_shape: tuple[int, int],
                step: ScaleStep) -> tuple[list[tuple[int, int, int, int]], np.ndarray | None]:
    """The patches on the depth grid, and for a manual layout the map of which patch owns each pixel."""
    if params.patch_layout is not None:
        return _manual_patches(params.patch_layout, depth_shape, step.color_shape)
    return patch_grid(depth_shape, params.patches), None


def _solve_patches(ctx: _Context, lr_patches: list[tuple[int, int, int, int]]) -> Iterator[_PatchResult]:
    """Each patch's result, in order.

    Patches are independent: for a large image they are solved in threads
    (NumPy and OpenCV release the GIL) and yielded in order, so the result
    does not depend on timing.
    """
    from ..._threads import threads  # the cores this process may use (depthrefine.batch gives a worker its share)

    workers = min(len(lr_patches), threads(), _MAX_THREADS)
    solve = functools.partial(_solve_patch, ctx, lr_patches)
    if workers <= 1 or ctx.color.shape[0] * ctx.color.shape[1] < _PARALLEL_MIN_PIXELS:
        for index in range(len(lr_patches)):
            yield solve(index)
        return
    pool = ThreadPoolExecutor(max_workers=workers)
    try:
        yield from pool.map(solve, range(len(lr_patches)))
    finally:
        pool.shutdown(cancel_futures=True)


def _result(canvas: _Canvas, ctx: _Context, step: ScaleStep, lr_patches: list[tuple[int, int, int, int]],
            filtered: np.ndarray) -> Refinement:
    """The :class:`Refinement`; without ``keep`` the work-grid intermediates are empty arrays."""
    s = ctx.s
    with _timed("resize back"):
        depth_hr = resize_depth_nearest(canvas.depth, step.color_shape)
    common = dict(depth_hr=depth_hr, scale=step, patches=[(r0 * s, r1 * s, c0 * s, c1 * s)
                                                          for r0, r1, c0, c1 in lr_patches],
                  labels_lr=canvas.labels_lr, corrected_lr=canvas.corrected_lr, level_size=ctx.levels.level_size)
    if not ctx.keep:
        empty = np.empty((0,), dtype=np.float32)
        return Refinement(**common, rgb_filtered=empty, lab_unified=empty, labels=empty, patch_index=empty,
                          sparse_depth=empty, corrected_sparse=empty, cluster_pieces=empty)
    return Refinement(
        **common, rgb_filtered=filtered, lab_unified=canvas.lab, labels=canvas.labels,
        patch_index=canvas.patch_index, sparse_depth=_spread(ctx.depth, s, step.work_shape),
        corrected_sparse=_spread(canvas.corrected_lr, s, step.work_shape), cluster_pieces=canvas.pieces,
    )


def _solve_patch(ctx: _Context, lr_patches: list[tuple[int, int, int, int]], index: int) -> _PatchResult:
    """Steps 5-7 for patch ``index`` (pure: reads ``ctx``, writes nothing shared)."""
    from .segment import _kernels

    kernels = _kernels()
    r0, r1, c0, c1 = lr_patches[index]
    s, params, levels = ctx.s, ctx.params, ctx.levels
    init = None if ctx.init_means is None else ctx.init_means[index]
    # 4.3.2-4.3.3: unified L*, k-means.
    with _timed("lab"):
        lab = rgb_to_lab(ctx.color[r0 * s:r1 * s, c0 * s:c1 * s])
    with _timed("clustering"):
        clustered = cluster_colors(
            lab, n_clusters=params.n_clusters,
            iterations=params.kmeans_iterations, unify=params.unify_lightness, black_bound=params.black_bound,
            white_bound=params.white_bound, max_lightness=params.max_lightness,
            lightness_weight=params.lightness_weight, return_features=ctx.keep or ctx.want_means,
            init_means=init)
    labels, features = clustered if ctx.keep or ctx.want_means else (clustered, None)
    k = int(labels.max()) + 1
    means = None
    if ctx.want_means:  # each cluster's mean (w L*, a*, b*): where the next frame's k-means starts
        flat = labels.ravel()
        counts = np.bincount(flat, minlength=k).astype(np.float64)
        means = np.stack([np.bincount(flat, weights=features[..., d].ravel(), minlength=k) for d in range(3)], axis=1)
        means = means / np.maximum(counts, 1)[:, None]
        means[:, 0] *= params.lightness_weight

    # 4.4.1-4.4.2: spreading and classification: sample (i, j) sits at (i*s + s//2, j*s + s//2).
    lab_samples = labels[s // 2::s, s // 2::s]
    d_patch = ctx.depth[r0:r1, c0:c1]

    # 4.4.3-4.4.4: per-cluster histogram correction.
    with _timed("correction"):
        corrected = np.full(d_patch.shape, np.nan, dtype=np.float64)
        kernels.correct_patch(d_patch, lab_samples, k, bool(params.correct_depth), float(levels.origin),
                              float(levels.level_size), float(levels.bin_width), int(levels.n_bins),
                              float(params.dominant_fraction), float(params.tolerance_levels * levels.level_size),
                              corrected)

    # 4.5: per-cluster expansion, interpolation, reshaping, combination.
    with _timed("interpolation"):
        result, per_cluster, n_missing = _interpolate_clusters(corrected, lab_samples, labels, k, s,
                                                               params.expansion, ctx.keep)
        if n_missing:
            fallback = fill_invalid_nearest(corrected) if np.isfinite(corrected).any() else ctx.nearest[r0:r1, c0:c1]
            kernels.fill_missing(result, fallback, _nearest_samples(result.shape[0], s, r1 - r0),
                                 _nearest_samples(result.shape[1], s, c1 - c0))
    return _PatchResult(depth=result, corrected=corrected, lab_samples=lab_samples,
                        labels=labels if ctx.keep else None, features=features if ctx.keep else None,
                        per_cluster=per_cluster if ctx.keep else None, means=means)


# ----------------------------------------------------------------------------
# Step timing, for benchmarks
# ----------------------------------------------------------------------------

_STEP_TIMES: dict[str, float] | None = None
_STEP_LOCK = threading.Lock()


@contextmanager
def step_times() -> Iterator[dict[str, float]]:
    """Seconds spent in each step of the thesis runs inside the ``with`` block.

    For benchmarks (``benchmarks/bench_speed.py``). Steps solved per patch
    (clustering, correction, interpolation) are summed over patches, which may
    run in threads, so the sum of the steps can exceed the wall time. Not for
    concurrent runs: all runs inside the block add to the same dict.

    Examples
    --------
    >>> depth = np.full((4, 4), 30, np.uint8); rgb = np.zeros((8, 8, 3), np.uint8)
    >>> with step_times() as times:
    ...     _ = refine_thesis(depth, rgb)
    >>> sorted(times)[:3]
    ['clustering', 'correction', 'interpolation']
    """
    global _STEP_TIMES
    times: dict[str, float] = {}
    previous, _STEP_TIMES = _STEP_TIMES, times
    try:
        yield times
    finally:
        _STEP_TIMES = previous


@contextmanager
def _timed(name: str) -> Iterator[None]:
    if _STEP_TIMES is None:
        yield
        return
    start = time.perf_counter()
    try:
        yield
    finally:
        elapsed = time.perf_counter() - start
        with _STEP_LOCK:
            if _STEP_TIMES is not None:
                _STEP_TIMES[name] = _STEP_TIMES.get(name, 0.0) + elapsed
