""":func:`upsample_gbp`, the default method, as its steps; :func:`upsample_gbp_stateful` for video."""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from ..._validate import as_depth, check_rgb, guide_uint8
from .measure import InputMeasures, measure_input
from .params import GbpParams
from . import solve
from .solve import back_project, clip_to_bounds, flat_blend, local_bounds, make_solver
from .edges import snap_edges
from .fattening import thin_if_fattened
from .trust import blend_fallback, measured_trust

__all__ = ["upsample_gbp", "upsample_gbp_stateful"]

Progress = Callable[[int, int], None]


def upsample_gbp(depth_lr: np.ndarray, rgb_hr: np.ndarray, *, params: GbpParams | None = None,
                 progress: Progress | None = None) -> np.ndarray:
    """Guided back-projection: upsample ``depth_lr`` to the grid of ``rgb_hr``.

    1. measure the input once (noise, range, sampling model, depth jumps, the guide's noise);
       where its depth jumps sit consistently beyond the color edges on one side
       (a direct-ToF camera's fattening), thin that side by as much (measured
       on the full guide where a cheap check on the guide reduced does not
       clearly say there is none); on a
       reprojected input (``params.reprojected``) move the whole map back by
       the shift its jumps show against the color edges;
    2. start from the bicubic enlargement, clipped at the input's depth jumps;
    3. back-project: ``iterations`` rounds of residual correction and edge-aware smoothing;
    4. blend in a stronger color-guided smoother where the input shows no depth edge;
    5. check the guide against the input one octave down and fall back to
       clipped bicubic interpolation where its detail is not confirmed;
    6. with ``snap_edges``, move each large depth jump onto the color edge.

    Parameters
    ----------
    depth_lr : (h, w) ndarray
        Low-resolution depth, any units; 0/NaN/inf/negative = no measurement.
    rgb_hr : (H, W, 3) ndarray
        Registered color image (RGB; uint8, uint16 or float in [0, 1]), at
        any factor (integer or not) of the depth map.
    params : GbpParams, optional
    progress : callable, optional
        ``progress(done, total)`` after each back-projection round and at the end.

    Returns
    -------
    (H, W) float32 ndarray
        Depth in the units of ``depth_lr``, within its valid range.

    Raises
    ------
    TypeError, ValueError
        Wrong params type, bad arrays, or no valid depth pixel.

    Examples
    --------
    >>> out = upsample_gbp(np.full((8, 8), 7.0, np.float32), np.zeros((32, 32, 3), np.uint8))
    >>> out.shape, float(out.min()), float(out.max())
    ((32, 32), 7.0, 7.0)
    """
    return _refine(as_depth(depth_lr), guide_uint8(check_rgb(rgb_hr)), params, progress)[0]


def _refine(depth: np.ndarray, guide: np.ndarray, params: GbpParams | None,
            progress: Progress | None, keep: dict | None = None) -> tuple[np.ndarray, InputMeasures]:
    """:func:`upsample_gbp`'s steps on the float input and the 8-bit guide; the result and the input's measures.

    ``keep``, when given, receives what the confidence map needs
    (:mod:`.confidence`): ``guided``, the result before step 5's fallback,
    and ``trust``, the guide's trust per input pixel (None without step 5);
    step 6 (``snap_edges``) comes after, so with it ``|result - guided|``
    also counts the moves of the snapped edges.
    """
    p = GbpParams() if params is None else params
    if not isinstance(p, GbpParams):
        raise TypeError(f"params must be GbpParams or None; got {type(p).__name__}.")
    measures = thin_if_fattened(measure_input(depth, guide, sampling=p.sampling), guide,   # 1, 1b
                                shift=bool(p.reprojected))
    solver = make_solver(guide, measures, p, solve.GUIDE_NOISE, keep_guide=p.snap_edges)
    bounds = local_bounds(measures.depth, solver.shape)
    result = back_project(measures, solver, p, bounds, progress)               # 2, 3
    result = flat_blend(result, measures, solver, p)                           # 4
    # the solves' weights are done with: free them before step 5 makes its own (the call's peak memory); the
    # smoothed guide is kept only for step 6
    smoothed_guide, scale = (solver.guide if p.snap_edges else None), solver.scale
    del solver
    if keep is not None:
        keep.update(guided=result, trust=None)
    if p.trust:                                                                # 5
        clip_to_bounds(result, bounds)
        del bounds
        trust = measured_trust(measures, guide, p)
        if keep is not None:
            keep.update(guided=result.copy(), trust=trust)
        result = blend_fallback(result, trust, measures)
    if p.snap_edges:                                                           # 6
        result = snap_edges(result, measures, smoothed_guide, scale)
    if progress is not None:
        progress(p.iterations + 1, p.iterations + 1)
    return result.astype(np.float32, copy=False), measures


