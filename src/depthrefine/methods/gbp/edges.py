"""Step 6 of gbp: put each large depth jump on the color edge, and each mixed pixel on one surface.

A real depth camera does not place a depth jump where the color camera sees
the object's outline: a direct-ToF pixel that sees a near and a far surface
reports the nearer (the near surface spills over the far one), an
indirect-ToF pixel reports a mixture (a "flying" value between the two), and
a calibration error of a fraction of a depth pixel shifts the whole outline.
Within the input's uncertainty, a band of :data:`BAND_RADIUS` depth pixels
on each side of a large jump, every color pixel takes the depth of the
surface it is joined to by the cheapest path through the color image (the
geodesic nearest pixel outside the band, the cost of a step being its color
difference): the boundary between the two surfaces falls on the strongest
color edge between them. Where the two sides of the band do not differ in
color (the guide shows no edge), the result is left as it is.
"""

from __future__ import annotations

import math

import numpy as np

from .measure import InputMeasures
from .solve import resize

__all__ = ["jump_band", "snap_edges"]

#: A jump to snap: the range of the input's 5x5 neighbourhood exceeds this many noise sigmas ...
SNAP_SIGMAS = 8.0
#: ... and this share of the depth range (and the input shows a discontinuity there, ``InputMeasures.jump``).
SNAP_SPAN = 0.08
#: Half-width of the band around a jump, depth pixels: the input's uncertainty about where the jump is.
BAND_RADIUS = 2
#: A step of the geodesic path costs its color difference (Euclidean, 8-bit levels) plus this many levels.
STEP_LEVELS = 2.0
#: Smoothing of the snapped band along each surface, per squared band width.
SNAP_SMOOTH = 1.0
#: The color image is blurred by this sigma, color pixels, before the path costs (fine texture makes no path).
GUIDE_BLUR = 1.0
#: The two sides of a band must differ in mean color by this many levels (plus 3 guide noise sigmas) for the
#: guide to be followed; at twice that it is followed fully.
CONTRAST_LEVELS = 12.0


def jump_band(m: InputMeasures) -> np.ndarray:
    """The input pixels within :data:`BAND_RADIUS` of a large depth jump, (h, w) bool."""
    import cv2

    size = 2 * BAND_RADIUS + 1
    kernel = np.ones((size, size), np.uint8)
    spread = cv2.dilate(m.filled, kernel) - cv2.erode(m.filled, kernel)
    threshold = max(SNAP_SIGMAS * m.sigma, SNAP_SPAN * m.span)
    return (spread > threshold) & (m.jump >= 0.5)


def snap_edges(result: np.ndarray, m: InputMeasures, guide: np.ndarray, scale: float) -> np.ndarray:
    """Give every color pixel in the band around a large jump the depth of the surface it is joined to.

    ``guide`` is the (H, W, 3) uint8 guide after step 2's bilateral filter
    (``Solver.guide``), ``scale`` the enlargement factor. ``result`` (H, W)
    float32 is updated in place and returned.
    """
    import cv2

    from .. import _wls
    from ..._geodesic import color_step_costs, nearest_seed

    band_lr = m.large_jumps
    if not band_lr.any():
        return result
    shape = result.shape
    band = resize(band_lr.astype(np.uint8), shape, cv2.INTER_NEAREST) > 0
    guide = cv2.GaussianBlur(guide, (0, 0), GUIDE_BLUR).astype(np.float32)
    source = nearest_seed(*color_step_costs(guide, blur=0, step_levels=STEP_LEVELS), band)

    # which surface each band pixel is joined to: the depth of its geodesic nearest pixel outside the band, then
    # smoothed along that surface only (no weight across the new boundary), so the copies leave no streaks
    joined = np.where(source >= 0, result.ravel()[np.maximum(source, 0)].reshape(shape), result).astype(np.float32)
    kernel = np.ones((4 * BAND_RADIUS + 1,) * 2, np.uint8)     # the band and the seeds beside it
    low = resize(cv2.erode(m.filled, kernel), shape, cv2.INTER_NEAREST)
    high = resize(cv2.dilate(m.filled, kernel), shape, cv2.INTER_NEAREST)
    near = joined < 0.5 * (low + high)
    weight_x = (near[:, 1:] == near[:, :-1]).astype(np.float32)
    weight_y = (near[1:] == near[:-1]).astype(np.float32)
    weight_x = np.pad(weight_x, ((0, 0), (0, 1)))
    weight_y = np.pad(weight_y, ((0, 1), (0, 0)))
    snapped = _wls.smooth(joined, weight_x, weight_y, SNAP_SMOOTH * (BAND_RADIUS * scale) ** 2)
    seeds = ~band
    near_seed = seeds & near
    far_seed = seeds & ~near

    # follow the guide only where the two sides differ in color: mean color of the near and far seeds around
    size = 2 * (2 * BAND_RADIUS + 1) * int(math.ceil(scale)) + 1     # reaches past the band from inside it
    near, far = near_seed.astype(np.float32), far_seed.astype(np.float32)
    box = (size, size)
    n_near = cv2.boxFilter(near, -1, box, normalize=False)
    n_far = cv2.boxFilter(far, -1, box, normalize=False)
    contrast = np.zeros(shape, np.float32)
    for channel in range(guide.shape[2]):
        c = guide[:, :, channel]
        mean_near = cv2.boxFilter(c * near, -1, box, normalize=False) / np.maximum(n_near, 1)
        mean_far = cv2.boxFilter(c * far, -1, box, normalize=False) / np.maximum(n_far, 1)
        contrast += np.square(mean_near - mean_far)
    contrast = np.sqrt(contrast)
    floor = CONTRAST_LEVELS + 3.0 * m.guide_noise
    follow = np.clip(contrast / floor - 1.0, 0.0, 1.0) * ((n_near > 0) & (n_far > 0))
    follow *= band
    # result <- result + follow * (snapped - result)
    snapped -= result
    snapped *= follow
    result += snapped
    return result

