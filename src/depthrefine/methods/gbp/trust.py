"""Step 5 of gbp: how far the guide can be trusted, and the fallback where it cannot (do no harm).

Real guides carry texture that is not depth. :func:`guide_trust` checks the
guide against the input one octave down: the input is reduced x2, steps 2-4
run on it with the color image at the input's resolution, and per region a
least-squares fit says how much of the guided detail the withheld input
confirms, only near a depth jump the input itself shows (a guide's edges
over a smooth surface, however curved, are texture). :func:`blend_fallback`
keeps that share of the guided detail and falls back elsewhere to the
clipped bicubic enlargement of the input (or, as the input's noise grows, of
the result's own denoised reduction).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .measure import InputMeasures, block_mean_valid, measure_input, noise_levels, noise_share
from .solve import (back_project, clamped_bicubic, flat_blend, local_bounds, make_solver, reduce, resize,
                    resize_to_scratch)

if TYPE_CHECKING:
    from .params import GbpParams

__all__ = ["guide_trust", "measured_trust", "blend_fallback"]

#: Half-size, depth pixels, of the regions over which the guide's trust is fitted (tuning mean 2.4048 / 2.3947 /
#: 2.3899 for 2 / 4 / 8).
TRUST_RADIUS = 8
#: The prior "trust the guide" of each region's fit, as a guided detail of this many levels of the depth range:
#: where the detail is much weaker, the fit is noise and the guide is trusted.
TRUST_PRIOR = 1.0
#: Trust shares below this count as none and the rest is stretched to [0, 1] (a textured guide leaves a small
#: spurious trust everywhere).
TRUST_FLOOR = 0.1
#: The color-sensitivity floor of the check one octave down, in multiples of the reduced guide's noise (its finest
#: band is then mostly fine texture rather than noise: a smoother check estimate).
TRUST_GUIDE_NOISE = 4.0
#: Noise below this many levels counts as none in the fallback: 8-bit rounding (0.29 levels) and what is left of a
#: smooth surface in the noise band are not noise to average away.
NOISE_FLOOR = 0.5
#: Inputs reduced below this many pixels on a side are not checked (trust 1).
MIN_CHECK_SIDE = 4


def guide_trust(depth: np.ndarray, guide: np.ndarray, params: GbpParams | None = None) -> np.ndarray:
    """How far the guided detail can be trusted, per input pixel, in [0, 1] (:func:`measured_trust` of the input).

    Parameters
    ----------
    depth : (h, w) float32 ndarray
        The input, NaN where invalid.
    guide : (H, W, 3) uint8 ndarray
        The color image.
    params : GbpParams, optional

    Returns
    -------
    (h, w) float32 ndarray
    """
    from .params import GbpParams

    p = GbpParams() if params is None else params
    return measured_trust(measure_input(depth, guide, sampling=p.sampling), guide, p)


def measured_trust(m: InputMeasures, guide: np.ndarray, p: GbpParams) -> np.ndarray:
    """How far the guided detail can be trusted, per input pixel, in [0, 1].

    The input is reduced x2 (mean of the valid pixels of each 2x2 block), the
    guided estimate ``g`` is computed from it with the guide resized (area)
    to the input's grid, and in each window of ``2 * TRUST_RADIUS + 1``
    pixels the share ``a`` of its guided detail ``g - b`` (``b``: bicubic
    enlargement of ``g`` reduced x2) that best explains the withheld input
    ``y`` is fitted by least squares on valid pixels,
    ``a = (sum (y - b)(g - b) + e) / (sum (g - b)**2 + e)``, with the prior
    ``e = (TRUST_PRIOR * range / 255)**2`` (``range``: the valid range), clipped to [0, 1] and smoothed
    over the same window; then multiplied by the nearness to a depth jump of
    the input (``m.jump``).

    Parameters
    ----------
    m : InputMeasures
        The input's measures (:func:`~.measure.measure_input`).
    guide : (H, W, 3) uint8 ndarray
    p : GbpParams

    Returns
    -------
    (h, w) float32 ndarray
        1 everywhere when the input is too small to reduce.
    """
    import cv2

    depth = m.depth
    h, w = depth.shape
    trust = np.ones((h, w), np.float32)
    small = block_mean_valid(depth, 2)
    if min(small.shape) < MIN_CHECK_SIDE or not np.isfinite(small).any():
        return trust
    hc, wc = small.shape[0] * 2, small.shape[1] * 2
    guide_lr = np.ascontiguousarray(resize(guide, (h, w), cv2.INTER_AREA)[:hc, :wc])
    check = measure_input(small, guide_lr, sampling="mean")
    solver = make_solver(guide_lr, check, p, TRUST_GUIDE_NOISE)
    g = flat_blend(back_project(check, solver, p, local_bounds(small, (hc, wc))), check, solver, p)
    b = resize(resize(g, small.shape, cv2.INTER_AREA), (hc, wc), cv2.INTER_CUBIC)
    # g - b and y - b, 0 at invalid pixels, each in place of an array done with (at x2 each of these arrays is a
    # quarter of the output: the call's peak memory)
    invalid = ~m.valid[:hc, :wc]
    detail = np.subtract(g, b, out=g)
    explained = np.subtract(depth[:hc, :wc], b, out=b)
    detail[invalid] = explained[invalid] = 0.0
    del g, b, invalid
    size = (2 * TRUST_RADIUS + 1,) * 2
    num = cv2.boxFilter(np.multiply(explained, detail, out=explained), -1, size, borderType=cv2.BORDER_REFLECT)
    den = cv2.boxFilter(np.multiply(detail, detail, out=detail), -1, size, borderType=cv2.BORDER_REFLECT)
    del explained, detail
    span = float(np.float32(m.high) - np.float32(m.low))    # the valid range, as float32 values subtract
    prior = (TRUST_PRIOR * span / 255.0) ** 2 + 1e-30
    num += prior
    den += prior
    np.clip(np.divide(num, den, out=num), 0.0, 1.0, out=trust[:hc, :wc])
    trust[hc:, :] = trust[hc - 1:hc, :]
    trust[:, wc:] = trust[:, wc - 1:wc]
    trust = cv2.boxFilter(trust, -1, size, borderType=cv2.BORDER_REFLECT)
    return trust * m.jump


def blend_fallback(result: np.ndarray, trust: np.ndarray, m: InputMeasures) -> np.ndarray:
    """Keep ``trust`` of the guided detail of ``result``; fall back to clipped bicubic interpolation elsewhere.

    The fallback is the clipped bicubic enlargement of the result's own
    reduction, moved towards the input itself as far as the input is
    noise-free (its noise, measured on a band blind to smooth curvature,
    below ``NOISE_FLOOR`` levels: nothing to average away). Trust shares
    below ``TRUST_FLOOR`` count as none. ``result`` is updated in place and
    returned, within the input's valid range.
    """
    import cv2

    h, w = m.depth.shape
    reduced = reduce(result, (h, w), m.footprint)
    share = noise_share(max(0.0, noise_levels(m) - NOISE_FLOOR))
    reduced = np.where(m.valid, reduced + (1.0 - share) * (m.filled - reduced), reduced).astype(np.float32)
    base = clamped_bicubic(reduced, result.shape, m.jump)
    # the enlarged trust in a scratch array of the solver's, once the fallback has made its own use of it
    trust = np.clip((trust - TRUST_FLOOR) / (1.0 - TRUST_FLOOR), 0.0, 1.0).astype(np.float32, copy=False)
    trust = resize_to_scratch(trust, result.shape, cv2.INTER_LINEAR)
    # result <- base + trust * (result - base), in place
    result -= base
    result *= trust
    result += base
    return np.clip(result, m.low, m.high, out=result)
