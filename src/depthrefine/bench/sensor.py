"""Ground truth seen through a simulated real depth camera beside the color camera (the ``sensor`` protocol).

The ``tof`` protocol degrades the ground truth on the color camera's own
grid. A real depth camera sits beside the color camera, integrates a
footprint wider than its pixel, mixes or picks surfaces inside it, drops
out on dark surfaces and is calibrated to a fraction of a pixel. This
module makes the low-resolution input that way, from a Middlebury 2005
disparity ground truth ``D`` (levels = full-size pixels of disparity,
larger = nearer) on the color grid, an integer factor ``s`` and a
:class:`SensorModel`:

1. **Into the depth camera's view.** The depth camera sits ``baseline_mm``
   to the left of the color camera, on the same image row, with the color
   camera's optics at ``s`` times coarser pixels. A point of disparity ``d``
   seen at column ``x`` by the color camera is seen at ``x + r d`` by the
   depth camera, ``r = baseline_mm / 160 mm`` (the Middlebury stereo
   baseline): a horizontal shift by the disparity. :func:`warp_horizontal`
   forward-warps the ground truth and the color's luminance with a z-buffer
   (the nearer point wins); what the depth camera sees but the color camera
   does not (behind a foreground edge) is taken from the farther side, the
   background continuing.
2. **Footprint.** Depth pixel ``(i, j)`` integrates a square of
   ``footprint`` depth pixels centred on it (fractional edge pixels weighted
   by their coverage), misplaced by ``misregistration`` depth pixels in a
   seeded direction: the calibration error the chain does not know about.
3. **Mixing.** Inside a footprint two surfaces are told apart by the
   largest jump between its sorted values, if at least ``surface_gap``
   levels. ``itof`` (amplitude-modulated, continuous-wave): the pixel reads
   the coverage-weighted mean, so a pixel across an edge reads a *flying*
   value between the two surfaces (``mixed_invalid`` optionally drops the
   strongly mixed ones, as the Azure Kinect's depth engine does). ``dtof``
   (direct, pulsed): the nearer surface wins as soon as it covers
   ``near_wins`` of the footprint (its return comes first and strongest),
   so foreground objects grow by about ``(1/2 - near_wins) * footprint``
   depth pixels (*fattening*); otherwise the farther surface's mean.
4. **Noise** growing with distance: ``sigma_Z = noise_mm_at_1m *
   (Z / 1 m) ** noise_exponent`` millimetres, Gaussian, then the value is
   rounded to whole millimetres as a sensor stores it. Distances come from
   the Middlebury 2005 geometry, ``Z = f B / (d + d_min)`` with
   ``f = 3740`` px, ``B = 160`` mm and a nominal ``d_min = 200`` levels
   (the scenes at 1.4-2.2 m).
5. **Dark dropouts.** The footprint's mean linear luminance (the color seen
   from the depth camera) below ``dark_low`` never returns, above
   ``dark_high`` always; in between with a linearly falling probability.
6. **Back through the rig chain.** The measured depth map is reprojected
   into the color camera with :func:`depthrefine.rig.align_reproject` (the
   calibrated rig without the misregistration), onto the color image's
   grid divided by ``s``: the nearer point wins, a pixel between two
   samples of one surface is closed, and the strip beside a foreground edge
   that the depth camera could not see stays empty (NaN): occlusion holes.

Randomness (the misregistration's direction, noise, dropouts) comes from
``numpy.random.default_rng(seed)``; a seed gives a bit-identical map.
:data:`SENSOR_MODELS` holds the two models of the protocol and the real
figures each parameter was set from (also in ``docs/bench.md``).
"""

from __future__ import annotations

import math
import zlib
from dataclasses import dataclass, fields
from typing import TYPE_CHECKING

# numpy and the validators load on first use: ``depthrefine bench --help`` reads this module's
# constants through the protocol registry without them (fast start-up).
from .._lazy import numpy as np

