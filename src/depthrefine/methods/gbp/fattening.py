"""Step 1b of gbp: thin the surface a direct-ToF camera has grown over its neighbours; undo a reprojected map's shift.

A direct-ToF pixel (phone LiDAR, SPAD arrays) reports the first strong
return inside its footprint: where a near and a far surface share it, the
near one wins, so every object is "fattened" by a fraction of the footprint
and each depth jump of the input sits beyond the color edge, on the far
side, all around the object. A registered input (the benchmarks' block
means, an indirect-ToF pixel's coverage-weighted mean) has its jumps on the
color edges, give or take the guide's texture.

:func:`edge_offset` measures, at every large jump of the input, how far the
strongest color edge lies along the depth gradient, and combines the
medians of opposite directions (a shift of the whole map cancels, a
fattening does not): a signed distance in depth pixels, positive when the
larger values spill over the smaller ones. Only a consistent offset of at
least :data:`FATTEN_MIN` depth pixels counts: on the benchmarks' registered
inputs it stays at most 0.40, on the simulated direct-ToF camera of the
``sensor`` protocol it is 0.58-1.04 in 11 of its 15 cases
(``python benchmarks/edge_offsets.py``; ``docs/tuning.md``).
:func:`thin_fattened` then shrinks the spilled side by that much on the
color grid (a grey-level erosion of the larger values, or dilation) and
reduces it back to the input's grid: the input the later steps see is the
footprint mean the jumps would have had without the fattening.

The same medians measure a shift of the whole map against the color image
(:func:`edge_shift`: opposite sectors' medians differ by twice the shift
along their axis, and a fattening cancels). A depth map reprojected from a
camera beside the color camera (``GbpParams.reprojected``) carries one: the
calibration's error, the parallax its reprojection leaves. With ``shift``,
:func:`thin_fattened` moves the input back by it when it is at least
:data:`SHIFT_MIN` depth pixels. Registered inputs are not moved: their
textured scenes measure shifts up to 0.9 depth pixels where there is none
(a strong color edge beside half of their jumps), as they do fattenings.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .measure import InputMeasures, near_jump
from .solve import resize, work_shape

__all__ = ["edge_offset", "edge_shift", "offset_axes", "sector_medians", "clearly_unfattened", "edge_offsets",
           "thin_fattened", "thin_if_fattened", "check_skips"]

#: An offset of the color edges below this many depth pixels is left alone (registered benchmark inputs: <= 0.40).
FATTEN_MIN = 0.5
#: The color edge is looked for this many depth pixels either side of the depth jump.
SEARCH_RADIUS = 2.5
#: The offsets are measured on a grid of at most this many pixels per depth pixel (the guide reduced to it).
PROFILE_STEPS = 8
#: A pixel's color-gradient profile counts when its peak holds this many times the profile's mean.
PEAK_RATIO = 2.5
#: Sigma of the blur of the enlarged depth before its gradient, in depth pixels (at least one color pixel).
DEPTH_BLUR = 0.5
#: Sigma of the blur of the guide's luminance before its gradient, color pixels (fine texture makes no edge).
GUIDE_BLUR = 1.0
#: The directions of the depth gradient are grouped into this many sectors (opposite ones make an axis) ...
DIRECTIONS = 8
#: ... a sector counts when it holds counted jump pixels along this many depth pixels of outline ...
MIN_SECTOR_PIXELS = 25
#: ... and at least this many axes need both of their sectors.
MIN_AXES = 3
#: The cheap check (:func:`clearly_unfattened`) looks at the guide reduced by an integer factor of at least 2, to
#: at least this many color pixels per depth pixel where the color grid is finer than that (:func:`~.solve.work_shape`:
#: 2 at x4, 3.5 at x7, 4 at x8 and x16; a color grid under twice the depth grid is not reduced and gets no check) ...
CHECK_SCALE = 4.0
#: ... and skips the full measure where each axis's median is within half of ``FATTEN_MIN`` and these quantiles
#: within ``FATTEN_MIN``: a median that 5 % of the offsets would carry past ``FATTEN_MIN`` does not count as clear.
CHECK_QUANTILES = (0.45, 0.55)
#: A reprojected input's shift (:func:`edge_shift`) is undone from this many depth pixels (sensor tuning means
#: 0.1 / 0.25 / 0.4: 5.2369 / 5.2257 / 5.2410, never 5.6116; docs/tuning.md).
SHIFT_MIN = 0.25


def edge_offset(m: InputMeasures, guide: np.ndarray, medians: np.ndarray | None = None) -> float:
    """How far the color edges lie from the input's large depth jumps, depth pixels, signed (see :func:`offset_axes`).

    The median over the axes of :func:`offset_axes`, and 0.0 when fewer than
    :data:`MIN_AXES` axes have both sectors (an outline facing one way, a
    single straight edge say, cannot tell a fattening from a shift or a
    shadow). Positive: the color edges lie on the side of the larger
    values, i.e. the larger values spill over the smaller. ``medians``:
    :func:`sector_medians`, when measured already.
    """
    axes = offset_axes(m, guide, medians)
    return float(np.median(axes)) if len(axes) >= MIN_AXES else 0.0


def edge_shift(m: InputMeasures, guide: np.ndarray, medians: np.ndarray | None = None) -> tuple[float, float]:
    """The shift ``(dy, dx)`` of the input's depth jumps from the color edges, depth pixels; (0, 0) when unmeasured.

    Where the whole map sits displaced by ``u`` from the color image, a jump
    whose depth gradient points along ``g`` has its color edge at ``-u.g``
    (plus any fattening), the opposite sector's at ``+u.g``: half the
    difference of two opposite sectors' medians (:func:`sector_medians`) is
    ``u`` along their axis. ``u`` is the least-squares fit over the axes
    with both sectors, at least two of them.
    """
    if medians is None:
        medians = sector_medians(m, guide)
    half = DIRECTIONS // 2
    rows, along = [], []
    for i in range(half):
        if np.isfinite(medians[i]) and np.isfinite(medians[i + half]):
            angle = 2.0 * np.pi * i / DIRECTIONS
            rows.append((math.sin(angle), math.cos(angle)))      # the axis's direction, (y, x)
            along.append((medians[i + half] - medians[i]) / 2.0)
    if len(rows) < 2:
        return 0.0, 0.0
    shift = np.linalg.lstsq(np.array(rows), np.array(along), rcond=None)[0]
    return float(shift[0]), float(shift[1])


def clearly_unfattened(m: InputMeasures, guide: np.ndarray) -> bool:
    """Whether a cheap measure on a reduced ``guide`` already says there is no fattening to thin.

    The offsets of :func:`edge_offsets` on ``guide`` (step 1b's check grid,
    gbp-fast's work grid), per sector and axis as for :func:`offset_axes`.
    True when at least one axis has both sectors and on every such axis the
    mean of the two sectors' medians lies within half of :data:`FATTEN_MIN`
    and the means of their :data:`CHECK_QUANTILES` within ``FATTEN_MIN``: a
    fattening grows an object on every side alike, so it shows on every axis
    that can be measured, and the full-resolution medians differ from the
    coarse ones by at most 0.21 depth pixels on the benchmark's inputs. The
    quantiles keep the check from skipping where a median is a toss-up
    between two populations (objects fattened and objects not, half and
    half): there the medians of the two grids can land on different sides
    (generated scenes of that kind were skipped on the medians alone, and
    the full measure thinned them). Otherwise only the full-resolution
    measure decides (``python benchmarks/edge_offsets.py`` prints both
    verdicts per benchmark case).
    """
    sectors = _sector_offsets(m, guide)
    half = DIRECTIONS // 2
    axes = [(sectors[i], sectors[i + half]) for i in range(half)
            if sectors[i] is not None and sectors[i + half] is not None]
    for a, b in axes:
        low_a, high_a = np.quantile(a, CHECK_QUANTILES)
        low_b, high_b = np.quantile(b, CHECK_QUANTILES)
        if (abs((np.median(a) + np.median(b)) / 2.0) > FATTEN_MIN / 2
                or (low_a + low_b) / 2.0 < -FATTEN_MIN or (high_a + high_b) / 2.0 > FATTEN_MIN):
            return False
    return len(axes) >= 1


def offset_axes(m: InputMeasures, guide: np.ndarray, medians: np.ndarray | None = None) -> list[float]:
    """The offset of the color edges from the input's large depth jumps per axis that has both sectors, depth pixels.

    A fattening grows an object on opposite sides alike, while a shift of
    the whole map moves opposite sides' edges in opposite directions, so the
    offset is measured per axis, as the mean of two opposite sectors'
    medians (:func:`sector_medians`; a shift cancels).
    """
    if medians is None:
        medians = sector_medians(m, guide)
    half = DIRECTIONS // 2
    axes = [(medians[i] + medians[i + half]) / 2.0 for i in range(half)]
    return [float(a) for a in axes if np.isfinite(a)]


def sector_medians(m: InputMeasures, guide: np.ndarray) -> np.ndarray:
    """The median offset (:func:`edge_offsets`) per direction of the depth gradient, depth pixels; NaN where too few.

    The offsets are grouped by the direction of the depth gradient into
    :data:`DIRECTIONS` sectors (centred on the image axes and diagonals,
    sector ``i`` on the angle ``2 pi i / DIRECTIONS`` from the x axis towards
    the y axis); a sector counts when it holds counted pixels along
    :data:`MIN_SECTOR_PIXELS` depth pixels of outline.
    """
    return np.array([np.nan if offsets is None else np.median(offsets) for offsets in _sector_offsets(m, guide)])


def _sector_offsets(m: InputMeasures, guide: np.ndarray) -> list[np.ndarray | None]:
    """The offsets of :func:`edge_offsets` per sector (see :func:`sector_medians`); None where too few."""
    offsets, angles = edge_offsets(m, guide)
    enough = MIN_SECTOR_PIXELS * min(PROFILE_STEPS, guide.shape[0] / m.depth.shape[0])   # depth pixels of outline
    sector = np.floor(angles / (2.0 * np.pi) * DIRECTIONS + 0.5).astype(np.int64) % DIRECTIONS
    return [offsets[sector == i] if (sector == i).sum() >= enough else None for i in range(DIRECTIONS)]


def edge_offsets(m: InputMeasures, guide: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per jump pixel, the distance to the color edge along the depth gradient, and that gradient's angle.

    At each color pixel on a large jump of the enlarged input (the band of
    :func:`~.edges.jump_band`, thinned to the gradient's ridge), the guide's
    luminance gradient is sampled along the depth gradient, :data:`SEARCH_RADIUS`
    depth pixels either way (on the color grid, reduced to :data:`PROFILE_STEPS`
    pixels per depth pixel when finer); where it has a clear peak, the peak's position
    (sub-pixel, depth pixels, positive towards the larger values) is that
    pixel's offset.

    Returns
    -------
    offsets, angles : (n,) float ndarrays
        Offsets in depth pixels; angles of the depth gradient, radians.
    """
    import cv2

    band_lr = m.large_jumps
    if not band_lr.any():
        return np.zeros(0), np.zeros(0)
    shape = guide.shape[:2]
    luma = cv2.cvtColor(guide, cv2.COLOR_RGB2GRAY).astype(np.float32)
    if shape[0] > PROFILE_STEPS * m.depth.shape[0]:    # finer than the profile's samples: reduce the guide first
        shape = (PROFILE_STEPS * m.depth.shape[0], round(PROFILE_STEPS * m.depth.shape[0] * shape[1] / shape[0]))
        luma = resize(luma, shape, cv2.INTER_AREA)
    scale = shape[0] / m.depth.shape[0]
    band = resize(band_lr.astype(np.uint8), shape, cv2.INTER_NEAREST) > 0
    # each image-sized temporary is let go as soon as it is used (the call's peak memory on a x2 input)
    luma = cv2.GaussianBlur(luma, (0, 0), GUIDE_BLUR)
    edges_x, edges_y = cv2.Sobel(luma, cv2.CV_32F, 1, 0), cv2.Sobel(luma, cv2.CV_32F, 0, 1)
    del luma
    # numpy's exactly rounded square root, not cv2.magnitude: its vector and scalar paths round differently, and
    # where they meet moves with the arrays' alignment, so the offsets changed from one process to the next
    edges = _hypot(edges_x, edges_y)
    del edges_x, edges_y
    depth = cv2.GaussianBlur(resize(m.filled, shape, cv2.INTER_LINEAR), (0, 0), max(1.0, DEPTH_BLUR * scale))
    gx, gy = cv2.Sobel(depth, cv2.CV_32F, 1, 0), cv2.Sobel(depth, cv2.CV_32F, 0, 1)
    del depth
    magnitude = _hypot(gx, gy)

    from ._offsets import jump_offsets

    offsets, angles = jump_offsets(band, magnitude, gx, gy, edges, math.ceil(SEARCH_RADIUS * scale), PEAK_RATIO)
    return offsets / scale, angles


def _hypot(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``sqrt(x**2 + y**2)`` of two (H, W) float32 arrays, each operation rounded to float32 (the same bits in
    every process): depthrefine's C kernel over threads when built, else numpy's three passes."""
    from ..._native import c_kernels
    from ..._threads import run_split

    c = c_kernels()
    if c is not None and x.ndim == 2:
        out = np.empty_like(x)
        run_split(c.hypot_rows, x.shape[0], np.ascontiguousarray(x), np.ascontiguousarray(y), out)
        return out
    out = x * x
    out += y * y
    return np.sqrt(out, out=out)


def thin_if_fattened(m: InputMeasures, guide: np.ndarray, *, shift: bool = False,
                     guide_reduced: np.ndarray | None = None) -> InputMeasures:
    """Step 1b with a cheap check first: :func:`thin_fattened`, skipped where the check clearly sees no fattening.

    The check is :func:`clearly_unfattened` on ``guide_reduced`` (default:
    ``guide`` reduced by area to :func:`~.solve.work_shape` with
    :data:`CHECK_SCALE`), a fraction of the full measure's cost (a fifth to
    a third of it on the 1.4 MP inputs of ``benchmarks/bench_speed.py``).
    Where it clearly sees no fattening, ``m`` is returned as it is, as the
    full measure would return it unless it would thin: a heuristic, checked
    on every benchmark case (``python benchmarks/edge_offsets.py`` prints both
    verdicts: none skipped that the full measure thins) and on generated
    scenes where half the objects are fattened. A reprojected input
    (``shift``) always gets the full measure, which also reads its shift; so
    does a guide too small to reduce.
    """
    if not shift and check_skips(m, guide, guide_reduced):
        return m
    return thin_fattened(m, guide, shift=shift)


def check_skips(m: InputMeasures, guide: np.ndarray, guide_reduced: np.ndarray | None = None) -> bool:
    """Whether step 1b's cheap check spares the full measure (:func:`thin_if_fattened`, unless ``shift``).

    :func:`clearly_unfattened` on ``guide_reduced``, by default ``guide``
    reduced by area to :func:`~.solve.work_shape` with :data:`CHECK_SCALE`;
    never where the guide is not reduced (the check would be the full measure).
    """
    import cv2

    if guide_reduced is None:
        reduced = work_shape(m.depth.shape, guide.shape[:2], CHECK_SCALE)
        guide_reduced = guide if reduced == guide.shape[:2] else resize(guide, reduced, cv2.INTER_AREA)
    return guide_reduced is not guide and clearly_unfattened(m, guide_reduced)


def thin_fattened(m: InputMeasures, guide: np.ndarray, *, shift: bool = False) -> InputMeasures:
    """The input's measures with a fattened side thinned (step 1b); ``m`` itself when no offset counts.

    The hole-filled input is enlarged to the color grid (nearest), the side
    that spills (:func:`edge_offset`) shrunk by the offset with a disc
    (grey-level erosion of the larger values, dilation of the smaller), and
    reduced back by area; holes stay holes. With ``shift`` (a reprojected
    input), when its shift (:func:`edge_shift`) is at least
    :data:`SHIFT_MIN`, the input and its holes are first moved back by it,
    bilinearly (a jump can land between two input pixels' borders), on a
    grid an integer multiple of the input's (so that enlarging and reducing
    move nothing else), a pixel staying a hole where it is moved at least
    half into one. Noise, range, sampling model and the guide's noise are
    the input's own; the jump map is measured anew.
    """
    import cv2

    medians = sector_medians(m, guide)
    offset = edge_offset(m, guide, medians)
    dy, dx = edge_shift(m, guide, medians) if shift else (0.0, 0.0)
    shifted = shift and math.hypot(dy, dx) >= SHIFT_MIN
    fattened = abs(offset) >= FATTEN_MIN
    if not (fattened or shifted):
        return m
    h, w = m.depth.shape
    valid = m.valid
    if shifted:
        k = math.ceil(max(guide.shape[0] / h, guide.shape[1] / w))
        shape = (k * h, k * w)
        move = np.float32([[1, 0, -dx * k], [0, 1, -dy * k]])

        def moved(image: np.ndarray) -> np.ndarray:
            return cv2.warpAffine(resize(image, shape, cv2.INTER_NEAREST), move, (shape[1], shape[0]),
                                  flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)

        enlarged = moved(m.filled)
        if not valid.all():
            valid = resize(moved(valid.astype(np.float32)), (h, w), cv2.INTER_AREA) > 0.5
    else:
        shape = guide.shape[:2]
        enlarged = resize(m.filled, shape, cv2.INTER_NEAREST)
    if fattened:
        radius = int(round(abs(offset) * shape[0] / h))
        disc = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * radius + 1,) * 2)
        enlarged = cv2.erode(enlarged, disc) if offset > 0 else cv2.dilate(enlarged, disc)
    filled = resize(enlarged, (h, w), cv2.INTER_AREA)
    depth = np.where(valid, filled, np.nan).astype(np.float32)
    return dataclasses.replace(m, depth=depth, valid=valid, filled=filled, jump=near_jump(filled, m.sigma, m.span))
