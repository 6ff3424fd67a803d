"""Color-guided peers from OpenCV-contrib ``ximgproc``, as registry methods.

These are the filters a practitioner would pick instead of the thesis
method. Each one enlarges the depth map bilinearly to the color image's grid
(:func:`depthrefine.methods.baselines.upsample`, which first fills invalid pixels
from their nearest valid neighbour, so no invalid pixel is averaged in) and
then filters it with the color image as guide:

================  ==============================================  ===================
method            OpenCV function                                 reference
================  ==============================================  ===================
``jbf``           ``cv2.ximgproc.jointBilateralFilter``           Kopf et al. 2007
``guided``        ``cv2.ximgproc.guidedFilter``                   He et al. 2013
``fgs``           ``cv2.ximgproc.fastGlobalSmootherFilter``       Min et al. 2014
``wmf``           ``cv2.ximgproc.weightedMedianFilter``           Zhang et al. 2014
================  ==============================================  ===================

Lengths are given in **low-resolution pixels** (``*_lr`` fields) and
multiplied by the scale factor ``s`` (color / depth size), so one parameter
set fits every factor. The fast global smoother's ``lambda`` is a squared
length, so it is ``lambda_lr * s**2``. Color parameters are in units of the
guide as the filter sees it (stated per field). The defaults are the values
tuned by ``benchmarks/tune_peers.py`` on the benchmark's tuning scenes
(Park's noisy Dolls and Laundry and four noise-free scenes of the
30-image Middlebury set, at x4, x8 and x16; grid and results in
``docs/bench.md``).

The fast bilateral solver (``fbs``, ``cv2.ximgproc.fastBilateralSolverFilter``,
Barron and Poole 2016) is registered only when the installed OpenCV has a
working one (:func:`fast_bilateral_solver_available`): the function exists in
the contrib wheels, but OpenCV builds its body only with Eigen, and the PyPI
wheels have no Eigen, so there the call raises "needs to be compiled with
EIGEN" (:func:`fast_bilateral_solver_status` says which case holds).

References
----------
J. Kopf, M. F. Cohen, D. Lischinski, M. Uyttendaele, "Joint bilateral
upsampling", SIGGRAPH 2007. K. He, J. Sun, X. Tang, "Guided image
filtering", TPAMI 2013. D. Min, S. Choi, J. Lu, B. Ham, K. Sohn, M. N. Do,
"Fast global image smoothing based on weighted least squares", TIP 2014.
Q. Zhang, L. Xu, J. Jia, "100+ times faster weighted median filter", CVPR 2014.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from .._lazy import cv2
from .._validate import as_rgb_float, check_number, check_rgb, guide_uint8
from .baselines import upsample

__all__ = [
    "JointBilateralParams",
    "GuidedParams",
    "FastGlobalSmootherParams",
    "WeightedMedianParams",
    "upsample_jbf",
    "upsample_guided",
    "upsample_fgs",
    "upsample_wmf",
    "FastBilateralSolverParams",
    "upsample_fbs",
    "fast_bilateral_solver_available",
    "fast_bilateral_solver_status",
]

Progress = Callable[[int, int], None]


def _check_positive(params: object, *names: str) -> None:
    for name in names:
        check_number(name, getattr(params, name), positive=True)


@dataclass(frozen=True)
class JointBilateralParams:
    """Joint bilateral filter parameters.

    Attributes
    ----------
    sigma_space_lr : float
        Spatial standard deviation, low-resolution pixels.
    sigma_color : float
        Color standard deviation, guide in [0, 1] (RGB).
    max_diameter : int
        Largest filter window, color pixels (odd); caps the cost at large
        factors (the window is ``2 * ceil(1.5 * sigma) + 1`` otherwise).
    """

    sigma_space_lr: float = 2.0
    sigma_color: float = 0.05
    max_diameter: int = 31

    def __post_init__(self) -> None:
        _check_positive(self, "sigma_space_lr", "sigma_color")
        if isinstance(self.max_diameter, bool) or not isinstance(self.max_diameter, int) or self.max_diameter < 3:
            raise ValueError(f"max_diameter must be an integer >= 3 pixels; got {self.max_diameter!r}.")


@dataclass(frozen=True)
class GuidedParams:
    """Guided filter parameters.

    Attributes
    ----------
    radius_lr : float
        Window radius, low-resolution pixels (at least one color pixel).
    eps : float
        Regularisation, in squared guide units (guide in [0, 1] RGB).
    """

    radius_lr: float = 0.5
    eps: float = 1e-2

    def __post_init__(self) -> None:
        _check_positive(self, "radius_lr", "eps")


@dataclass(frozen=True)
class FastGlobalSmootherParams:
    """Fast global smoother (weighted least squares) parameters.

    Attributes
    ----------
    lambda_lr : float
        Smoothness weight per squared low-resolution pixel (``lambda = lambda_lr * s**2``).
    sigma_color : float
        Color sensitivity, guide in 8-bit levels (0..255).
    lambda_attenuation : float
        OpenCV's attenuation of lambda between iterations.
    num_iter : int
        Iterations (OpenCV default 3).
    """

    lambda_lr: float = 4.0
    sigma_color: float = 2.0
    lambda_attenuation: float = 0.25
    num_iter: int = 3

    def __post_init__(self) -> None:
        _check_positive(self, "lambda_lr", "sigma_color", "lambda_attenuation")
        if isinstance(self.num_iter, bool) or not isinstance(self.num_iter, int) or self.num_iter < 1:
            raise ValueError(f"num_iter must be an integer >= 1; got {self.num_iter!r}.")


@dataclass(frozen=True)
class WeightedMedianParams:
    """Weighted median filter parameters.

    Attributes
    ----------
    radius_lr : float
        Window radius, low-resolution pixels (at least one color pixel).
    sigma : float
        Color sensitivity of the exponential weight, guide in 8-bit levels.
    """

    radius_lr: float = 1.0
    sigma: float = 10.0

    def __post_init__(self) -> None:
        _check_positive(self, "radius_lr", "sigma")


def _prepare(depth_lr: np.ndarray, rgb_hr: np.ndarray, params, params_type):
    """Checked params, color, the bilinear start and the scale factor ``s``."""
    params = params_type() if params is None else params
    if not isinstance(params, params_type):
        raise TypeError(f"params must be {params_type.__name__} or None; got {type(params).__name__}.")
    rgb = check_rgb(rgb_hr)
    start = upsample(depth_lr, rgb.shape[:2], cv2.INTER_LINEAR)
    h, w = np.shape(depth_lr)[:2]
    s = 0.5 * (rgb.shape[0] / h + rgb.shape[1] / w)
    return params, rgb, start, s


def _done(progress: Progress | None) -> None:
    if progress is not None:
        progress(1, 1)


def upsample_jbf(depth_lr: np.ndarray, rgb_hr: np.ndarray, *, params: JointBilateralParams | None = None,
                 progress: Progress | None = None) -> np.ndarray:
    """Bilinear enlargement, then a joint bilateral filter guided by the color image.

    Parameters
    ----------
    depth_lr : (h, w) ndarray
        Low-resolution depth, any units; 0/NaN/inf/negative = no measurement.
    rgb_hr : (H, W, 3) ndarray
        Registered color image (RGB).
    params : JointBilateralParams, optional
    progress : callable, optional
        ``progress(done, total)``, called once at the end.

    Returns
    -------
    (H, W) float32 ndarray, units of ``depth_lr``.

    Examples
    --------
    >>> out = upsample_jbf(np.full((4, 4), 7.0, np.float32), np.zeros((16, 16, 3), np.uint8))
    >>> out.shape, round(float(out.min()), 4), round(float(out.max()), 4)
    ((16, 16), 7.0, 7.0)
    """
    params, rgb, start, s = _prepare(depth_lr, rgb_hr, params, JointBilateralParams)
    sigma_space = params.sigma_space_lr * s
    diameter = min(2 * math.ceil(1.5 * sigma_space) + 1, params.max_diameter | 1)
    guide = as_rgb_float(rgb)
    out = cv2.ximgproc.jointBilateralFilter(guide, start, diameter, params.sigma_color, sigma_space)
    _done(progress)
    return out.astype(np.float32, copy=False)


def upsample_guided(depth_lr: np.ndarray, rgb_hr: np.ndarray, *, params: GuidedParams | None = None,
                    progress: Progress | None = None) -> np.ndarray:
    """Bilinear enlargement, then a guided filter with the color image as guide.

    Parameters and returns as :func:`upsample_jbf` (params: :class:`GuidedParams`).

    Examples
    --------
    >>> out = upsample_guided(np.full((4, 4), 7.0, np.float32), np.zeros((16, 16, 3), np.uint8))
    >>> out.shape, round(float(out.mean()), 4)
    ((16, 16), 7.0)
    """
    params, rgb, start, s = _prepare(depth_lr, rgb_hr, params, GuidedParams)
    radius = max(1, int(round(params.radius_lr * s)))
    out = cv2.ximgproc.guidedFilter(as_rgb_float(rgb), start, radius, params.eps)
    _done(progress)
    return out.astype(np.float32, copy=False)


def upsample_fgs(depth_lr: np.ndarray, rgb_hr: np.ndarray, *, params: FastGlobalSmootherParams | None = None,
                 progress: Progress | None = None) -> np.ndarray:
    """Bilinear enlargement, then the fast global smoother guided by the color image.

    Parameters and returns as :func:`upsample_jbf` (params: :class:`FastGlobalSmootherParams`).

    Examples
    --------
    >>> out = upsample_fgs(np.full((4, 4), 7.0, np.float32), np.zeros((16, 16, 3), np.uint8))
    >>> out.shape, round(float(out.mean()), 3)
    ((16, 16), 7.0)
    """
    params, rgb, start, s = _prepare(depth_lr, rgb_hr, params, FastGlobalSmootherParams)
    out = cv2.ximgproc.fastGlobalSmootherFilter(
        guide_uint8(rgb), start, params.lambda_lr * s * s, params.sigma_color,
        lambda_attenuation=params.lambda_attenuation, num_iter=params.num_iter,
    )
    _done(progress)
    return out.astype(np.float32, copy=False)


def upsample_wmf(depth_lr: np.ndarray, rgb_hr: np.ndarray, *, params: WeightedMedianParams | None = None,
                 progress: Progress | None = None) -> np.ndarray:
    """Bilinear enlargement, then a weighted median filter guided by the color image.

    OpenCV bins floating-point input into at most 256 values before taking
    the median, so the result is quantised to about ``range / 256``. It
    also clusters a color guide with k-means seeded from OpenCV's global
    random generator; the generator is reseeded (``cv2.setRNGSeed(0)``)
    right before the call (a side effect on OpenCV's RNG state). Even so,
    OpenCV 5.0.0's filter is **not** bit-identical from run to run on noisy
    float input (the fuzz tests found up to 22 % of the pixels differing; it
    looks like a read of uninitialised memory), so the method is registered
    with ``deterministic=False`` and the determinism tests leave it out.
    Parameters and returns as :func:`upsample_jbf` (params: :class:`WeightedMedianParams`).

    Examples
    --------
    >>> out = upsample_wmf(np.full((4, 4), 7.0, np.float32), np.zeros((16, 16, 3), np.uint8))
    >>> out.shape, float(out.min()), float(out.max())
    ((16, 16), 7.0, 7.0)
    """
    params, rgb, start, s = _prepare(depth_lr, rgb_hr, params, WeightedMedianParams)
    radius = max(1, int(round(params.radius_lr * s)))
    cv2.setRNGSeed(0)  # the filter clusters the guide colors with OpenCV's RNG (see the docstring)
    out = cv2.ximgproc.weightedMedianFilter(guide_uint8(rgb), start, radius, params.sigma)
    _done(progress)
    return out.astype(np.float32, copy=False)


@dataclass(frozen=True)
class FastBilateralSolverParams:
    """Fast bilateral solver parameters (OpenCV's defaults; not tuned: no build here has the solver).

    Attributes
    ----------
    sigma_spatial_lr : float
        Spatial bandwidth, low-resolution pixels.
    sigma_luma, sigma_chroma : float
        Luma and chroma bandwidths, 8-bit guide units.
    lam : float
        Smoothness weight (OpenCV's ``lambda``).
    num_iter : int
        Conjugate-gradient iterations.
    """

    sigma_spatial_lr: float = 2.0
    sigma_luma: float = 8.0
    sigma_chroma: float = 8.0
    lam: float = 128.0
    num_iter: int = 25

    def __post_init__(self) -> None:
        _check_positive(self, "sigma_spatial_lr", "sigma_luma", "sigma_chroma", "lam", "num_iter")


def upsample_fbs(depth_lr: np.ndarray, rgb_hr: np.ndarray, *, params: FastBilateralSolverParams | None = None,
                 progress: Progress | None = None) -> np.ndarray:
    """Bilinear enlargement, then the fast bilateral solver guided by the color image.

    Parameters and returns as :func:`upsample_jbf` (params:
    :class:`FastBilateralSolverParams`).

    Raises
    ------
    ValueError
        The installed OpenCV has no working solver (the message says why).
    """
    reason = fast_bilateral_solver_status()
    if reason:
        raise ValueError(f"method 'fbs' is unavailable: {reason}")
    params, rgb, start, s = _prepare(depth_lr, rgb_hr, params, FastBilateralSolverParams)
    confidence = np.ones(start.shape, np.float32)
    out = cv2.ximgproc.fastBilateralSolverFilter(
        guide_uint8(rgb), start.astype(np.float32), confidence, params.sigma_spatial_lr * s, params.sigma_luma,
        params.sigma_chroma, params.lam, int(params.num_iter))
    _done(progress)
    return out.astype(np.float32, copy=False)


def fast_bilateral_solver_status() -> str:
    """Why the fast bilateral solver cannot run here, or ``""`` when it can.

    Examples
    --------
    >>> isinstance(fast_bilateral_solver_status(), str)
    True
    """
    fbs = getattr(getattr(cv2, "ximgproc", None), "fastBilateralSolverFilter", None)
    if fbs is None:
        return (f"the installed OpenCV {cv2.__version__} has no cv2.ximgproc.fastBilateralSolverFilter "
                "(install opencv-contrib-python-headless).")
    guide = np.zeros((4, 4, 3), np.uint8)
    try:
        fbs(guide, np.ones((4, 4), np.float32), np.ones((4, 4), np.float32))
    except cv2.error as exc:
        if "EIGEN" in str(exc).upper():
            return (f"cv2.ximgproc.fastBilateralSolverFilter exists in the installed OpenCV {cv2.__version__}, "
                    "but this build has no Eigen, so the call raises 'needs to be compiled with EIGEN'.")
        return f"cv2.ximgproc.fastBilateralSolverFilter failed on a 4x4 test image: {str(exc).strip()}"
    return ""


def fast_bilateral_solver_available() -> bool:
    """Whether the installed OpenCV has a working ``fastBilateralSolverFilter`` (needs Eigen).

    Examples
    --------
    >>> fast_bilateral_solver_available() == (fast_bilateral_solver_status() == "")
    True
    """
    return fast_bilateral_solver_status() == ""
