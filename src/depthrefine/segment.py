"""Color clustering of the thesis (section 4.3, spec step 5).

Median filter on R, G and B; RGB -> CIE L*a*b*; L* unified to the mean of its
black / color / white class; deterministic k-means on (w L*, a*, b*).
All functions are pure: arrays in, new arrays out.
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage

from ._validate import as_rgb_float, check_positive_int

__all__ = ["median_rgb", "rgb_to_lab", "unify_lightness", "kmeans", "initial_means"]


def median_rgb(rgb: np.ndarray, size: int = 7) -> np.ndarray:
    """Median filter each of R, G and B separately (thesis 4.3.1).

    Parameters
    ----------
    rgb : (M, N, 3) uint8, uint16 or float ndarray
        Color image.
    size : int
        Odd side of the square window (thesis: 7). Borders replicate the
        edge pixel.

    Returns
    -------
    (M, N, 3) ndarray
        Filtered image, same dtype.

    Examples
    --------
    >>> img = np.zeros((9, 9, 3), np.uint8); img[4, 4] = 255   # one salt pixel
    >>> int(median_rgb(img, 7).max())
    0
    """
    size = check_positive_int(size, "median_size")
    if size % 2 == 0:
        raise ValueError(f"median_size must be odd; got {size}.")
    if size == 1:
        return rgb.copy()
    if rgb.dtype == np.uint8 or (size <= 5 and rgb.dtype in (np.uint16, np.float32)):
        return cv2.medianBlur(np.ascontiguousarray(rgb), size)
    out = np.empty_like(rgb)
    for ch in range(rgb.shape[2]):
        ndimage.median_filter(rgb[:, :, ch], size=size, mode="nearest", output=out[:, :, ch])
    return out


def rgb_to_lab(rgb: np.ndarray) -> np.ndarray:
    """sRGB (uint8, uint16 or float in [0, 1]) to CIE L*a*b* (D65), float32.

    L* is in [0, 100]; a* and b* roughly in [-128, 127] (thesis 4.3.2).

    Examples
    --------
    >>> lab = rgb_to_lab(np.array([[[255, 255, 255], [0, 0, 0]]], np.uint8))
    >>> np.round(lab[0, :, 0]).tolist()
    [100.0, 0.0]
    """
    return cv2.cvtColor(as_rgb_float(rgb), cv2.COLOR_RGB2Lab)


def unify_lightness(
    lab: np.ndarray,
    *,
    black_bound: float = 0.20,
    white_bound: float = 0.80,
    max_lightness: float = 100.0,
) -> np.ndarray:
    """Replace L* by the mean L* of its class: black, color or white (Fig. 32).

    L* <= ``black_bound * max_lightness`` is black, L* >=
    ``white_bound * max_lightness`` is white, the rest is color. The means are
    taken over the pixels of ``lab`` (one patch, in the thesis).

    Returns
    -------
    (..., 3) float32 ndarray
        A new array; a* and b* unchanged.

    Examples
    --------
    >>> lab = np.array([[[10, 0, 0], [30, 5, 5], [50, 5, 5], [90, 0, 0]]], np.float32)
    >>> unify_lightness(lab)[0, :, 0].tolist()
    [10.0, 40.0, 40.0, 90.0]
    """
    out = np.array(lab, dtype=np.float32, copy=True)
    lightness = out[..., 0]
    black = lightness <= black_bound * max_lightness
    white = lightness >= white_bound * max_lightness
    color = ~(black | white)
    for cls in (black, white, color):
        if cls.any():
            lightness[cls] = np.float32(lightness[cls].mean(dtype=np.float64))
    return out


def initial_means(features: np.ndarray, n_clusters: int) -> np.ndarray:
    """Deterministic initial means: evenly spaced on the bounding-box diagonal.

    Mean ``j`` of ``k`` sits at ``lo + (j + 0.5) / k * (hi - lo)``, where
    ``lo`` and ``hi`` are the per-feature min and max (spec decision 5.4).

    Examples
    --------
    >>> initial_means(np.array([[0., 0.], [4., 8.]]), 2).tolist()
    [[1.0, 2.0], [3.0, 6.0]]
    """
    lo = features.min(axis=0).astype(np.float64)
    hi = features.max(axis=0).astype(np.float64)
    steps = (np.arange(n_clusters, dtype=np.float64) + 0.5) / n_clusters
    return lo[None, :] + steps[:, None] * (hi - lo)[None, :]


def kmeans(features: np.ndarray, n_clusters: int = 4, iterations: int = 10) -> tuple[np.ndarray, np.ndarray]:
    """Deterministic k-means (thesis 4.3.3, spec step 5.4).

    Starts from :func:`initial_means`, then ``iterations`` times assigns each
    point to its nearest mean (ties go to the lower index) and moves each mean
    to its points' average. A cluster left with no point is dropped. Labels
    are the final assignment, renumbered ``0 .. k'-1`` in the order of the
    surviving means.

    Parameters
    ----------
    features : (N, D) float ndarray
    n_clusters : int
        k (thesis: 4).
    iterations : int
        Number of update rounds (spec decision: 10); 0 assigns to the
        initial means.

    Returns
    -------
    labels : (N,) int32 ndarray
        Values in ``[0, k')``, ``k' <= k``.
    means : (k', D) float64 ndarray

    Examples
    --------
    >>> pts = np.array([[0., 0.], [0., 1.], [10., 10.], [10., 11.]])
    >>> labels, means = kmeans(pts, 2)
    >>> labels.tolist(), means.tolist()
    ([0, 0, 1, 1], [[0.0, 0.5], [10.0, 10.5]])
    """
    n_clusters = check_positive_int(n_clusters, "n_clusters")
    if isinstance(iterations, bool) or not isinstance(iterations, (int, np.integer)) or iterations < 0:
        raise ValueError(f"kmeans iterations must be an integer >= 0; got {iterations!r}.")
    x = np.asarray(features, dtype=np.float32)
    if x.ndim != 2 or x.shape[0] == 0:
        raise ValueError(f"features must be a non-empty (N, D) array; got shape {x.shape}.")
    means = initial_means(x, n_clusters)
    labels = _assign(x, means)
    for _ in range(iterations):
        counts = np.bincount(labels, minlength=len(means))
        keep = counts > 0
        sums = np.stack(
            [np.bincount(labels, weights=x[:, d], minlength=len(means)) for d in range(x.shape[1])], axis=1
        )
        means = sums[keep] / counts[keep, None]
        labels = _assign(x, means)
    used = np.bincount(labels, minlength=len(means)) > 0
    if not used.all():
        remap = np.cumsum(used) - 1
        labels = remap[labels].astype(np.int32)
        means = means[used]
    return labels.astype(np.int32, copy=False), means


def _assign(x: np.ndarray, means: np.ndarray) -> np.ndarray:
    """Index of the nearest mean for each row of ``x`` (first index on ties)."""
    m = means.astype(np.float32)
    best = np.zeros(x.shape[0], dtype=np.int32)
    best_d = _sqdist(x, m[0])
    for j in range(1, len(m)):
        d = _sqdist(x, m[j])
        closer = d < best_d
        best[closer] = j
        best_d = np.where(closer, d, best_d)
    return best


def _sqdist(x: np.ndarray, mean: np.ndarray) -> np.ndarray:
    diff = x - mean[None, :]
    return np.einsum("ij,ij->i", diff, diff)
