"""The thesis's shift alignment (spec step 3; thesis 3.2.2, eq. 1, Fig. 23-24).

The cameras sit side by side, so every depth pixel moves horizontally by
``shift = k * (d - d_bg)`` depth pixels, ``d`` being the depth intensity
(proportional to 1 / distance) and ``d_bg`` the background's (the x-axis
intercept, so the background does not move). Nearer pixels win collisions;
occlusion holes take the nearest valid depth on the background side (the side
of the color camera); a hole with nothing on that side (at the image border)
takes the foreground's depth from the other side (Fig. 24c). The output has
the depth map's own shape: it lies on the color image's grid after the scale
step, which ``refine`` applies.

**Decision (grid):** the shift is done on the low-resolution grid, each pixel
landing on ``col + round(shift)`` with a fractional ``shift``, at ``1/s**2`` of
the cost of shifting the ``s``-times enlarged map; ``k`` is therefore in depth
pixels per depth unit and does not depend on ``s``. It is close to, not the
same as, shifting the enlarged map by ``s * shift`` and reading it back at the
depth-pixel centres: where the two round differently, a hole left by a moved
pixel can take the foreground that moved in instead of the background (a
one-pixel difference at depth edges).

The shift assumes the color image shows the depth camera's field of view: the
background (``d_bg``) must land where the depth grid stretched over the color
image puts it. :func:`shift_misregistration` measures how far it does not
(different focal lengths, principal points, a rotation); the chain
(:func:`depthrefine.rig.chain.align_depth`) refuses the shift beyond one depth
pixel.

Invalid depth (NaN / 0) stays invalid: an invalid pixel is moved as its
nearest valid neighbour would be, loses every collision against a valid one,
and marks where it lands as unmeasured (never filled).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from .._fill import fill_invalid_nearest
from .._validate import as_depth, check_choice, check_number
from ._names import COLOR_SIDES, ENCODINGS
from ._geometry import depth_conversion, zbuffer
from .camera import StereoRig

__all__ = [
    "COLOR_SIDES",
    "ENCODINGS",
    "MAX_PARALLEL_ROTATION",
    "MAX_SHIFT_MISREGISTRATION",
    "AlignmentWarning",
    "background_depth",
    "align_shift",
    "ShiftModel",
    "shift_from_rig",
    "shift_misregistration",
]

#: A rig rotated more than this (degrees) is not the parallel rig the shift assumes.
MAX_PARALLEL_ROTATION = 2.0
#: The chain refuses the shift alignment when the background lands farther than this (depth pixels)
#: from where the stretched depth grid puts it (see :func:`shift_misregistration`).
MAX_SHIFT_MISREGISTRATION = 1.0


class AlignmentWarning(UserWarning):
    """The rig does not fit the assumptions of the chosen alignment."""


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
    check_choice("encoding", encoding, ENCODINGS)
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
    k = check_number("slope", slope, nonnegative=True)
    check_choice("color_side", color_side, COLOR_SIDES)
    check_choice("encoding", encoding, ENCODINGS)
    if background is None:
        background = background_depth(d, encoding=encoding)
    d_bg = check_number("background", background, positive=True)
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
    target, source = zbuffer(target, priority, source)

    out = np.full(h * w, np.nan, dtype=np.float32)
    landed = np.zeros(h * w, dtype=bool)
    out[target] = d.ravel()[source]
    landed[target] = True
    out = out.reshape(h, w)
    _fill_holes_along_rows(out, ~landed.reshape(h, w), from_right=(color_side == "right"))
    return out


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
    >>> from depthrefine.rig import CameraModel
    >>> cam = CameraModel(np.array([[200., 0, 87.5], [0, 200., 71.5], [0, 0, 1]]), np.zeros(5), (176, 144))
    >>> rig = StereoRig(cam, cam, np.eye(3), np.array([-0.05, 0.0, 0.0]))
    >>> shift_from_rig(rig, depth_units=0.001)
    ShiftModel(slope=10000.0, color_side='right', encoding='distance')
    """
    kind, value = depth_conversion(depth_units, inverse_scale)
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
    >>> from depthrefine.rig import CameraModel
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
        z_background = check_number("z_background", z_background, positive=True)
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
