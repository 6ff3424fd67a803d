"""Confidence maps: which output pixels to trust (issue 23).

:func:`refine_with_confidence` returns a method's depth (bit-identical to
:func:`~depthrefine.methods.registry.refine`'s) and a confidence map on the
same grid: float32 in [0, 1], 1 = most trusted, 0 where there is no depth.
A method registered with a ``confidence`` hook (gbp) makes its own from its
internals; every other method gets :func:`generic_confidence`, from the
input's support and the output's shape.

The map is built from an *expected error* per pixel, from the root of a sum
of squared terms in the depth's units (:func:`error_terms`):

- ``near``: the output's steepness within one color pixel, times
  ``NEAR_LENGTH`` pixels (an edge placed a pixel or two off);
- ``reach``: its steepness within half an input pixel, times
  ``REACH_LENGTH`` pixels (where an input pixel's footprint straddles an
  edge, the output may put the edge anywhere inside it);
- ``hole``: the distance to the nearest valid input pixel (input pixels)
  times the input's 3x3 depth range there (beyond ``HOLE_RANGE_NOISE``
  noise sigmas) plus ``HOLE_LEVELS`` levels, times ``HOLE_WEIGHT`` (depth
  invented across a hole: even on a flat surface it is not measured);
- ``disagree``: where the output's reduction (area mean over each input
  pixel) misses the input by more than its noise, the RMS of the miss over
  3x3 input pixels, times ``DISAGREE_WEIGHT`` (a method that moved a
  region's depth away from its measurements, as a mislabelled cluster of
  the thesis method does);
- ``noise``: the input's noise (:func:`~depthrefine.methods.gbp.estimate_noise`)
  times ``NOISE_SHARE``, a floor for what smoothing leaves of it.

The root sum ``r`` is in *levels* of the input's depth range (1st to 99th
percentile / 255) and calibrated to the RMS error observed on the tuning
scenes, ``e = ERROR_SCALE * sqrt(r)`` levels (large steepness overstates
the error, which grows about as its square root), then mapped to
``1 / (1 + (e / CONFIDENCE_LEVELS)**2)``: confidence 0.5 means an expected
error of 2 levels, 0.1 of 6 levels. The weights were chosen on the benchmark's tuning scenes (a coordinate
search on a half-decade grid; ``benchmarks/confidence_table.py --split tune
--set NAME=VALUE`` scores any setting); ``docs/confidence.md`` shows the
sparsification curves and AUSE against the steepness baseline
(:func:`steepness_confidence`).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Callable

import numpy as np

from .._fill import fill_invalid_nearest
from .._validate import as_depth

if TYPE_CHECKING:
    from .registry import Method

__all__ = ["refine_with_confidence", "method_with_confidence", "confidence_of", "confidence_on_grid",
           "apply_min_confidence", "generic_confidence", "steepness_confidence", "error_terms", "expected_error",
           "confidence_from_error", "depth_level", "NEAR_LENGTH", "REACH_LENGTH", "REACH_PIXELS", "HOLE_WEIGHT",
           "HOLE_LEVELS", "HOLE_RANGE_NOISE", "DISAGREE_WEIGHT", "NOISE_SHARE", "ERROR_SCALE", "CONFIDENCE_LEVELS"]

#: Weight of the output's steepness within one color pixel (3x3), in color pixels.
NEAR_LENGTH = 1.78
#: Weight of the output's steepness within half an input pixel, in color pixels.
REACH_LENGTH = 1.0
#: How far from an edge the ``reach`` term looks, in input pixels (``error_terms(reach=...)``'s default).
REACH_PIXELS = 0.5
#: Weight of (distance to valid input, input pixels) x (the input's 3x3 range + ``HOLE_LEVELS`` levels).
HOLE_WEIGHT = 1.0
#: A filled pixel's error grows by at least this many levels per input pixel of distance to a measurement.
HOLE_LEVELS = 1.0
#: Around a hole the input's 3x3 range counts beyond this many noise sigmas (9 noisy samples span about 3).
HOLE_RANGE_NOISE = 3.0
#: Weight of the local disagreement: the RMS of input minus the output's reduction beyond the noise.
DISAGREE_WEIGHT = 0.5
#: The share of the input's noise a pixel's expected error has at least.
NOISE_SHARE = 0.2
#: The expected error, levels, is ``ERROR_SCALE * sqrt(r)`` of the terms' root sum of squares ``r``, levels
#: (fitted, with the square root, to the binned RMS error of the tuning scenes).
ERROR_SCALE = 1.46
#: Confidence 0.5: an expected error of this many levels of the input's depth range (range / 255).
CONFIDENCE_LEVELS = 2.0

Progress = Callable[[int, int], None]


def refine_with_confidence(
    depth_lr: np.ndarray,
    rgb_hr: np.ndarray,
    *,
    method: str | None = None,
    params: Any = None,
    progress: Progress | None = None,
    max_pixels: int | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Refine as :func:`depthrefine.refine` does, and say per pixel how far to trust the result.

    Parameters
    ----------
    depth_lr, rgb_hr, params, progress, max_pixels
        As for :func:`depthrefine.refine`.
    method : str, optional
        A registered method (default: :data:`~depthrefine.DEFAULT_METHOD`).

    Returns
    -------
    depth_hr : (H, W) float32 ndarray
        Bit-identical to ``refine(depth_lr, rgb_hr, method=method, params=params)``.
    confidence : (H, W) float32 ndarray
        In [0, 1]: 1 = most trusted, 0 where ``depth_hr`` has no depth. The
        method's own map when it registered one (gbp), else
        :func:`generic_confidence`.

    Raises
    ------
    ValueError, TypeError
        As :func:`depthrefine.refine`.

    Examples
    --------
    >>> import numpy as np, depthrefine
    >>> depth_lr = np.full((8, 8), 100, np.uint8); depth_lr[:, 4:] = 200
    >>> depth_hr, confidence = depthrefine.refine_with_confidence(depth_lr, np.zeros((32, 32, 3), np.uint8))
    >>> confidence.dtype, confidence.shape, bool(confidence[:, 16].max() < confidence[:, 0].min())
    (dtype('float32'), (32, 32), True)
    """
    from .registry import DEFAULT_METHOD, check_call, get_method

    entry = get_method(DEFAULT_METHOD if method is None else method)
    check_call(entry, depth_lr, rgb_hr, params, max_pixels)
    return method_with_confidence(entry, depth_lr, rgb_hr, params=params, progress=progress)


