"""Does a depth map line up with its color image? Silhouette edges of the depth against edges of the color.

A real capture has no ground truth, but a registered depth map must put an
object's outline where the color image shows it. :func:`edge_overlap`
takes the silhouette of the near objects in the depth map (near pixels next
to far ones) and measures how far each silhouette pixel lies from the
nearest Canny edge of the color image.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import check_depth, check_number, check_rgb

__all__ = ["EdgeOverlap", "depth_silhouette", "color_edges", "edge_overlap"]


@dataclass(frozen=True)
class EdgeOverlap:
    """How well depth silhouettes meet color edges.

    Attributes
    ----------
    fraction : float
        Share of silhouette pixels within ``tolerance`` pixels of a color edge (0..1).
    median_px : float
        Median distance from a silhouette pixel to the nearest color edge, pixels.
    pixels : int
        Number of silhouette pixels measured.
    tolerance : float
        The tolerance of ``fraction``, pixels.
    """

    fraction: float
    median_px: float
    pixels: int
    tolerance: float


def depth_silhouette(depth: np.ndarray, *, near: float, far: float, reach: int = 8) -> np.ndarray:
    """The outline of the near objects: pixels nearer than ``near`` with a pixel farther than ``far`` close by.

    Holes inside the near region (unmeasured pixels, NaN or 0) are filled
    first, so their borders do not count; only outline pixels with a far
    pixel within ``reach`` pixels count (an outline against unmeasured
    pixels says nothing about the alignment).

    Examples
    --------
    >>> d = np.full((6, 8), 2000.0); d[2:5, 2:5] = 300
    >>> depth_silhouette(d, near=600, far=1000, reach=1).astype(int)[1:6, 1:6].tolist()
    [[0, 0, 0, 0, 0], [0, 1, 1, 1, 0], [0, 1, 0, 1, 0], [0, 1, 1, 1, 0], [0, 0, 0, 0, 0]]
    """
    from scipy import ndimage as ndi

    z = check_depth(depth, "depth").astype(np.float64)
    near = check_number("near", near, positive=True)
    far = check_number("far", far, positive=True)
    valid = np.isfinite(z) & (z > 0)
    close = ndi.binary_fill_holes(valid & (z < near))
    outline = close & ~ndi.binary_erosion(close, border_value=1)
    far_zone = ndi.binary_dilation(valid & (z > far), np.ones((2 * reach + 1,) * 2, bool))
    return outline & far_zone


def color_edges(rgb: np.ndarray) -> np.ndarray:
    """Canny edges of the color image (gray, Gaussian blur sigma 1.5, thresholds 30 / 90)."""
    import cv2

    rgb = check_rgb(rgb, "rgb")
    gray = cv2.cvtColor(np.ascontiguousarray(rgb[..., :3]).astype(np.uint8), cv2.COLOR_RGB2GRAY)
    return cv2.Canny(cv2.GaussianBlur(gray, (5, 5), 1.5), 30, 90) > 0


def edge_overlap(depth: np.ndarray, rgb: np.ndarray, *, near: float, far: float,
                 tolerance: float = 2.0) -> EdgeOverlap:
    """Measure how well the depth's near-object silhouette meets the color image's edges.

    Parameters
    ----------
    depth : (H, W) ndarray
        Depth on the color image's grid, any units that grow with distance; 0 / NaN = unmeasured.
    rgb : (H, W, 3) uint8 ndarray
    near, far : float
        Depths (in ``depth``'s units) below which a pixel is near and above which it is far.
    tolerance : float
        Pixels; see :attr:`EdgeOverlap.fraction`.

    Returns
    -------
    EdgeOverlap
        ``fraction`` and ``median_px`` are NaN when there is no silhouette.
    """
    import cv2

    if np.shape(depth)[:2] != np.shape(rgb)[:2]:
        raise ValueError(f"depth {np.shape(depth)[:2]} and rgb {np.shape(rgb)[:2]} must have one grid.")
    tolerance = check_number("tolerance", tolerance, nonnegative=True)
    silhouette = depth_silhouette(depth, near=near, far=far)
    edges = color_edges(rgb)
    distance = cv2.distanceTransform((~edges).astype(np.uint8), cv2.DIST_L2, 5)[silhouette]
    if distance.size == 0:
        return EdgeOverlap(float("nan"), float("nan"), 0, tolerance)
    return EdgeOverlap(float((distance <= tolerance).mean()), float(np.median(distance)), int(distance.size),
                       tolerance)
