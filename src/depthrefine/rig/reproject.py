"""Calibrated reprojection of depth into the color camera (beyond the thesis).

For calibrated rigs that need not be parallel: back-project each depth pixel
with the depth camera's intrinsics (undoing its lens distortion), move it with
``R, t``, project it into the color camera and keep the nearest point per
pixel (z-buffer), like ``cv2.registerDepth``. It renders into a color-camera
grid of ``(round(H / s), round(W / s))`` pixels whose intrinsics are the color
camera's scaled to that grid: a grid at the depth camera's own resolution
(about one depth sample per grid pixel), which the refinement then
upsamples. ``s`` defaults to the focal-length ratio rounded to an integer
when that is at least 2 (the grid then divides the color image), else to
the ratio itself (the Azure Kinect's 1.21: a 1056x594 grid for the 1280x720
color image, where an integer would throw samples away or leave nothing
to upsample). Each depth pixel writes every grid
pixel its footprint covers (its angular size through the lens, times the
depth ratio), so a surface seen slightly magnified has no gaps for the
background to show through (``cv2.registerDepth`` writes one pixel per sample
and has them). An invalid depth pixel travels with its nearest valid
neighbour and hides what lies behind it without writing a depth, and a far
sample the parallax moved between nearer ones is hidden (the wall seen
through the gaps between a mug's samples). An empty pixel between two
opposite samples takes the farther one; wider disocclusions stay invalid
(NaN) and are filled by the refinement.
The values are the depth along the *color* camera's axis, in the input's
units. Invalid depth (NaN / 0) stays invalid and is never filled here.
"""

from __future__ import annotations


import numpy as np

from .._fill import fill_invalid_nearest
from .._validate import as_depth
from ._geometry import depth_conversion, metres64, zbuffer
from .camera import CameraModel, StereoRig, check_camera_shape
from .pointcloud import metres_to_depth, pixel_rays, project_points

__all__ = ["reproject_camera", "default_factor", "align_reproject"]

#: A sample hides behind nearer ones (:func:`_seen_between`; an invalid pixel's guess, too) when it is farther than
#: they are by this share ...
SAME_SURFACE = 0.05
#: ... and comes from more than this many pixels away from them in the depth image (moved there by the parallax,
#: not seen through a gap between them).
PARALLAX_JUMP = 2.5



def reproject_camera(rig: StereoRig, *, factor: float | None = None,
                     distorted: bool = False) -> tuple[float, CameraModel]:
    """The factor ``s`` and the low-resolution color-camera grid :func:`align_reproject` renders into.

    Parameters
    ----------
    rig : StereoRig
    factor : float, optional
        ``s`` (any number >= 1; an integer divides the color image evenly).
        Default: the focal-length ratio ``f_color / f_depth`` (mean of x and
        y), rounded to an integer when that is at least 2, else the ratio
        itself (at least 1): a grid at the depth camera's resolution.
    distorted : bool
        Keep the color camera's distortion (grid of a raw color image).

    Returns
    -------
    s : int or float
    camera : CameraModel
        The color camera resized to ``(round(H / s), round(W / s))``.

    Examples
    --------
    >>> d = CameraModel(np.array([[100., 0, 43.5], [0, 100., 35.5], [0, 0, 1]]), np.zeros(5), (88, 72))
    >>> c = CameraModel(np.array([[700., 0, 307.5], [0, 700., 251.5], [0, 0, 1]]), np.zeros(5), (616, 504))
    >>> s, grid = reproject_camera(StereoRig(d, c, np.eye(3), np.zeros(3)))
    >>> s, grid.image_size, grid.K[0].tolist()
    (7, (88, 72), [100.0, 0.0, 43.5])
    >>> c12 = CameraModel(np.array([[120., 0, 52.3], [0, 120., 42.5], [0, 0, 1]]), np.zeros(5), (106, 86))
    >>> s, grid = reproject_camera(StereoRig(d, c12, np.eye(3), np.zeros(3)))
    >>> s, grid.image_size
    (1.2, (88, 72))
    """
    color = rig.color_camera
    if factor is None:
        factor = default_factor(rig)
    elif (isinstance(factor, bool) or not isinstance(factor, (int, float, np.integer, np.floating))
          or not np.isfinite(factor) or factor < 1):
        raise ValueError(f"factor must be a number >= 1 (the color grid / the rendered grid); got {factor!r}.")
    rows, cols = color.shape
    grid = (max(1, int(np.floor(rows / factor + 0.5))), max(1, int(np.floor(cols / factor + 0.5))))
    camera = color.resized(grid)
    factor = int(factor) if float(factor).is_integer() else float(factor)
    return factor, (camera if distorted else camera.without_distortion())


def default_factor(rig: StereoRig) -> float:
    """The default ``s`` of :func:`reproject_camera`: ``round(f_color / f_depth)`` if at least 2, else the ratio (>= 1).

    Examples
    --------
    >>> d = CameraModel(np.array([[100., 0, 43.5], [0, 100., 35.5], [0, 0, 1]]), np.zeros(5), (88, 72))
    >>> c = CameraModel(np.array([[740., 0, 307.5], [0, 740., 251.5], [0, 0, 1]]), np.zeros(5), (616, 504))
    >>> default_factor(StereoRig(d, c, np.eye(3), np.zeros(3)))
    7
    """
    ratio = float(np.mean(np.array(rig.color_camera.focal) / np.array(rig.depth_camera.focal)))
    rounded = int(np.floor(ratio + 0.5))
    return rounded if rounded >= 2 else max(1.0, ratio)