def method_with_confidence(entry: Method, depth_lr: np.ndarray, rgb_hr: np.ndarray, *, params: Any = None,
                           progress: Progress | None = None) -> tuple[np.ndarray, np.ndarray]:
    """A registered method's depth and confidence, its own hook's or the generic map (no checks: see
    :func:`refine_with_confidence`)."""
    if entry.confidence is not None:
        return entry.confidence(depth_lr, rgb_hr, params=params, progress=progress)
    depth_hr = entry.func(depth_lr, rgb_hr, params=params, progress=progress)
    return depth_hr, generic_confidence(depth_lr, depth_hr)


def confidence_of(entry: Method, depth_lr: np.ndarray, rgb_hr: np.ndarray, depth_hr: np.ndarray, *,
                  params: Any = None) -> np.ndarray:
    """The confidence of a result ``depth_hr`` the method made otherwise (a warm-started frame of a sequence).

    Without a hook it is :func:`generic_confidence` of ``depth_hr`` itself;
    with one it is the hook's map of the frame refined on its own (its
    extra work runs again): a warm start only averages noise away where the
    input did not change, so that map does not overstate the trust.
    """
    if entry.confidence is None:
        return generic_confidence(depth_lr, depth_hr)
    return entry.confidence(depth_lr, rgb_hr, params=params, progress=None)[1]


