"""Undistortion and alignment: bring the depth map onto the color image's grid (spec steps 1 and 3).

Two alignments, both returning a *low-resolution* depth map for
:func:`depthrefine.refine`, which spreads depth pixel ``(i, j)`` to color
pixel ``(i*s + s//2, j*s + s//2)``:

``shift`` (the thesis, 3.2.2, eq. 1, Fig. 23-24)
    The cameras sit side by side, so every depth pixel moves horizontally by
    ``shift = k * (d - d_bg)`` depth pixels, ``d`` being the depth intensity
    (proportional to 1 / distance) and ``d_bg`` the background's (the x-axis
    intercept, so the background does not move). Nearer pixels win
    collisions; occlusion holes take the nearest valid depth on the
    background side (the side of the color camera); a hole with nothing on
    that side (at the image border) takes the foreground's depth from the
    other side (Fig. 24c). The output has the depth map's own shape: it lies
    on the color image's grid after the scale step, which ``refine`` applies.

    **Decision (grid):** the shift is done on the low-resolution grid, each
    pixel landing on ``col + round(shift)`` with a fractional ``shift``, at
    ``1/s**2`` of the cost of shifting the ``s``-times enlarged map; ``k`` is
    therefore in depth pixels per depth unit and does not depend on ``s``.
    It is close to, not the same as, shifting the enlarged map by
    ``s * shift`` and reading it back at the depth-pixel centres: where the
    two round differently, a hole left by a moved pixel can take the
    foreground that moved in instead of the background (a one-pixel
    difference at depth edges).

    The shift assumes the color image shows the depth camera's field of
    view: the background (``d_bg``) must land where the depth grid stretched
    over the color image puts it. :func:`shift_misregistration` measures how
    far it does not (different focal lengths, principal points, a rotation);
    :func:`align_depth` refuses the shift beyond one depth pixel.

``reproject`` (beyond the thesis, for calibrated rigs that need not be parallel)
    Back-project each depth pixel with the depth camera's intrinsics (undoing
    its lens distortion), move it with ``R, t``, project it into the color
    camera and keep the nearest point per pixel (z-buffer), like
    ``cv2.registerDepth``. It renders into a color-camera grid of
    ``(round(H / s), round(W / s))`` pixels whose intrinsics are the color
    camera's scaled to that grid, ``s`` defaulting to the focal-length ratio
    (about one depth sample per grid pixel). Each depth pixel writes every
    grid pixel its footprint covers (its angular size through the lens, times
    the depth ratio), so a surface seen slightly magnified has no gaps for
    the background to show through (``cv2.registerDepth`` writes one pixel
    per sample and has them). An empty pixel between two opposite samples
    takes the farther one; wider disocclusions stay invalid (NaN) and are
    filled by the refinement. The values are the depth along the *color*
    camera's axis, in the input's units.

In both, invalid depth (NaN / 0) stays invalid: an invalid pixel is moved as
its nearest valid neighbour would be, loses every collision against a valid
one, and marks where it lands as unmeasured (never filled).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import asdict, dataclass
from typing import Any

import cv2
import numpy as np

from ._validate import as_depth, check_depth, check_rgb
from .baselines import fill_invalid_nearest
from .calibrate import CameraModel, StereoRig
from .pointcloud import _conversion, _metres64, metres_to_depth, pixel_rays, project_points

__all__ = [
    "COLOR_SIDES",
    "ENCODINGS",
    "ALIGN_METHODS",
    "AlignmentWarning",
    "undistort_maps",
    "distort_maps",
    "undistort_depth",
    "undistort_image",
    "distort_depth",
    "distort_image",
    "background_depth",
    "align_shift",
    "ShiftModel",
    "shift_from_rig",
    "shift_misregistration",
    "MAX_SHIFT_MISREGISTRATION",
    "reproject_camera",
    "align_reproject",
    "AlignSettings",
    "AlignedPair",
    "align_depth",
    "align_pair",
]

#: Where the color camera sits, seen from behind the depth camera.
COLOR_SIDES = ("right", "left")
#: How a depth value relates to distance: "inverse" (the thesis's depth
#: intensity, disparity: larger = nearer) or "distance" (mm, m: larger = farther).
ENCODINGS = ("inverse", "distance")

#: A rig rotated more than this (degrees) is not the parallel rig the shift assumes.
MAX_PARALLEL_ROTATION = 2.0
#: The chain refuses the shift alignment when the background lands farther than this (depth pixels)
#: from where the stretched depth grid puts it (see :func:`shift_misregistration`).
MAX_SHIFT_MISREGISTRATION = 1.0


class AlignmentWarning(UserWarning):
    """The rig does not fit the assumptions of the chosen alignment."""


# ----------------------------------------------------------------------------
# Undistortion (spec step 1)
# ----------------------------------------------------------------------------


def undistort_maps(camera: CameraModel) -> tuple[np.ndarray, np.ndarray]:
    """For every pixel of the undistorted image, where to read the raw image.

    The undistorted image keeps the camera's ``K`` (only the distortion is
    removed), so ``camera.without_distortion()`` describes it.

    Returns
    -------
    map_x, map_y : (rows, cols) float32 ndarray
        Raw-image column and row of each undistorted pixel (``cv2.remap`` maps).
    """
    return cv2.initUndistortRectifyMap(camera.K, camera.dist, None, camera.K, camera.image_size, cv2.CV_32FC1)


def distort_maps(camera: CameraModel) -> tuple[np.ndarray, np.ndarray]:
    """For every pixel of the raw (distorted) image, where to read the undistorted image.

    The inverse of :func:`undistort_maps`; used to simulate raw captures and
    to check round trips.
    """
    rays = pixel_rays(camera, distorted=True)
    K = camera.K
    map_x = K[0, 0] * rays[..., 0] + K[0, 2]  # CameraModel has no skew
    map_y = K[1, 1] * rays[..., 1] + K[1, 2]
    return map_x.astype(np.float32), map_y.astype(np.float32)


def _check_camera_shape(shape: tuple[int, ...], camera: CameraModel, name: str) -> None:
    if tuple(shape[:2]) != camera.shape:
        w, h = camera.image_size
        raise ValueError(
            f"{name} is {shape[1]}x{shape[0]} (width x height) but the camera was calibrated on {w}x{h} "
            "images; use the camera file of this camera at this resolution."
        )


def _remap_depth(depth: np.ndarray, maps: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    d = as_depth(depth, "depth")
    return cv2.remap(d, maps[0], maps[1], cv2.INTER_NEAREST, borderMode=cv2.BORDER_CONSTANT,
                     borderValue=float("nan"))


def _remap_image(image: np.ndarray, maps: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    if not isinstance(image, np.ndarray) or image.ndim not in (2, 3):
        raise ValueError(f"image must be a (rows, cols[, channels]) array; got {getattr(image, 'shape', image)!r}.")
    return cv2.remap(np.ascontiguousarray(image), maps[0], maps[1], cv2.INTER_LINEAR,
                     borderMode=cv2.BORDER_CONSTANT, borderValue=0)


def undistort_depth(depth: np.ndarray, camera: CameraModel) -> np.ndarray:
    """Remove the lens distortion from a depth map with nearest sampling (spec step 1).

    Parameters
    ----------
    depth : (rows, cols) ndarray
        Raw depth of the camera, any units; 0 / NaN = invalid.
    camera : CameraModel
        Its calibration (from the intensity images, thesis 3.2.1).

    Returns
    -------
    (rows, cols) float32 ndarray
        Undistorted depth in the same units; NaN where invalid or outside the
        raw image. Nearest sampling never blends two surfaces' depths.

    Examples
    --------
    >>> cam = CameraModel(np.array([[20., 0, 3.5], [0, 20., 3.5], [0, 0, 1]]), np.zeros(5), (8, 8))
    >>> undistort_depth(np.full((8, 8), 7, np.uint8), cam)[0, :3].tolist()
    [7.0, 7.0, 7.0]
    """
    check_depth(depth, "depth")
    _check_camera_shape(depth.shape, camera, "depth")
    return _remap_depth(depth, undistort_maps(camera))


def undistort_image(image: np.ndarray, camera: CameraModel) -> np.ndarray:
    """Remove the lens distortion from an intensity or color image (bilinear, dtype kept)."""
    _check_camera_shape(np.shape(image), camera, "image")
    return _remap_image(image, undistort_maps(camera))


def distort_depth(depth: np.ndarray, camera: CameraModel) -> np.ndarray:
    """Apply the lens distortion to an undistorted depth map (nearest; the inverse of :func:`undistort_depth`)."""
    check_depth(depth, "depth")
    _check_camera_shape(depth.shape, camera, "depth")
    return _remap_depth(depth, distort_maps(camera))


def distort_image(image: np.ndarray, camera: CameraModel) -> np.ndarray:
    """Apply the lens distortion to an undistorted image (bilinear; the inverse of :func:`undistort_image`)."""
    _check_camera_shape(np.shape(image), camera, "image")
    return _remap_image(image, distort_maps(camera))


# ----------------------------------------------------------------------------
# The thesis's shift alignment (spec step 3)
# ----------------------------------------------------------------------------


def _check_choice(name: str, value: Any, choices: tuple[str, ...]) -> str:
    if value not in choices:
        raise ValueError(f"{name} must be one of {list(choices)}; got {value!r}.")
    return value


def _check_number(name: str, value: Any, *, positive: bool = False, nonnegative: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a number; got {value!r}.")
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{name} must be finite; got {value}.")
    if positive and value <= 0:
        raise ValueError(f"{name} must be > 0; got {value}.")
    if nonnegative and value < 0:
        raise ValueError(f"{name} must be >= 0; got {value}.")
    return value


def background_depth(depth: np.ndarray, *, encoding: str = "inverse") -> float:
    """The background depth ``d_bg``: the mean of the farther half of the valid depths.

    The farther half is taken by rank: the ``n // 2`` farthest of the ``n``
    valid values (at least one), i.e. the smallest for ``encoding="inverse"``
    (depth intensity, larger = nearer) and the largest for ``"distance"``
    [spec step 3 decision]. Ties at the median count like any other value,
    so a single outlier cannot become the background. A constant map is its
    own background.

    Examples
    --------
    >>> background_depth(np.array([[10, 20, 200, 210]], np.uint8))
    15.0
    >>> background_depth(np.array([[1.0, 1.5, 3.0, 3.5]]), encoding="distance")
    3.25

    One far outlier among ties is averaged with them, not taken alone:

    >>> background_depth(np.array([[5, 40, 40, 40, 200, 200]], np.uint8))
    28.333333333333332
    """
    _check_choice("encoding", encoding, ENCODINGS)
    d = as_depth(depth, "depth")
    values = np.sort(d[np.isfinite(d)].astype(np.float64))  # nearest last for "inverse", farthest last for "distance"
    n_farther = max(values.size // 2, 1)
    farther = values[:n_farther] if encoding == "inverse" else values[values.size - n_farther:]
    return float(farther.mean())


def _nearness(d: np.ndarray, encoding: str) -> np.ndarray:
    """A value that grows as the surface gets nearer, proportional to 1 / distance."""
    if encoding == "inverse":
        return d.astype(np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        return 1.0 / d.astype(np.float64)


def align_shift(
    depth_lr: np.ndarray,
    *,
    slope: float,
    background: float | None = None,
    color_side: str = "right",
    encoding: str = "inverse",
) -> np.ndarray:
    """The thesis's alignment: shift every depth pixel horizontally by ``k * (d - d_bg)``.

    Parameters
    ----------
    depth_lr : (h, w) ndarray
        Undistorted depth map, any units; 0 / NaN = invalid.
    slope : float
        ``k``, in depth pixels per depth unit (``encoding="inverse"``), or in
        depth pixels times depth units (``"distance"``, where the shift is
        ``k * (1/D - 1/D_bg)``). :func:`shift_from_rig` computes it from a
        calibrated rig. 0 leaves the map as it is.
    background : float, optional
        ``d_bg`` in depth units, the depth that does not move; default
        :func:`background_depth`.
    color_side : {"right", "left"}
        Side of the color camera, seen from behind the rig (thesis: right).
        Nearer pixels move away from it; holes are filled from its side.
    encoding : {"inverse", "distance"}
        ``"inverse"``: depth intensity or disparity (larger = nearer, the
        thesis's 8-bit maps); ``"distance"``: millimetres, metres.

    Returns
    -------
    (h, w) float32 ndarray
        The depth as the color camera sees it, same units, NaN = invalid.

    References
    ----------
    Chen Ching-Kun, "TOF-Sensor Captured Depth Map Refinement Using
    High-Resolution Color Images", NCTU, 2014, section 3.2.2, eq. (1),
    Figs. 23-24.

    Examples
    --------
    A near object (200) moves one pixel left; its old place is background again:

    >>> row = np.array([[50, 50, 50, 200, 50, 50]], np.uint8)
    >>> align_shift(row, slope=1 / 150, background=50).tolist()
    [[50.0, 50.0, 200.0, 50.0, 50.0, 50.0]]
    """
    d = as_depth(depth_lr, "depth_lr")
    k = _check_number("slope", slope, nonnegative=True)
    _check_choice("color_side", color_side, COLOR_SIDES)
    _check_choice("encoding", encoding, ENCODINGS)
    if background is None:
        background = background_depth(d, encoding=encoding)
    d_bg = _check_number("background", background, positive=True)
    h, w = d.shape
    valid = np.isfinite(d)
    q = _nearness(d, encoding)
    q_bg = float(_nearness(np.array([d_bg]), encoding)[0])
    q_move = fill_invalid_nearest(q)  # invalid pixels move as their nearest valid neighbour

    # eq. (1) with the background intercept (Fig. 23b); nearer pixels move away from the color camera.
    sign = -1.0 if color_side == "right" else 1.0
    shift = sign * k * (q_move - q_bg)
    rows, cols = np.indices((h, w))
    target_cols = cols + np.floor(shift + 0.5).astype(np.int64)
    inside = (target_cols >= 0) & (target_cols < w)
    target = (rows * w + target_cols)[inside]
    source = np.flatnonzero(inside)
    priority = np.where(valid, q_move, -np.inf).ravel()[source]  # nearer wins; invalid loses
    target, source = _zbuffer(target, priority, source)

    out = np.full(h * w, np.nan, dtype=np.float32)
    landed = np.zeros(h * w, dtype=bool)
    out[target] = d.ravel()[source]
    landed[target] = True
    out = out.reshape(h, w)
    _fill_holes_along_rows(out, ~landed.reshape(h, w), from_right=(color_side == "right"))
    return out


def _zbuffer(target: np.ndarray, priority: np.ndarray, source: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each distinct target, the source with the highest priority (ties: the lowest source index)."""
    order = np.lexsort((source, -priority, target))
    target_sorted = target[order]
    first = np.ones(target_sorted.size, dtype=bool)
    first[1:] = target_sorted[1:] != target_sorted[:-1]
    return target_sorted[first], source[order][first]


def _fill_holes_along_rows(depth: np.ndarray, holes: np.ndarray, *, from_right: bool) -> None:
    """Fill ``holes`` in place with the nearest valid depth on one side of the row, else the other.

    The background side (``from_right``: the right) comes first; a hole with
    no valid pixel on that side (it touches the border) extends the depth
    from the other side, the foreground (thesis Fig. 24c).
    """
    h, w = depth.shape
    valid = np.isfinite(depth) & ~holes
    cols = np.broadcast_to(np.arange(w), (h, w))
    right = np.minimum.accumulate(np.where(valid, cols, w)[:, ::-1], axis=1)[:, ::-1]
    left = np.maximum.accumulate(np.where(valid, cols, -1), axis=1)
    first, second = (right, left) if from_right else (left, right)
    source = np.where((first >= 0) & (first < w), first, second)
    fill = holes & (source >= 0) & (source < w)
    rows = np.broadcast_to(np.arange(h)[:, None], (h, w))
    depth[fill] = depth[rows[fill], source[fill]]


@dataclass(frozen=True)
class ShiftModel:
    """Parameters of the shift alignment derived from a rig.

    Attributes
    ----------
    slope : float
        ``k`` for :func:`align_shift` (units there).
    color_side : str
        ``"right"`` or ``"left"``.
    encoding : str
        ``"inverse"`` or ``"distance"``.
    """

    slope: float
    color_side: str
    encoding: str


def shift_from_rig(
    rig: StereoRig, *, depth_units: float | None = None, inverse_scale: float | None = None
) -> ShiftModel:
    """Estimate the shift alignment's slope ``k`` and direction from a calibrated rig.

    A point at distance ``Z`` (metres) moves by ``f * b / Z`` depth pixels
    between two parallel cameras, ``f`` being the depth camera's horizontal
    focal length (pixels) and ``b`` the horizontal baseline (metres). With
    ``Z = depth_units * D`` (``encoding="distance"``) that is
    ``k * (1/D)`` with ``k = f b / depth_units``; with ``Z = inverse_scale / d``
    (``"inverse"``, the thesis's depth intensity) it is ``k * d`` with
    ``k = f b / inverse_scale``.

    Warns
    -----
    AlignmentWarning
        The rig is rotated by more than 2 degrees or its baseline is not
        mostly horizontal: the shift (a thesis assumption) will be off; use
        the ``reproject`` alignment.

    Examples
    --------
    >>> cam = CameraModel(np.array([[200., 0, 87.5], [0, 200., 71.5], [0, 0, 1]]), np.zeros(5), (176, 144))
    >>> rig = StereoRig(cam, cam, np.eye(3), np.array([-0.05, 0.0, 0.0]))
    >>> shift_from_rig(rig, depth_units=0.001)
    ShiftModel(slope=10000.0, color_side='right', encoding='distance')
    """
    kind, value = _conversion(depth_units, inverse_scale)
    centre = rig.color_centre
    baseline = float(abs(centre[0]))
    if rig.rotation_degrees > MAX_PARALLEL_ROTATION or abs(centre[1]) > 0.25 * baseline \
            or abs(centre[2]) > 0.5 * baseline:
        warnings.warn(
            f"the rig is not a parallel side-by-side pair (rotation {rig.rotation_degrees:.1f} degrees, "
            f"color camera at {np.round(centre, 4).tolist()} m): the shift alignment assumes one; "
            "use the reproject alignment.",
            AlignmentWarning, stacklevel=2,
        )
    fx = rig.depth_camera.focal[0]
    return ShiftModel(slope=fx * baseline / value, color_side="right" if centre[0] >= 0 else "left",
                      encoding=kind)


def shift_misregistration(
    rig: StereoRig,
    depth_shape: tuple[int, ...],
    color_shape: tuple[int, ...],
    z_background: float | None = None,
) -> float:
    """How far the shift alignment misplaces the background on this rig, in depth pixels.

    The shift leaves the background (``d_bg``) where it is on the depth grid,
    and the refinement stretches that grid over the color image (depth pixel
    ``(i, j)`` at color pixel ``((i + 0.5) H / h - 0.5, (j + 0.5) W / w - 0.5)``).
    That is right only if the color image shows the depth camera's field of
    view. This maps a 3 x 3 grid of depth pixels (corners, edge midpoints,
    centre) at the background distance through the rig into the color image
    and returns the largest distance between where they land and where the
    stretched grid puts them, in depth pixels. Both cameras are taken
    without lens distortion (the chain undistorts both images first).

    Parameters
    ----------
    rig : StereoRig
    depth_shape : tuple
        ``(h, w)`` of the depth map (the rig's depth camera).
    color_shape : tuple
        ``(H, W[, 3])`` of the color image (the rig's color camera).
    z_background : float, optional
        Distance of the background along the depth camera's axis, metres;
        ``None``: at infinity (only the rotation and the intrinsics count).

    Returns
    -------
    float
        Depth pixels; ``inf`` when a probe point is behind the color camera.

    Examples
    --------
    >>> cam = CameraModel(np.array([[80., 0, 47.5], [0, 80., 35.5], [0, 0, 1]]), np.zeros(5), (96, 72))
    >>> shift_misregistration(StereoRig(cam, cam, np.eye(3), np.zeros(3)), (72, 96), (72, 96))
    0.0
    >>> wide = CameraModel(np.array([[70., 0, 47.5], [0, 70., 35.5], [0, 0, 1]]), np.zeros(5), (96, 72))
    >>> round(shift_misregistration(StereoRig(cam, wide, np.eye(3), np.zeros(3)), (72, 96), (72, 96)), 3)
    7.413
    """
    if not isinstance(rig, StereoRig):
        raise TypeError(f"rig must be a StereoRig; got {type(rig).__name__}.")
    (h, w), (rows_c, cols_c) = tuple(depth_shape[:2]), tuple(color_shape[:2])
    if min(h, w, rows_c, cols_c) < 1:
        raise ValueError(f"depth_shape and color_shape must be positive; got {depth_shape!r}, {color_shape!r}.")
    if z_background is not None:
        z_background = _check_number("z_background", z_background, positive=True)
    K_d, K_c = rig.depth_camera.K, rig.color_camera.K
    v, u = (g.ravel() for g in np.meshgrid([0.0, (h - 1) / 2, h - 1.0], [0.0, (w - 1) / 2, w - 1.0], indexing="ij"))
    rays = np.column_stack([(u - K_d[0, 2]) / K_d[0, 0], (v - K_d[1, 2]) / K_d[1, 1], np.ones(u.size)])
    points = rays @ rig.R.T if z_background is None else (rays * z_background) @ rig.R.T + rig.t
    if not (points[:, 2] > 1e-9).all():
        return math.inf
    u_c = K_c[0, 0] * points[:, 0] / points[:, 2] + K_c[0, 2]
    v_c = K_c[1, 1] * points[:, 1] / points[:, 2] + K_c[1, 2]
    sx, sy = cols_c / w, rows_c / h
    error = np.hypot((u_c - ((u + 0.5) * sx - 0.5)) / sx, (v_c - ((v + 0.5) * sy - 0.5)) / sy)
    return float(error.max())


# ----------------------------------------------------------------------------
# The calibrated alignment (reprojection)
# ----------------------------------------------------------------------------


def reproject_camera(rig: StereoRig, *, factor: int | None = None, distorted: bool = False) -> tuple[int, CameraModel]:
    """The factor ``s`` and the low-resolution color-camera grid :func:`align_reproject` renders into.

    Parameters
    ----------
    rig : StereoRig
    factor : int, optional
        ``s``; default ``round(f_color / f_depth)`` (mean of x and y), at least
        1: one depth sample per grid pixel.
    distorted : bool
        Keep the color camera's distortion (grid of a raw color image).

    Returns
    -------
    s : int
    camera : CameraModel
        The color camera resized to ``(round(H / s), round(W / s))``.

    Examples
    --------
    >>> d = CameraModel(np.array([[100., 0, 43.5], [0, 100., 35.5], [0, 0, 1]]), np.zeros(5), (88, 72))
    >>> c = CameraModel(np.array([[700., 0, 307.5], [0, 700., 251.5], [0, 0, 1]]), np.zeros(5), (616, 504))
    >>> s, grid = reproject_camera(StereoRig(d, c, np.eye(3), np.zeros(3)))
    >>> s, grid.image_size, grid.K[0].tolist()
    (7, (88, 72), [100.0, 0.0, 43.5])
    """
    color = rig.color_camera
    if factor is None:
        ratio = np.mean(np.array(color.focal) / np.array(rig.depth_camera.focal))
        factor = max(1, int(np.floor(ratio + 0.5)))
    elif isinstance(factor, bool) or not isinstance(factor, (int, np.integer)) or factor < 1:
        raise ValueError(f"factor must be an integer >= 1; got {factor!r}.")
    rows, cols = color.shape
    grid = (max(1, int(np.floor(rows / factor + 0.5))), max(1, int(np.floor(cols / factor + 0.5))))
    camera = color.resized(grid)
    return int(factor), (camera if distorted else camera.without_distortion())


def align_reproject(
    depth: np.ndarray,
    rig: StereoRig,
    *,
    depth_units: float | None = None,
    inverse_scale: float | None = None,
    factor: int | None = None,
    radial: bool = False,
    depth_distorted: bool = True,
    color_distorted: bool = False,
) -> np.ndarray:
    """Reproject a depth map into the color camera (calibrated alignment, z-buffered).

    Parameters
    ----------
    depth : (h, w) ndarray
        The depth camera's depth map, any units (see ``depth_units``); 0 /
        NaN = invalid. Its shape must be the rig's depth camera's.
    rig : StereoRig
        From ``depthrefine calibrate-stereo``.
    depth_units, inverse_scale : float
        Exactly one: metres per depth unit (0.001 for uint16 mm), or
        ``metres = inverse_scale / value`` for 8-bit depth intensity /
        disparity (see :mod:`depthrefine.pointcloud`). Without it the depth
        cannot be placed in 3-D: ``ValueError``.
    factor : int, optional
        ``s`` (see :func:`reproject_camera`).
    radial : bool
        The depth is the distance along each pixel's ray, not ``Z``.
    depth_distorted : bool
        ``depth`` is the raw map (undo the depth camera's distortion while
        back-projecting: no resampling). False if it is already undistorted.
    color_distorted : bool
        Render for the raw color image (apply the color camera's distortion).
        False (default) renders for the undistorted color image.

    Returns
    -------
    (round(H / s), round(W / s)) float32 ndarray
        Depth along the color camera's optical axis, in the input's units,
        on the color image's grid divided by ``s``; NaN = no depth (invalid
        input, disocclusion, outside the depth camera's view).

    Notes
    -----
    z-buffer: the nearest point wins each grid pixel; every depth pixel
    writes its footprint (see the module docstring); then an empty pixel
    between two opposite samples takes the farther one.

    Examples
    --------
    Two identical cameras at one place: the map is unchanged.

    >>> cam = CameraModel(np.array([[50., 0, 3.5], [0, 50., 3.5], [0, 0, 1]]), np.zeros(5), (8, 8))
    >>> depth = np.full((8, 8), 1500, np.uint16)
    >>> out = align_reproject(depth, StereoRig(cam, cam, np.eye(3), np.zeros(3)), depth_units=0.001)
    >>> out.shape, float(out[3, 3])
    ((8, 8), 1500.0)
    """
    if not isinstance(rig, StereoRig):
        raise TypeError(f"rig must be a StereoRig; got {type(rig).__name__}.")
    _conversion(depth_units, inverse_scale)
    d = as_depth(depth, "depth")
    _check_camera_shape(d.shape, rig.depth_camera, "depth")
    _, grid = reproject_camera(rig, factor=factor, distorted=color_distorted)
    rows_t, cols_t = grid.shape

    z = _metres64(d, depth_units, inverse_scale)
    valid = np.isfinite(z).ravel()
    z = fill_invalid_nearest(z)  # invalid pixels travel with their nearest valid neighbour
    rays = pixel_rays(rig.depth_camera, distorted=depth_distorted).reshape(-1, 2)
    z = z.ravel()
    if radial:
        z = z / np.sqrt(1.0 + rays[:, 0] ** 2 + rays[:, 1] ** 2)
    points = np.column_stack([rays[:, 0] * z, rays[:, 1] * z, z]) @ rig.R.T + rig.t
    front = np.flatnonzero(points[:, 2] > 1e-9)
    uv = project_points(points[front], grid, distorted=color_distorted)
    z_color = points[:, 2]
    # Footprint: a depth pixel spans d(ray)/d(col) + d(ray)/d(row) in normalized coordinates (its lens
    # included), i.e. about f_grid * span * Z_depth / Z_color grid pixels; it writes every grid pixel whose
    # centre lies within half of that (at least its own pixel), so that no gap opens inside a surface.
    span = _ray_span(rays.reshape(d.shape + (2,)), rig.depth_camera).reshape(-1, 2)[front]
    focal_grid = np.array([grid.K[0, 0], grid.K[1, 1]])
    half = np.maximum(span * focal_grid * (z[front] / z_color[front])[:, None], 1.0) / 2.0
    reach = int(np.ceil(np.nanmax(half))) if half.size else 0
    sources, targets = [], []
    for d_row in range(-reach, reach + 1):
        for d_col in range(-reach, reach + 1):
            col = np.floor(uv[:, 0] + 0.5) + d_col
            row = np.floor(uv[:, 1] + 0.5) + d_row
            inside = (np.abs(col - uv[:, 0] - 1e-9) < half[:, 0]) & (np.abs(row - uv[:, 1] - 1e-9) < half[:, 1])
            inside &= (col >= 0) & (col < cols_t) & (row >= 0) & (row < rows_t)
            sources.append(front[inside])
            targets.append(row[inside].astype(np.int64) * cols_t + col[inside].astype(np.int64))
    source = np.concatenate(sources)
    target = np.concatenate(targets)
    priority = np.where(valid[source], -z_color[source], -np.inf)  # nearest wins; invalid loses
    target, source = _zbuffer(target, priority, source)

    out = np.full(rows_t * cols_t, np.nan)
    landed = np.zeros(rows_t * cols_t, dtype=bool)
    out[target] = np.where(valid[source], z_color[source], np.nan)
    landed[target] = True
    out = out.reshape(rows_t, cols_t)
    _close_pinholes(out, ~landed.reshape(rows_t, cols_t))
    return metres_to_depth(out, depth_units=depth_units, inverse_scale=inverse_scale)


def _ray_span(rays: np.ndarray, camera: CameraModel) -> np.ndarray:
    """(rows, cols, 2): how far, in normalized x and y, one pixel of the camera reaches."""
    rows, cols = rays.shape[:2]
    if rows < 2 or cols < 2:
        return np.broadcast_to(1.0 / np.array(camera.focal), rays.shape).copy()
    return np.abs(np.gradient(rays, axis=1)) + np.abs(np.gradient(rays, axis=0))


def _close_pinholes(z: np.ndarray, empty: np.ndarray) -> None:
    """Fill, in place, empty pixels between two opposite samples with the farther of them.

    Opposite: left/right, up/down or either diagonal. A gap between samples
    of one surface closes; a disocclusion (samples on one side only) stays.
    """
    pad = np.pad(z, 1, constant_values=np.nan)
    farther = np.full(z.shape, np.nan)
    for (r0, c0), (r1, c1) in (((1, 0), (1, 2)), ((0, 1), (2, 1)), ((0, 0), (2, 2)), ((0, 2), (2, 0))):
        a = pad[r0:r0 + z.shape[0], c0:c0 + z.shape[1]]
        b = pad[r1:r1 + z.shape[0], c1:c1 + z.shape[1]]
        both = np.isfinite(a) & np.isfinite(b)
        farther = np.fmax(farther, np.where(both, np.fmax(a, b), np.nan))
    fill = empty & np.isfinite(farther)
    z[fill] = farther[fill]


# ----------------------------------------------------------------------------
# The chain: raw captures -> a registered low-resolution depth + color pair
# ----------------------------------------------------------------------------


#: Alignment methods of :func:`align_pair` (keys of the chain settings' ``method``).
ALIGN_METHODS = ("reproject", "shift")


@dataclass(frozen=True)
class AlignSettings:
    """How to bring a raw depth map onto the color image's grid (the ``[align]`` table).

    Attributes
    ----------
    method : {"reproject", "shift"}
        Calibrated reprojection, or the thesis's horizontal shift.
    depth_units : float, optional
        Metres per depth unit (depth grows with distance, e.g. 0.001 for mm).
    inverse_scale : float, optional
        ``metres = inverse_scale / value`` (8-bit depth intensity, disparity).
        ``reproject`` needs one of the two; ``shift`` needs one only to
        estimate ``slope`` from the rig.
    factor : int, optional
        ``reproject``: the scale factor ``s`` (default: focal-length ratio).
    radial : bool
        ``reproject``: depth is the distance along the ray, not ``Z``.
    undistort_depth : bool
        Undo the depth camera's lens distortion (spec step 1); false: the
        depth map is already undistorted.
    undistort_color : bool
        Undo the color camera's distortion (the thesis's lens has none; a
        rig calibrated with zero distortion leaves the image unchanged);
        false: the color image is already undistorted, so it is used as it
        is and the depth is aligned to the undistorted color camera.
    slope : float, optional
        ``shift``: ``k`` (default: from the rig, :func:`shift_from_rig`).
    background : float, optional
        ``shift``: ``d_bg`` in depth units (default: :func:`background_depth`).
    color_side : {"right", "left"}, optional
        ``shift``: default from the rig's translation, else ``"right"``.
    encoding : {"inverse", "distance"}, optional
        ``shift``: default ``"distance"`` when ``depth_units`` is given,
        else ``"inverse"`` (the thesis's depth intensity).
    """

    method: str = "reproject"
    depth_units: float | None = None
    inverse_scale: float | None = None
    factor: int | None = None
    radial: bool = False
    undistort_depth: bool = True
    undistort_color: bool = True
    slope: float | None = None
    background: float | None = None
    color_side: str | None = None
    encoding: str | None = None

    def __post_init__(self) -> None:
        _check_choice("method", self.method, ALIGN_METHODS)
        if self.depth_units is not None and self.inverse_scale is not None:
            raise ValueError("give either depth_units or inverse_scale, not both.")
        for name in ("depth_units", "inverse_scale", "background"):
            if getattr(self, name) is not None:
                _check_number(name, getattr(self, name), positive=True)
        if self.slope is not None:
            _check_number("slope", self.slope, nonnegative=True)
        if self.factor is not None and (isinstance(self.factor, bool) or not isinstance(self.factor, int)
                                        or self.factor < 1):
            raise ValueError(f"factor must be an integer >= 1; got {self.factor!r}.")
        for name in ("radial", "undistort_depth", "undistort_color"):
            if not isinstance(getattr(self, name), bool):
                raise TypeError(f"{name} must be true or false; got {getattr(self, name)!r}.")
        if self.color_side is not None:
            _check_choice("color_side", self.color_side, COLOR_SIDES)
        if self.encoding is not None:
            _check_choice("encoding", self.encoding, ENCODINGS)

    def to_dict(self) -> dict[str, Any]:
        """All fields (``None`` for unset ones)."""
        return asdict(self)


@dataclass(frozen=True, eq=False)
class AlignedPair:
    """A registered pair ready for :func:`depthrefine.refine`.

    Attributes
    ----------
    depth_lr : (h', w') float32 ndarray
        Depth on the color image's grid divided by ``s``, input units, NaN = invalid.
    rgb_hr : (H, W, 3) ndarray
        The color image (undistorted if asked), input dtype.
    camera : CameraModel
        The camera of ``rgb_hr``'s grid (for point clouds of the refined map).
    method : str
        The alignment used.
    notes : tuple of str
        What each step did, one line each, for the user.
    """

    depth_lr: np.ndarray
    rgb_hr: np.ndarray
    camera: CameraModel
    method: str
    notes: tuple[str, ...]


def align_depth(
    depth_raw: np.ndarray, rig: StereoRig, *, settings: AlignSettings | None = None
) -> tuple[np.ndarray, tuple[str, ...]]:
    """Undistort and align a raw depth map with a calibrated rig (spec steps 1 and 3).

    Parameters
    ----------
    depth_raw : (h, w) ndarray
        The depth camera's raw map, any units; 0 / NaN = invalid. Its shape
        must be the rig's depth camera's.
    rig : StereoRig
    settings : AlignSettings, optional
        Defaults: ``AlignSettings()`` (reprojection, which needs depth units).

    Returns
    -------
    depth_lr : float32 ndarray
        Depth for the *undistorted* color image (``reproject``: on its grid
        divided by ``s``; ``shift``: on the depth map's own grid, which the
        refinement stretches over the color image), input units, NaN =
        invalid. With a color lens that has distortion, refine against the
        undistorted color image (:func:`undistort_image`), as
        :func:`align_pair` does.
    notes : tuple of str
        What each step did, one line each.

    Raises
    ------
    ValueError
        A depth size that differs from the rig's, missing depth units,
        settings the method cannot use, or a rig on which the shift would
        misplace the background by more than one depth pixel
        (:func:`shift_misregistration`).
    """
    settings = AlignSettings() if settings is None else settings
    if not isinstance(settings, AlignSettings):
        raise TypeError(f"settings must be AlignSettings; got {type(settings).__name__}.")
    if not isinstance(rig, StereoRig):
        raise TypeError(f"rig must be a StereoRig; got {type(rig).__name__}.")
    check_depth(depth_raw, "depth")
    _check_camera_shape(depth_raw.shape, rig.depth_camera, "the depth map")
    notes: list[str] = []
    depth_lr = _CHAIN_ALIGNERS[settings.method](depth_raw, rig, settings, notes)
    return depth_lr, tuple(notes)


def align_pair(
    depth_raw: np.ndarray, rgb_raw: np.ndarray, rig: StereoRig, *, settings: AlignSettings | None = None
) -> AlignedPair:
    """Undistort and align a raw depth map and color image with a calibrated rig (spec steps 1-3).

    The scale step (spec step 2) follows in :func:`depthrefine.refine`,
    which finds the integer factor between ``depth_lr`` and ``rgb_hr`` and
    resizes the color bilinearly when the ratio is not an integer.

    Parameters
    ----------
    depth_raw : (h, w) ndarray
        The depth camera's raw map, any units; 0 / NaN = invalid.
    rgb_raw : (H, W, 3) ndarray
        The color camera's raw image (RGB).
    rig : StereoRig
    settings : AlignSettings, optional
        Defaults: ``AlignSettings()`` (reprojection, which needs depth units).

    Returns
    -------
    AlignedPair

    Raises
    ------
    ValueError
        Image sizes that differ from the rig's, missing depth units, or
        settings the method cannot use.
    """
    settings = AlignSettings() if settings is None else settings
    if not isinstance(rig, StereoRig):
        raise TypeError(f"rig must be a StereoRig; got {type(rig).__name__}.")
    rgb = check_rgb(rgb_raw, "color image")
    _check_camera_shape(rgb.shape, rig.color_camera, "the color image")
    depth_lr, depth_notes = align_depth(depth_raw, rig, settings=settings)
    color_cam = rig.color_camera
    notes = []
    if _undistorts_color(rig, settings):
        rgb = undistort_image(rgb, color_cam)
        notes.append("color image undistorted (bilinear)")
    elif color_cam.has_distortion:
        notes.append("color image taken as already undistorted")
    return AlignedPair(depth_lr, rgb, color_cam.without_distortion(), settings.method,
                       tuple(notes) + depth_notes)


def _undistorts_color(rig: StereoRig, settings: AlignSettings) -> bool:
    return settings.undistort_color and rig.color_camera.has_distortion


def _chain_reproject(depth_raw, rig, settings, notes) -> np.ndarray:
    if settings.depth_units is None and settings.inverse_scale is None:
        raise ValueError(
            "the reproject alignment needs the depth's units: depth_units (--depth-units; metres per unit, "
            "e.g. 0.001 for uint16 mm) or, for 8-bit depth intensity (larger = nearer), inverse_scale "
            "(--inverse-depth-scale) with metres = inverse_scale / value; or use the shift alignment."
        )
    s, grid = reproject_camera(rig, factor=settings.factor)
    out = align_reproject(
        depth_raw, rig, depth_units=settings.depth_units, inverse_scale=settings.inverse_scale,
        factor=s, radial=settings.radial, depth_distorted=settings.undistort_depth, color_distorted=False,
    )
    w, h = grid.image_size
    notes.append(f"depth reprojected into the color camera ({w}x{h} grid, s = {s}, z-buffer"
                 f"{', depth lens distortion undone' if settings.undistort_depth else ''})")
    return out


def _chain_shift(depth_raw, rig, settings, notes) -> np.ndarray:
    depth = depth_raw
    if settings.undistort_depth and rig.depth_camera.has_distortion:
        depth = undistort_depth(depth_raw, rig.depth_camera)
        notes.append("depth undistorted (nearest)")
    encoding = settings.encoding or ("distance" if settings.depth_units is not None else "inverse")
    slope, color_side = settings.slope, settings.color_side
    if slope is None or color_side is None:
        if settings.depth_units is None and settings.inverse_scale is None:
            if slope is None:
                raise ValueError(
                    "the shift alignment needs its slope: give slope (--slope; depth pixels per depth unit), "
                    "or the depth's units (--depth-units or --inverse-depth-scale) to compute it from the rig."
                )
            color_side = "right" if rig.color_centre[0] >= 0 else "left"
        else:
            model = shift_from_rig(rig, depth_units=settings.depth_units, inverse_scale=settings.inverse_scale)
            if model.encoding != encoding:
                raise ValueError(
                    f"encoding {encoding!r} does not match the units given "
                    f"({'depth_units' if model.encoding == 'distance' else 'inverse_scale'} implies "
                    f"{model.encoding!r})."
                )
            slope = model.slope if slope is None else slope
            color_side = model.color_side if color_side is None else color_side
    background = settings.background
    if background is None:
        background = background_depth(depth, encoding=encoding)
    z_background = None  # metres, when the units say so; else the check looks at infinity
    if encoding == "distance" and settings.depth_units is not None:
        z_background = background * settings.depth_units
    elif encoding == "inverse" and settings.inverse_scale is not None:
        z_background = settings.inverse_scale / background
    error = shift_misregistration(rig, depth.shape, rig.color_camera.shape, z_background)
    if error > MAX_SHIFT_MISREGISTRATION:
        at = f"{z_background:.3g} m" if z_background is not None else "infinity (depth units unknown)"
        raise ValueError(
            f"the shift alignment would misplace the depth by {error:.1f} depth pixels on this rig (the color "
            f"image does not show the depth camera's field of view: different focal lengths, principal points "
            f"or a rotation; checked at the background, {at}); use the reproject alignment (the default: "
            f"--align reproject in run, --method reproject in align) or crop the color image to the depth "
            f"camera's view."
        )
    out = align_shift(depth, slope=slope, background=background, color_side=color_side, encoding=encoding)
    notes.append(f"depth shifted horizontally (thesis eq. 1): k = {slope:.6g}, d_bg = {background:.6g}, "
                 f"color camera on the {color_side}, {encoding} depth")
    return out


_CHAIN_ALIGNERS = {"reproject": _chain_reproject, "shift": _chain_shift}