def align_reproject(
    depth: np.ndarray,
    rig: StereoRig,
    *,
    depth_units: float | None = None,
    inverse_scale: float | None = None,
    factor: float | None = None,
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
        disparity (see :mod:`depthrefine.rig.pointcloud`). Without it the depth
        cannot be placed in 3-D: ``ValueError``.
    factor : float, optional
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
    writes its footprint (see the module docstring); a far sample between
    nearer ones that the parallax moved there from elsewhere in the depth
    image is hidden (:func:`_seen_between`); then an empty pixel between
    two opposite samples takes the farther one.

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
    depth_conversion(depth_units, inverse_scale)
    d = as_depth(depth, "depth")
    check_camera_shape(d.shape, rig.depth_camera, "depth")
    _, grid = reproject_camera(rig, factor=factor, distorted=color_distorted)
    rows_t, cols_t = grid.shape

    z = metres64(d, depth_units, inverse_scale)
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
    # nearest wins; an invalid pixel, at its nearest valid neighbour's depth, hides what lies behind it (writing
    # no depth) but loses to a valid sample of its own surface (within SAME_SURFACE)
    priority = np.where(valid[source], -z_color[source], -z_color[source] * (1.0 + SAME_SURFACE))
    target, source = zbuffer(target, priority, source)

    out = np.full(rows_t * cols_t, np.nan)
    winner = np.full(rows_t * cols_t, np.nan)   # the depth of each pixel's sample, an invalid one's neighbour's too
    origin = np.full((2, rows_t * cols_t), np.nan)   # and where that sample lies in the depth image (row, column)
    out[target] = np.where(valid[source], z_color[source], np.nan)
    winner[target] = z_color[source]
    origin[:, target] = np.divmod(source, d.shape[1])
    out, winner = out.reshape(rows_t, cols_t), winner.reshape(rows_t, cols_t)
    hidden = _seen_between(winner, origin.reshape(2, rows_t, cols_t))
    out[hidden] = np.nan
    _close_pinholes(out, np.isnan(winner) | hidden)
    return metres_to_depth(out, depth_units=depth_units, inverse_scale=inverse_scale)


def _ray_span(rays: np.ndarray, camera: CameraModel) -> np.ndarray:
    """(rows, cols, 2): how far, in normalized x and y, one pixel of the camera reaches."""
    rows, cols = rays.shape[:2]
    if rows < 2 or cols < 2:
        return np.broadcast_to(1.0 / np.array(camera.focal), rays.shape).copy()
    return np.abs(np.gradient(rays, axis=1)) + np.abs(np.gradient(rays, axis=0))


def _seen_between(z: np.ndarray, origin: np.ndarray) -> np.ndarray:
    """Where a far sample shows between two nearer ones from elsewhere in the depth image: background through a gap.

    Samples of a near surface land on the grid about one pixel apart, but
    not exactly: their spacing changes with the parallax, which changes
    with the depth, so a pixel here and there gets none, and a sample of
    the surface behind, moved farther by the parallax, takes it. Such a
    sample is farther by more than :data:`SAME_SURFACE` than the samples on
    both sides of it (along a row, a column or a diagonal, in a run of at
    most two such pixels), and it comes from more than
    :data:`PARALLAX_JUMP` pixels away from both in the depth image. A gap
    the depth camera saw between two near samples (two pencils, a handle)
    lies between them in the depth image too, and stays. ``z`` holds each
    pixel's sample (an invalid depth pixel's the depth of its nearest valid
    one: the Azure Kinect leaves 2-3 pixels empty between a mug and the
    wall, and the mug's ones must hide the wall too), ``origin``
    (2, rows, cols) the depth image row and column of each pixel's sample
    (NaN where none).
    """
    rows, cols = z.shape
    pad = np.pad(z, 2, constant_values=np.nan)
    pad_origin = np.pad(origin, ((0, 0), (2, 2), (2, 2)), constant_values=np.nan)

    def nearer_from_afar(dr: int, dc: int) -> np.ndarray:
        window = (slice(2 + dr, 2 + dr + rows), slice(2 + dc, 2 + dc + cols))
        apart = np.hypot(*(pad_origin[(k, *window)] - origin[k] for k in (0, 1)))
        return (pad[window] < z / (1.0 + SAME_SURFACE)) & (apart > PARALLAX_JUMP)

    hidden = np.zeros(z.shape, bool)
    with np.errstate(invalid="ignore"):
        for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):
            side = {k: nearer_from_afar(k * dr, k * dc) for k in (-2, -1, 1, 2)}
            hidden |= (side[-1] & side[1]) | (side[-1] & side[2]) | (side[-2] & side[1])   # runs of 1 and 2
    return hidden


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