def confidence_on_grid(confidence: np.ndarray, depth_hr: np.ndarray) -> np.ndarray:
    """``confidence`` on ``depth_hr``'s grid (nearest, when a chain resized the result after refining), 0 where
    ``depth_hr`` has no depth.

    Examples
    --------
    >>> depth = np.array([[1.0, np.nan, 2.0, 2.0]] * 2, np.float32)
    >>> confidence_on_grid(np.array([[0.5, 0.75]], np.float32), depth).tolist()
    [[0.5, 0.0, 0.75, 0.75], [0.5, 0.0, 0.75, 0.75]]
    """
    import cv2

    confidence = np.asarray(confidence, dtype=np.float32)
    if confidence.shape != depth_hr.shape:
        rows, cols = depth_hr.shape
        confidence = cv2.resize(confidence, (cols, rows), interpolation=cv2.INTER_NEAREST_EXACT)
    return np.where(np.isfinite(depth_hr), confidence, np.float32(0.0)).astype(np.float32)


def apply_min_confidence(depth_hr: np.ndarray, confidence: np.ndarray | None,
                         minimum: float | None) -> tuple[np.ndarray, np.ndarray | None]:
    """``depth_hr`` with NaN (written as 0, no measurement) where ``confidence < minimum``, and the confidence
    with 0 there (no depth); both unchanged without a minimum.

    Examples
    --------
    >>> depth, confidence = apply_min_confidence(np.array([1.0, 2.0]), np.array([0.2, 0.8]), 0.5)
    >>> depth.tolist(), confidence.tolist()
    ([nan, 2.0], [0.0, 0.800000011920929])
    """
    if minimum is None or confidence is None:
        return depth_hr, confidence
    below = confidence < minimum
    return (np.where(below, np.float32(np.nan), depth_hr).astype(np.float32),
            np.where(below, np.float32(0.0), confidence).astype(np.float32))


def generic_confidence(depth_lr: np.ndarray, depth_hr: np.ndarray) -> np.ndarray:
    """A confidence map for any method's result, from the input's support and the output's shape.

    The expected error is the root sum of the squared terms of
    :func:`error_terms` (steepness near and within half an input pixel,
    holes, a noise floor), mapped by :func:`confidence_from_error`.

    Parameters
    ----------
    depth_lr : (h, w) ndarray
        The method's input (0, NaN, inf, negative = no measurement).
    depth_hr : (H, W) ndarray
        Its result on the color grid (NaN = no depth).

    Returns
    -------
    (H, W) float32 ndarray
        In [0, 1]; 0 where ``depth_hr`` is not finite.

    Examples
    --------
    >>> depth_lr = np.array([[1, 1, 5, 5]] * 4, np.float32)
    >>> c = generic_confidence(depth_lr, np.repeat(np.repeat(depth_lr, 4, 0), 4, 1))
    >>> bool(c[:, 0].min() > 0.99 > c[:, 8].max())
    True
    """
    from .gbp import estimate_noise

    depth = as_depth(depth_lr)
    valid = np.isfinite(depth)
    filled = fill_invalid_nearest(depth)
    level = depth_level(filled, valid)
    noise = estimate_noise(filled, valid)
    terms = error_terms(depth_hr, valid, filled, level, noise)
    return confidence_from_error(expected_error(terms, NOISE_SHARE * noise, level), depth_hr)


