"""gbp's confidence map, from its own internals (:func:`upsample_gbp_with_confidence`).

Of the terms every other method gets (:func:`~depthrefine.methods.confidence.error_terms`)
gbp keeps the output's steepness near and within half an input pixel and the
distance to valid input across holes; the local disagreement with the input
says nothing here (back-projection makes the result's reduction match the
input, what is left is noise), except on a reprojected input
(``GbpParams.reprojected``), whose stronger smoothing leaves it carrying
the misplaced samples (the ``sensor`` protocol's test scenes: AUSE 0.555 /
0.609 / 0.615 of the baseline's without it, 0.538 / 0.592 / 0.583 with it). gbp knows two more things: the input's noise,
measured once (step 1), sets the floor; and step 5 says how far the guide
was trusted: where the result falls back from the guided estimate to the
clipped bicubic one, guide and input disagree, and by about the size of
that fallback (``|result - guided|``, weighted by ``FALLBACK_WEIGHT``).
The depth is :func:`~.upsample.upsample_gbp`'s, bit for bit; the extra work
(a copy of the guided estimate, a few filters) runs only here.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from ..._validate import as_depth, check_rgb, guide_uint8
from ..confidence import NOISE_SHARE, REACH_PIXELS, confidence_from_error, error_terms, expected_error
from .measure import InputMeasures
from .params import GbpParams
from .upsample import _refine

__all__ = ["upsample_gbp_with_confidence", "gbp_confidence", "FALLBACK_WEIGHT", "REPROJECTED_REACH"]

#: Weight of the fallback's size ``|result - guided|`` in the expected error.
FALLBACK_WEIGHT = 1.78
#: How far from an edge (input pixels) the ``reach`` term looks on a reprojected input: the calibration error and
#: the reprojection move an edge within a whole input pixel, not half of one as the footprint alone does (the
#: ``sensor`` protocol's AUSE ratio: tuning scenes 0.38 / 0.66 / 0.58 -> 0.36 / 0.65 / 0.57, test scenes 0.57 /
#: 0.62 / 0.59 -> 0.55 / 0.61 / 0.58 at x4 / x8 / x16).
REPROJECTED_REACH = 1.0


def upsample_gbp_with_confidence(depth_lr: np.ndarray, rgb_hr: np.ndarray, *, params: GbpParams | None = None,
                                 progress: Callable[[int, int], None] | None = None
                                 ) -> tuple[np.ndarray, np.ndarray]:
    """:func:`~.upsample.upsample_gbp` and its confidence map.

    Returns
    -------
    depth_hr : (H, W) float32 ndarray
        Bit-identical to ``upsample_gbp(depth_lr, rgb_hr, params=params)``.
    confidence : (H, W) float32 ndarray
        In [0, 1], 1 = most trusted (:func:`gbp_confidence`).

    Examples
    --------
    >>> from depthrefine.methods.gbp import upsample_gbp
    >>> depth = np.array([[10, 10, 50, 50]] * 4, np.float32)
    >>> rgb = np.zeros((8, 8, 3), np.uint8); rgb[:, 4:] = 200
    >>> out, confidence = upsample_gbp_with_confidence(depth, rgb)
    >>> bool((out == upsample_gbp(depth, rgb)).all()), bool(confidence[:, 0].min() > confidence[:, 4].max())
    (True, True)
    """
    keep: dict = {}
    result, measures = _refine(as_depth(depth_lr), guide_uint8(check_rgb(rgb_hr)), params, progress, keep=keep)
    reprojected = params is not None and bool(params.reprojected)
    return result, gbp_confidence(result, measures, keep["guided"], disagreement=reprojected)


def gbp_confidence(result: np.ndarray, measures: InputMeasures, guided: np.ndarray, *,
                   disagreement: bool = False) -> np.ndarray:
    """The confidence of gbp's ``result`` from its input's ``measures`` and its ``guided`` estimate before step 5.

    The expected error is the root sum of squares of the generic terms, the
    fallback's size times ``FALLBACK_WEIGHT`` and the noise floor
    (``NOISE_SHARE`` of the measured noise), mapped to [0, 1] by
    :func:`~depthrefine.methods.confidence.confidence_from_error` against
    the measured depth range. ``disagreement`` says the input is reprojected
    (``GbpParams.reprojected``): its result, smoothed more, gets the generic
    disagreement term, and the ``reach`` term looks ``REPROJECTED_REACH``
    input pixels from an edge instead of half of one.
    """
    level = measures.span / 255.0
    terms = error_terms(result, measures.valid, measures.filled, level, measures.sigma, disagreement=disagreement,
                        reach=REPROJECTED_REACH if disagreement else REACH_PIXELS)
    fallback = np.abs(result - guided)
    fallback *= np.float32(FALLBACK_WEIGHT)
    terms["fallback"] = np.square(fallback)
    expected = expected_error(terms, NOISE_SHARE * measures.sigma, level)
    return confidence_from_error(expected, result)
