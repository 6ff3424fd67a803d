"""Guided back-projection (``gbp``): the default method.

The method upsamples a low-resolution depth map ``y`` (``h x w``) to the grid
of a registered color image (``H x W``, factor ``s``, integer or not) in four
steps. Every parameter is a field of :class:`GbpParams`; what the method needs
to know about the input (its noise level, where its depth edges are, how far
the color image can be trusted) it measures from the input itself, so one set
of defaults serves clean and noisy inputs, 8-bit levels and millimetres.

1. **Noise and sampling.** The noise ``sigma`` is estimated from the finest
   diagonal Haar band of ``y`` (a clipped RMS, robust to the few depth edges
   in that band), and expressed in 8-bit levels of the map's own depth range
   (1st to 99th percentile), so the same value means the same thing in any
   unit. The guide's own noise is estimated the same way (its color
   sensitivity in both solves is at least ``guide_noise`` times it), and
   whether the input holds footprint means or point samples is told from
   its edges (:func:`footprint_share`: footprint means leave mixed pixels
   between the two sides of a jump, point samples do not).
2. **Detail: back-projection with an edge-aware solve.** Start from the
   clipped bicubic enlargement (bicubic, clipped to the range of each
   pixel's 3x3 input neighbourhood, so that it does not ring at depth
   jumps); repeat ``iterations`` times: add the Lanczos enlargement of
   the residual ``y - D(x)`` (``residual_interp``; ``D``: the mean over each pixel's footprint,
   the integration a ToF pixel does; for a point-sampled input the value at
   each pixel's centre, with ``point_lambda`` times the smoothing to fill
   the gaps between the samples), then smooth with the fast global
   smoother (weighted least squares, Min et al. 2014; :mod:`._wls`, equal
   to OpenCV-contrib's filter for color weights) whose weights between
   neighbours fall with their color difference (on the guide after a 3x3
   bilateral filter, ``guide_smoothing``) and with the current
   estimate's own gradient (``gradient_levels``: where the back-projection
   put a depth jump the guide does not show, the solve does not blur it),
   with a strength that grows with ``sigma**2`` and falls geometrically
   over the rounds (``lambda_first`` to ``lambda_last``: early rounds place
   the edges, late ones keep the detail); clip to the input's range, and
   each pixel to the range of the valid input pixels of its input pixel's
   3x3 neighbourhood (``clip_rounds``, the bound of step 4's
   ``local_range``; also after adding the residual, in every round but the
   last, and in step 4's check estimate), so that no round builds on an
   overshoot. The residual is zero at invalid input pixels, so they never
   pull the result.
3. **Flat areas.** Where the input shows no depth edge above the noise (its
   3x3 range is below ``edge_low * sigma``), a much stronger smoother of the
   bilinear enlargement takes over, blended in over ``edge_width * sigma``:
   noise is averaged over whole color segments there, while depth edges keep
   the back-projected detail. On a noise-free input there is nothing to
   average away, so this share fades out below ``flat_noise`` levels.
4. **Guide trust (do no harm).** Real guides carry texture that is not depth.
   The method checks the guide against the input one octave down: the input
   is reduced x2 (mean of the valid pixels), steps 1-3 are run on it with the
   color image at the input's resolution, and per region of
   ``2 * trust_radius + 1`` input pixels a least-squares fit says how much of
   the guided detail (the result minus the bicubic enlargement of its own
   reduction) agrees with the withheld input, in [0, 1], with a prior towards
   trust where the detail is weaker than ``trust_prior`` levels, no trust
   away from a depth jump of the input (a change of its curvature above the
   noise, ``jump_levels``: a guide's edges over a smooth surface, however
   curved, are texture) nor
   within ``hole_margin`` pixels of a missing input pixel (none by default),
   and shares below ``trust_floor`` counted as none. First the guided result
   is clipped, wherever its input pixel is valid, to the range of the valid
   input pixels of that pixel's 3x3 neighbourhood (``local_range``; beyond
   the border the input is continued linearly): a value beyond every
   measurement around it is the solve's overshoot at a large jump, not
   detail. The full-resolution result keeps that share of its guided detail
   and falls back to clipped bicubic interpolation elsewhere: of the input
   itself when it is noise-free, of the result's own (denoised) reduction
   as the noise grows (from half a level of the depth range, over
   ``flat_noise`` levels; this noise is measured with a band that is blind
   to smooth curvature, so a curved noise-free surface falls back to the
   input itself).

Invalid input pixels (0, NaN, inf, negative) are filled from the nearest
valid pixel before any interpolation, as the other methods do, and no
invalid value is ever averaged in. The output is clipped to the input's
valid range and is deterministic (bit-identical for the same input).

Parameters were chosen on the benchmark's tuning scenes (Park's Dolls and
Laundry, four scenes of the 30-image Middlebury set; ``docs/bench.md``), with
two exceptions said on their fields: ``hole_margin`` and ``local_range`` were
chosen with the real Kinect capture in view, and ``point_lambda`` (which no
benchmark input uses: all hold footprint means) on generated point-sampled
scenes.

References
----------
M. Irani, S. Peleg, "Improving resolution by image registration", CVGIP 1991
(back-projection). D. Min, S. Choi, J. Lu, B. Ham, K. Sohn, M. N. Do, "Fast
global image smoothing based on weighted least squares", TIP 2014.
D. L. Donoho, I. M. Johnstone, "Ideal spatial adaptation by wavelet
shrinkage", Biometrika 1994 (noise from the finest wavelet band).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from .._fill import fill_invalid_nearest
from .._validate import as_depth, check_choice, check_int, check_number, check_rgb
from .peers import _guide8

__all__ = ["GbpParams", "upsample_gbp", "upsample_gbp_stateful", "estimate_noise", "estimate_guide_noise",
           "footprint_share", "guide_trust", "block_mean_valid"]

Progress = Callable[[int, int], None]


@dataclass(frozen=True)
class GbpParams:
    """Parameters of guided back-projection (the defaults, each with the reason for it).

    Lengths are in low-resolution pixels; a smoothing weight ``lambda`` of
    the fast global smoother is a squared length in color pixels, so it is
    given per squared low-resolution pixel and multiplied by ``s**2`` (or by
    ``s``, stated per field). Color sensitivities are in 8-bit guide levels.

    Attributes
    ----------
    iterations : int
        Back-projection rounds (8). In a first version of this method the
        tuning-scene mean RMSE went 2.66 / 2.63 / 2.61 for 3 / 4 / 6 rounds;
        each round costs one smoother pass (30-60 ms at 1.5 Mpx here).
    lambda_first, lambda_last : float
        The detail solve's smoothing falls geometrically over the rounds,
        from ``lambda_first`` to ``lambda_last`` times its nominal value
        (6 and 0.35): early rounds place the edges, late ones keep the
        detail. Tuning-scene mean RMSE (Park, Middlebury, ToF, x4/x8/x16)
        2.737 with a constant value and 6 rounds, 2.710 with 10 rounds,
        2.674 / 2.665 / 2.658 for 4 -> 0.5 / 6 -> 0.35 (8 rounds) / 8 -> 0.25
        (10 rounds); every cell improved with 6 -> 0.35.
    lambda_lr : float
        Smoothness of the detail solve on a noise-free input, per squared
        low-resolution pixel (0.06). With ``gradient_levels`` 96 the tuning
        mean was 2.5896 / 2.5854 for 0.045 / 0.06, and 2.6039 for 0.1 (with
        128 levels: 2.5983 / 2.5860 / 2.6039 for 0.03 / 0.06 / 0.1). Stronger
        smoothing rounds the depth edges. (Before ``gradient_levels`` this
        was 0.03, chosen after seeing the ``lu`` scenes; 0.06 is chosen on
        the tuning scenes alone.)
    sigma_color : float
        Color sensitivity of the detail solve (4). In the first prototype, 8
        lost detail at every scale (tuning mean 3.98 against 3.18); 2 was
        worse than 3 and 4 on the noisy scenes.
    noise_ref : float
        The noise (8-bit levels of the depth range) at which the detail
        solve's smoothing doubles; it grows with ``(sigma / noise_ref)**2``,
        the ratio of noise to data weight of a least-squares fit (1): Park's
        noisy inputs (sigma about 6.5 levels) are smoothed about 40 times
        as strongly as a noise-free input.
    flat_lambda_lr : float
        Smoothness of the flat-area solve, ``lambda = flat_lambda_lr * s``
        (32). Growing with ``s`` rather than ``s**2`` kept x16 from
        oversmoothing (Park x4 / x16: 2.17 / 3.93 against 2.30 / 3.94 with
        ``8 * s**2``).
    flat_sigma_color : float
        Color sensitivity of the flat-area solve (4; 3 gave a tuning mean of
        2.618 against 2.604).
    edge_low : float
        A 3x3 input range below ``edge_low * sigma`` counts as flat (6): with
        Gaussian noise, the range of 9 samples is about 3 sigma, so only
        real depth steps pass 6 sigma. 2 and 4 kept more noise on Park
        (Park and ToF tuning mean 3.19 / 3.04 / 2.97 for 2 / 4 / 6).
    edge_width : float
        The flat / edge blend ramps over ``edge_width * sigma`` above
        ``edge_low * sigma`` (4; 2 gave 2.97, 4 gave 2.67 on the tuning mean).
    flat_noise : float
        Noise (levels of the depth range) below which the flat-area solve
        and the denoised fallback fade out (2; the fallback's above a floor
        of half a level). On a noise-free step the
        flat solve spread the mixed edge pixel over the whole flat side
        (42.5 instead of 40); the tuning mean moved 2.640 / 2.639 / 2.637
        for 0.5 / 1 / 2.
    trust : bool
        Measure how far the guide can be trusted, per region, and fall back
        towards plain interpolation where it cannot (True). It made the
        real-ToF self-benchmark better at every cell (``realtof``,
        ``docs/bench.md``).
    trust_radius : int
        Half-size of the trust regions, low-resolution pixels (4). 2 and 8
        gave the same scores within 1 %.
    local_range : bool
        Clip the guided result, wherever its input pixel is valid, to the
        range of the valid input pixels of its 3x3 neighbourhood before the
        trust blends it with the fallback (True; the input is continued
        linearly beyond the border, so a slope keeps its last pixels). At a
        large depth jump whose color edge is weak or offset the solve
        overshoots both sides (the Azure Kinect mug: 1107 mm on a 1004 mm
        wall, 167 mm on a 270 mm mug). Tuning mean 2.6322 -> 2.6189 alone,
        2.5955 with ``hole_margin`` 0 (2.6116 for that alone), every tuning
        protocol x scale better (simulated ToF x4 / x8 / x16 2.115 / 2.593 /
        3.507 -> 2.074 / 2.516 / 3.389; 2.103 / 2.540 / 3.387 with the
        margin's change alone); real-ToF Kinect x4 / x8
        18.58 / 30.70 -> 17.14 / 29.72 mm alone, 16.83 / 29.18 with the
        margin 0; iPhone 24.01 / 38.60 -> 23.97 / 38.54 mm. A 5x5
        neighbourhood gave 2.5956 and Kinect 17.56 / 29.88; clipping over
        missing input pixels too (from the valid neighbours) cost the
        simulated ToF about 1 %; repeating the border pixels instead of
        continuing the slope cost Laundry x16 3 %. Clipping the guide trust's
        check estimate likewise gave 2.5910 and Kinect 16.58 / 28.98, but
        trusted a weak color edge one or two input pixels off a large jump
        more (RMSE up to 20 % worse than without any clip there; this clip
        alone is never worse on that case, ``tests/test_gbp.py``). What it
        cannot keep: a structure thinner than an input pixel whose depth no
        input pixel around it reaches (Art's sticks at x16).
    hole_margin : int
        Guided detail is not trusted within this many low-resolution pixels
        of a missing input pixel (0), where the withheld input cannot check
        it. Without ``local_range``, 2 was best on the Azure Kinect
        self-benchmark (holes at object outlines; x4 21.5 / 20.8 / 20.3 mm
        for 0 / 1 / 2), but what it hid there was the overshoot at the jumps
        beside the holes: with the clip, Kinect x4 / x8 16.83 / 29.18 mm for
        0, 16.92 / 29.30 for 1, 17.14 / 29.72 for 2, and on the simulated ToF
        tuning scenes (dropouts on dark surfaces, where the fallback next to
        a hole only blurs the result's edges) x4 / x8 / x16 2.074 / 2.516 /
        3.389 for 0, 2.091 / 2.578 / 3.521 for 2 (tuning mean 2.5955 /
        2.6078 / 2.6189 for 0 / 1 / 2).
    trust_prior : float
        The prior "trust the guide" of each region's fit, as a guided detail
        of this many levels of the depth range (1): where the detail is much
        weaker the fit is noise and the guide is trusted. A prior relative to
        the image's own mean detail (tried first) kept the trust near 0.5 on
        a uniformly textured guide (checkerboard over a smooth surface: RMSE
        0.67 against bicubic 0.16); in levels it falls to 0.1 there (0.17).
        0.5 / 1 / 2 levels gave the same tuning mean within 0.001.
    trust_floor : float
        Trust shares below this count as none and the rest is stretched to
        [0, 1] (0.1): a textured guide leaves a small spurious trust
        everywhere. 0.2 cost 0.6 % on the tuning mean and 5 % on the Kinect.
    jump_levels, jump_noise : float
        Guided detail is trusted only near a depth jump of the input: where
        the 4-neighbour Laplacian of the input differs from its own 3x3 mean
        by more than ``jump_noise * sigma + jump_levels`` levels of its
        depth range (3 and 4), ramping to full trust at twice that, within
        ``jump_margin`` input pixels (2). A smooth surface under a textured
        guide has no such jump, so its texture is not copied (striped guide
        over a smooth surface: RMSE 0.277 without this test, 0.167 with 2
        levels, equal to bicubic's 0.1628 with 3; the tuning mean moved
        2.6462 / 2.6465 / 2.6469 for 2 / 3 / 4 levels, 2.674 with
        ``jump_noise = 6``). The Laplacian itself (the test's first form)
        passed a small input's smooth curvature for a jump (a quadratic
        under a checkerboard, 12 x 16 input, x4: 1.63 times bicubic's RMSE);
        its deviation from its 3x3 mean is near zero on any smooth surface
        (the same case: equal to bicubic; with the fourth-order noise band of
        the fallback, tuning mean 2.4371 -> 2.4368, and
        2.4366 / 2.4372 for 2 / 4 levels; simulated ToF test scenes 3.0377
        -> 3.0393, real-ToF x4 / x8 19.899 / 32.739 -> 19.904 / 32.747 mm).
    jump_margin : int
        See ``jump_levels`` (2).
    guide_noise : float
        The color sensitivity of both solves is at least this many times the
        guide's own noise (3; its finest diagonal Haar band, as for the depth,
        RMS over R, G, B): a noisy guide's pixel-to-pixel differences would
        otherwise count as edges everywhere and stop the smoothing. The
        benchmark guides measure 0.3-2.2 levels (Middlebury's 1.6-2.2, so
        their sensitivity rises from 4 to 5-6.6); on
        :func:`~depthrefine.bench.synthetic.make_sequence` (color noise 6
        levels) it is what lets the guide place the edges at all.
    trust_guide_noise : float
        The same floor for the guide trust's check one octave down (4), on
        the guide reduced to the input's grid, whose finest band is then
        mostly fine texture rather than noise: a smoother check estimate.
        Tuning mean 2.6581 / 2.6543 / 2.6401 / 2.6322 for 0 / 2 / 3 / 4 (with
        ``guide_noise`` 3); on the scored scenes 4 against 0 moved
        middlebury30 x16 4.64 -> 4.51, realtof x8 35.06 -> 34.65 mm, and the
        simulated ToF x4 / x8 2.380 / 3.104 -> 2.385 / 3.115 (the one
        protocol it costs).
    mixed_low, mixed_high : float
        The input's sampling model is estimated from the input
        (:func:`footprint_share`): a ToF pixel integrates its footprint,
        leaving mixed values at depth edges, while a point-sampled map has
        none. Where fewer than ``mixed_low`` (0.02) of the pixels between two
        sides of a large jump are mixed, the back-projection compares the
        estimate's point samples with the input, above ``mixed_high`` (0.08)
        its footprint means, and a blend in between. Every input of the
        benchmark measures 0.10-0.85 (all footprint means or antialiased
        reductions); the point-sampled synthetic scenes 0-0.016.
    point_lambda : float
        On a point-sampled input only one color pixel in ``s**2`` is tied to
        a measurement, so the detail solve's smoothing is multiplied by this
        factor there (10; scaled by the point share): it fills the gaps along
        the color segments. Chosen on :func:`~depthrefine.bench.synthetic.make_scene`
        scenes (x4 and x8, color noise 6, with and without depth noise): mean
        RMSE 63 / 17 / 10.1 / 10.6 mm for 1 / 3 / 10 / 30.
    gradient_levels : float
        The detail solve's weight between two neighbours is their color
        weight times ``exp(-|dx| / t)``, ``dx`` the current estimate's
        difference and ``t`` this many levels of the input's depth range per
        low-resolution pixel (96; ``t = gradient_levels * range / 255 / s``,
        since a jump the back-projection places spreads over about ``s``
        color pixels): where the input shows a depth jump the guide does not
        (a color edge a few pixels off, a jump between two like colors), the
        solve keeps it instead of blurring it. 0 turns it off. Tuning mean
        (with ``lambda_lr`` 0.06) 2.6034 / 2.5854 / 2.5860 / 2.5925 for 64 /
        96 / 128 / 192 levels; 2.6322 without (and ``lambda_lr`` 0.03, the
        best value then); the probe of issue 9 found the depth's gradients
        worth 4 % too. Smaller values follow the input's own edges more
        (``lu`` x4 1.93 with 64, 2.03 with 96, 2.09 with 128).
    clip_rounds : bool
        After each round's smoothing, clip the full-resolution estimate,
        wherever its input pixel is valid, to the range of the valid input
        pixels of that pixel's 3x3 neighbourhood (True; the bound of
        ``local_range``, inside the rounds): an overshoot at a jump is gone
        before the next round's residual and depth weights build on it.
        The same clip follows the residual's addition in every round but
        the last (not within one input pixel of a missing one), and both
        clips run in the guide trust's check estimate too: with
        ``guide_smoothing`` and Lanczos residuals, tuning mean 2.4066 ->
        2.3952 (x4 / x8 / x16 1.533 / 2.284 / 3.402 -> 1.524 / 2.271 /
        3.391; every tuning protocol x scale better), real-ToF
        self-benchmark x4 / x8 19.48 / 32.22 -> 19.18 / 31.87. Clipped next to holes too (2.3961), the free pixels over a
        hole carried the clipped rim's pull into it: beside a hole near a
        jump the result moved 1.26 levels from the hole-free one, against
        0.60 without the residual clip and 0.59 with the margin
        (``tests/test_gbp.py``). Clipping the last round's residual too (2.3935)
        keeps the back-projection from matching the input there: on a weak
        color edge beside a large jump (``tests/test_gbp.py``) it was worse
        than no clip at all one input pixel off the jump (RMSE 41.51
        against 39.99; 0.125 against 0.007 for the final clip alone on the
        jump); sparing the last round, every offset is better than with the
        final clip alone or equal within 0.01 % of the jump. Sparing the
        last two rounds gave 2.3977, the residual clip over a 5x5
        neighbourhood 2.3991; without the check estimate's clips 2.4008
        (3x3) / 2.4022 (5x5, clipping every round), widened by a tenth of
        the local range 2.4063. Earlier, with bicubic residuals and no guide
        smoothing, the smoothing's clip alone: tuning mean 2.4416 ->
        2.4288 (x4 / x8 / x16 1.554 / 2.318 / 3.452 -> 1.540 / 2.308 /
        3.439), every tuning protocol x scale better or equal; real-ToF
        self-benchmark x4 / x8 19.91 / 32.77 -> 19.32 / 32.05 (before
        ``guide_smoothing`` and ``residual_interp``); clipping every
        round's residual too, and in the check estimate, gave 2.4161 but was
        worse than no clip at all on that weak color edge (41.10 against
        39.77 one input pixel off the jump). About 25 ms per 1.5 Mpx image
        (15 clips of about 1.5 ms, plus the check estimate's on a quarter
        of the pixels).
    guide_smoothing : float
        Before the color weights of both solves, the guide goes through a
        3x3 bilateral filter (spatial sigma 3 pixels) with this color sigma,
        in 8-bit levels (5; 0 turns it off): texture and noise inside a
        color region flatten, the edges between regions stay, so fewer
        spurious edges stop the smoothing. With ``clip_rounds`` and Lanczos
        residuals, tuning mean 2.4194 without it, 2.4104 with it (x4 / x8 /
        x16 1.532 / 2.299 / 3.427 -> 1.534 / 2.289 / 3.409); together with
        ``residual_interp`` every tuning protocol x scale better than with
        neither. Tried before the Lanczos residuals: color sigma 3 / 5 / 8
        / 20 with a 5x5 filter gave 2.4361 / 2.4315 / 2.4343 / 2.4476
        without the clip (2.4416 without the filter), and on the clipped
        version 5x5 2.4189, 3x3 2.4195 (6 ms against 26 ms per 1.5 Mpx
        image); a 3x3 median instead 2.4866, a guided-filter smoothing
        2.4392 (x16 worse), L*a*b* colors 2.4947.
    residual_interp : {"lanczos", "cubic"}
        The enlargement of each round's residual ``y - D(x)`` (``lanczos``,
        OpenCV's 8x8 Lanczos): a sharper kernel puts the correction closer
        to the input pixel it comes from. Tuning mean 2.4193 with bicubic,
        2.4104 with Lanczos (both with ``guide_smoothing``); without the
        filter, bilinear / bicubic / Lanczos gave 2.4580 / 2.4288 / 2.4194
        (Lanczos better on the Middlebury scenes at every scale, within
        0.5 % worse on the noisy Park and simulated ToF, which the guide
        filter makes up). Real-ToF self-benchmark x4 / x8 19.32 / 32.05
        (bicubic, no filter) -> 19.48 / 32.22 with both (0.8 % / 0.5 %
        worse; 19.91 / 32.77 before ``clip_rounds``). Both cost about 40 ms
        per 1.5 Mpx image together.
    """

    iterations: int = 8
    lambda_first: float = 6.0
    lambda_last: float = 0.35
    lambda_lr: float = 0.06
    sigma_color: float = 4.0
    noise_ref: float = 1.0
    flat_lambda_lr: float = 32.0
    flat_sigma_color: float = 4.0
    edge_low: float = 6.0
    edge_width: float = 4.0
    flat_noise: float = 2.0
    trust: bool = True
    trust_radius: int = 4
    local_range: bool = True
    hole_margin: int = 0
    trust_prior: float = 1.0
    trust_floor: float = 0.1
    jump_levels: float = 3.0
    jump_noise: float = 4.0
    jump_margin: int = 2
    guide_noise: float = 3.0
    trust_guide_noise: float = 4.0
    mixed_low: float = 0.02
    mixed_high: float = 0.08
    point_lambda: float = 10.0
    gradient_levels: float = 96.0
    clip_rounds: bool = True
    guide_smoothing: float = 5.0
    residual_interp: str = "lanczos"

    def __post_init__(self) -> None:
        check_int("iterations", self.iterations, minimum=1)
        check_int("trust_radius", self.trust_radius, minimum=1)
        check_int("hole_margin", self.hole_margin, minimum=0)
        check_int("jump_margin", self.jump_margin, minimum=0)
        for name in ("lambda_lr", "sigma_color", "noise_ref", "flat_lambda_lr", "flat_sigma_color", "edge_width",
                     "flat_noise", "lambda_first", "lambda_last", "point_lambda"):
            check_number(name, getattr(self, name), positive=True)
        for name in ("edge_low", "trust_prior", "jump_levels", "jump_noise", "guide_noise", "trust_guide_noise",
                     "mixed_low", "gradient_levels", "guide_smoothing"):
            check_number(name, getattr(self, name), nonnegative=True)
        if not 0 <= check_number("trust_floor", self.trust_floor) < 1:
            raise ValueError(f"trust_floor must be in [0, 1); got {self.trust_floor}.")
        if not check_number("mixed_high", self.mixed_high) > self.mixed_low:
            raise ValueError(f"mixed_high must be above mixed_low ({self.mixed_low}); got {self.mixed_high}.")
        check_choice("residual_interp", self.residual_interp, ("cubic", "lanczos"))
        for name in ("trust", "local_range", "clip_rounds"):
            if not isinstance(getattr(self, name), (bool, np.bool_)):
                raise TypeError(f"{name} must be True or False; got {getattr(self, name)!r}.")


#: RMS of a standard normal variable clipped at +-2.5 (the noise estimate's correction).
_CLIPPED_RMS = 0.9542
#: Clip level of the noise estimate, in standard deviations.
_CLIP = 2.5


def estimate_noise(depth: np.ndarray, valid: np.ndarray) -> float:
    """Noise standard deviation of a depth map, in its units, from its finest diagonal Haar band.

    The band ``(a - b - c + d) / 2`` of each 2x2 block with four valid pixels
    has the noise's standard deviation and almost no signal on smooth
    surfaces. Its RMS is taken after clipping at 2.5 times the current
    estimate (five rounds), so depth edges do not count as noise, and
    corrected for the clipping. The median absolute value (Donoho 1994) is
    not used because quantised maps make it jump between few values.

    Parameters
    ----------
    depth : (h, w) float ndarray
        Depth, invalid pixels already filled.
    valid : (h, w) bool ndarray
        Pixels that hold a measurement.

    Returns
    -------
    float
        0.0 when fewer than 16 blocks are fully valid.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> noisy = (100 + rng.normal(0, 3, (200, 200))).astype(np.float32)
    >>> round(estimate_noise(noisy, np.ones(noisy.shape, bool)), 1)
    3.0
    """
    h, w = (depth.shape[0] // 2) * 2, (depth.shape[1] // 2) * 2
    d = depth[:h, :w].astype(np.float64)
    band = (d[0::2, 0::2] - d[0::2, 1::2] - d[1::2, 0::2] + d[1::2, 1::2]) / 2.0
    v = valid[:h, :w]
    ok = v[0::2, 0::2] & v[0::2, 1::2] & v[1::2, 0::2] & v[1::2, 1::2]
    coef = band[ok]
    if coef.size < 16:
        return 0.0
    return _clipped_rms(coef, np.ones(coef.shape))


def _clipped_rms(values: np.ndarray, counts: np.ndarray) -> float:
    """RMS of ``values`` (each counted ``counts`` times), clipped at 2.5 times the estimate, five rounds."""
    squares = values * values
    sigma = math.sqrt(float(np.sum(counts * squares) / np.sum(counts)))
    for _ in range(5):
        kept = np.abs(values) <= _CLIP * sigma
        total = float(np.sum(counts[kept]))
        if total == 0:
            return 0.0
        sigma = math.sqrt(float(np.sum(counts[kept] * squares[kept])) / total) / _CLIPPED_RMS
    return sigma


def estimate_guide_noise(guide: np.ndarray) -> float:
    """Noise standard deviation of an 8-bit color image, in levels (RMS over its channels).

    The same estimate as :func:`estimate_noise` (the finest diagonal Haar
    band, clipped RMS), over the bands of all channels at once; the band of
    8-bit values takes at most 1021 values, so it is taken from their
    histogram (about 25 ms for 1.5 megapixels).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> noisy = np.clip(128 + rng.normal(0, 5, (200, 200, 3)), 0, 255).round().astype(np.uint8)
    >>> round(estimate_guide_noise(noisy))
    5
    """
    h, w = (guide.shape[0] // 2) * 2, (guide.shape[1] // 2) * 2
    if h == 0 or w == 0:
        return 0.0
    g = guide[:h, :w].astype(np.int16)
    band = g[0::2, 0::2] - g[0::2, 1::2]
    band -= g[1::2, 0::2]
    band += g[1::2, 1::2]
    counts = np.bincount((band + 510).ravel(), minlength=1021).astype(np.float64)
    return _clipped_rms((np.arange(1021) - 510) * 0.5, counts)


#: The mixed-pixel test of :func:`footprint_share`: a jump is larger than this many noise sigmas ...
_MIXED_SIGMAS = 8.0
#: ... and than this share of the depth range (1st to 99th percentile).
_MIXED_SPAN = 0.1
#: A middle pixel is mixed when it is off both sides by more than this many noise sigmas and share of the jump.
_MIXED_APART_SIGMAS, _MIXED_APART = 4.0, 0.05
#: Fewer jumps than this: too few to tell, the input counts as footprint means.
_MIXED_MIN_JUMPS = 20


def footprint_share(depth: np.ndarray, params: GbpParams | None = None) -> float:
    """How far the input looks like footprint means (1) rather than point samples (0), from the input alone.

    Over every three consecutive valid pixels of a row or a column whose
    outer two differ by a large jump (more than 8 noise sigmas and 10 % of
    the depth range), the share ``m`` of middle pixels that lie between the
    outer two, off both by more than 4 noise sigmas and 5 % of the jump, is
    counted. A pixel that integrates its footprint (a ToF pixel; an area or
    antialiased reduction) straddles an edge in about half of such
    triplets; a point sample is on one side of it.
    The result ramps from 0 at ``m = mixed_low`` to 1 at ``mixed_high``;
    it is 1 when the input has fewer than 20 such jumps.

    Examples
    --------
    >>> point, mean = np.array([[5, 5, 15, 15]] * 16, np.float32), np.array([[5, 5, 10, 15, 15]] * 16, np.float32)
    >>> footprint_share(point), footprint_share(mean)
    (0.0, 1.0)
    """
    p = GbpParams() if params is None else params
    d = as_depth(depth)
    valid = np.isfinite(d)
    if valid.sum() < 4:
        return 1.0
    filled = fill_invalid_nearest(d)
    sigma = estimate_noise(filled, valid)
    jump = max(_MIXED_SIGMAS * sigma, _MIXED_SPAN * _span(filled, valid))
    middles = 0
    jumps = 0
    for a, b, c in ((d[:, :-2], d[:, 1:-1], d[:, 2:]), (d[:-2], d[1:-1], d[2:])):
        with np.errstate(invalid="ignore"):
            ok = (np.abs(c - a) > jump) & np.isfinite(b)     # False where any of the three is NaN
        a, b, c = a[ok], b[ok], c[ok]
        # mixed: the middle pixel is off both sides, by more than the noise and 5 % of the jump
        apart = np.maximum(_MIXED_APART_SIGMAS * sigma, _MIXED_APART * np.abs(c - a))
        middles += int(np.count_nonzero((np.minimum(np.abs(b - a), np.abs(c - b)) > apart)
                                        & (np.sign(b - a) == np.sign(c - b))))
        jumps += int(a.size)
    if jumps < _MIXED_MIN_JUMPS:
        return 1.0
    return float(np.clip((middles / jumps - p.mixed_low) / (p.mixed_high - p.mixed_low), 0.0, 1.0))


def _resize(image: np.ndarray, shape: tuple[int, int], interpolation: int) -> np.ndarray:
    import cv2

    return cv2.resize(image, (shape[1], shape[0]), interpolation=interpolation)


def _clamped_bicubic(depth: np.ndarray, shape: tuple[int, int], jump: np.ndarray) -> np.ndarray:
    """Bicubic enlargement, clipped near depth jumps to the range of each pixel's 3x3 input neighbourhood.

    Plain bicubic rings at a depth jump (values beyond both sides); clipped
    there, it keeps bicubic's sharpness, and on smooth surfaces (``jump`` 0:
    :func:`_near_jump` of ``depth``) it stays plain bicubic, whose peaks may
    rightly pass the samples. As the fallback of the guide trust (step 4)
    and the start of the back-projection it took the real Kinect
    self-benchmark from 20.55 to 18.6 mm at x4 (33.4 to 30.7 at x8) and the
    tuning mean from 2.665 to 2.657; clipped everywhere, a smooth surface
    under a textured guide lost 10 % to bicubic.
    """
    import cv2

    kernel = np.ones((3, 3), np.uint8)
    up = _resize(depth, shape, cv2.INTER_CUBIC)
    low = _resize(cv2.erode(depth, kernel), shape, cv2.INTER_NEAREST)
    high = _resize(cv2.dilate(depth, kernel), shape, cv2.INTER_NEAREST)
    clipped = np.clip(up, low, high)
    # up <- up + jump * (clipped - up), in place
    clipped -= up
    clipped *= _resize(jump, shape, cv2.INTER_LINEAR)
    up += clipped
    return up


def block_mean_valid(depth: np.ndarray, factor: int) -> np.ndarray:
    """Mean of the valid (finite) pixels of each ``factor x factor`` block; NaN where none is.

    Rows and columns beyond a multiple of ``factor`` are dropped. No invalid
    pixel is averaged in: a block's mean is over its valid pixels only.

    Examples
    --------
    >>> block_mean_valid(np.array([[1, np.nan, 5, 5], [3, np.nan, 5, 5]], np.float32), 2).tolist()
    [[2.0, 5.0]]
    """
    h, w = depth.shape[0] // factor, depth.shape[1] // factor
    x = depth[: h * factor, : w * factor]
    valid = np.isfinite(x)
    total = np.where(valid, x, 0).reshape(h, factor, w, factor).sum(axis=(1, 3), dtype=np.float64)
    count = valid.reshape(h, factor, w, factor).sum(axis=(1, 3))
    out = np.full((h, w), np.nan, np.float32)
    np.divide(total, count, out=out, where=count > 0, casting="unsafe")
    return out


def _span(filled: np.ndarray, valid: np.ndarray) -> float:
    """The depth range the noise is measured against: 1st to 99th percentile of the valid pixels."""
    low, high = np.percentile(filled[valid], [1, 99])
    return float(high - low) if high > low else max(abs(float(filled.max())), 1.0)


def _noise_levels(filled: np.ndarray, valid: np.ndarray) -> float:
    """The input's noise in 8-bit levels of its own depth range (unit-free), blind to smooth curvature.

    The band is the 5x5 product of fourth differences ``[1, -4, 6, -4, 1]``
    along rows and columns (divided by 70: unit noise gain), which is zero on
    any surface cubic in each direction and nearly so on a surface resolved
    by 9 input pixels per period (1 % of what the second differences
    ``[1, -2, 1]`` see there), where the diagonal Haar band of
    :func:`estimate_noise` sees a curved surface's twist as noise; clipped
    RMS as there. On white noise both bands give its standard deviation (the
    benchmark's noisy inputs measure within 3 % of each other). It decides
    how far the fallback is denoised (step 4).
    """
    import cv2

    band = cv2.filter2D(filled.astype(np.float32), -1, _FOURTH_ORDER, borderType=cv2.BORDER_REFLECT)[2:-2, 2:-2]
    inner = cv2.erode(valid.astype(np.uint8), np.ones((5, 5), np.uint8))[2:-2, 2:-2] > 0
    coef = band[inner].astype(np.float64)
    if coef.size < 16:
        return 0.0
    return 255.0 * _clipped_rms(coef, np.ones(coef.shape)) / _span(filled, valid)


#: Noise below this many levels counts as none in the fallback: 8-bit rounding (0.29 levels of a 255-level range)
#: and what is left of a smooth surface in the noise band are not noise to average away. Tuning mean (with the
#: fourth-order band) 2.4386 / 2.4380 / 2.4368 for 0.2 / 0.3 / 0.5 (2.4406 with the second-order band and 0.2,
#: 2.4416 with it and 0.02); larger floors gain more there (2.4336 / 2.4308 for 1 / 2) by denoising the noisy
#: inputs less, which is the ramp's tuning (``flat_noise``), not a floor.
_NOISE_FLOOR = 0.5
#: Product of fourth differences along rows and columns, unit noise gain (``_noise_levels``).
_FOURTH_ORDER = np.outer(*(np.array([1, -4, 6, -4, 1], np.float32),) * 2) / 70.0


def _noise_share(sigma_levels: float, p: GbpParams) -> float:
    """0 for a noise-free input, rising to 1 at ``flat_noise`` levels of noise."""
    return min(1.0, sigma_levels / p.flat_noise)


def _reduce(x: np.ndarray, shape: tuple[int, int], box: float) -> np.ndarray:
    """The data model ``D``: footprint means (``box = 1``), point samples (0, at the pixels' centres), or a blend."""
    import cv2

    if box >= 1.0:
        return _resize(x, shape, cv2.INTER_AREA)
    point = _resize(x, shape, cv2.INTER_NEAREST_EXACT)
    if box <= 0.0:
        return point
    return point + box * (_resize(x, shape, cv2.INTER_AREA) - point)


#: The bilateral filter of ``guide_smoothing``: its diameter and spatial sigma, color pixels.
_GUIDE_SMOOTHING_SIZE, _GUIDE_SMOOTHING_SPACE = 3, 3.0


def _guided_estimate(depth: np.ndarray, guide: np.ndarray, p: GbpParams, guide_sigma: float, jump: np.ndarray,
                     progress: Progress | None = None, box: float = 1.0) -> np.ndarray:
    """Steps 1-3: back-projected, edge-aware detail blended with the flat-area solve.

    ``depth`` is float32 with NaN for invalid pixels (at least one valid);
    ``guide`` is the (H, W, 3) uint8 color image and ``guide_sigma`` the
    floor of the solves' color sensitivity (from the guide's noise, step 1);
    ``jump`` the input's :func:`_near_jump` map (where the start is clipped);
    ``box`` the input's footprint share
    (:func:`footprint_share`). With ``p.clip_rounds`` each round's smoothed
    estimate, and the estimate after adding the residual in every round but
    the last (not next to a hole), is clipped to the input's local range.
    Returns (H, W) float32, clipped to the valid range of ``depth``.
    """
    import cv2

    from . import _wls

    valid = np.isfinite(depth)
    filled = fill_invalid_nearest(depth)
    lo, hi = float(filled.min()), float(filled.max())
    (h, w), (H, W) = depth.shape, guide.shape[:2]
    s = 0.5 * (H / h + W / w)
    span = _span(filled, valid)
    sigma = estimate_noise(filled, valid)
    sigma_levels = 255.0 * sigma / span

    lam = p.lambda_lr * s * s * (1.0 + (sigma_levels / p.noise_ref) ** 2) * (1.0 + (p.point_lambda - 1.0) * (1.0 - box))
    if p.guide_smoothing > 0:
        # a 3x3 bilateral filter: flattens texture and noise within a color region, keeps the edges between regions
        guide = cv2.bilateralFilter(guide, _GUIDE_SMOOTHING_SIZE, p.guide_smoothing, _GUIDE_SMOOTHING_SPACE,
                                    borderType=cv2.BORDER_REPLICATE)
    color_x, color_y = _wls.color_weights(guide, max(p.sigma_color, guide_sigma))
    # the depth's own gradients, per low-resolution pixel in levels of the range (a jump spreads over s pixels)
    gradient_sigma = p.gradient_levels * span / 255.0 / s
    x = _clamped_bicubic(filled, (H, W), jump)
    bounds = residual_bounds = _local_bounds(depth, (H, W)) if p.clip_rounds else None
    if p.clip_rounds and not valid.all():
        # after the residual, not within one input pixel of a missing one: the free pixels over a hole would
        # otherwise carry the clipped rim's pull into it
        residual_bounds = _local_bounds(depth, (H, W), hole_margin=1)
    interp = cv2.INTER_LANCZOS4 if p.residual_interp == "lanczos" else cv2.INTER_CUBIC
    for k in range(p.iterations):
        # geometric schedule lambda_first -> lambda_last over the rounds
        ratio = p.lambda_first * (p.lambda_last / p.lambda_first) ** (k / max(1, p.iterations - 1))
        residual = filled - _reduce(x, (h, w), box)
        residual[~valid] = 0.0
        x += _resize(residual, (H, W), interp)
        if residual_bounds is not None and k < p.iterations - 1:
            # the last round's residual stays whole, so that the result's reduction matches the input
            _clip_to_local_range(x, depth, residual_bounds)
        if p.gradient_levels > 0:
            weight_x, weight_y = _wls.depth_weights(x, gradient_sigma, color_x, color_y)
        else:
            weight_x, weight_y = color_x, color_y
        x = _wls.smooth(x, weight_x, weight_y, lam * ratio)
        np.clip(x, lo, hi, out=x)
        if bounds is not None:
            _clip_to_local_range(x, depth, bounds)
        if progress is not None:
            progress(k + 1, p.iterations + 1)

    if p.flat_sigma_color != p.sigma_color:
        color_x, color_y = _wls.color_weights(guide, max(p.flat_sigma_color, guide_sigma))
    flat = _wls.smooth(_resize(filled, (H, W), cv2.INTER_LINEAR), color_x, color_y, p.flat_lambda_lr * s)
    kernel = np.ones((3, 3), np.uint8)
    local_range = cv2.dilate(filled, kernel) - cv2.erode(filled, kernel)
    edge = np.clip((local_range - p.edge_low * sigma) / (p.edge_width * sigma + 1e-6 * span), 0.0, 1.0)
    edge = cv2.dilate(edge.astype(np.float32), kernel)
    # a noise-free input has nothing to average away: the flat solve's share fades out below flat_noise
    edge = 1.0 - (1.0 - edge) * _noise_share(sigma_levels, p)
    edge = _resize(edge, (H, W), cv2.INTER_LINEAR)
    # x <- edge * x + (1 - edge) * flat, in place
    x -= flat
    x *= edge
    x += flat
    return np.clip(x, lo, hi, out=x)


def guide_trust(depth: np.ndarray, guide: np.ndarray, params: GbpParams | None = None) -> np.ndarray:
    """How far the guided detail can be trusted, per low-resolution pixel, in [0, 1] (step 4).

    The input is reduced x2 (mean of the valid pixels of each 2x2 block), the
    guided estimate is computed from it with the guide resized (area) to the
    input's grid, and in each window of ``2 * trust_radius + 1`` pixels the
    share ``a`` of its guided detail ``g - b`` (``b``: bicubic enlargement of
    ``g`` reduced x2) that best explains the withheld input ``y`` is fitted
    by least squares, ``a = (sum (y - b)(g - b) + e) / (sum (g - b)**2 + e)``
    on valid pixels, with the prior ``e = (trust_prior * range / 255)**2``
    per pixel (``range``: the input's 1st to 99th percentile), clipped to
    [0, 1], set to 0 within ``hole_margin`` pixels of a missing input pixel,
    and smoothed over the same window. It is then multiplied by the
    nearness to a depth jump of the input (``jump_levels``): a guide's
    edges are trusted only where the input confirms a discontinuity, and a
    smooth surface, however curved, shows none.

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
        1 everywhere when the input is too small to reduce (under 8 pixels
        on a side).
    """
    import cv2

    p = GbpParams() if params is None else params
    h, w = depth.shape
    trust = np.ones((h, w), np.float32)
    small = block_mean_valid(depth, 2)
    if min(small.shape) < 4 or not np.isfinite(small).any():
        return trust
    hc, wc = small.shape[0] * 2, small.shape[1] * 2
    guide_lr = np.ascontiguousarray(_resize(guide, (h, w), cv2.INTER_AREA)[:hc, :wc])
    # on the guide reduced to the input's grid the finest band is mostly fine texture, not noise: its own factor
    g = _guided_estimate(small, guide_lr, p, p.trust_guide_noise * estimate_guide_noise(guide_lr),
                         _near_jump(small, p))
    b = _resize(_resize(g, small.shape, cv2.INTER_AREA), (hc, wc), cv2.INTER_CUBIC)
    valid = np.isfinite(depth[:hc, :wc])
    y = np.where(valid, depth[:hc, :wc], b)
    detail = np.where(valid, g - b, 0).astype(np.float32)
    explained = np.where(valid, y - b, 0).astype(np.float32)
    size = (2 * p.trust_radius + 1,) * 2
    num = cv2.boxFilter(explained * detail, -1, size, borderType=cv2.BORDER_REFLECT)
    den = cv2.boxFilter(detail * detail, -1, size, borderType=cv2.BORDER_REFLECT)
    span = float(np.nanmax(depth) - np.nanmin(depth))
    prior = (p.trust_prior * span / 255.0) ** 2 + 1e-30
    trust[:hc, :wc] = np.clip((num + prior) / (den + prior), 0.0, 1.0)
    trust[hc:, :] = trust[hc - 1:hc, :]
    trust[:, wc:] = trust[:, wc - 1:wc]
    holes = ~np.isfinite(depth)
    if p.hole_margin > 0 and holes.any():
        near = cv2.dilate(holes.astype(np.uint8), np.ones((2 * p.hole_margin + 1,) * 2, np.uint8)) > 0
        trust[near] = 0.0
    trust = cv2.boxFilter(trust, -1, size, borderType=cv2.BORDER_REFLECT)
    return trust * _near_jump(depth, p)


def _clip_to_local_range(result: np.ndarray, depth: np.ndarray,
                         bounds: tuple[np.ndarray, np.ndarray] | None = None) -> None:
    """Clip ``result`` in place, wherever its input pixel is valid, to the range of the valid input pixels around it.

    ``result`` is (H, W) float32 on the color grid, ``depth`` the (h, w)
    input with NaN for invalid pixels. The range is that of the valid pixels
    of each input pixel's 3x3 neighbourhood, the input continued linearly
    beyond its border (odd reflection: a slope keeps its last pixels'
    values); output pixels over a missing input pixel are left as they are.
    ``bounds``: :func:`_local_bounds` of ``depth`` on the grid of ``result``,
    when already computed.
    """
    import cv2

    low, high = _local_bounds(depth, result.shape) if bounds is None else bounds
    cv2.max(result, low, dst=result)    # in place, 3x np.clip's speed
    cv2.min(result, high, dst=result)


def _local_bounds(depth: np.ndarray, shape: tuple[int, int], hole_margin: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """The bounds of :func:`_clip_to_local_range` on a grid of ``shape``: (low, high), float32.

    They are +-inf (no bound) over missing input pixels and, with
    ``hole_margin``, over the input pixels within that many pixels of one.
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
    return _resize(low, shape, cv2.INTER_NEAREST), _resize(high, shape, cv2.INTER_NEAREST)


def _near_jump(depth: np.ndarray, p: GbpParams) -> np.ndarray:
    """1 near a depth jump of the input, 0 on smooth surfaces (``jump_levels``), per input pixel.

    The jump is measured as the 4-neighbour Laplacian's deviation from its
    own 3x3 mean: a smooth surface's curvature changes slowly (a quadratic's
    is constant), so however curved it is this stays near zero, while at a
    jump the Laplacian flips sign from one side to the other.
    ``depth`` is (h, w) float32 with NaN for invalid pixels (at least one
    valid); under 3 pixels on a side nothing is measured and it is 0.
    """
    import cv2

    if min(depth.shape) < 3:
        return np.zeros(depth.shape, np.float32)

    valid = np.isfinite(depth)
    filled = fill_invalid_nearest(depth)
    span = _span(filled, valid)
    laplacian = cv2.Laplacian(filled, cv2.CV_32F, ksize=1)
    # the reflected border turns a slope into a kink: take the border from the pixels inside
    laplacian[0], laplacian[-1] = laplacian[1], laplacian[-2]
    laplacian[:, 0], laplacian[:, -1] = laplacian[:, 1], laplacian[:, -2]
    # a curved surface's Laplacian is locally constant, a jump's is not
    curvature = np.abs(laplacian - cv2.blur(laplacian, (3, 3), borderType=cv2.BORDER_REFLECT))
    threshold = p.jump_noise * estimate_noise(filled, valid) + p.jump_levels * span / 255.0 + 1e-6 * span
    jump = np.clip(curvature / threshold - 1.0, 0.0, 1.0).astype(np.float32)
    if p.jump_margin > 0:
        jump = cv2.dilate(jump, np.ones((2 * p.jump_margin + 1,) * 2, np.uint8))
    return cv2.boxFilter(jump, -1, (3, 3))


def upsample_gbp(depth_lr: np.ndarray, rgb_hr: np.ndarray, *, params: GbpParams | None = None,
                 progress: Progress | None = None) -> np.ndarray:
    """Guided back-projection: upsample ``depth_lr`` to the grid of ``rgb_hr`` (see the module docstring).

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
    import cv2

    p = GbpParams() if params is None else params
    if not isinstance(p, GbpParams):
        raise TypeError(f"params must be GbpParams or None; got {type(p).__name__}.")
    guide = _guide8(check_rgb(rgb_hr))
    depth = as_depth(depth_lr)
    (h, w), (H, W) = depth.shape, guide.shape[:2]
    box = footprint_share(depth, p)
    jump = _near_jump(depth, p)  # where the input shows a depth jump: the start and the fallback are clipped there
    result = _guided_estimate(depth, guide, p, p.guide_noise * estimate_guide_noise(guide), jump, progress, box)
    if p.trust:
        if p.local_range:
            _clip_to_local_range(result, depth)
        trust = guide_trust(depth, guide, p)
        if p.trust_floor > 0:
            trust = np.clip((trust - p.trust_floor) / (1.0 - p.trust_floor), 0.0, 1.0)
        trust = _resize(trust, (H, W), cv2.INTER_LINEAR)
        # the fallback: clipped bicubic enlargement of the result's own reduction, moved towards the input itself as
        # far as the input is noise-free (there is nothing to average away then)
        filled = fill_invalid_nearest(depth)
        valid = np.isfinite(depth)
        reduced = _reduce(result, (h, w), box)
        share = _noise_share(max(0.0, _noise_levels(filled, valid) - _NOISE_FLOOR), p)
        reduced = np.where(valid, reduced + (1.0 - share) * (filled - reduced), reduced).astype(np.float32)
        base = _clamped_bicubic(reduced, (H, W), jump)
        # result <- base + trust * (result - base), in place
        result -= base
        result *= trust
        result += base
        lo, hi = float(np.nanmin(depth)), float(np.nanmax(depth))
        np.clip(result, lo, hi, out=result)
    if progress is not None:
        progress(p.iterations + 1, p.iterations + 1)
    return result.astype(np.float32, copy=False)


#: Frames a pixel's running average spans at most (the warm start's memory).
_WARM_FRAMES = 8
#: An input pixel changed when its 3x3 mean moved by more than this many noise sigmas.
_WARM_SIGMAS = 3.0


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
    flickering. Elsewhere (a moving object, a new or lost measurement; the
    3x3 mean flags the input pixels next to a change too; a color edge that
    moved between two input samples, which the result follows) the pixel
    starts afresh with this frame's result.
    The output is clipped to this frame's valid input range. Deterministic.

    With ``state=None`` (the first frame) the result is :func:`upsample_gbp`'s,
    bit for bit; a state from a frame of another size is ignored (a cold start).

    Returns
    -------
    depth_hr : (H, W) float32 ndarray
    state : dict
        Opaque (the previous input's 3x3 means and validity, the guide's 3x3
        means, the output, and each pixel's frame count); pass it with the
        next frame.

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

    result = upsample_gbp(depth_lr, rgb_hr, params=params, progress=progress)
    depth = as_depth(depth_lr)
    guide = _guide8(check_rgb(rgb_hr))
    guide3 = cv2.blur(guide.astype(np.float32), (3, 3), borderType=cv2.BORDER_REPLICATE)
    valid = np.isfinite(depth)
    filled = fill_invalid_nearest(depth)
    mean3 = cv2.blur(filled, (3, 3), borderType=cv2.BORDER_REPLICATE)
    valid3 = cv2.erode(valid.astype(np.uint8), np.ones((3, 3), np.uint8), borderType=cv2.BORDER_REPLICATE) > 0
    shape = depth.shape + result.shape
    out = result
    count = np.ones(result.shape, np.float32)
    if state is not None and state.get("shape") == shape:
        sigma = estimate_noise(filled, valid)
        tolerance = _WARM_SIGMAS * sigma if sigma > 0 else 1e-6 * _span(filled, valid)
        steady = valid3 & state["valid3"] & (np.abs(mean3 - state["mean3"]) <= tolerance)
        # no margin beyond the 3x3 mean's own reach: a margin of 1 or 2 more input pixels cut the flicker less
        # (make_sequence, 12 frames: -30 % / -25 % against -38 %) and did not lower the RMSE
        changed = _resize((~steady).astype(np.uint8), result.shape, cv2.INTER_NEAREST) > 0
        # the guide moved (an edge the result follows) although the input did not: start afresh there too,
        # as far as the solve's reach (one input pixel)
        guide_tolerance = _WARM_SIGMAS * estimate_guide_noise(guide) / 3.0 * math.sqrt(2.0) + 1.0
        moved = (np.abs(guide3 - state["guide3"]).max(axis=2) > guide_tolerance).astype(np.uint8)
        reach = 2 * math.ceil(result.shape[0] / depth.shape[0]) + 1
        changed |= cv2.dilate(moved, np.ones((reach, reach), np.uint8)) > 0
        count = np.where(changed, 1.0, np.minimum(state["count"] + 1.0, _WARM_FRAMES)).astype(np.float32)
        # out <- prev + (result - prev) / count where steady; result where changed (count 1)
        prev = state["out"]
        out = (prev + (result - prev) / count).astype(np.float32)
        out[changed] = result[changed]
        np.clip(out, float(np.nanmin(depth)), float(np.nanmax(depth)), out=out)
    return out, {"shape": shape, "mean3": mean3, "valid3": valid3, "guide3": guide3, "out": out.copy(), "count": count}
