"""Color clustering of the thesis (section 4.3, spec step 5).

Median filter on R, G and B; RGB -> CIE L*a*b*; L* unified to the mean of its
black / color / white class; deterministic k-means on (w L*, a*, b*).
All functions are pure: arrays in, new arrays out.
"""

from __future__ import annotations

import numpy as np

from ..._lazy import cv2, ndimage
from ..._validate import as_rgb_float, check_int
from .median import median_filter

__all__ = [
    "median_rgb",
    "rgb_to_lab",
    "lightness_classes",
    "unify_lightness",
    "kmeans",
    "initial_means",
    "cluster_colors",
]


#: Largest window filtered with the min/max network; beyond it OpenCV's
#: histogram median (constant time per pixel) is faster.
NETWORK_MAX_SIZE = 9


def median_rgb(rgb: np.ndarray, size: int = 7) -> np.ndarray:
    """Median filter each of R, G and B separately (thesis 4.3.1).

    Parameters
    ----------
    rgb : (M, N, 3) uint8, uint16 or float ndarray
        Color image.
    size : int
        Odd side of the square window (thesis: 7). Borders replicate the
        edge pixel. Integer images up to :data:`NETWORK_MAX_SIZE` use the
        exact min/max network of :mod:`.median` (the same output as
        ``cv2.medianBlur``, in about 15 % of its time at 7x7 on 1232x1008
        on a loaded 2-core machine; ``benchmarks/bench_speed.py`` prints the
        median step).

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
    size = check_int("median_size", size, minimum=1)
    if size % 2 == 0:
        raise ValueError(f"median_size must be odd; got {size}.")
    if size == 1:
        return rgb.copy()
    if rgb.dtype in (np.uint8, np.uint16) and size <= NETWORK_MAX_SIZE:
        return median_filter(rgb, size)
    if rgb.dtype == np.uint8 or (size <= 5 and rgb.dtype in (np.uint16, np.float32)):
        return cv2.medianBlur(np.ascontiguousarray(rgb), size)
    out = np.empty_like(rgb)
    for ch in range(rgb.shape[2]):
        ndimage.median_filter(rgb[:, :, ch], size=size, mode="nearest", output=out[:, :, ch])
    return out


def lightness_classes(lightness: np.ndarray, *, black_bound: float = 0.20, white_bound: float = 0.80,
                      max_lightness: float = 100.0) -> np.ndarray:
    """Class of each pixel from its L*: 0 black, 1 color, 2 white (thesis Fig. 32).

    Black: L* <= ``black_bound * max_lightness``; white: L* >=
    ``white_bound * max_lightness``; color otherwise.

    Examples
    --------
    >>> lightness_classes(np.array([0.0, 20.0, 20.5, 79.9, 80.0, 100.0])).tolist()
    [0, 0, 1, 1, 2, 2]
    """
    black = lightness <= black_bound * max_lightness
    white = lightness >= white_bound * max_lightness
    return (1 - black.astype(np.uint8) + white.astype(np.uint8)).astype(np.uint8)


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


def kmeans(
    features: np.ndarray, n_clusters: int = 4, iterations: int = 10, *, weights: np.ndarray | None = None,
    init_means: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
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
    weights : (N,) ndarray, optional
        Multiplicity of each point: k-means over a histogram of distinct
        features gives the same clusters as over every pixel.
    init_means : (k0, D) ndarray, optional
        A warm start, e.g. the previous video frame's means, so that pixels
        keep their clusters (and labels their numbers) from frame to frame.
        k-means first runs from :func:`initial_means` as usual; if that finds
        ``k0`` clusters, it runs again from ``init_means`` and returns that
        result; otherwise (a color appeared or vanished) the first result
        stands.

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
    n_clusters = check_int("n_clusters", n_clusters, minimum=1)
    if isinstance(iterations, bool) or not isinstance(iterations, (int, np.integer)) or iterations < 0:
        raise ValueError(f"kmeans iterations must be an integer >= 0; got {iterations!r}.")
    x = np.asarray(features, dtype=np.float32)
    if x.ndim != 2 or x.shape[0] == 0:
        raise ValueError(f"features must be a non-empty (N, D) array; got shape {x.shape}.")
    if not np.isfinite(x).all():
        raise ValueError("features must be finite (no NaN or inf).")
    w = np.ones(x.shape[0]) if weights is None else np.asarray(weights, dtype=np.float64)
    if w.shape != (x.shape[0],) or not (np.isfinite(w).all() and (w > 0).all()):
        raise ValueError(f"weights must be {x.shape[0]} finite values > 0, one per point; got shape {w.shape}"
                         + ("" if w.shape != (x.shape[0],) else f", min {w.min()}") + ".")
    labels, means = _lloyd(x, w, initial_means(x, n_clusters), iterations)
    if init_means is not None:
        warm = np.asarray(init_means, dtype=np.float64)
        if warm.ndim != 2 or warm.shape[1] != x.shape[1] or not 1 <= len(warm) <= n_clusters \
                or not np.isfinite(warm).all():
            raise ValueError(f"init_means must be a finite (k, {x.shape[1]}) array with 1 <= k <= n_clusters "
                             f"({n_clusters}); got shape {warm.shape}.")
        if len(warm) == len(means):
            labels, means = _lloyd(x, w, warm, iterations)
    return labels, means


def _kernels():
    """The thesis method's kernels: the C ones when built (:mod:`depthrefine._native`), else numba's (:mod:`._jit`)."""
    from ..._native import kernels

    return kernels(__package__ + "._jit")


def _lloyd(x: np.ndarray, w: np.ndarray, means: np.ndarray, iterations: int) -> tuple[np.ndarray, np.ndarray]:
    """``iterations`` rounds of assignment and update from ``means``; empty clusters dropped, labels renumbered."""
    return _kernels().lloyd(np.ascontiguousarray(x, dtype=np.float32), np.ascontiguousarray(w, dtype=np.float64),
                            np.ascontiguousarray(means, dtype=np.float64), iterations)


#: k-means runs over the histogram of distinct features, with a* and b*
#: binned at this step (L*a*b* units); every pixel of a bin takes its bin's
#: center, at most half a step from its exact value (a just-noticeable color
#: difference is about 2.3 units). 1.0 measured against 0.5 on the Art scene:
#: RMSE within 0.25 at x4/x8/x16, a third of the bins, 10-25 % less time.
AB_STEP = 1.0


def cluster_colors(
    lab_patch: np.ndarray,
    *,
    n_clusters: int = 4,
    iterations: int = 10,
    unify: bool = True,
    black_bound: float = 0.20,
    white_bound: float = 0.80,
    max_lightness: float = 100.0,
    lightness_weight: float = 1.0,
    return_features: bool = False,
    init_means: np.ndarray | None = None,
) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """Cluster one patch's colors (thesis 4.3.2-4.3.3) from its L*a*b* values.

    L* is unified to the mean L* of its black / color / white class (if
    ``unify``; the means are the patch's) and weighted by
    ``lightness_weight``; then deterministic k-means (:func:`kmeans`) runs on
    (w L*, a*, b*). For speed it runs over the histogram of distinct features,
    weighted by their pixel counts, which gives the clusters of k-means over
    every pixel of the binned features: a* and b* are binned at
    :data:`AB_STEP` units (L* too when it is not unified).

    Parameters
    ----------
    lab_patch : (M, N, 3) float ndarray
        CIE L*a*b* of the patch (:func:`rgb_to_lab`).
    init_means : (k0, 3) ndarray, optional
        Warm start of the k-means (:func:`kmeans`), in (w L*, a*, b*).

    Returns
    -------
    labels : (M, N) int16 ndarray
        Cluster of each pixel, ``0 .. k'-1``.
    features : (M, N, 3) float32 ndarray
        Only with ``return_features``: the L*a*b* of each pixel with L*
        unified (not weighted).

    Examples
    --------
    >>> rgb = np.array([[[250, 0, 0], [240, 5, 5], [0, 0, 250], [5, 5, 240]]], np.uint8)
    >>> cluster_colors(rgb_to_lab(rgb), n_clusters=2).tolist()
    [[1, 1, 0, 0]]
    """
    kernels = _kernels()
    lab_patch = np.ascontiguousarray(lab_patch)  # one compiled signature per dtype
    shape = lab_patch.shape[:2]
    # Bin a* and b* (and L* when it is not unified); codes are local to the
    # patch's range so that the histogram stays small. The thresholds compare
    # in the dtype NumPy would use for ``L* <= bound``.
    bounds = [np.result_type(lab_patch.dtype, v).type(v) for v in (black_bound * max_lightness,
                                                                   white_bound * max_lightness)]
    qa, qb, first = (np.empty(shape, np.int32) for _ in range(3))
    a0, a1, b0, b1, f0, f1, n_cls, sum_l = kernels.quantize_lab(
        lab_patch, np.float32(1.0 / AB_STEP), np.float32(0.5), bool(unify), *bounds, qa, qb, first)
    na, nb = a1 - a0 + 1, b1 - b0 + 1
    if unify:
        class_l = np.divide(sum_l, n_cls, out=np.zeros(3), where=n_cls > 0)
        f0, n_first = 0, 3
        lightness_of = lambda index: class_l[index]  # noqa: E731
    else:
        n_first = f1 - f0 + 1
        lightness_of = lambda index: (index + f0) * AB_STEP  # noqa: E731
    space = n_first * na * nb
    dense = space <= 4 * qa.size
    code = np.empty(shape, np.int32)
    counts = np.zeros(space if dense else 0, np.intp)
    kernels.feature_codes(qa, qb, first, a0, na, b0, nb, f0, code, counts)
    if dense:
        bins = np.flatnonzero(counts)
        weights = counts[bins]
        inverse = None
    else:  # a sparse histogram: sort instead
        bins, inverse, weights = np.unique(code.ravel(), return_inverse=True, return_counts=True)
    feats = np.stack([
        lightness_of(bins // (na * nb)) * lightness_weight,
        ((bins // nb) % na + a0) * AB_STEP,
        (bins % nb + b0) * AB_STEP,
    ], axis=1).astype(np.float32)
    bin_labels, _ = kmeans(feats, n_clusters, iterations, weights=weights, init_means=init_means)
    if inverse is None:
        lut = np.empty(space, dtype=np.int16)
        lut[bins] = bin_labels
        labels = np.empty(shape, dtype=np.int16)
        kernels.lookup(lut, code, labels)
    else:
        labels = bin_labels.astype(np.int16)[inverse].reshape(code.shape)
    if not return_features:
        return labels
    features = np.array(lab_patch, dtype=np.float32, copy=True)
    if unify:
        features[..., 0] = class_l[first]
    return labels, features
