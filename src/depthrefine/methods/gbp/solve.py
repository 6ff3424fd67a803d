"""Steps 2-4 of gbp: the start, the back-projection rounds and the flat-area blend.

- :func:`clamped_bicubic`: bicubic enlargement, held near the input's depth
  jumps within each pixel's 3x3 input range so that it does not ring (the
  start, and the fallback of step 5).
- :func:`back_project`: ``iterations`` rounds of "add the enlarged residual
  ``y - D(x)``, then smooth with an edge-aware weighted least-squares solve"
  (Irani & Peleg 1991; the fast global smoother of Min et al. 2014, with
  weights that fall with the color difference and with the estimate's own
  gradient), each round held within the local range of the input.
- :func:`flat_blend`: where the input shows no depth edge above its noise, a
  stronger color-guided smoother of the bilinear enlargement takes over.

Where the color grid reduced x2 is still at least ``COARSE_MIN_SCALE`` times
the depth grid (x4 and up), the first ``COARSE_ROUNDS`` rounds and the
flat-area solve run on that reduced grid (a quarter of the pixels): the
early rounds, whose strong smoothing places the edges, and the flat-area
solve, which averages over whole segments, lose nothing by it (figures in
``docs/speed.md``); the last rounds, which keep the detail, run at full
resolution.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable

import numpy as np

from .measure import InputMeasures, noise_share

if TYPE_CHECKING:
    from .params import GbpParams

__all__ = ["Solver", "Bounds", "make_solver", "smoothed_guide", "clamped_bicubic", "local_bounds", "nearest_index",
           "clip_to_bounds", "back_project", "detail_lambda", "flat_blend", "reduce", "resize", "resize_to_scratch",
           "work_shape"]

# ---- the detail solve
#: The smoothing falls geometrically over the rounds, from this many times its nominal value ...
LAMBDA_FIRST = 6.0
#: ... to this many times it (early rounds place the edges, late ones keep the detail).
LAMBDA_LAST = 0.35
#: Noise (levels of the depth range) at which the smoothing doubles: it grows with ``(sigma / NOISE_REF)**2``.
NOISE_REF = 1.0
#: On a point-sampled input the smoothing is this many times stronger (it fills the gaps between the samples).
POINT_LAMBDA = 10.0
#: On a reprojected input (``GbpParams.reprojected``) the detail solve's smoothness is at least this, per squared
#: depth pixel: the ``sensor`` protocol's tuning mean (both sensor models) fell from 0.06 to 2 and stayed within
#: 0.3 % at 4 (``docs/tuning.md``).
REPROJECTED_LAMBDA_LR = 2.0
#: The color sensitivity of the solves is at least this many times the guide's own noise.
GUIDE_NOISE = 3.0
#: The guide's 3x3 bilateral filter (``GbpParams.guide_smoothing``): diameter and spatial sigma, color pixels.
GUIDE_SMOOTHING_SIZE, GUIDE_SMOOTHING_SPACE = 3, 3.0

#: Iterations of each round's solve (one pass along the rows and one along the columns each; the third
#: iteration's smoothing, a sixteenth of the first's, changed the tuning mean by 0.15 %).
SOLVE_ITERATIONS = 2

# ---- coarse to fine
#: The first rounds run on the color grid reduced by this factor (area mean of the guide) ...
COARSE_FACTOR = 2
#: ... this many of them (real captures lose their fine structure with more: ``docs/speed.md``) ...
COARSE_ROUNDS = 4
#: ... when the reduced grid is at least this many times the depth grid (x4 and up; not the check one octave down).
COARSE_MIN_SCALE = 2.0
#: ... and when the input is footprint means (a point-sampled input's gaps are filled by the full-resolution solves:
#: on flat-colored point-sampled scenes with a noisy guide, 4 reduced rounds raised the RMSE 9 -> 156).
COARSE_MIN_FOOTPRINT = 1.0
#: The enlargement to full resolution after them weighs colors with this many times the solves' color sensitivity.
ENLARGE_SIGMA_COLOR = 16.0

#: A reduced grid (gbp-fast's work grid, step 1b's check: :func:`work_shape`) is the color grid reduced by an integer
#: factor of at least this (a quarter of the pixels).
WORK_MIN_REDUCTION = 2

# ---- the flat-area solve
#: Color sensitivity of the flat-area solve, 8-bit levels.
FLAT_SIGMA_COLOR = 4.0
#: A 3x3 input range below ``EDGE_LOW`` noise sigmas counts as flat ...
EDGE_LOW = 6.0
#: ... and the blend to the detail solve ramps over ``EDGE_WIDTH`` sigmas above it.
EDGE_WIDTH = 4.0

Progress = Callable[[int, int], None]


@dataclass(frozen=True, eq=False)
class Solver:
    """The guide as the solves see it: color weights of the detail and flat-area solves on one grid.

    ``scale`` is the mean enlargement factor from the input's grid to the
    guide's; ``guide`` the guide after its bilateral filter, or None where
    nothing after the weights reads it (see :func:`make_solver`); ``color_x``,
    ``color_y`` (``flat_x``, ``flat_y``) the edge weights of the detail
    (flat-area) solve; ``sigma_color`` and ``flat_sigma_color`` the color
    sensitivities they were made with. With ``coarse``, :meth:`reduced` gives
    the same on the grid reduced by ``COARSE_FACTOR`` where that grid is at
    least ``COARSE_MIN_SCALE`` times the depth grid.
    """

    shape: tuple[int, int]
    scale: float
    guide: np.ndarray | None
    color_x: np.ndarray
    color_y: np.ndarray
    flat_x: np.ndarray
    flat_y: np.ndarray
    sigma_color: float = 0.0
    flat_sigma_color: float = 0.0
    coarse: bool = False

    @functools.cached_property
    def reduced(self) -> Solver | None:
        """This solver on the grid reduced by ``COARSE_FACTOR`` (made once, on first use), or None.

        None without ``coarse`` or where the reduced grid would be less than
        ``COARSE_MIN_SCALE`` times the depth grid.
        """
        import cv2

        from .. import _wls

        f = COARSE_FACTOR
        if not self.coarse or self.scale / f < COARSE_MIN_SCALE:
            return None
        shape = (-(-self.shape[0] // f), -(-self.shape[1] // f))
        # the mean of each f x f block (an odd last row or column is repeated): OpenCV's fast integer-factor path
        pad_rows, pad_cols = shape[0] * f - self.shape[0], shape[1] * f - self.shape[1]
        guide = self.guide
        if pad_rows or pad_cols:
            guide = cv2.copyMakeBorder(guide, 0, pad_rows, 0, pad_cols, cv2.BORDER_REPLICATE)
        guide = np.ascontiguousarray(resize(guide, shape, cv2.INTER_AREA))
        color_x, color_y = _wls.color_weights(guide, self.sigma_color)
        flat_x, flat_y = color_x, color_y
        if self.flat_sigma_color != self.sigma_color:
            flat_x, flat_y = _wls.color_weights(guide, self.flat_sigma_color)
        scale = 0.5 * (shape[0] / self.shape[0] + shape[1] / self.shape[1]) * self.scale
        return Solver(shape, scale, guide, color_x, color_y, flat_x, flat_y, self.sigma_color,
                      self.flat_sigma_color)


def smoothed_guide(guide: np.ndarray, guide_smoothing: float) -> np.ndarray:
    """The guide after the 3x3 bilateral filter of color sigma ``guide_smoothing`` (``GbpParams``); as it is at 0.

    It flattens texture and noise within a color region and keeps the edges between regions.
    """
    import cv2

    if guide_smoothing <= 0:
        return guide
    return cv2.bilateralFilter(guide, GUIDE_SMOOTHING_SIZE, guide_smoothing, GUIDE_SMOOTHING_SPACE,
                               borderType=cv2.BORDER_REPLICATE)


def make_solver(guide: np.ndarray, m: InputMeasures, p: GbpParams, floor_factor: float, *,
                coarse: bool = True, keep_guide: bool = False) -> Solver:
    """The guide's color weights for the solves of an input measured as ``m``.

    The guide goes through a 3x3 bilateral filter (``p.guide_smoothing``)
    first; each solve's color sensitivity is at least ``floor_factor``
    times the guide's noise (``m.guide_noise``), so pixel noise is not taken
    for edges. ``coarse=False`` keeps every round and the flat-area solve
    on this grid (:attr:`Solver.reduced` is None). The filtered guide is
    kept (:attr:`Solver.guide`) where the reduced grid is made from it (x4
    and up) or with ``keep_guide``; elsewhere it goes once the weights are
    made: three bytes per pixel less through the solves (at x2, a 1280x720
    frame's solves held 9.5 times the output, 0.75 of it this guide).
    """
    import cv2

    from .. import _wls

    (h, w), (H, W) = m.depth.shape, guide.shape[:2]
    guide = smoothed_guide(guide, p.guide_smoothing)
    floor = floor_factor * m.guide_noise
    sigma_color, flat_sigma_color = max(p.sigma_color, floor), max(FLAT_SIGMA_COLOR, floor)
    color_x, color_y = _wls.color_weights(guide, sigma_color)
    flat_x, flat_y = color_x, color_y
    if FLAT_SIGMA_COLOR != p.sigma_color:
        flat_x, flat_y = _wls.color_weights(guide, flat_sigma_color)
    scale = 0.5 * (H / h + W / w)
    if not (keep_guide or (coarse and scale / COARSE_FACTOR >= COARSE_MIN_SCALE)):
        guide = None
    return Solver((H, W), scale, guide, color_x, color_y, flat_x, flat_y, sigma_color, flat_sigma_color, coarse)


def resize(image: np.ndarray, shape: tuple[int, int], interpolation: int) -> np.ndarray:
    """``cv2.resize`` to ``shape`` (rows, columns)."""
    import cv2

    return cv2.resize(image, (shape[1], shape[0]), interpolation=interpolation)


def resize_to_scratch(image: np.ndarray, shape: tuple[int, int], interpolation: int, slot: int = 0) -> np.ndarray:
    """:func:`resize` into scratch array ``slot`` (0 or 1) of the solver's for ``shape``: no new image-sized array.

    For a float32 temporary between two solves (:func:`depthrefine.methods._wls.scratch`): the next solve in
    this thread overwrites it, and two held at once need the two slots.
    """
    import cv2

    from .. import _wls

    return cv2.resize(image, (shape[1], shape[0]), dst=_wls.scratch(shape)[slot], interpolation=interpolation)


def work_shape(depth_shape: tuple[int, int], color_shape: tuple[int, int], work_scale: float) -> tuple[int, int]:
    """The color grid reduced by an integer factor ``k >= 2``: the largest that keeps ``work_scale`` x the depth grid.

    ``k`` is ``color / depth // work_scale``, at least 2 (so at x4 with
    ``work_scale`` 4 the grid is 2 color pixels per depth pixel). An integer
    factor keeps OpenCV's area reduction of the guide on its fast path (a
    fractional one took ten times longer). A color grid less than ``k``
    times the depth grid is not reduced.

    Examples
    --------
    >>> work_shape((272, 344), (1088, 1376), 4.0), work_shape((68, 86), (1088, 1376), 4.0)
    ((544, 688), (272, 344))
    >>> work_shape((100, 100), (150, 150), 4.0)
    (150, 150)
    """
    (h, w), (H, W) = depth_shape, color_shape
    scale = min(H / h, W / w)
    k = max(WORK_MIN_REDUCTION, int(scale // work_scale))
    if scale < k:
        return H, W
    return -(-H // k), -(-W // k)


def clamped_bicubic(depth: np.ndarray, shape: tuple[int, int], jump: np.ndarray, *,
                    neighbourhood: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
    """Bicubic enlargement, clipped near depth jumps to the range of each pixel's 3x3 input neighbourhood.

    Plain bicubic rings at a depth jump (values beyond both sides); clipped
    there, it keeps bicubic's sharpness, and on smooth surfaces (``jump`` 0)
    it stays plain bicubic, whose peaks may rightly pass the samples.
    ``depth`` is hole-filled; ``jump`` is its jump map (:func:`.measure.near_jump`);
    ``neighbourhood``, when given, is the (min, max) of ``depth``'s 3x3
    neighbourhoods already measured (:meth:`.measure.InputMeasures.neighbourhood`).
    The enlarged jump map goes to the solver's scratch slot 0
    (:func:`resize_to_scratch`), so a caller must not hold that slot across
    this call.
    """
    import cv2

    from .. import _resample

    if neighbourhood is None:
        kernel = np.ones((3, 3), np.uint8)
        neighbourhood = cv2.erode(depth, kernel), cv2.dilate(depth, kernel)
    up = resize(depth, shape, cv2.INTER_CUBIC)
    # up <- up + jump * (clip(up, low, high) - up), in place, the bounds on the input's grid, the enlarged jump map
    # in a scratch array of the solver's (free between solves): no image-sized array beside the result
    (h, w), (H, W) = depth.shape, shape
    _resample.clip_toward(up, resize_to_scratch(jump, shape, cv2.INTER_LINEAR), *neighbourhood,
                          nearest_index(h, H), nearest_index(w, W))
    return up


@dataclass(frozen=True, eq=False)
class Bounds:
    """:func:`local_bounds`: the input grid's bounds and, per row and column of the grid they bound, the input's.

    ``low``, ``high`` (h, w) float32; ``rows`` (H,), ``cols`` (W,) int32:
    pixel ``(i, j)`` of the grid is bounded by ``low[rows[i], cols[j]]`` and
    ``high[rows[i], cols[j]]``, the nearest-neighbour enlargement
    (``cv2.INTER_NEAREST``'s own index map) without its two image-sized
    arrays. :meth:`full` makes them.
    """

    low: np.ndarray
    high: np.ndarray
    rows: np.ndarray
    cols: np.ndarray

    @property
    def shape(self) -> tuple[int, int]:
        return len(self.rows), len(self.cols)

    def full(self) -> tuple[np.ndarray, np.ndarray]:
        """(low, high) on the grid: ``cv2.resize(..., INTER_NEAREST)`` of the input grid's, bit for bit."""
        index = np.ix_(self.rows, self.cols)
        return self.low[index], self.high[index]

    def on(self, shape: tuple[int, int]) -> Bounds:
        """The same bounds on the grid of ``shape`` = (rows, cols) instead."""
        (h, w), (H, W) = self.low.shape, shape
        return Bounds(self.low, self.high, nearest_index(h, H), nearest_index(w, W))


def nearest_index(n: int, size: int) -> np.ndarray:
    """The source index of each of ``size`` pixels in ``cv2.resize(..., INTER_NEAREST)`` from ``n`` pixels (int32).

    Taken from OpenCV itself (the enlargement of ``0, 1, ..., n - 1``), so it
    is its map whatever its rounding.

    Examples
    --------
    >>> nearest_index(3, 7).tolist()
    [0, 0, 0, 1, 1, 2, 2]
    """
    import cv2

    source = np.arange(n, dtype=np.float32).reshape(1, n)
    return cv2.resize(source, (size, 1), interpolation=cv2.INTER_NEAREST).ravel().astype(np.int32)


def local_bounds(depth: np.ndarray, shape: tuple[int, int], hole_margin: int = 0) -> Bounds:
    """The range of the valid input pixels of each input pixel's 3x3 neighbourhood, on a grid of ``shape``.

    ``depth`` is the input with NaN for invalid pixels, continued linearly
    beyond its border (odd reflection: a slope keeps its last pixels'
    values). Returns :class:`Bounds` (low, high float32 on the input's grid
    and the grid's nearest input rows and columns); they are +-inf (no
    bound) over missing input pixels and over the input pixels within
    ``hole_margin`` pixels of one.
    """
    import cv2

    padded = np.pad(depth, 1, mode="reflect", reflect_type="odd")   # NaN stays NaN
    valid = np.isfinite(padded)
    kernel = np.ones((3, 3), np.uint8)
    low = cv2.erode(np.where(valid, padded, np.inf).astype(np.float32), kernel)[1:-1, 1:-1]
    high = cv2.dilate(np.where(valid, padded, -np.inf).astype(np.float32), kernel)[1:-1, 1:-1]
    missing = ~valid[1:-1, 1:-1]
    if hole_margin > 0:
        missing = cv2.dilate(missing.astype(np.uint8), np.ones((2 * hole_margin + 1,) * 2, np.uint8)) > 0
    low[missing], high[missing] = -np.inf, np.inf
    (h, w), (H, W) = depth.shape, shape
    return Bounds(np.ascontiguousarray(low), np.ascontiguousarray(high), nearest_index(h, H), nearest_index(w, W))


def clip_to_bounds(x: np.ndarray, bounds: Bounds, low: float = -np.inf, high: float = np.inf) -> None:
    """Clip ``x`` in place to ``[low, high]``, then to ``bounds`` (:func:`local_bounds`).

    The same bits as ``np.clip(x, low, high)`` followed by ``np.clip`` to the
    bounds' image-sized arrays (:meth:`Bounds.full`), in one pass without them.
    """
    from .. import _resample

    _resample.clip_nearest(x, low, high, bounds.low, bounds.high, bounds.rows, bounds.cols)


def reduce(x: np.ndarray, shape: tuple[int, int], footprint: float) -> np.ndarray:
    """The data model ``D``: footprint means (``footprint = 1``), point samples (0, at the pixels' centres), a blend."""
    import cv2

    if footprint >= 1.0:
        return resize(x, shape, cv2.INTER_AREA)
    point = resize(x, shape, cv2.INTER_NEAREST_EXACT)
    if footprint <= 0.0:
        return point
    return point + footprint * (resize(x, shape, cv2.INTER_AREA) - point)


def _coarse(solver: Solver, m: InputMeasures) -> Solver | None:
    """:attr:`Solver.reduced` for an input of footprint means (``COARSE_MIN_FOOTPRINT``), else None."""
    return solver.reduced if m.footprint >= COARSE_MIN_FOOTPRINT else None


def detail_lambda(p: GbpParams) -> float:
    """The detail solve's smoothness per squared depth pixel: ``p.lambda_lr``, at least
    :data:`REPROJECTED_LAMBDA_LR` on a reprojected input (``p.reprojected`` True; None counts as False)."""
    return max(p.lambda_lr, REPROJECTED_LAMBDA_LR) if p.reprojected else p.lambda_lr


def back_project(m: InputMeasures, solver: Solver, p: GbpParams, bounds: Bounds,
                 progress: Progress | None = None, *, solve_iterations: int | None = None) -> np.ndarray:
    """Steps 2-3: the clipped bicubic start, then ``p.iterations`` back-projection rounds.

    Each round adds the Lanczos enlargement of the residual ``y - D(x)``
    (zero at invalid input pixels, so they never pull the result), clips the
    estimate to the input's local range (every round but the last, whose
    residual stays whole so the result's reduction matches the input; not
    within one input pixel of a hole, whose free pixels would carry the
    clipped rim's pull into it), smooths it with weights that fall with the
    color difference and with the estimate's own gradient (a jump the input
    shows is kept where the guide does not show it), and clips it to the
    input's local range again. The smoothing grows with the input's noise
    and falls geometrically over the rounds; each solve runs
    ``solve_iterations`` iterations (default ``SOLVE_ITERATIONS``). With
    :attr:`Solver.reduced` and an input of footprint means, the start and
    the first ``COARSE_ROUNDS`` rounds (never the last) are made on the
    reduced grid with the same smoothing strength (and ``bounds`` there),
    and the estimate is then enlarged by
    :func:`~depthrefine.methods._resample.guided_enlarge` (each pixel from the
    reduced pixels of its own color). ``bounds`` is :func:`local_bounds` of
    ``m.depth`` on the solver's grid.
    Returns (H, W) float32.
    """
    import cv2

    from .. import _resample, _wls

    (h, w), shape = m.depth.shape, solver.shape
    solve_iterations = SOLVE_ITERATIONS if solve_iterations is None else solve_iterations
    # the smoothing strength per round, the same on either grid
    lam = detail_lambda(p) * solver.scale * solver.scale * (1.0 + (m.sigma_levels / NOISE_REF) ** 2) * (
        1.0 + (POINT_LAMBDA - 1.0) * (1.0 - m.footprint))
    coarse = _coarse(solver, m)
    first = min(COARSE_ROUNDS, p.iterations - 1) if coarse is not None else 0
    grid = coarse if first > 0 else solver
    grid_bounds = bounds if grid is solver else bounds.on(grid.shape)
    # the residual's clip spares the pixels within one input pixel of a hole (measured once, on the input's grid)
    hole_bounds = None if m.valid.all() else local_bounds(m.depth, shape, hole_margin=1)
    residual_bounds = grid_bounds if hole_bounds is None else hole_bounds.on(grid.shape)
    x = clamped_bicubic(m.filled, grid.shape, m.jump, neighbourhood=m.neighbourhood())
    for k in range(p.iterations):
        if k == first and grid is not solver:
            # each pixel from the reduced pixels of its own color: the edges stay sharp
            x = _resample.guided_enlarge(x, coarse.guide, solver.guide, ENLARGE_SIGMA_COLOR * solver.sigma_color)
            grid, grid_bounds = solver, bounds
            residual_bounds = bounds if hole_bounds is None else hole_bounds
        ratio = LAMBDA_FIRST * (LAMBDA_LAST / LAMBDA_FIRST) ** (k / max(1, p.iterations - 1))
        residual = reduce(x, (h, w), m.footprint)
        np.subtract(m.filled, residual, out=residual)
        residual[~m.valid] = 0.0
        # its enlargement in a scratch array of the solver's (free between solves): no more memory
        x += resize_to_scratch(residual, grid.shape, cv2.INTER_LANCZOS4)
        del residual      # before the next round's reduction
        if k < p.iterations - 1:
            clip_to_bounds(x, residual_bounds)
        if p.gradient_levels > 0:
            # a jump the back-projection places spreads over about ``grid.scale`` pixels
            gradient_sigma = p.gradient_levels * m.span / 255.0 / grid.scale
            _wls.smooth_with_gradient(x, grid.color_x, grid.color_y, gradient_sigma, lam * ratio,
                                      iterations=solve_iterations)
        else:
            x = _wls.smooth(x, grid.color_x, grid.color_y, lam * ratio, iterations=solve_iterations)
        clip_to_bounds(x, grid_bounds, m.low, m.high)
        if progress is not None:
            progress(k + 1, p.iterations + 1)
    return x


def flat_blend(x: np.ndarray, m: InputMeasures, solver: Solver, p: GbpParams) -> np.ndarray:
    """Step 4: where the input shows no depth edge above its noise, a stronger color-guided smoother takes over.

    A 3x3 input range below ``EDGE_LOW`` noise sigmas counts as flat; the
    blend ramps over ``EDGE_WIDTH`` sigmas above it. The flat-area solve
    (``p.flat_lambda_lr`` per depth pixel, of the bilinear enlargement)
    averages noise over whole color segments; on a noise-free input there
    is nothing to average and its share fades out (below
    :data:`~.measure.FLAT_NOISE` levels). With :attr:`Solver.reduced` (as
    in :func:`back_project`) the
    solve runs on the reduced grid (the same smoothness per depth pixel) and
    is enlarged bilinearly. ``x`` is updated in place and returned, within
    the input's range.
    """
    import cv2

    from .. import _wls

    # the blend's weights on the input's grid first, before the solve's image-sized result exists (peak memory)
    low, high = m.neighbourhood()
    local_range = np.subtract(high, low, out=high)
    del low, high
    edge = np.clip((local_range - EDGE_LOW * m.sigma) / (EDGE_WIDTH * m.sigma + 1e-6 * m.span), 0.0, 1.0)
    edge = cv2.dilate(edge.astype(np.float32), np.ones((3, 3), np.uint8))
    edge = (1.0 - (1.0 - edge) * noise_share(m.sigma_levels)).astype(np.float32)
    del local_range
    grid = _coarse(solver, m) or solver
    # the solve's start in a scratch array of the solver's (free between solves), solved there
    start = resize_to_scratch(m.filled, grid.shape, cv2.INTER_LINEAR)
    flat = _wls.smooth(start, grid.flat_x, grid.flat_y, p.flat_lambda_lr * grid.scale, out=start)
    del start
    # the two image-sized temporaries in the solver's scratch arrays (free between solves): no more memory
    if grid is not solver:
        flat = resize_to_scratch(flat, solver.shape, cv2.INTER_LINEAR, slot=0)
    edge = resize_to_scratch(edge, solver.shape, cv2.INTER_LINEAR, slot=1)
    # x <- edge * x + (1 - edge) * flat, in place
    x -= flat
    x *= edge
    x += flat
    return np.clip(x, m.low, m.high, out=x)