def error_terms(depth_hr: np.ndarray, valid: np.ndarray, filled: np.ndarray, level: float,
                noise: float = 0.0, *, disagreement: bool = True, reach: float = REACH_PIXELS
                ) -> dict[str, np.ndarray]:
    """The squared error terms of the expected error, weighted, on the grid of ``depth_hr`` (depth units squared).

    Parameters
    ----------
    depth_hr : (H, W) ndarray
        The result (NaN pixels are filled from their nearest neighbour first).
    valid : (h, w) bool ndarray
        The input's valid pixels.
    filled : (h, w) float32 ndarray
        The input with holes filled from the nearest valid pixel.
    level : float
        One level of the input's depth range (:func:`depth_level`).
    noise : float
        The input's noise standard deviation (depth units): a 3x3 range
        below ``HOLE_RANGE_NOISE`` times it counts as flat around a hole,
        and the disagreement counts beyond it.
    disagreement : bool
        Include the ``disagree`` term (False for a method whose output's
        reduction matches its input by construction, as gbp's).
    reach : float
        How far from an edge, in input pixels, the ``reach`` term looks
        (0.5: where an input pixel's footprint straddles an edge, the output
        may put it anywhere inside that pixel); at least one color pixel.

    Returns
    -------
    dict
        ``near``, ``reach``, ``hole`` and ``disagree``: (H, W) float32, each
        already weighted (see the module's notes).
    """
    import cv2

    out = np.asarray(depth_hr, dtype=np.float32)
    if not np.isfinite(out).all():
        out = fill_invalid_nearest(out) if np.isfinite(out).any() else np.zeros(out.shape, np.float32)
    (H, W), (h, w) = out.shape, filled.shape
    scale = 0.5 * (H / h + W / w)
    gx = cv2.Sobel(out, cv2.CV_32F, 1, 0, ksize=3, borderType=cv2.BORDER_REPLICATE)
    gy = cv2.Sobel(out, cv2.CV_32F, 0, 1, ksize=3, borderType=cv2.BORDER_REPLICATE)
    # not cv2.magnitude: its vector and scalar paths round differently, and where they meet moves with its
    # threads (not bit-identical from run to run)
    steep = np.sqrt(gx * gx + gy * gy) / np.float32(8.0)   # depth per color pixel
    radius = max(1, int(round(scale * reach)))
    near = cv2.dilate(steep, np.ones((3, 3), np.uint8))
    wide = cv2.dilate(steep, np.ones((2 * radius + 1,) * 2, np.uint8))
    kernel = np.ones((3, 3), np.uint8)
    if valid.all():
        hole = np.zeros((H, W), np.float32)
    else:
        distance = cv2.distanceTransform((~valid).astype(np.uint8), cv2.DIST_L2, 3)
        span = cv2.dilate(filled, kernel) - cv2.erode(filled, kernel) - np.float32(HOLE_RANGE_NOISE * noise)
        span = np.maximum(span, 0.0) + np.float32(HOLE_LEVELS * level)
        hole = cv2.resize(distance * span, (W, H), interpolation=cv2.INTER_LINEAR)
    terms = {"near": np.square(NEAR_LENGTH * near), "reach": np.square(REACH_LENGTH * wide),
             "hole": np.square(HOLE_WEIGHT * hole)}
    if not disagreement:
        return terms
    # local disagreement: the RMS of the input minus the output's reduction over 3x3 input pixels, beyond the noise
    reduced = cv2.resize(out, (w, h), interpolation=cv2.INTER_AREA)
    residual = np.where(valid, filled - reduced, np.float32(0.0)).astype(np.float32)
    count = cv2.blur(valid.astype(np.float32), (3, 3), borderType=cv2.BORDER_REFLECT)
    mean_square = cv2.blur(residual * residual, (3, 3), borderType=cv2.BORDER_REFLECT) / np.maximum(count, 1e-3)
    beyond = np.maximum(mean_square - np.float32(noise) ** 2, 0.0)
    terms["disagree"] = np.float32(DISAGREE_WEIGHT ** 2) * cv2.resize(beyond, (W, H), interpolation=cv2.INTER_LINEAR)
    return terms


