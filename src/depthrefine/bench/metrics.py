"""Error metrics of a depth map against ground truth, on a validity mask.

All functions are pure and print nothing. Depth maps are float arrays in one
unit (the ground truth's); ``NaN`` (and, in the ground truth, ``0`` or a
negative value) marks "no measurement". Only pixels where the ground truth is
valid *and* inside ``valid`` count. A prediction that is ``NaN`` on such a
pixel is not scored but lowers :attr:`Scores.coverage`, so a method cannot
look better by leaving hard pixels empty without it showing.

The bad-pixel thresholds and the edge threshold are in *levels*; ``level`` is
the size of one level in depth units (1 for the 8-bit maps of every benchmark
protocol, so "bad > 1" means "off by more than one disparity level").

A confidence map is scored by its sparsification curve (:func:`sparsification`):
the RMSE of the pixels left after removing the least confident fraction, beside
the oracle curve that removes by true error; AUSE is the area between them.

References
----------
Errors as reported for guided depth upsampling: RMSE and MAE (Park et al.,
ICCV 2011; Ferstl et al., ICCV 2013), bad-pixel percentages (Scharstein and
Szeliski, IJCV 2002). Sparsification curves and AUSE: E. Ilg et al.,
"Uncertainty estimates and multi-hypotheses networks for optical flow", ECCV
2018.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .._lazy import cv2

__all__ = [
    "Scores",
    "score",
    "valid_mask",
    "depth_edges",
    "edge_band",
    "rmse",
    "mae",
    "bad_pixel_share",
    "flicker",
    "Sparsification",
    "sparsification",
    "sparsification_curve",
    "ause",
    "SPARSIFICATION_STEPS",
    "EDGE_THRESHOLD_LEVELS",
    "EDGE_RADIUS",
]

#: A jump of at least this many levels between 4-neighbours is a depth edge.
EDGE_THRESHOLD_LEVELS = 4.0
#: Half-width, in pixels, of the band around depth edges (a 7-pixel band).
EDGE_RADIUS = 3


@dataclass(frozen=True)
class Scores:
    """Errors of one depth map against its ground truth.

    Attributes
    ----------
    rmse : float
        Root-mean-square error, depth units.
    mae : float
        Mean absolute error, depth units.
    edge_rmse : float
        RMSE within :data:`EDGE_RADIUS` pixels of a ground-truth depth edge
        (NaN when the ground truth has no edge).
    bad_1, bad_3 : float
        Share (0..1) of scored pixels off by more than 1 and 3 levels.
    coverage : float
        Share (0..1) of the valid ground-truth pixels where the prediction is
        finite (the pixels that were scored).
    n_pixels : int
        Number of scored pixels.
    n_edge : int
        Number of scored pixels in the edge band.
    """

    rmse: float
    mae: float
    edge_rmse: float
    bad_1: float
    bad_3: float
    coverage: float
    n_pixels: int
    n_edge: int

    def to_dict(self) -> dict[str, float | int]:
        """The fields as a plain dict (for CSV rows)."""
        return dataclasses.asdict(self)


def _as_float(depth: np.ndarray, name: str) -> np.ndarray:
    if not isinstance(depth, np.ndarray):
        raise TypeError(f"{name} must be a numpy array; got {type(depth).__name__}.")
    if depth.ndim != 2:
        raise ValueError(f"{name} must be 2-D (rows, cols); got shape {depth.shape}.")
    if depth.dtype.kind not in "uif":
        raise TypeError(f"{name} has dtype {depth.dtype}; expected an integer or float depth map.")
    return depth.astype(np.float64, copy=False)


def _check_pair(depth_pred: np.ndarray, depth_gt: np.ndarray, valid: np.ndarray | None):
    pred = _as_float(depth_pred, "depth_pred")
    gt = _as_float(depth_gt, "depth_gt")
    if pred.shape != gt.shape:
        raise ValueError(
            f"depth_pred has shape {pred.shape} but depth_gt has shape {gt.shape}; "
            "score a prediction on the ground truth's grid (crop both the same way)."
        )
    mask = valid_mask(gt)
    if valid is not None:
        valid = np.asarray(valid)
        if valid.shape != gt.shape or valid.dtype != bool:
            raise ValueError(
                f"valid must be a boolean array of shape {gt.shape}; got {valid.dtype} of shape {valid.shape}."
            )
        mask &= valid
    return pred, gt, mask


def valid_mask(depth_gt: np.ndarray, *, border: int = 0) -> np.ndarray:
    """Pixels with a ground-truth measurement (finite and > 0), minus a border.

    Parameters
    ----------
    depth_gt : (H, W) ndarray
        Ground truth; 0, negative and NaN mean "no measurement".
    border : int
        Pixels dropped on each side (the 6-pixel crop of the Lu protocol).

    Returns
    -------
    (H, W) bool ndarray

    Examples
    --------
    >>> valid_mask(np.array([[0, 1, 2, 3]] * 3, np.uint8), border=1).astype(int).tolist()
    [[0, 0, 0, 0], [0, 1, 1, 0], [0, 0, 0, 0]]
    """
    gt = np.asarray(depth_gt, dtype=np.float64)
    if border < 0:
        raise ValueError(f"border must be >= 0 pixels; got {border}.")
    with np.errstate(invalid="ignore"):
        mask = np.isfinite(gt) & (gt > 0)
    if border:
        inner = np.zeros_like(mask)
        inner[border:-border, border:-border] = True
        mask &= inner
    return mask


def depth_edges(depth_gt: np.ndarray, *, threshold: float) -> np.ndarray:
    """Pixels on either side of a depth jump of at least ``threshold``.

    A pixel is an edge pixel when it and one of its 4-neighbours are both
    valid and differ by ``threshold`` or more (depth units).

    Examples
    --------
    >>> depth_edges(np.array([[10, 10, 50, 50]], np.float32), threshold=4).astype(int).tolist()
    [[0, 1, 1, 0]]
    """
    gt = np.asarray(depth_gt, dtype=np.float64)
    ok = valid_mask(gt)
    edges = np.zeros(gt.shape, dtype=bool)
    for axis in (0, 1):
        a = [slice(None)] * 2
        b = [slice(None)] * 2
        a[axis], b[axis] = slice(None, -1), slice(1, None)
        a, b = tuple(a), tuple(b)
        with np.errstate(invalid="ignore"):
            jump = ok[a] & ok[b] & (np.abs(gt[a] - gt[b]) >= threshold)
        edges[a] |= jump
        edges[b] |= jump
    return edges


def edge_band(depth_gt: np.ndarray, *, threshold: float, radius: int = EDGE_RADIUS) -> np.ndarray:
    """Pixels within ``radius`` pixels (chessboard distance) of a depth edge.

    Examples
    --------
    >>> edge_band(np.array([[10, 10, 10, 50, 50, 50]], np.float32), threshold=4, radius=1).astype(int).tolist()
    [[0, 1, 1, 1, 1, 0]]
    """
    edges = depth_edges(depth_gt, threshold=threshold)
    if radius <= 0:
        return edges
    kernel = np.ones((2 * radius + 1, 2 * radius + 1), np.uint8)
    return cv2.dilate(edges.astype(np.uint8), kernel) > 0


def _errors(pred: np.ndarray, gt: np.ndarray, mask: np.ndarray) -> np.ndarray:
    scored = mask & np.isfinite(pred)
    return pred[scored] - gt[scored]


def rmse(depth_pred: np.ndarray, depth_gt: np.ndarray, *, valid: np.ndarray | None = None) -> float:
    """Root-mean-square error over the scored pixels (NaN if there are none).

    Examples
    --------
    >>> rmse(np.array([[1.0, 2.0]]), np.array([[1.0, 4.0]]))
    1.4142135623730951
    """
    err = _errors(*_check_pair(depth_pred, depth_gt, valid))
    return float(np.sqrt(np.mean(err * err))) if err.size else float("nan")


def mae(depth_pred: np.ndarray, depth_gt: np.ndarray, *, valid: np.ndarray | None = None) -> float:
    """Mean absolute error over the scored pixels (NaN if there are none).

    Examples
    --------
    >>> mae(np.array([[1.0, 2.0]]), np.array([[1.0, 4.0]]))
    1.0
    """
    err = _errors(*_check_pair(depth_pred, depth_gt, valid))
    return float(np.mean(np.abs(err))) if err.size else float("nan")


def bad_pixel_share(
    depth_pred: np.ndarray, depth_gt: np.ndarray, *, threshold: float, valid: np.ndarray | None = None
) -> float:
    """Share (0..1) of scored pixels whose error exceeds ``threshold`` (strictly).

    Examples
    --------
    >>> bad_pixel_share(np.array([[1.0, 2.0, 9.0, 4.0]]), np.array([[1.0, 3.0, 5.0, 4.0]]), threshold=1)
    0.25
    """
    err = _errors(*_check_pair(depth_pred, depth_gt, valid))
    return float(np.mean(np.abs(err) > threshold)) if err.size else float("nan")


def flicker(depth_preds, depth_gts) -> float:
    """Temporal flicker: mean absolute frame-to-frame change of the predictions where the truth did not change.

    For each pair of consecutive frames, the pixels whose ground truth is
    valid in both and equal are scored with ``|pred[t] - pred[t-1]|``; the
    result is the mean over all scored pixels of all pairs (NaN if there are
    none). 0 for a perfectly steady result; noise and cluster labels that
    change from frame to frame raise it.

    Parameters
    ----------
    depth_preds, depth_gts : sequences of (H, W) ndarray
        Predictions and ground truths, one per frame, in order.

    Examples
    --------
    >>> gts = [np.array([[5.0, 5.0]]), np.array([[5.0, 9.0]]), np.array([[5.0, 9.0]])]
    >>> preds = [np.array([[5.0, 5.0]]), np.array([[6.0, 8.0]]), np.array([[6.0, 9.0]])]
    >>> flicker(preds, gts)   # pair 1: |6-5| on the left pixel; pair 2: |6-6| and |9-8|
    0.6666666666666666
    """
    preds, gts = list(depth_preds), list(depth_gts)
    if len(preds) != len(gts):
        raise ValueError(f"flicker needs one ground truth per prediction; got {len(preds)} and {len(gts)}.")
    total, count = 0.0, 0
    for t in range(1, len(preds)):
        pred_now, gt_now, valid_now = _check_pair(preds[t], gts[t], None)
        pred_prev, gt_prev, valid_prev = _check_pair(preds[t - 1], gts[t - 1], None)
        if pred_now.shape != pred_prev.shape:
            raise ValueError(f"frames {t - 1} and {t} have shapes {pred_prev.shape} and {pred_now.shape}; flicker "
                             "needs one shape.")
        steady = (valid_now & valid_prev & (gt_now == gt_prev) & np.isfinite(pred_now) & np.isfinite(pred_prev))
        total += float(np.abs(pred_now[steady] - pred_prev[steady]).sum())
        count += int(steady.sum())
    return total / count if count else float("nan")


def score(
    depth_pred: np.ndarray,
    depth_gt: np.ndarray,
    *,
    valid: np.ndarray | None = None,
    border: int = 0,
    level: float = 1.0,
    edge_threshold: float | None = None,
    edge_radius: int = EDGE_RADIUS,
) -> Scores:
    """All the metrics of ``depth_pred`` against ``depth_gt``.

    Parameters
    ----------
    depth_pred : (H, W) ndarray
        Prediction, depth units; NaN = no value.
    depth_gt : (H, W) ndarray
        Ground truth, same units; 0, negative or NaN = no measurement.
    valid : (H, W) bool ndarray, optional
        Further restricts the scored pixels.
    border : int
        Pixels dropped on each side before scoring.
    level : float
        Depth units per level, for the bad-pixel and edge thresholds.
    edge_threshold : float, optional
        Depth jump (depth units) that makes an edge; default
        :data:`EDGE_THRESHOLD_LEVELS` levels.
    edge_radius : int
        Half-width of the edge band, pixels.

    Returns
    -------
    Scores

    Raises
    ------
    ValueError, TypeError
        Arrays that are not 2-D depth maps of the same shape.

    Examples
    --------
    >>> gt = np.array([[10, 10, 50, 50]] * 4, np.float32)
    >>> pred = gt + np.float32(2)
    >>> s = score(pred, gt)
    >>> s.rmse, s.mae, s.bad_1, s.bad_3, s.n_edge
    (2.0, 2.0, 1.0, 0.0, 16)
    """
    if not level > 0:
        raise ValueError(f"level must be > 0 depth units; got {level}.")
    pred, gt, mask = _check_pair(depth_pred, depth_gt, valid)
    if border:
        mask &= valid_mask(gt, border=border)
    n_valid = int(mask.sum())
    scored = mask & np.isfinite(pred)
    err = pred[scored] - gt[scored]
    n = int(err.size)
    threshold = EDGE_THRESHOLD_LEVELS * level if edge_threshold is None else float(edge_threshold)
    band = edge_band(gt, threshold=threshold, radius=edge_radius)[scored]
    err_edge = err[band]
    abs_err = np.abs(err)
    nan = float("nan")
    return Scores(
        rmse=float(np.sqrt(np.mean(err * err))) if n else nan,
        mae=float(np.mean(abs_err)) if n else nan,
        edge_rmse=float(np.sqrt(np.mean(err_edge * err_edge))) if err_edge.size else nan,
        bad_1=float(np.mean(abs_err > 1.0 * level)) if n else nan,
        bad_3=float(np.mean(abs_err > 3.0 * level)) if n else nan,
        coverage=n / n_valid if n_valid else nan,
        n_pixels=n,
        n_edge=int(err_edge.size),
    )


# ---------------------------------------------------------------- confidence

#: The sparsification curve removes 0, 1, ..., 99 % of the scored pixels.
SPARSIFICATION_STEPS = 100


@dataclass(frozen=True, eq=False)
class Sparsification:
    """How well a confidence map ranks the errors of a depth map (:func:`sparsification`).

    Attributes
    ----------
    fractions : (S,) float64 ndarray
        Shares of the scored pixels removed: 0, 0.01, ..., 0.99.
    curve : (S,) float64 ndarray
        RMSE of the pixels left after removing the least confident ``fractions``.
    oracle : (S,) float64 ndarray
        The same, removing the pixels of largest true error first (the best any
        confidence can do).
    ause : float
        Area between ``curve`` and ``oracle`` over ``fractions`` (depth units;
        0 for a perfect ranking).
    rmse : float
        RMSE of all scored pixels (``curve[0]``).
    confident_rmse, doubtful_rmse : float
        RMSE of the more and of the less confident half of the scored pixels.
    n_pixels : int
        Number of scored pixels.
    """

    fractions: np.ndarray
    curve: np.ndarray
    oracle: np.ndarray
    ause: float
    rmse: float
    confident_rmse: float
    doubtful_rmse: float
    n_pixels: int

    @property
    def relative_ause(self) -> float:
        """``ause / rmse``: comparable across scenes and units."""
        return self.ause / self.rmse if self.rmse > 0 else float("nan")

    @property
    def half_ratio(self) -> float:
        """``confident_rmse / doubtful_rmse``: below 1 when confidence means lower error."""
        return self.confident_rmse / self.doubtful_rmse if self.doubtful_rmse > 0 else float("nan")


def _removed_squares(squares: np.ndarray, order_key: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Knots ``(k, S(k))`` of the sum of squares ``S`` of the ``k`` pixels of lowest ``order_key``.

    Pixels of equal key are removed as one group, evenly (``S`` is linear
    within a group): a tie is not broken in anyone's favour.
    """
    order = np.argsort(order_key, kind="stable")
    key = order_key[order]
    sums = np.concatenate(([0.0], np.cumsum(squares[order], dtype=np.float64)))
    knots = np.concatenate(([0], np.flatnonzero(key[1:] != key[:-1]) + 1, [key.size]))
    return knots.astype(np.float64), sums[knots]


