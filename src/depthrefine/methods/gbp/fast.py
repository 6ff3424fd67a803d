"""``gbp-fast``: guided back-projection for video rates (:func:`upsample_gbp_fast`).

gbp's own steps on a reduced grid, then one edge-aware solve at full resolution:

1. measure the input (:func:`~.measure.measure_input`; the guide's noise from
   every eighth pair of its rows, which gave the same figure), and thin a
   direct-ToF camera's fattened side (gbp's step 1b, :mod:`.fattening`): a
   cheap measure on the work grid of step 2 first, and where it does not
   clearly say "no fattening", gbp's own measure on the full-resolution
   guide (on the work grid alone, 4 of the 15 direct-ToF cases of the
   ``sensor`` protocol went unmeasured); a reprojected input always gets the
   full measure, and is moved back by its shift (:func:`~.fattening.edge_shift`);
2. reduce the guide by an integer factor ``k >= 2`` (area mean), so that the
   work grid is at least ``work_scale`` times the depth grid;
3. on the work grid, gbp's steps 2-4 (:func:`~.solve.back_project` with
   ``rounds`` rounds, :func:`~.solve.flat_blend`), and with ``trust`` its step 5;
4. enlarge the result bicubically to the color grid and smooth it once (one
   pass along the rows and one along the columns) with weights from the
   full-resolution guide and the result's own gradient
   (:func:`~depthrefine.methods._wls.guided_smooth`): the edges the work grid
   placed snap to the color edges. That solve lowers a curved surface by
   about ``lam`` times its Laplacian (a wave's crests, a floor's crease into
   a wall); away from the input's jumps and on an input without noise, the
   input's residual against the result's reduction is enlarged and added
   back (:func:`restore_smooth_surfaces`);
5. with ``snap_edges`` (off by default), gbp's step 6 (:func:`~.edges.snap_edges`)
   on the full-resolution guide: each large depth jump moves onto the color
   edge within two depth pixels (on the guide after gbp's 3x3 bilateral
   filter, ``guide_smoothing``, as gbp gives it; 9 ms of a 2.8 MP frame).

Where gbp solves eight times at full resolution, this solves twice on a grid
of a quarter (or less) of the pixels and once, one iteration, at full
resolution. Figures (speed beside FGS, accuracy per benchmark cell) and the
commands that reproduce them: ``docs/speed.md``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..._validate import as_depth, check_int, check_number, check_rgb, guide_uint8
from .edges import snap_edges
from .fattening import thin_if_fattened
from .measure import InputMeasures, measure_input, noise_levels, noise_share
from .params import GbpParams
from .solve import (GUIDE_NOISE, back_project, clip_to_bounds, flat_blend, local_bounds, make_solver, reduce,
                    resize, smoothed_guide, work_shape)
from .trust import blend_fallback, measured_trust

__all__ = ["GbpFastParams", "upsample_gbp_fast", "restore_smooth_surfaces"]

Progress = Callable[[int, int], None]

#: The full-resolution solve's smoothness, in multiples of the nominal ``lambda_lr * s**2``.
FINAL_LAMBDA = 4.0
#: Its iterations (one pass along the rows and one along the columns each); 2 gained 0.3 % on the tuning mean.
FINAL_ITERATIONS = 1
#: Iterations of each work-grid round's solve (gbp's before it went to 2; as tuned).
WORK_ITERATIONS = 3
#: The guide's noise is measured on every this-many-th pair of its rows (8 gave the same tuning mean as 1).
NOISE_ROWS = 8


@dataclass(frozen=True)
class GbpFastParams:
    """Parameters of ``gbp-fast`` (``method="gbp-fast"``).

    ``lambda_lr``, ``sigma_color``, ``flat_lambda_lr``, ``gradient_levels``,
    ``guide_smoothing``, ``snap_edges``, ``sampling`` and ``reprojected`` are gbp's
    (:class:`~.params.GbpParams`, same defaults and meaning; with
    ``reprojected`` the work-grid rounds smooth at least as much as
    ``lambda_lr = 2``, the full-resolution solve as without it: raised too,
    it gained 4 % more on the ``sensor`` protocol but smeared the real Kinect
    mug's rim, 2416 pixels of intermediate depth in the frame instead of 836,
    ``docs/tuning.md``).

    Attributes
    ----------
    rounds : int
        Back-projection rounds on the work grid (2; 3 gained 1.6 % on the
        tuning mean for a tenth more time).
    work_scale : float
        The work grid is the color grid reduced by the largest integer
        factor (at least 2) that keeps it at least this many times the depth
        grid (4): x4 and x8 inputs are solved at half the color resolution,
        x16 at a quarter.
    trust : bool
        gbp's check of the guide one octave down and its fallback (False:
        on the benchmark it changed no cell by more than 1 %, and cost a
        fifth of the time).
    """

    rounds: int = 2
    work_scale: float = 4.0
    lambda_lr: float = GbpParams.lambda_lr
    sigma_color: float = GbpParams.sigma_color
    flat_lambda_lr: float = GbpParams.flat_lambda_lr
    gradient_levels: float = GbpParams.gradient_levels
    guide_smoothing: float = GbpParams.guide_smoothing
    trust: bool = False
    snap_edges: bool = GbpParams.snap_edges
    sampling: str = GbpParams.sampling
    reprojected: bool | None = GbpParams.reprojected

    def __post_init__(self) -> None:
        check_int("rounds", self.rounds, minimum=1)
        check_number("work_scale", self.work_scale, positive=True)
        self.gbp_params()   # gbp's checks of the shared fields

    def gbp_params(self) -> GbpParams:
        """The :class:`~.params.GbpParams` of the work-grid steps (``iterations = rounds``)."""
        shared = {f.name for f in dataclasses.fields(GbpParams)} & {f.name for f in dataclasses.fields(self)}
        return GbpParams(iterations=self.rounds, **{name: getattr(self, name) for name in shared})


def noise_rows(guide: np.ndarray) -> np.ndarray:
    """Every :data:`NOISE_ROWS`-th pair of rows of ``guide``: the 2x2 blocks its noise is measured on.

    :func:`~.measure.estimate_guide_noise` measures each 2x2 block of rows
    ``2i, 2i + 1``; these are a subset of them, evenly spread.

    Examples
    --------
    >>> noise_rows(np.arange(48).reshape(48, 1))[:, 0].tolist()
    [0, 1, 16, 17, 32, 33]
    """
    period = 2 * NOISE_ROWS
    rows = guide.shape[0] // period * period
    if rows == 0:
        return guide
    return guide[:rows].reshape(rows // period, period, *guide.shape[1:])[:, :2].reshape(-1, *guide.shape[1:])


def restore_smooth_surfaces(x: np.ndarray, m: InputMeasures) -> None:
    """Add back to ``x``, in place, the input's residual ``y - D(x)`` where the input is smooth and noise-free.

    The residual (zero at invalid input pixels) is weighted by one minus the
    jump map (:func:`~.measure.near_jump`: the edges stay as the solve put
    them) and by one minus the input's noise share measured blind to
    curvature (:func:`~.measure.noise_levels`: noise is not put back), and
    enlarged bicubically. On generated smooth surfaces under a featureless
    guide it took gbp-fast on a wave and a bowl from 1.1-11x bicubic's RMSE
    to 0.57-0.97x, on a sphere before a wall, whose rim is a jump, from
    1.10-1.43x to 1.04-1.29x (``python benchmarks/smooth_surfaces.py``); the
    tuning mean went 2.6076 -> 2.6045 (``docs/speed.md``, gbp-fast).
    """
    import cv2

    share = 1.0 - noise_share(noise_levels(m))
    if share <= 0.0:
        return
    residual = m.filled - reduce(x, m.depth.shape, m.footprint)
    residual[~m.valid] = 0.0
    residual *= share * (1.0 - m.jump)
    x += resize(residual, x.shape, cv2.INTER_CUBIC)


def upsample_gbp_fast(depth_lr: np.ndarray, rgb_hr: np.ndarray, *, params: GbpFastParams | None = None,
                      progress: Progress | None = None) -> np.ndarray:
    """gbp on a reduced grid and one edge-aware solve at full resolution: upsample ``depth_lr`` to ``rgb_hr``'s grid.

    The arguments, the result (float32 on the color grid, in ``depth_lr``'s
    units, within its valid range) and the errors are those of
    :func:`~.upsample.upsample_gbp`; ``params`` is a :class:`GbpFastParams`,
    and ``progress(done, total)`` is called after each round and at the end.

    Examples
    --------
    >>> out = upsample_gbp_fast(np.full((8, 8), 7.0, np.float32), np.zeros((32, 32, 3), np.uint8))
    >>> out.shape, float(out.min()), float(out.max())
    ((32, 32), 7.0, 7.0)
    """
    import cv2

    from .. import _wls

    p = GbpFastParams() if params is None else params
    if not isinstance(p, GbpFastParams):
        raise TypeError(f"params must be GbpFastParams or None; got {type(p).__name__}.")
    depth, guide = as_depth(depth_lr), guide_uint8(check_rgb(rgb_hr))
    g = p.gbp_params()
    shape = guide.shape[:2]
    work = work_shape(depth.shape, shape, p.work_scale)
    total = p.rounds + 2

    def step(done: int) -> None:
        if progress is not None:
            progress(done, total)

    if work == shape:   # a color grid under twice the depth grid: gbp's steps there, nothing to enlarge
        guide_work = guide
    else:
        guide_work = np.ascontiguousarray(resize(guide, work, cv2.INTER_AREA))       # 2
    m = measure_input(depth, noise_rows(guide), sampling=p.sampling)                 # 1
    m = thin_if_fattened(m, guide, shift=bool(p.reprojected), guide_reduced=guide_work)     # 1b
    solver = make_solver(guide_work, m, g, GUIDE_NOISE, coarse=False)   # the work grid is reduced already
    bounds = local_bounds(m.depth, work)
    x = back_project(m, solver, g, bounds, None if progress is None else lambda k, _: step(k),    # 3
                     solve_iterations=WORK_ITERATIONS)
    x = flat_blend(x, m, solver, g)
    clip_to_bounds(x, bounds)
    step(p.rounds + 1)
    s = 0.5 * (shape[0] / depth.shape[0] + shape[1] / depth.shape[1])
    if work != shape:                                                                # 4
        x = resize(x, shape, cv2.INTER_CUBIC)
        sigma_color = max(p.sigma_color, GUIDE_NOISE * m.guide_noise)
        lam = FINAL_LAMBDA * p.lambda_lr * s * s   # not raised on a reprojected input: it smeared real rims
        if p.gradient_levels > 0:
            _wls.guided_smooth(x, guide, sigma_color, p.gradient_levels * m.span / 255.0 / s, lam,
                               iterations=FINAL_ITERATIONS, out=x)   # in place: no second output-sized array
        else:
            _wls.smooth(x, *_wls.color_weights(guide, sigma_color), lam, iterations=FINAL_ITERATIONS, out=x)
        restore_smooth_surfaces(x, m)
        np.clip(x, m.low, m.high, out=x)
    if p.trust:                                                                      # 3, with trust
        x = blend_fallback(x, measured_trust(m, guide_work, g), m)
    if p.snap_edges:                                                                 # 5
        x = snap_edges(x, m, smoothed_guide(guide, p.guide_smoothing), s)
    step(total)
    return x.astype(np.float32, copy=False)