#: Frames a pixel's running average spans at most (the warm start's memory).
WARM_FRAMES = 8
#: An input pixel changed when its 3x3 mean moved by more than this many noise sigmas.
WARM_SIGMAS = 3.0


def upsample_gbp_stateful(depth_lr: np.ndarray, rgb_hr: np.ndarray, *, params: GbpParams | None = None,
                          state: dict | None = None,
                          progress: Progress | None = None) -> tuple[np.ndarray, dict]:
    """:func:`upsample_gbp` for a video: a running average over frames where the input did not change.

    Each frame is refined as by :func:`upsample_gbp`. Where the input did not
    change since the previous frame (its 3x3 mean, valid in both frames,
    moved by at most 3 noise sigmas of the current frame; any change at all
    on a noise-free input) and the guide did not move either (no channel of
    its 3x3 mean moved by more than 3 of its noise sigmas, scaled to the
    mean, plus one level, within one input pixel's reach), the output is
    the running mean of this result and the previous output, over at most
    8 frames: the noise left in each frame's result averages out instead of
    flickering. Elsewhere (a moving object, a new or lost measurement, a
    color edge that moved) the pixel starts afresh with this frame's result.
    The output is clipped to this frame's valid input range. Deterministic.

    With ``state=None`` (the first frame) the result is :func:`upsample_gbp`'s,
    bit for bit; a state from a frame of another size is ignored (a cold start).

    Returns
    -------
    depth_hr : (H, W) float32 ndarray
    state : dict
        Opaque; pass it with the next frame.

    Examples
    --------
    >>> depth = np.array([[10, 10, 50, 50]] * 4, np.float32)
    >>> rgb = np.zeros((8, 8, 3), np.uint8); rgb[:, 4:] = 200
    >>> out, state = upsample_gbp_stateful(depth, rgb)
    >>> out2, state = upsample_gbp_stateful(depth, rgb, state=state)
    >>> bool((out == upsample_gbp(depth, rgb)).all()), bool((out2 == out).all())
    (True, True)
    """
    import cv2

    guide = guide_uint8(check_rgb(rgb_hr))
    result, m = _refine(as_depth(depth_lr), guide, params, progress)
    guide3 = cv2.blur(guide.astype(np.float32), (3, 3), borderType=cv2.BORDER_REPLICATE)
    mean3 = cv2.blur(m.filled, (3, 3), borderType=cv2.BORDER_REPLICATE)
    valid3 = cv2.erode(m.valid.astype(np.uint8), np.ones((3, 3), np.uint8), borderType=cv2.BORDER_REPLICATE) > 0
    shape = m.depth.shape + result.shape
    out = result
    count = np.ones(result.shape, np.float32)
    if state is not None and state.get("shape") == shape:
        tolerance = WARM_SIGMAS * m.sigma if m.sigma > 0 else 1e-6 * m.span
        steady = valid3 & state["valid3"] & (np.abs(mean3 - state["mean3"]) <= tolerance)
        changed = solve.resize((~steady).astype(np.uint8), result.shape, cv2.INTER_NEAREST) > 0
        # the guide moved (an edge the result follows) although the input did not: start afresh there too,
        # as far as the solve's reach (one input pixel)
        guide_tolerance = WARM_SIGMAS * m.guide_noise / 3.0 * math.sqrt(2.0) + 1.0
        moved = (np.abs(guide3 - state["guide3"]).max(axis=2) > guide_tolerance).astype(np.uint8)
        reach = 2 * math.ceil(result.shape[0] / m.depth.shape[0]) + 1
        changed |= cv2.dilate(moved, np.ones((reach, reach), np.uint8)) > 0
        count = np.where(changed, 1.0, np.minimum(state["count"] + 1.0, WARM_FRAMES)).astype(np.float32)
        # out <- prev + (result - prev) / count where steady; result where changed (count 1)
        prev = state["out"]
        out = (prev + (result - prev) / count).astype(np.float32)
        out[changed] = result[changed]
        np.clip(out, m.low, m.high, out=out)
    return out, {"shape": shape, "mean3": mean3, "valid3": valid3, "guide3": guide3, "out": out.copy(), "count": count}