def sparsification_curve(errors: np.ndarray, confidence: np.ndarray, fractions: np.ndarray) -> np.ndarray:
    """RMSE of ``errors`` left after removing the least confident ``fractions`` of them (ties removed evenly).

    Parameters
    ----------
    errors, confidence : (N,) ndarray
        One value per scored pixel; higher confidence means more trusted.
    fractions : (S,) ndarray
        Shares in [0, 1) to remove.

    Examples
    --------
    >>> sparsification_curve(np.array([3.0, 0.0, 4.0, 0.0]), np.array([0.1, 0.9, 0.2, 0.8]), np.array([0, 0.5]))
    array([2.5, 0. ])
    """
    squares = np.square(np.asarray(errors, dtype=np.float64))
    knots, sums = _removed_squares(squares, np.asarray(confidence, dtype=np.float64))
    n = squares.size
    removed = np.asarray(fractions, dtype=np.float64) * n
    left = np.maximum(sums[-1] - np.interp(removed, knots, sums), 0.0)
    return np.sqrt(left / np.maximum(n - removed, 1e-12))


def sparsification(
    depth_pred: np.ndarray,
    depth_gt: np.ndarray,
    confidence: np.ndarray,
    *,
    valid: np.ndarray | None = None,
    border: int = 0,
    steps: int = SPARSIFICATION_STEPS,
) -> Sparsification:
    """The sparsification curve of ``confidence`` on the errors of ``depth_pred``, its oracle and AUSE.

    The scored pixels are those of :func:`score` (valid ground truth, inside
    ``valid`` and the border, finite prediction). The curve is the RMSE
    after removing the least confident share of them, at ``steps`` shares
    from 0 to ``1 - 1/steps``; the oracle removes the largest errors first;
    AUSE is the area between the two (trapezoid rule). Pixels of equal
    confidence are removed together, evenly, so a constant confidence gives
    a flat curve. A non-finite confidence counts as 0.

    Parameters
    ----------
    depth_pred, depth_gt : (H, W) ndarray
        As for :func:`score`.
    confidence : (H, W) ndarray
        Higher = more trusted (any monotone scale: only the order counts).
    valid : (H, W) bool ndarray, optional
    border : int
    steps : int

    Returns
    -------
    Sparsification
        NaN figures when no pixel is scored.

    Examples
    --------
    >>> gt = np.ones((1, 4)); pred = np.array([[1.0, 2.0, 3.0, 5.0]])
    >>> s = sparsification(pred, gt, -np.abs(pred - gt))   # a perfect ranking
    >>> round(s.ause, 12), s.confident_rmse, s.doubtful_rmse
    (0.0, 0.7071067811865476, 3.1622776601683795)
    """
    pred, gt, mask = _check_pair(depth_pred, depth_gt, valid)
    conf = np.asarray(confidence, dtype=np.float64)
    if conf.shape != gt.shape:
        raise ValueError(f"confidence has shape {conf.shape} but depth_gt has shape {gt.shape}; give one "
                         "confidence per pixel of the prediction.")
    if int(steps) < 2:
        raise ValueError(f"steps must be >= 2; got {steps}.")
    if border:
        mask &= valid_mask(gt, border=border)
    scored = mask & np.isfinite(pred)
    err = np.abs(pred[scored] - gt[scored])
    fractions = np.arange(int(steps)) / float(steps)
    n = int(err.size)
    if n == 0:
        nan = np.full(fractions.shape, np.nan)
        return Sparsification(fractions, nan, nan, float("nan"), float("nan"), float("nan"), float("nan"), 0)
    c = conf[scored]
    c = np.where(np.isfinite(c), c, 0.0)
    curve = sparsification_curve(err, c, fractions)
    oracle = sparsification_curve(err, -err, fractions)
    squares = err * err
    knots, sums = _removed_squares(squares, c)
    doubtful = float(np.interp(n / 2.0, knots, sums))
    return Sparsification(
        fractions=fractions, curve=curve, oracle=oracle,
        ause=float(np.trapezoid(curve - oracle, fractions)),
        rmse=float(curve[0]),
        confident_rmse=float(np.sqrt(max(sums[-1] - doubtful, 0.0) / (n / 2.0))),
        doubtful_rmse=float(np.sqrt(doubtful / (n / 2.0))),
        n_pixels=n,
    )


def ause(depth_pred: np.ndarray, depth_gt: np.ndarray, confidence: np.ndarray, *,
         valid: np.ndarray | None = None, border: int = 0) -> float:
    """Area between the sparsification curve of ``confidence`` and its oracle (:func:`sparsification`).

    Examples
    --------
    >>> gt = np.ones((1, 4)); pred = np.array([[1.0, 2.0, 3.0, 5.0]])
    >>> ause(pred, gt, np.ones((1, 4))) > ause(pred, gt, -pred) == 0.0
    True
    """
    return sparsification(depth_pred, depth_gt, confidence, valid=valid, border=border).ause
