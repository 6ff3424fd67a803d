"""Leave-out hole filling on real captures: hide valid depth shaped like the real holes, fill, score.

A real capture has no ground truth for its holes, but it has valid depth
around them and holes of a real shape. :func:`hole_shapes` takes the
capture's own holes that lie inside the measured area (connected invalid
regions that touch no image border: not the outside of the field of view),
:func:`place_holes` moves each one onto valid surface (a seeded random
offset where the shape and a ring of ``margin`` pixels around it are all
valid, never overlapping another hidden one), and :func:`leave_out` fills
the depth with those regions hidden and scores the filling against the
hidden depth: RMSE and mean absolute error over the hidden pixels, in the
depth's units.

Fillers (:data:`BASELINE_FILLERS`, or any registered refinement method):

``nearest``
    Each hidden pixel takes its nearest valid pixel (Euclidean distance).
``inpaint``
    OpenCV's Telea inpainting (``cv2.inpaint``, ``INPAINT_TELEA``, radius
    :data:`INPAINT_RADIUS`) on the float depth: a smooth continuation of the
    border inward ("bicubic inpainting" in issue 20's wording).
a method name
    The refinement (:func:`depthrefine.rig.chain.refine_pair`, as ``run``
    does; told the depth is reprojected only with ``reprojected``) upsamples
    the depth with the hidden regions invalid onto the color image's grid;
    its result is read back at the centre of each hidden depth pixel (nearest).

Everything is pure and deterministic (seeded placement).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._fill import fill_invalid_nearest
from .._lazy import cv2
from .._validate import check_depth, check_int

__all__ = ["BASELINE_FILLERS", "INPAINT_RADIUS", "LeaveOutScore", "hole_shapes", "rescale_shapes", "place_holes",
           "fill_holes", "leave_out"]

#: The fillers that need no color image.
BASELINE_FILLERS = ("nearest", "inpaint")
#: Radius of ``cv2.inpaint`` (pixels): the neighbourhood each filled pixel is taken from.
INPAINT_RADIUS = 5


@dataclass(frozen=True)
class LeaveOutScore:
    """The errors of one filler on the hidden pixels of a capture.

    Attributes
    ----------
    filler : str
    rmse, mae : float
        Over the hidden pixels the filler gave a value, depth units.
    pixels : int
        Hidden pixels scored.
    coverage : float
        Share (0..1) of hidden pixels the filler gave a value.
    """

    filler: str
    rmse: float
    mae: float
    pixels: int
    coverage: float


def _invalid(depth: np.ndarray) -> np.ndarray:
    d = np.asarray(depth, dtype=np.float64)
    with np.errstate(invalid="ignore"):
        return ~(np.isfinite(d) & (d > 0))


def hole_shapes(depth: np.ndarray, *, min_pixels: int = 2, max_pixels: int | None = None) -> list[np.ndarray]:
    """The shapes of the holes inside the measured area of ``depth``, each a cropped boolean mask.

    A hole is a connected (8-neighbour) region of invalid pixels (0, NaN)
    that touches no border of the image (a region that does, such as the
    Azure Kinect's outside of the NFOV hexagon, lies beyond any measurement).

    Parameters
    ----------
    depth : (H, W) ndarray
    min_pixels, max_pixels : int
        Keep holes of this many pixels (``max_pixels``: no limit when None).

    Returns
    -------
    list of (h, w) bool ndarray
        Largest first.

    Examples
    --------
    >>> d = np.ones((6, 8)); d[2:4, 2:5] = 0; d[0, 7] = 0
    >>> [s.shape for s in hole_shapes(d)]
    [(2, 3)]
    """
    invalid = _invalid(check_depth(depth, "depth"))
    count, labels, stats, _ = cv2.connectedComponentsWithStats(invalid.astype(np.uint8), connectivity=8)
    rows, cols = invalid.shape
    shapes = []
    for k in np.argsort(-stats[1:, cv2.CC_STAT_AREA], kind="stable") + 1:
        x, y, w, h, area = stats[k]
        if x == 0 or y == 0 or x + w == cols or y + h == rows or area < min_pixels:
            continue
        if max_pixels is not None and area > max_pixels:
            continue
        shapes.append(labels[y:y + h, x:x + w] == k)
    return shapes


def rescale_shapes(shapes: list[np.ndarray], factor: float) -> list[np.ndarray]:
    """Hole shapes resized by ``factor`` (nearest), for a map of another resolution; shapes that vanish are dropped.

    Examples
    --------
    >>> [s.shape for s in rescale_shapes([np.ones((8, 4), bool), np.ones((1, 1), bool)], 0.5)]
    [(4, 2)]
    """
    if not factor > 0:
        raise ValueError(f"factor must be > 0; got {factor}.")
    out = []
    for shape in shapes:
        rows, cols = (int(round(n * factor)) for n in shape.shape)
        if rows < 1 or cols < 1:
            continue
        resized = cv2.resize(shape.astype(np.uint8), (cols, rows), interpolation=cv2.INTER_NEAREST_EXACT) > 0
        if resized.any():
            out.append(resized)
    return out


def place_holes(depth: np.ndarray, shapes: list[np.ndarray], *, seed: int = 0, margin: int = 2,
                attempts: int = 200) -> np.ndarray:
    """Hide valid regions of ``depth`` shaped like ``shapes``: the mask of the hidden pixels.

    Each shape is tried at up to ``attempts`` seeded random positions; it is
    placed at the first where it and a ring of ``margin`` pixels around it
    lie on valid pixels that no other placed shape (or its ring) uses. A
    shape that fits nowhere is skipped.

    Examples
    --------
    >>> d = np.ones((20, 20)); square = np.ones((3, 3), bool)
    >>> int(place_holes(d, [square, square], seed=1).sum())
    18
    """
    valid = ~_invalid(check_depth(depth, "depth"))
    margin = check_int("margin", margin, minimum=0)
    rng = np.random.default_rng(seed)
    free = valid.copy()
    hidden = np.zeros(valid.shape, dtype=bool)
    rows, cols = valid.shape
    ring = np.ones((2 * margin + 1, 2 * margin + 1), np.uint8)
    for shape in shapes:
        grown = cv2.dilate(np.pad(shape, margin).astype(np.uint8), ring) > 0
        h, w = grown.shape
        if h > rows or w > cols:
            continue
        for r, c in zip(rng.integers(0, rows - h + 1, attempts), rng.integers(0, cols - w + 1, attempts)):
            if free[r:r + h, c:c + w][grown].all():
                hidden[r + margin:r + margin + shape.shape[0], c + margin:c + margin + shape.shape[1]] |= shape
                free[r:r + h, c:c + w] &= ~grown
                break
    return hidden


def fill_holes(depth: np.ndarray, filler: str) -> np.ndarray:
    """``depth`` (float32) with every invalid pixel filled by a baseline filler (:data:`BASELINE_FILLERS`).

    Examples
    --------
    >>> fill_holes(np.array([[1.0, np.nan, np.nan, 4.0]]), "nearest").tolist()
    [[1.0, 1.0, 4.0, 4.0]]
    """
    d = check_depth(depth, "depth").astype(np.float32)
    invalid = _invalid(d)
    d[invalid] = np.nan
    if filler == "nearest":
        return fill_invalid_nearest(d)
    if filler == "inpaint":
        start = np.where(invalid, 0.0, d).astype(np.float32)
        return cv2.inpaint(start, invalid.astype(np.uint8), INPAINT_RADIUS, cv2.INPAINT_TELEA)
    raise ValueError(f"unknown filler {filler!r}; use one of {', '.join(BASELINE_FILLERS)} or a refinement method.")


def leave_out(depth: np.ndarray, rgb_hr: np.ndarray | None, hidden: np.ndarray, fillers: list[str], *,
              reprojected: bool = False) -> list[LeaveOutScore]:
    """Fill ``depth`` with the ``hidden`` pixels taken out, with each filler, and score the hidden pixels.

    Parameters
    ----------
    depth : (h, w) ndarray
        The real depth (its own holes stay holes), depth units.
    rgb_hr : (H, W, 3) ndarray or None
        The color image ``depth`` is registered to (needed by refinement methods).
    hidden : (h, w) bool ndarray
        The valid pixels to hide (:func:`place_holes`).
    fillers : list of str
        Baseline fillers or registered method names.
    reprojected : bool
        ``depth`` was reprojected onto the color camera by the rig chain (the mug's, not the iPhone's):
        methods that take ``reprojected`` (gbp, gbp-fast) are told so, as ``run`` tells them.

    Returns
    -------
    list of LeaveOutScore
        One per filler, in order.

    Examples
    --------
    >>> d = np.tile(np.arange(1.0, 9.0), (8, 1)); hidden = np.zeros((8, 8), bool); hidden[3:5, 3:5] = True
    >>> [(s.filler, round(s.rmse, 3)) for s in leave_out(d, None, hidden, ["nearest"])]
    [('nearest', 0.707)]
    """
    truth = check_depth(depth, "depth").astype(np.float64)
    hidden = np.asarray(hidden, dtype=bool)
    if hidden.shape != truth.shape:
        raise ValueError(f"hidden {hidden.shape} must have the depth's shape {truth.shape}.")
    if (_invalid(truth) & hidden).any():
        raise ValueError("hidden covers invalid depth pixels; hide valid pixels only (place_holes).")
    taken = np.where(hidden, np.nan, truth).astype(np.float32)
    scores = []
    for filler in fillers:
        if filler in BASELINE_FILLERS:
            filled = fill_holes(taken, filler)
        else:
            if rgb_hr is None:
                raise ValueError(f"the refinement method {filler!r} needs the color image.")
            filled = _refined_on_depth_grid(taken, rgb_hr, filler, reprojected)
        err = filled[hidden].astype(np.float64) - truth[hidden]
        err = err[np.isfinite(err)]
        n = int(err.size)
        scores.append(LeaveOutScore(filler, float(np.sqrt(np.mean(err * err))) if n else float("nan"),
                                    float(np.mean(np.abs(err))) if n else float("nan"), n,
                                    n / max(1, int(hidden.sum()))))
    return scores


def _refined_on_depth_grid(depth: np.ndarray, rgb_hr: np.ndarray, method: str, reprojected: bool) -> np.ndarray:
    """Refine onto the color grid (as ``run`` does) and read the result at each depth pixel's centre."""
    from ..rig.chain import refine_pair

    refined, _ = refine_pair(depth, rgb_hr, method=method, reprojected=reprojected)
    rows, cols = depth.shape
    return cv2.resize(np.asarray(refined, np.float32), (cols, rows), interpolation=cv2.INTER_NEAREST_EXACT)