if TYPE_CHECKING:
    from .protocols import Protocol, Scene
    from .runner import BenchCase

__all__ = [
    "SensorModel",
    "SENSOR_MODELS",
    "MIDDLEBURY_FOCAL_PX",
    "MIDDLEBURY_BASELINE_MM",
    "MIDDLEBURY_DMIN",
    "warp_horizontal",
    "mix_footprints",
    "simulate_sensor",
    "sensor_seed",
    "sensor_case",
    "sensor_cases",
    "sensor_protocol_cases",
    "SENSOR_TUNING_SCENES",
    "SENSOR_PEER_PARAMS",
]

#: Focal length of the Middlebury 2005 full-size images, pixels (the dataset page's figure).
MIDDLEBURY_FOCAL_PX = 3740.0
#: Baseline of the Middlebury 2005 stereo pairs, millimetres (the dataset page's figure).
MIDDLEBURY_BASELINE_MM = 160.0
#: The disparity offset ``d_min`` of the 8-bit ground truth, levels (nominal: 200 to 230 per scene).
MIDDLEBURY_DMIN = 200.0
#: Footprint taps per block of depth-pixel rows processed at once (bounds the memory).
_TAPS_PER_BLOCK = 2_000_000
_MIXINGS = ("itof", "dtof")


@dataclass(frozen=True)
class SensorModel:
    """A simulated depth camera (see the module docstring for what each step does).

    Attributes
    ----------
    name : str
        Short name; the ``sensor`` protocol's scenes are ``<scene>-<name>``.
    mixing : {"itof", "dtof"}
        Coverage-weighted mean (flying pixels) or the nearer surface wins (fattening).
    baseline_mm : float
        Distance from the color camera to the depth camera (the depth camera on the left), mm.
    footprint : float
        Side of the square each depth pixel integrates, depth pixels (>= 1).
    near_wins : float
        ``dtof``: share of the footprint (0..1) the nearer surface must cover to win.
    mixed_invalid : float or None
        ``itof``: a pixel mixing two surfaces whose smaller share is at least
        this (0..0.5) returns nothing; None keeps every flying pixel.
    surface_gap : float
        A jump of at least this many levels inside a footprint separates two surfaces.
    noise_mm_at_1m, noise_exponent : float
        ``sigma_Z = noise_mm_at_1m * (Z / 1 m) ** noise_exponent`` millimetres.
    dark_low, dark_high : float
        Footprint reflectance (linear luminance 0..1) below which a pixel always
        drops out, and above which it never does.
    misregistration : float
        Calibration error, depth pixels, in a seeded direction.
    """

    name: str
    mixing: str
    baseline_mm: float
    footprint: float
    near_wins: float
    mixed_invalid: float | None
    surface_gap: float
    noise_mm_at_1m: float
    noise_exponent: float
    dark_low: float
    dark_high: float
    misregistration: float

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name or "-" in self.name:
            raise ValueError(f"name must be a non-empty string without '-'; got {self.name!r}.")
        if self.mixing not in _MIXINGS:
            raise ValueError(f"mixing must be one of {', '.join(_MIXINGS)}; got {self.mixing!r}.")
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name in ("name", "mixing") or (f.name == "mixed_invalid" and value is None):
                continue
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0:
                raise ValueError(f"{f.name} must be a finite number >= 0; got {value!r}.")
        if self.footprint < 1:
            raise ValueError(f"footprint must be >= 1 depth pixel (a pixel sees at least itself); got {self.footprint}.")
        if not 0 <= self.near_wins <= 1:
            raise ValueError(f"near_wins must be a share in 0..1; got {self.near_wins}.")
        if self.mixed_invalid is not None and not 0 <= self.mixed_invalid <= 0.5:
            raise ValueError(f"mixed_invalid must be a share in 0..0.5 or None; got {self.mixed_invalid}.")
        if self.dark_high < self.dark_low:
            raise ValueError(f"dark_high ({self.dark_high}) must be >= dark_low ({self.dark_low}).")