def expected_error(terms: dict[str, np.ndarray], floor: float, level: float) -> np.ndarray:
    """The expected error, levels: ``ERROR_SCALE * sqrt(r)``, ``r = sqrt(floor**2 + sum(terms)) / level``.

    ``terms`` are squared depth errors (:func:`error_terms`), ``floor`` the
    noise floor and ``level`` one level of the depth range, both in depth
    units. Returns float32.

    Examples
    --------
    >>> round(float(expected_error({"near": np.array([16.0])}, 3.0, 1.0)[0]), 3)   # 1.46 * sqrt(5)
    3.265
    """
    total = np.full(next(iter(terms.values())).shape, np.float32(floor) ** 2, np.float32)
    for value in terms.values():
        total += value
    level = np.float32(level if level > 0 else 1.0)
    # square roots only: numpy's vectorised and scalar ``**`` differ in the last bit (not bit-identical)
    return (np.float32(ERROR_SCALE) * np.sqrt(np.sqrt(total) / level)).astype(np.float32)


def depth_level(filled: np.ndarray, valid: np.ndarray) -> float:
    """One level of the input's depth range: (99th - 1st percentile of the valid pixels) / 255.

    Examples
    --------
    >>> round(depth_level(np.linspace(0, 255, 1001, dtype=np.float32).reshape(7, 143), np.ones((7, 143), bool)), 4)
    0.98
    """
    low, high = np.percentile(filled[valid], [1, 99])
    span = float(high - low) if high > low else max(abs(float(filled[valid].max())), 1.0)
    return span / 255.0


def confidence_from_error(expected: np.ndarray, depth_hr: np.ndarray | None = None) -> np.ndarray:
    """``1 / (1 + (expected / CONFIDENCE_LEVELS)**2)`` (``expected`` in levels), 0 where ``depth_hr`` is not finite.

    Examples
    --------
    >>> confidence_from_error(np.array([0.0, 2.0, 6.0])).tolist()
    [1.0, 0.5, 0.10000000149011612]
    """
    ratio = np.asarray(expected, dtype=np.float32) / np.float32(CONFIDENCE_LEVELS)
    confidence = np.float32(1.0) / (np.float32(1.0) + ratio * ratio)
    confidence = np.where(np.isfinite(confidence), confidence, np.float32(0.0)).astype(np.float32)
    if depth_hr is not None:
        confidence[~np.isfinite(depth_hr)] = 0.0
    return confidence


def steepness_confidence(depth_hr: np.ndarray) -> np.ndarray:
    """The baseline "trust falls where the output is steep": ``exp(-g / p90(g))``.

    ``g`` is the Sobel gradient magnitude of ``depth_hr``, max-filtered over
    3x3 pixels, and ``p90`` its 90th percentile. It knows nothing but the
    output's own shape; the benchmark compares every confidence map with it.

    Examples
    --------
    >>> d = np.zeros((8, 8), np.float32); d[:, 4:] = 10
    >>> c = steepness_confidence(d)
    >>> float(c[0, 0]), bool(c[0, 4] < 1)
    (1.0, True)
    """
    import cv2

    out = np.asarray(depth_hr, dtype=np.float32)
    finite = np.isfinite(out)
    if not finite.all():
        out = fill_invalid_nearest(out) if finite.any() else np.zeros(out.shape, np.float32)
    gx = cv2.Sobel(out, cv2.CV_32F, 1, 0, ksize=3, borderType=cv2.BORDER_REPLICATE)
    gy = cv2.Sobel(out, cv2.CV_32F, 0, 1, ksize=3, borderType=cv2.BORDER_REPLICATE)
    g = cv2.dilate(np.sqrt(gx * gx + gy * gy), np.ones((3, 3), np.uint8))   # numpy: bit-identical (see error_terms)
    p90 = float(np.percentile(g, 90))
    confidence = np.exp(-g.astype(np.float64) / max(p90, math.ulp(1.0) * max(1.0, float(g.max())))).astype(np.float32)
    confidence[~finite] = 0.0
    return confidence
