"""Step 1 of gbp: what the method needs to know about its input, measured once.

:func:`measure_input` returns an :class:`InputMeasures`: the input with its
holes filled, its validity, its range and noise (in 8-bit levels of its own
depth range, so one set of defaults serves levels and millimetres), whether
its pixels are footprint means or point samples, where it shows a depth
jump, and the guide's own noise. Every later step reads these values; none
measures the input again.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from ..._fill import enclosed_holes, fill_invalid_nearest, fill_smooth
from ..._validate import as_depth
from ._options import check_sampling

__all__ = ["InputMeasures", "measure_input", "estimate_noise", "estimate_guide_noise",
           "footprint_share", "near_jump", "noise_levels", "noise_share", "block_mean_valid"]

# ---- the noise estimate (finest diagonal Haar band, clipped RMS)
#: Band values beyond this many standard deviations are left out (depth edges are not noise).
NOISE_CLIP = 2.5
#: RMS of a standard normal variable with the values beyond +-``NOISE_CLIP`` left out (a truncated normal's
#: ``sqrt(1 - 2 c phi(c) / (2 Phi(c) - 1))``): the estimate's correction, 0.9546 for 2.5 (until 0.2 a hand-copied
#: 0.9542).
NOISE_CLIPPED_RMS = math.sqrt(1.0 - 2.0 * NOISE_CLIP * math.exp(-0.5 * NOISE_CLIP ** 2) / math.sqrt(2.0 * math.pi)
                              / math.erf(NOISE_CLIP / math.sqrt(2.0)))
#: Rounds of the clipped RMS.
NOISE_ROUNDS = 5
#: :func:`estimate_guide_noise` takes this many pairs of rows at a time.
GUIDE_NOISE_ROWS = 64
#: Fewer fully valid 2x2 blocks than this: too few to tell, the noise counts as 0.
NOISE_MIN_BLOCKS = 16
#: Noise, in levels of the depth range, at which the flat-area solve and the denoised fallback take full
#: effect (from 0 on a noise-free input).
FLAT_NOISE = 2.0
#: The fallback's noise band: product of fourth differences along rows and columns, unit noise gain.
FOURTH_ORDER = np.outer(*(np.array([1, -4, 6, -4, 1], np.float32),) * 2) / 70.0

# ---- the sampling model (footprint means or point samples)
#: A jump between two pixels two apart is larger than this many noise sigmas ...
MIXED_SIGMAS = 8.0
#: ... and than this share of the depth range.
MIXED_SPAN = 0.1
#: A middle pixel is mixed when it is off both sides by more than this many noise sigmas and share of the jump.
MIXED_APART_SIGMAS, MIXED_APART = 4.0, 0.05
#: Fewer jumps than this: too few to tell, the input counts as footprint means.
MIXED_MIN_JUMPS = 20
#: The share of mixed middle pixels at which the input counts as point samples (below) or footprint means (above).
MIXED_LOW, MIXED_HIGH = 0.02, 0.08

# ---- the jump map (where the input shows a depth discontinuity)
#: A jump: the Laplacian's deviation from its 3x3 mean exceeds ``JUMP_NOISE`` sigmas plus ``JUMP_LEVELS`` levels.
JUMP_LEVELS, JUMP_NOISE = 3.0, 4.0
#: The jump map reaches this many depth pixels beyond the jump.
JUMP_MARGIN = 2


@dataclass(frozen=True, eq=False)
class InputMeasures:
    """The input as gbp's steps see it (:func:`measure_input`).

    Attributes
    ----------
    depth : (h, w) float32 ndarray
        The input, NaN where there is no measurement.
    valid : (h, w) bool ndarray
    filled : (h, w) float32 ndarray
        ``depth`` with every hole filled (:func:`fill_holes`).
    low, high : float
        The valid range.
    span : float
        The depth range the noise is measured against (1st to 99th percentile).
    sigma : float
        Noise standard deviation, in the input's units.
    sigma_levels : float
        ``sigma`` in 8-bit levels of ``span``.
    footprint : float
        1 for footprint means (a ToF pixel integrates), 0 for point samples.
    jump : (h, w) float32 ndarray
        1 near a depth jump of the input, 0 on smooth surfaces.
    guide_noise : float
        The guide's noise standard deviation, 8-bit levels.

    Two more measures are taken on first use and kept (each is measured
    once however many steps read it): :attr:`curvature_blind_noise` and
    :attr:`large_jumps`; :meth:`neighbourhood` is made where it is read
    (two arrays of the input's size, not held through the solves).
    """

    depth: np.ndarray
    valid: np.ndarray
    filled: np.ndarray
    low: float
    high: float
    span: float
    sigma: float
    sigma_levels: float
    footprint: float
    jump: np.ndarray
    guide_noise: float

    def neighbourhood(self) -> tuple[np.ndarray, np.ndarray]:
        """The smallest and the largest ``filled`` value of each input pixel's 3x3 neighbourhood, (h, w) float32 each.

        The start's clip near the jumps (:func:`~.solve.clamped_bicubic`, step 2)
        and the flat-area test (:func:`~.solve.flat_blend`, step 4) read it,
        each making it (an erosion and a dilation of the input, well under a
        millisecond at 640x360) rather than holding it through the solves
        between them.
        """
        import cv2

        kernel = np.ones((3, 3), np.uint8)
        return cv2.erode(self.filled, kernel), cv2.dilate(self.filled, kernel)

    @functools.cached_property
    def curvature_blind_noise(self) -> float:
        """The noise in levels of the depth range, blind to smooth curvature (:func:`noise_levels`; steps 5 and
        gbp-fast's residual)."""
        return _curvature_blind_noise(self)

    @functools.cached_property
    def large_jumps(self) -> np.ndarray:
        """The input pixels near a large depth jump, (h, w) bool (:func:`~.edges.jump_band`; steps 1b and 6)."""
        from .edges import jump_band

        return jump_band(self)


#: The footprint share each sampling model a user can name (``GbpParams.sampling``) stands for; ``"auto"``
#: measures it (:func:`footprint_share`).
SAMPLING_FOOTPRINT = {"point": 0.0, "mean": 1.0}


def measure_input(depth: np.ndarray, guide: np.ndarray, *, sampling: str = "auto") -> InputMeasures:
    """Measure the input once (step 1).

    Parameters
    ----------
    depth : (h, w) float32 ndarray
        NaN where invalid, at least one valid pixel.
    guide : (H, W, 3) uint8 ndarray
    sampling : {"auto", "point", "mean"}
        The sampling model: ``"auto"`` estimates it from the input
        (:func:`footprint_share`); ``"point"`` takes point samples at the
        pixels' centres, ``"mean"`` footprint means (the check one octave
        down, whose input is a block mean by construction).
    """
    check_sampling(sampling)
    valid = np.isfinite(depth)
    filled = fill_holes(depth, valid)
    span = _span(filled, valid)
    sigma = estimate_noise(filled, valid)
    return InputMeasures(
        depth=depth, valid=valid, filled=filled, low=float(filled.min()), high=float(filled.max()), span=span,
        sigma=sigma, sigma_levels=255.0 * sigma / span,
        footprint=(_footprint_share(depth, filled, valid, sigma, span) if sampling == "auto"
                   else SAMPLING_FOOTPRINT[sampling]),
        jump=near_jump(filled, sigma, span), guide_noise=estimate_guide_noise(guide))


def fill_holes(depth: np.ndarray, valid: np.ndarray) -> np.ndarray:
    """``depth`` with every hole filled: smoothly from the rim where one surface encloses it, else from the nearest pixel.

    A hole inside one measured surface (:func:`depthrefine._fill.enclosed_holes`:
    an ink drawing on a mug, a dropout on a dark spot) is spanned by the
    smoothest surface through its rim, so the surface goes on; any other
    hole (beyond the sensor's view, a shadow beside a depth jump) takes the
    nearest valid depth, which never invents a value between two surfaces.
    """
    if valid.all():
        return depth.copy()
    return fill_invalid_nearest(fill_smooth(depth, enclosed_holes(depth)))


def estimate_noise(depth: np.ndarray, valid: np.ndarray) -> float:
    """Noise standard deviation of a depth map, in its units, from its finest diagonal Haar band.

    The band ``(a - b - c + d) / 2`` of each 2x2 block with four valid pixels
    has the noise's standard deviation and almost no signal on smooth
    surfaces. Its RMS is taken after leaving out values beyond 2.5 times the
    current estimate (five rounds), so depth edges do not count as noise,
    and corrected for that. The median absolute value (Donoho 1994) is not
    used because quantised maps make it jump between few values.

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
    if coef.size < NOISE_MIN_BLOCKS:
        return 0.0
    return _clipped_rms(coef, np.ones(coef.shape))


def estimate_guide_noise(guide: np.ndarray) -> float:
    """Noise standard deviation of an 8-bit color image, in levels (RMS over its channels).

    The estimate of :func:`estimate_noise` over the bands of all channels at
    once; the band of 8-bit values takes at most 1021 values, so it is taken
    from their histogram.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> noisy = np.clip(128 + rng.normal(0, 5, (200, 200, 3)), 0, 255).round().astype(np.uint8)
    >>> round(estimate_guide_noise(noisy))
    5
    """
    import cv2

    h, w = (guide.shape[0] // 2) * 2, (guide.shape[1] // 2) * 2
    if h == 0 or w == 0:
        return 0.0
    g = np.ascontiguousarray(guide[:h, :w], dtype=np.uint8)
    channels = g.shape[2] if g.ndim == 3 else 1
    counts = np.zeros(1021, np.int64)
    for top in range(0, h, 2 * GUIDE_NOISE_ROWS):   # a strip of rows at a time: little memory
        strip = g[top:top + 2 * GUIDE_NOISE_ROWS]
        pairs = strip.shape[0] // 2
        # a - b - c + d of each 2x2 block [[a, b], [c, d]] as (a - c) - (b - d): first the row pairs, whole rows
        # at a time, then the column pairs (NumPy's strided views of single pixels took four times as long)
        rows = cv2.subtract(strip[0::2].reshape(pairs, -1), strip[1::2].reshape(pairs, -1), dtype=cv2.CV_16S)
        columns = rows.reshape(-1, 2 * channels)
        band = cv2.subtract(columns[:, :channels], columns[:, channels:])
        band += 510
        counts += np.bincount(band.ravel(), minlength=1021)
    return _clipped_rms((np.arange(1021) - 510) * 0.5, counts.astype(np.float64))


def _clipped_rms(values: np.ndarray, counts: np.ndarray) -> float:
    """RMS of ``values`` (each counted ``counts`` times), values beyond ``NOISE_CLIP`` times the estimate left out."""
    squares = values * values
    sigma = math.sqrt(float(np.sum(counts * squares) / np.sum(counts)))
    for _ in range(NOISE_ROUNDS):
        kept = np.abs(values) <= NOISE_CLIP * sigma
        total = float(np.sum(counts[kept]))
        if total == 0:
            return 0.0
        sigma = math.sqrt(float(np.sum(counts[kept] * squares[kept])) / total) / NOISE_CLIPPED_RMS
    return sigma


def noise_levels(m: InputMeasures) -> float:
    """The input's noise in levels of its depth range from a band blind to smooth curvature.

    The band is the 5x5 product of fourth differences ``[1, -4, 6, -4, 1]``
    along rows and columns (unit noise gain), zero on any surface cubic in
    each direction, where :func:`estimate_noise`'s Haar band sees a curved
    surface's twist as noise; clipped RMS as there. It decides how far the
    fallback is denoised (step 5) and whether gbp-fast puts the input's
    residual back. Measured once per ``m`` (:attr:`InputMeasures.curvature_blind_noise`).
    """
    return m.curvature_blind_noise


def _curvature_blind_noise(m: InputMeasures) -> float:
    """:func:`noise_levels`, measured."""
    import cv2

    band = cv2.filter2D(m.filled.astype(np.float32), -1, FOURTH_ORDER, borderType=cv2.BORDER_REFLECT)[2:-2, 2:-2]
    inner = cv2.erode(m.valid.astype(np.uint8), np.ones((5, 5), np.uint8))[2:-2, 2:-2] > 0
    coef = band[inner].astype(np.float64)
    if coef.size < NOISE_MIN_BLOCKS:
        return 0.0
    return 255.0 * _clipped_rms(coef, np.ones(coef.shape)) / m.span


def noise_share(sigma_levels: float) -> float:
    """0 for a noise-free input, rising to 1 at ``FLAT_NOISE`` levels of noise."""
    return min(1.0, sigma_levels / FLAT_NOISE)


def footprint_share(depth: np.ndarray) -> float:
    """How far the input looks like footprint means (1) rather than point samples (0), from the input alone.

    Over every three consecutive valid pixels of a row or a column whose
    outer two differ by a large jump (more than 8 noise sigmas and 10 % of
    the depth range), the share ``m`` of middle pixels that lie between the
    outer two, off both by more than 4 noise sigmas and 5 % of the jump, is
    counted. A pixel that integrates its footprint (a ToF pixel; an area or
    antialiased reduction) straddles an edge in about half of such
    triplets; a point sample is on one side of it. The result ramps from 0
    at ``m = 0.02`` to 1 at ``0.08``; it is 1 with fewer than 20 such jumps.

    Examples
    --------
    >>> point, mean = np.array([[5, 5, 15, 15]] * 16, np.float32), np.array([[5, 5, 10, 15, 15]] * 16, np.float32)
    >>> footprint_share(point), footprint_share(mean)
    (0.0, 1.0)
    """
    d = as_depth(depth)
    valid = np.isfinite(d)
    if valid.sum() < 4:
        return 1.0
    filled = fill_invalid_nearest(d)
    return _footprint_share(d, filled, valid, estimate_noise(filled, valid), _span(filled, valid))


def _footprint_share(d: np.ndarray, filled: np.ndarray, valid: np.ndarray, sigma: float, span: float) -> float:
    if valid.sum() < 4:
        return 1.0
    jump = max(MIXED_SIGMAS * sigma, MIXED_SPAN * span)
    middles = 0
    jumps = 0
    for a, b, c in ((d[:, :-2], d[:, 1:-1], d[:, 2:]), (d[:-2], d[1:-1], d[2:])):
        with np.errstate(invalid="ignore"):
            ok = (np.abs(c - a) > jump) & np.isfinite(b)     # False where any of the three is NaN
        a, b, c = a[ok], b[ok], c[ok]
        # mixed: the middle pixel is off both sides, by more than the noise and 5 % of the jump
        apart = np.maximum(MIXED_APART_SIGMAS * sigma, MIXED_APART * np.abs(c - a))
        middles += int(np.count_nonzero((np.minimum(np.abs(b - a), np.abs(c - b)) > apart)
                                        & (np.sign(b - a) == np.sign(c - b))))
        jumps += int(a.size)
    if jumps < MIXED_MIN_JUMPS:
        return 1.0
    return float(np.clip((middles / jumps - MIXED_LOW) / (MIXED_HIGH - MIXED_LOW), 0.0, 1.0))


def near_jump(filled: np.ndarray, sigma: float, span: float) -> np.ndarray:
    """1 near a depth jump of the input, 0 on smooth surfaces, per input pixel.

    The jump is measured as the 4-neighbour Laplacian's deviation from its
    own 3x3 mean: a smooth surface's curvature changes slowly (a quadratic's
    is constant), so however curved it is this stays near zero, while at a
    jump the Laplacian flips sign from one side to the other. ``filled`` is
    the hole-filled input, ``sigma`` its noise and ``span`` its range; under
    3 pixels on a side nothing is measured and it is 0.
    """
    import cv2

    if min(filled.shape) < 3:
        return np.zeros(filled.shape, np.float32)
    laplacian = cv2.Laplacian(filled, cv2.CV_32F, ksize=1)
    # the reflected border turns a slope into a kink: take the border from the pixels inside
    laplacian[0], laplacian[-1] = laplacian[1], laplacian[-2]
    laplacian[:, 0], laplacian[:, -1] = laplacian[:, 1], laplacian[:, -2]
    # a curved surface's Laplacian is locally constant, a jump's is not
    curvature = np.abs(laplacian - cv2.blur(laplacian, (3, 3), borderType=cv2.BORDER_REFLECT))
    threshold = JUMP_NOISE * sigma + JUMP_LEVELS * span / 255.0 + 1e-6 * span
    jump = np.clip(curvature / threshold - 1.0, 0.0, 1.0).astype(np.float32)
    if JUMP_MARGIN > 0:
        jump = cv2.dilate(jump, np.ones((2 * JUMP_MARGIN + 1,) * 2, np.uint8))
    return cv2.boxFilter(jump, -1, (3, 3))


def block_mean_valid(depth: np.ndarray, factor: int) -> np.ndarray:
    """Mean of the valid (finite) pixels of each ``factor x factor`` block; NaN where none is.

    Rows and columns beyond a multiple of ``factor`` are dropped. No invalid
    pixel is averaged in.

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