#: The two sensor models of the ``sensor`` protocol; the figures they were set from are in docs/bench.md.
SENSOR_MODELS: dict[str, SensorModel] = {
    # Azure Kinect geometry (32.1 mm depth -> color in the mug capture's factory calibration) with an
    # AMCW pixel that keeps its flying pixels (as the SR4000 does; the Kinect's depth engine drops most).
    "itof": SensorModel(name="itof", mixing="itof", baseline_mm=32.0, footprint=2.0, near_wins=0.5,
                        mixed_invalid=None, surface_gap=4.0, noise_mm_at_1m=0.5, noise_exponent=1.5,
                        dark_low=0.01, dark_high=0.03, misregistration=0.25),
    # A phone LiDAR (iPhone): a wide footprint whose nearer surface wins, 2 cm from the wide camera.
    "dtof": SensorModel(name="dtof", mixing="dtof", baseline_mm=20.0, footprint=3.0, near_wins=0.15,
                        mixed_invalid=None, surface_gap=4.0, noise_mm_at_1m=0.3, noise_exponent=2.7,
                        dark_low=0.01, dark_high=0.03, misregistration=0.5),
}


def warp_horizontal(disparity: np.ndarray, shift_per_level: float, *, surface_gap: float,
                    supersample: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """Forward-warp a disparity map by ``shift_per_level * d`` columns, nearer points winning.

    Each pixel is split into ``supersample`` sub-pixels along its row, with
    the disparity interpolated towards a neighbour of the same surface
    (closer than ``surface_gap``), so a surface stretched by less than
    ``supersample`` leaves no cracks.
    A pixel no sub-pixel reaches (seen from the new view only, behind a
    foreground edge) takes the farther of its nearest filled neighbours in
    the row: the background continues.

    Parameters
    ----------
    disparity : (H, W) ndarray
        Larger = nearer; 0 / NaN = no value (not warped).
    shift_per_level : float
        Columns per level (positive: nearer points move right).
    surface_gap : float
        Levels that separate two surfaces.
    supersample : int
        Sub-pixels per pixel.

    Returns
    -------
    warped : (H, W) float64 ndarray
        The disparity in the new view (NaN in a row with no value at all).
    source : (H, W) int64 ndarray
        The column each warped pixel came from (-1 where NaN), to carry other images along.

    Examples
    --------
    >>> d = np.array([[10, 10, 50, 10, 10, 10]], float)
    >>> warped, source = warp_horizontal(d, 0.04, surface_gap=4)
    >>> warped.tolist(), source.tolist()
    ([[10.0, 10.0, 10.0, 10.0, 50.0, 10.0]], [[0, 1, 1, 3, 2, 5]])
    """
    from .._validate import check_int

    d = np.asarray(disparity, dtype=np.float64)
    if d.ndim != 2:
        raise ValueError(f"disparity must be 2-D (rows, cols); got shape {d.shape}.")
    k = check_int("supersample", supersample, minimum=1)
    rows, cols = d.shape
    with np.errstate(invalid="ignore"):
        valid = np.isfinite(d) & (d > 0)
    d0 = np.where(valid, d, 0.0)
    offsets = (np.arange(k) + 0.5) / k - 0.5
    sub = np.repeat(d0[..., None], k, axis=2)
    for side, sel in ((-1, offsets < 0), (1, offsets > 0)):
        nb = np.roll(d0, -side, axis=1)
        nb_ok = np.roll(valid, -side, axis=1)
        if side < 0:
            nb_ok[:, 0] = False
        else:
            nb_ok[:, -1] = False
        same = valid & nb_ok & (np.abs(nb - d0) < surface_gap)
        slope = np.where(same, (nb - d0), 0.0)[..., None]
        sub[..., sel] += slope * np.abs(offsets[sel])
    position = np.arange(cols)[None, :, None] + offsets[None, None, :] + shift_per_level * sub
    target = np.floor(position + 0.5).astype(np.int64)
    keep = valid[..., None] & (target >= 0) & (target < cols)
    flat = (np.arange(rows)[:, None, None] * cols + target)[keep]
    value = sub[keep]
    source_col = np.broadcast_to(np.arange(cols)[None, :, None], sub.shape)[keep]
    best = np.full(rows * cols, -np.inf)
    np.maximum.at(best, flat, value)
    winner = value == best[flat]
    source = np.full(rows * cols, -1, dtype=np.int64)
    np.maximum.at(source, flat[winner], source_col[winner])
    warped = np.where(np.isfinite(best), best, np.nan).reshape(rows, cols)
    source = source.reshape(rows, cols)
    # Pixels no sub-pixel reached: the farther of the nearest filled neighbours in the row.
    filled = source >= 0
    idx = np.broadcast_to(np.arange(cols), (rows, cols))
    left = np.maximum.accumulate(np.where(filled, idx, -1), axis=1)
    right = np.minimum.accumulate(np.where(filled, idx, cols)[:, ::-1], axis=1)[:, ::-1]
    r_idx = np.broadcast_to(np.arange(rows)[:, None], (rows, cols))
    d_left = np.where(left >= 0, warped[r_idx, np.clip(left, 0, cols - 1)], np.inf)
    d_right = np.where(right < cols, warped[r_idx, np.clip(right, 0, cols - 1)], np.inf)
    take = np.where(d_left <= d_right, left, right)
    gap = ~filled & (np.isfinite(d_left) | np.isfinite(d_right))
    warped[gap] = warped[r_idx[gap], take[gap]]
    source[gap] = source[r_idx[gap], take[gap]]
    return warped, source


def _axis_taps(n_out: int, scale: int, footprint: float, offset: float, n_fine: int):
    """Fine-grid indices (n_out, n) and coverage weights of each depth pixel's footprint along one axis."""
    centre = scale * np.arange(n_out) + (scale - 1) / 2.0 + offset
    half = footprint * scale / 2.0
    lo, hi = centre - half, centre + half
    first = np.floor(lo + 0.5).astype(np.int64)
    taps = first[:, None] + np.arange(int(math.ceil(footprint * scale)) + 1)
    weight = np.clip(np.minimum(taps + 0.5, hi[:, None]) - np.maximum(taps - 0.5, lo[:, None]), 0.0, None)
    inside = (taps >= 0) & (taps < n_fine)
    return np.clip(taps, 0, n_fine - 1), np.where(inside, weight, 0.0)


def mix_footprints(values: np.ndarray, weights: np.ndarray, model: SensorModel) -> np.ndarray:
    """What each depth pixel reads from its footprint's ``values`` (levels) and coverage ``weights``.

    Parameters
    ----------
    values, weights : (P, T) ndarray
        ``T`` taps per pixel; NaN values and zero weights do not count.
    model : SensorModel
        ``mixing``, ``surface_gap``, ``near_wins`` and ``mixed_invalid`` are used.

    Returns
    -------
    (P,) float64 ndarray
        NaN where no tap counts or an ``itof`` pixel is too mixed.

    Examples
    --------
    A footprint a quarter on the near surface (50) and three quarters on the far one (10):

    >>> v, w = np.array([[50.0, 10.0, 10.0, 10.0]]), np.ones((1, 4))
    >>> mix_footprints(v, w, SENSOR_MODELS["itof"]).tolist(), mix_footprints(v, w, SENSOR_MODELS["dtof"]).tolist()
    ([20.0], [50.0])
    """
    v = np.asarray(values, dtype=np.float64)
    w = np.where(np.isfinite(v), np.asarray(weights, dtype=np.float64), 0.0)
    v = np.where(w > 0, v, np.nan)
    order = np.argsort(v, axis=1)  # NaN last
    sv = np.take_along_axis(v, order, axis=1)
    sw = np.take_along_axis(w, order, axis=1)
    steps = np.diff(sv, axis=1)
    steps = np.where(np.isfinite(steps), steps, -np.inf)
    split = np.argmax(steps, axis=1) if steps.shape[1] else np.zeros(len(v), np.int64)
    jump = np.take_along_axis(steps, split[:, None], axis=1)[:, 0] if steps.shape[1] else np.full(len(v), -np.inf)
    cw = np.cumsum(sw, axis=1)
    cv = np.cumsum(np.where(sw > 0, sw * np.nan_to_num(sv), 0.0), axis=1)
    total_w, total_v = cw[:, -1], cv[:, -1]
    far_w = np.take_along_axis(cw, split[:, None], axis=1)[:, 0]
    far_v = np.take_along_axis(cv, split[:, None], axis=1)[:, 0]
    mixed = jump >= model.surface_gap
    with np.errstate(invalid="ignore", divide="ignore"):
        mean_all = total_v / total_w
        near_share = np.where(mixed, (total_w - far_w) / total_w, 0.0)
        if model.mixing == "itof":
            out = mean_all
            if model.mixed_invalid is not None:
                out = np.where(mixed & (np.minimum(near_share, 1 - near_share) >= model.mixed_invalid), np.nan, out)
        else:
            mean_near = (total_v - far_v) / (total_w - far_w)
            mean_far = far_v / far_w
            out = np.where(mixed, np.where(near_share >= model.near_wins, mean_near, mean_far), mean_all)
    return np.where(total_w > 0, out, np.nan)


def _footprint_read(warped: np.ndarray, luminance: np.ndarray, scale: int, model: SensorModel,
                    offset: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """Each depth pixel's reading (levels, NaN = none) and its footprint's mean luminance."""
    rows, cols = warped.shape[0] // scale, warped.shape[1] // scale
    ky, wy = _axis_taps(rows, scale, model.footprint, offset[0], warped.shape[0])
    kx, wx = _axis_taps(cols, scale, model.footprint, offset[1], warped.shape[1])
    n_taps = ky.shape[1] * kx.shape[1]
    reading = np.empty((rows, cols))
    reflectance = np.empty((rows, cols))
    block = max(1, _TAPS_PER_BLOCK // max(1, cols * n_taps))
    for r0 in range(0, rows, block):
        r1 = min(rows, r0 + block)
        yy = ky[r0:r1, None, :, None]
        xx = kx[None, :, None, :]
        weight = (wy[r0:r1, None, :, None] * wx[None, :, None, :]).reshape(-1, n_taps)
        values = warped[yy, xx].reshape(-1, n_taps)
        reading[r0:r1] = mix_footprints(values, weight, model).reshape(r1 - r0, cols)
        lum = luminance[yy, xx].reshape(-1, n_taps)
        with np.errstate(invalid="ignore", divide="ignore"):
            reflectance[r0:r1] = ((weight * lum).sum(axis=1) / weight.sum(axis=1)).reshape(r1 - r0, cols)
    return reading, reflectance


def _depth_rig(shape: tuple[int, int], scale: int, model: SensorModel):
    """The calibrated rig the chain uses: depth and color cameras at the depth resolution, ``baseline_mm`` apart."""
    from ..rig import CameraModel, StereoRig

    rows, cols = shape
    f = MIDDLEBURY_FOCAL_PX / scale
    ratio = model.baseline_mm / MIDDLEBURY_BASELINE_MM
    cx, cy = (cols - 1) / 2.0, (rows - 1) / 2.0
    color = CameraModel(np.array([[f, 0, cx], [0, f, cy], [0, 0, 1.0]]), np.zeros(5), (cols, rows))
    # The principal point absorbs the constant part of the parallax (d_min): the two views agree at d = 0.
    depth = CameraModel(np.array([[f, 0, cx - MIDDLEBURY_DMIN * ratio / scale], [0, f, cy], [0, 0, 1.0]]),
                        np.zeros(5), (cols, rows))
    return StereoRig(depth, color, np.eye(3), np.array([-model.baseline_mm / 1000.0, 0.0, 0.0]))


def simulate_sensor(depth_gt: np.ndarray, rgb_hr: np.ndarray, *, scale: int, model: SensorModel,
                    seed: int = 0) -> np.ndarray:
    """The low-resolution depth a :class:`SensorModel` camera beside the color camera delivers (module docstring).

    Parameters
    ----------
    depth_gt : (H, W) ndarray
        Middlebury 2005 disparity in 8-bit levels on the color grid (larger =
        nearer; 0 / NaN = none), cropped to a multiple of ``scale``.
    rgb_hr : (H, W, 3) ndarray
        The color image on the same grid.
    scale : int
        Color pixels per depth pixel.
    model : SensorModel
    seed : int
        Seed of the misregistration's direction, the noise and the dropouts.

    Returns
    -------
    (H // scale, W // scale) float32 ndarray
        Disparity levels on the color image's grid divided by ``scale`` (the
        rig chain's output); NaN = no measurement (occlusion, dropout, outside the view).

    Examples
    --------
    A near surface on the left half: the dToF camera fattens it by one depth pixel.

    >>> gt = np.full((16, 32), 10.0); gt[:, :16] = 30.0
    >>> out = simulate_sensor(gt, np.full((16, 32, 3), 200, np.uint8), scale=4, model=SENSOR_MODELS["dtof"])
    >>> out.shape, np.round(out[1], -1).tolist()
    ((4, 8), [30.0, 30.0, 30.0, 30.0, 30.0, 10.0, 10.0, 10.0])
    """
    from .._validate import check_int, check_rgb
    from ..rig import align_reproject
    from .simulate import linear_luminance

    if not isinstance(model, SensorModel):
        raise TypeError(f"model must be a SensorModel; got {type(model).__name__}.")
    s = check_int("scale", scale, minimum=1)
    rgb = check_rgb(rgb_hr)
    gt = np.asarray(depth_gt, dtype=np.float64)
    if gt.ndim != 2 or rgb.shape[:2] != gt.shape:
        raise ValueError(f"depth_gt {gt.shape} must be 2-D and on the grid of rgb_hr {rgb.shape[:2]}.")
    if gt.shape[0] % s or gt.shape[1] % s or gt.shape[0] < s or gt.shape[1] < s:
        raise ValueError(f"depth_gt {gt.shape} must be a multiple of the scale {s}; crop it first.")
    if np.nanmax(np.where(np.isfinite(gt), gt, 0.0)) > 255.0:
        raise ValueError(f"depth_gt must be Middlebury disparity in 8-bit levels (0..255); its maximum is "
                         f"{float(np.nanmax(gt)):g}.")
    rng = np.random.default_rng(seed)
    angle = rng.uniform(0.0, 2.0 * math.pi)
    offset = (model.misregistration * s * math.sin(angle), model.misregistration * s * math.cos(angle))
    ratio = model.baseline_mm / MIDDLEBURY_BASELINE_MM
    warped, source = warp_horizontal(gt, ratio, surface_gap=model.surface_gap)
    lum_hr = linear_luminance(rgb)
    lum = np.where(source >= 0, lum_hr[np.arange(gt.shape[0])[:, None], np.clip(source, 0, None)], np.nan)
    reading, reflectance = _footprint_read(warped, lum, s, model, offset)
    measured = np.isfinite(reading) & (reading > 0)
    fb = MIDDLEBURY_FOCAL_PX * MIDDLEBURY_BASELINE_MM
    level = np.where(measured, reading, 1.0) + MIDDLEBURY_DMIN
    z_mm = fb / level
    sigma_mm = model.noise_mm_at_1m * (z_mm / 1000.0) ** model.noise_exponent
    z_mm = np.maximum(np.round(z_mm + sigma_mm * rng.standard_normal(z_mm.shape)), 1.0)
    span = model.dark_high - model.dark_low
    p_drop = (np.clip((model.dark_high - reflectance) / span, 0.0, 1.0) if span > 0
              else (reflectance < model.dark_low).astype(np.float64))
    dropped = rng.random(z_mm.shape) < np.nan_to_num(p_drop, nan=1.0)
    inverse = np.where(measured & ~dropped, fb / z_mm, np.nan)  # = d + d_min, the chain's inverse depth
    if not np.isfinite(inverse).any():
        return np.full(inverse.shape, np.nan, dtype=np.float32)
    aligned = align_reproject(inverse, _depth_rig(inverse.shape, s, model), inverse_scale=fb / 1000.0,
                              factor=1, depth_distorted=False)
    return (aligned - np.float32(MIDDLEBURY_DMIN)).astype(np.float32)


def sensor_seed(scene: str, model: str, scale: int) -> int:
    """The fixed seed of a scene's simulated input under a sensor model at a scale.

    Examples
    --------
    >>> sensor_seed("art", "itof", 8) == sensor_seed("art", "itof", 8) != sensor_seed("art", "dtof", 8)
    True
    """
    return zlib.crc32(f"sensor/{scene}/{model}/x{scale}".encode())


def sensor_case(scene: str, scale: int, rgb_hr: np.ndarray, depth_gt: np.ndarray, *, model: SensorModel,
                split: str = "test") -> BenchCase:
    """A case of the ``sensor`` protocol: scene ``<scene>-<model>``, scored on the whole color grid."""
    from .protocols import crop_to_multiple, gt_float
    from .runner import BenchCase

    gt = crop_to_multiple(depth_gt, scale)
    rgb = np.ascontiguousarray(rgb_hr[: gt.shape[0], : gt.shape[1]])
    depth_lr = simulate_sensor(gt, rgb, scale=scale, model=model, seed=sensor_seed(scene, model.name, scale))
    return BenchCase("sensor", f"{scene}-{model.name}", scale, depth_lr, rgb, gt_float(gt), border=0, split=split)


def sensor_cases(scene: str, scale: int, rgb_hr: np.ndarray, depth_gt: np.ndarray, *,
                 tuning: tuple[str, ...] = ()) -> list[BenchCase]:
    """The ``sensor`` protocol's cases of a scene at a scale, one per model of :data:`SENSOR_MODELS`."""
    return [sensor_case(scene, scale, rgb_hr, depth_gt, model=m, split="tune" if f"{scene}-{m.name}" in tuning
                        else "test") for m in SENSOR_MODELS.values()]


#: The ``sensor`` protocol's tuning scenes: Park's Dolls and Laundry under both models (as for ``park``).
SENSOR_TUNING_SCENES = tuple(f"{scene}-{m}" for scene in ("dolls", "laundry") for m in SENSOR_MODELS)
#: The OpenCV peers' parameters tuned on :data:`SENSOR_TUNING_SCENES` at x4, x8 and x16 by
#: ``benchmarks/tune_peers.py --protocol sensor`` (the usual grid, then ``--grid`` past the edge for jbf
#: and fgs; results in docs/bench.md).
SENSOR_PEER_PARAMS: dict[str, dict[str, float]] = {
    "jbf": {"sigma_space_lr": 8.0, "sigma_color": 0.1},
    "guided": {"radius_lr": 2.0, "eps": 0.01},
    "fgs": {"lambda_lr": 64.0, "sigma_color": 2.0},
    "wmf": {"radius_lr": 3.0, "sigma": 10.0},
}


def sensor_protocol_cases(protocol: Protocol, scene: Scene, scale: int) -> list[BenchCase]:
    """The ``build_case`` of the ``sensor`` protocol: :func:`sensor_cases`, tuning scenes marked."""
    return sensor_cases(scene.name, scale, scene.rgb_hr, scene.depth_gt, tuning=tuple(protocol.tuning_scenes))
