"""A simulated low-resolution ToF depth map, made from ground truth and the color image.

No public real-ToF set with ground truth is at hand, so the benchmark's
``tof`` protocol makes the low-resolution input the way a ToF sensor would.
**The model is ours** (it is not a published protocol); its parameters are
the fields of :class:`ToFModel`. For a ground-truth map ``D`` (8-bit depth
intensity, larger = nearer, the thesis's convention), a color image and an
integer factor ``s``, each low-resolution pixel ``(i, j)``:

1. **Footprint integration.** The pixel integrates its whole footprint, the
   ``s x s`` block of ground-truth pixels ``D[s*i : s*i+s, s*j : s*j+s]``:
   its value is the mean of the block's valid pixels. At a depth edge the
   block mixes foreground and background, which gives the mixed ("flying")
   values between the two surfaces that real ToF pixels show there.
2. **Distance-dependent noise.** Gaussian noise with standard deviation
   ``sigma = noise_near + (noise_far - noise_near) * t**2`` levels, where
   ``t`` in [0, 1] is the pixel's normalised distance within the scene,
   ``t = (max - d) / (max - min)`` over the integrated values ``d`` (0 for
   the nearest surface, 1 for the farthest). ToF noise grows roughly with
   the square of distance because the returned amplitude falls as 1/r^2.
3. **Dropouts on dark surfaces.** The reflectance of a footprint is the mean
   linear luminance of its color pixels (sRGB decoded, Rec. 709 weights,
   1 = white). Below ``dark_low`` the pixel returns no measurement (0);
   between ``dark_low`` and ``dark_high`` it drops out with a probability
   falling linearly from 1 to 0; above ``dark_high`` it never does.
4. **8-bit quantisation.** Values are rounded to whole levels and clipped
   to 1..255 (0 is reserved for "no measurement").

Randomness (noise and dropouts) comes from ``numpy.random.default_rng(seed)``,
so a seed gives a bit-identical map.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import as_rgb_float, check_int, check_rgb

__all__ = ["ToFModel", "simulate_tof", "footprint_mean", "linear_luminance"]

#: Rec. 709 luminance weights of linear R, G, B.
_LUMA = np.array([0.2126, 0.7152, 0.0722])


@dataclass(frozen=True)
class ToFModel:
    """Parameters of the simulated ToF sensor (see the module docstring).

    Attributes
    ----------
    noise_near : float
        Noise standard deviation at the nearest surface of the scene, levels.
    noise_far : float
        Noise standard deviation at the farthest surface, levels.
    dark_low : float
        Footprint reflectance (linear luminance, 0..1) below which a pixel
        always drops out.
    dark_high : float
        Reflectance above which a pixel never drops out.
    """

    noise_near: float = 1.0
    noise_far: float = 4.0
    dark_low: float = 0.01
    dark_high: float = 0.03

    def __post_init__(self) -> None:
        for name in ("noise_near", "noise_far", "dark_low", "dark_high"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise TypeError(f"{name} must be a finite number; got {value!r}.")
            if value < 0:
                raise ValueError(f"{name} must be >= 0; got {value}.")
        if self.dark_high < self.dark_low:
            raise ValueError(
                f"dark_high ({self.dark_high}) must be >= dark_low ({self.dark_low})."
            )


def linear_luminance(rgb: np.ndarray) -> np.ndarray:
    """Linear luminance (0..1) of an sRGB color image.

    Examples
    --------
    >>> linear_luminance(np.array([[[255, 255, 255], [0, 0, 0]]], np.uint8)).round(3).tolist()
    [[1.0, 0.0]]
    """
    c = as_rgb_float(check_rgb(rgb)).astype(np.float64)
    lin = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return lin @ _LUMA


def footprint_mean(values: np.ndarray, scale: int, *, valid: np.ndarray | None = None) -> np.ndarray:
    """Mean of each ``scale x scale`` block over its valid pixels (NaN if none).

    Parameters
    ----------
    values : (H, W) ndarray
        Cropped to a multiple of ``scale`` first (rows and columns beyond the
        last whole block are dropped).
    scale : int
        Block side, pixels.
    valid : (H, W) bool ndarray, optional
        Pixels to include (default: the finite ones).

    Returns
    -------
    (H // scale, W // scale) float64 ndarray

    Examples
    --------
    >>> footprint_mean(np.array([[1, 3, 5, 5], [1, 3, 5, 5]], float), 2).tolist()
    [[2.0, 5.0]]
    """
    s = check_int("scale", scale, minimum=1)
    values = np.asarray(values, dtype=np.float64)
    h, w = values.shape[0] // s, values.shape[1] // s
    if h < 1 or w < 1:
        raise ValueError(f"an image of shape {values.shape} has no whole {s}x{s} block; use a smaller scale.")
    values = values[: h * s, : w * s]
    ok = np.isfinite(values) if valid is None else (np.asarray(valid, dtype=bool)[: h * s, : w * s]
                                                    & np.isfinite(values))
    total = np.where(ok, values, 0.0).reshape(h, s, w, s).sum(axis=(1, 3))
    count = ok.reshape(h, s, w, s).sum(axis=(1, 3))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(count > 0, total / np.maximum(count, 1), np.nan)


def simulate_tof(
    depth_gt: np.ndarray,
    rgb_hr: np.ndarray,
    *,
    scale: int,
    model: ToFModel | None = None,
    seed: int = 0,
) -> np.ndarray:
    """A low-resolution ToF depth map simulated from ground truth (module docstring).

    Parameters
    ----------
    depth_gt : (H, W) ndarray
        Ground truth in 8-bit levels (0..255, larger = nearer); 0 or NaN = no
        measurement.
    rgb_hr : (H, W, 3) ndarray
        The registered color image (uint8, uint16 or float in [0, 1]).
    scale : int
        Integer factor between the ground truth and the simulated map.
    model : ToFModel, optional
        Sensor parameters (defaults when omitted).
    seed : int
        Seed of the noise and dropouts.

    Returns
    -------
    depth_lr : (H // scale, W // scale) uint8 ndarray
        Simulated measurement; 0 = no measurement (dropout, or no valid
        ground truth in the footprint).

    Raises
    ------
    ValueError
        Shapes that differ, a scale larger than the image, or ground truth
        outside 0..255.

    Examples
    --------
    >>> gt = np.full((8, 8), 100, np.uint8)
    >>> rgb = np.full((8, 8, 3), 200, np.uint8)
    >>> simulate_tof(gt, rgb, scale=4, model=ToFModel(noise_near=0, noise_far=0)).tolist()
    [[100, 100], [100, 100]]
    """
    model = ToFModel() if model is None else model
    if not isinstance(model, ToFModel):
        raise TypeError(f"model must be a ToFModel; got {type(model).__name__}.")
    s = check_int("scale", scale, minimum=1)
    rgb = check_rgb(rgb_hr)
    gt = np.asarray(depth_gt, dtype=np.float64)
    if gt.ndim != 2:
        raise ValueError(f"depth_gt must be 2-D (rows, cols); got shape {gt.shape}.")
    if rgb.shape[:2] != gt.shape:
        raise ValueError(
            f"depth_gt {gt.shape} and rgb_hr {rgb.shape[:2]} must be on the same grid; crop them alike."
        )
    with np.errstate(invalid="ignore"):
        valid = np.isfinite(gt) & (gt > 0)
    if valid.any() and float(gt[valid].max()) > 255.0:
        raise ValueError(
            f"depth_gt must be in 8-bit levels (0..255); its maximum is {float(gt[valid].max()):g}. "
            "Rescale it to 8-bit depth intensity first."
        )
    # 1. Footprint integration: mean of the valid ground truth in each block.
    depth = footprint_mean(gt, s, valid=valid)
    reflectance = footprint_mean(linear_luminance(rgb), s)
    measured = np.isfinite(depth)
    rng = np.random.default_rng(seed)
    # 2. Noise growing with the square of the normalised distance t.
    if measured.any():
        near, far = float(np.nanmax(depth)), float(np.nanmin(depth))
        t = np.where(measured, (near - np.where(measured, depth, near)) / max(near - far, 1e-12), 0.0)
    else:
        t = np.zeros(depth.shape)
    sigma = model.noise_near + (model.noise_far - model.noise_near) * t * t
    noisy = np.where(measured, depth, 0.0) + sigma * rng.standard_normal(depth.shape)
    # 3. Dropouts on dark (low-reflectance) footprints.
    span = model.dark_high - model.dark_low
    if span > 0:
        p_drop = np.clip((model.dark_high - reflectance) / span, 0.0, 1.0)
    else:
        p_drop = (reflectance < model.dark_low).astype(np.float64)
    dropped = rng.random(depth.shape) < p_drop
    # 4. 8-bit quantisation; 0 = no measurement.
    out = np.clip(np.floor(noisy + 0.5), 1, 255).astype(np.uint8)
    out[~measured | dropped] = 0
    return out
