"""From depth maps to 3-D points and back: metric conversion, back-projection, projection.

Used by the calibrated alignment (:func:`depthrefine.rig.align_reproject`)
and for exporting a refined depth map as a colored point cloud in the color
camera's frame (written as PLY by :func:`depthrefine.io.write_ply`).

Depth units
-----------
Depth inside the library is in the input's own units. Geometry needs metres,
so every function here takes exactly one of two conversions:

- ``depth_units``: metres per depth unit, for depth that grows with distance
  (``0.001`` for uint16 millimetres, ``1.0`` for float metres);
  ``metres = value * depth_units``.
- ``inverse_scale``: for depth that shrinks with distance, such as the
  thesis's 8-bit "depth intensity" (larger = nearer, proportional to
  1 / distance) or disparity; ``metres = inverse_scale / value``. For an
  8-bit map that puts 255 at the nearest distance ``z_min``,
  ``inverse_scale = 255 * z_min``.

The depth value is the ``Z`` coordinate (along the optical axis), as OpenCV
and ``cv2.registerDepth`` use it; pass ``radial=True`` where a camera reports
the distance along the ray instead.
"""

from __future__ import annotations

import math

import numpy as np

from .._lazy import cv2
from ._geometry import depth_conversion, metres64
from .camera import CameraModel

__all__ = [
    "PLAUSIBLE_DEPTH_M",
    "median_metres",
    "implausible_units",
    "depth_to_metres",
    "metres_to_depth",
    "pixel_rays",
    "backproject",
    "project_points",
    "depth_to_points",
    "color_grid_points",
]

_UNDISTORT_CRITERIA = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 50, 1e-10)


def depth_to_metres(
    depth: np.ndarray, *, depth_units: float | None = None, inverse_scale: float | None = None
) -> np.ndarray:
    """Convert depth in its own units to metres (NaN stays NaN).

    Parameters
    ----------
    depth : (rows, cols) ndarray
        Depth in any units; 0, NaN, inf and negative values are invalid.
    depth_units, inverse_scale : float
        Exactly one, see the module docstring.

    Returns
    -------
    (rows, cols) float32 ndarray
        Metres, NaN where invalid.

    Examples
    --------
    >>> depth_to_metres(np.array([[0, 1500]], np.uint16), depth_units=0.001).tolist()
    [[nan, 1.5]]
    >>> depth_to_metres(np.array([[255, 51]], np.uint8), inverse_scale=204.0).tolist()
    [[0.800000011920929, 4.0]]
    """
    return metres64(depth, depth_units, inverse_scale).astype(np.float32)


#: Median depths (metres) a ToF camera can report: outside, the depth units are likely wrong
#: (millimetres read as metres give kilometres; metres read as millimetres, millimetres).
PLAUSIBLE_DEPTH_M = (0.05, 50.0)


def median_metres(depth: np.ndarray, *, depth_units: float | None = None,
                  inverse_scale: float | None = None) -> float:
    """The median of the valid depths in metres (NaN when no pixel is valid): a check of the units.

    Compare it with :data:`PLAUSIBLE_DEPTH_M`.

    Examples
    --------
    >>> d = np.array([[0, 900, 1500, 2000]], np.uint16)
    >>> median_metres(d, depth_units=0.001), median_metres(d, depth_units=1.0)
    (1.5, 1500.0)
    """
    metres = metres64(depth, depth_units, inverse_scale)
    valid = metres[np.isfinite(metres) & (metres > 0)]
    return float(np.median(valid)) if valid.size else math.nan


def implausible_units(depth: np.ndarray, *, depth_units: float | None = None,
                      inverse_scale: float | None = None) -> str | None:
    """Why the units look wrong (the median depth is outside :data:`PLAUSIBLE_DEPTH_M`), or ``None``.

    The message names the units and the median, and for ``depth_units`` the
    units that would put the median in a room's range, worded for the
    command line (``--depth-units``). ``None`` also when no unit is given or
    no pixel is valid.

    Examples
    --------
    >>> d = np.array([[0, 900, 1500, 2000]], np.uint16)
    >>> implausible_units(d, depth_units=0.001) is None
    True
    >>> implausible_units(d, depth_units=1.0)
    'depth units 1 m per stored value give a median depth of 1.5 km, outside the 5 cm .. 50 m a ToF camera \
measures: the units are probably wrong; if the file holds millimetres, give --depth-units 0.001'
    """
    if depth_units is None and inverse_scale is None:
        return None
    median = median_metres(depth, depth_units=depth_units, inverse_scale=inverse_scale)
    lo, hi = PLAUSIBLE_DEPTH_M
    if not math.isfinite(median) or lo <= median <= hi:
        return None
    if depth_units is not None:
        units = f"depth units {depth_units:g} m per stored value"
        stored = median / depth_units
        names = {1.0: "metres", 0.01: "centimetres", 0.001: "millimetres", 0.0001: "0.1 mm"}
        fits = [u for u in names if lo <= stored * u <= hi]
        best = min(fits, key=lambda u: abs(math.log(stored * u / 2.0)), default=None)  # nearest a room's 2 m
        hint = f"; if the file holds {names[best]}, give --depth-units {best:g}" if best else ""
    else:
        units = f"inverse depth scale {inverse_scale:g} (metres = scale / value)"
        hint = ""
    return (f"{units} give a median depth of {_length(median)}, outside the {_length(lo)} .. {_length(hi)} a ToF "
            f"camera measures: the units are probably wrong{hint}")


def _length(metres: float) -> str:
    """``0.05`` -> ``"5 cm"``, ``1930.0`` -> ``"1.93 km"``.

    Examples
    --------
    >>> _length(0.05), _length(2.5), _length(1930.0), _length(0.0004)
    ('5 cm', '2.5 m', '1.93 km', '0.4 mm')
    """
    for unit, size in (("km", 1000.0), ("m", 1.0), ("cm", 0.01), ("mm", 0.001)):
        if metres >= size or unit == "mm":
            return f"{metres / size:.3g} {unit}"
    return f"{metres:g} m"


def metres_to_depth(
    z: np.ndarray, *, depth_units: float | None = None, inverse_scale: float | None = None
) -> np.ndarray:
    """The inverse of :func:`depth_to_metres` (float32, NaN stays NaN).

    Examples
    --------
    >>> metres_to_depth(np.array([1.5, np.nan]), depth_units=0.001).tolist()
    [1500.0, nan]
    """
    kind, value = depth_conversion(depth_units, inverse_scale)
    z = np.asarray(z, dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = z / value if kind == "distance" else value / z
    return out.astype(np.float32)


def pixel_rays(camera: CameraModel, *, distorted: bool = True) -> np.ndarray:
    """Normalized rays ``(x, y)`` of every pixel: the point at depth ``Z`` is ``(x Z, y Z, Z)``.

    Parameters
    ----------
    camera : CameraModel
    distorted : bool
        The pixels are those of a raw image (undo the lens distortion). False
        for an undistorted image (pure pinhole with ``camera.K``).

    Returns
    -------
    (rows, cols, 2) float64 ndarray
    """
    rows, cols = camera.shape
    grid = np.mgrid[0:rows, 0:cols].astype(np.float64)
    pix = np.stack([grid[1], grid[0]], axis=-1).reshape(-1, 1, 2)
    dist = camera.dist if (distorted and camera.has_distortion) else None
    norm = cv2.undistortPoints(pix, camera.K, dist, criteria=_UNDISTORT_CRITERIA)
    return norm.reshape(rows, cols, 2)


def backproject(
    cols: np.ndarray, rows: np.ndarray, z: np.ndarray, camera: CameraModel, *, distorted: bool = False
) -> np.ndarray:
    """3-D points of pixels ``(cols, rows)`` at depth ``z`` (metres) in the camera's frame.

    Parameters
    ----------
    cols, rows : (N,) ndarray
        Pixel coordinates (x = column, y = row; sub-pixel allowed).
    z : (N,) ndarray
        Depth along the optical axis, metres.
    camera : CameraModel
    distorted : bool
        Undo the lens distortion (pixels of a raw image).

    Returns
    -------
    (N, 3) float64 ndarray

    Examples
    --------
    >>> cam = CameraModel(np.array([[100., 0, 2], [0, 100., 2], [0, 0, 1]]), np.zeros(5), (5, 5))
    >>> backproject(np.array([4.0]), np.array([2.0]), np.array([2.0]), cam).tolist()
    [[0.04, 0.0, 2.0]]
    """
    cols, rows, z = (np.asarray(a, dtype=np.float64).ravel() for a in (cols, rows, z))
    if not (cols.shape == rows.shape == z.shape):
        raise ValueError(f"cols, rows and z must have the same length; got {cols.size}, {rows.size}, {z.size}.")
    if cols.size == 0:
        return np.zeros((0, 3))
    pix = np.stack([cols, rows], axis=-1).reshape(-1, 1, 2)
    dist = camera.dist if (distorted and camera.has_distortion) else None
    norm = cv2.undistortPoints(pix, camera.K, dist, criteria=_UNDISTORT_CRITERIA).reshape(-1, 2)
    return np.column_stack([norm[:, 0] * z, norm[:, 1] * z, z])


def project_points(points: np.ndarray, camera: CameraModel, *, distorted: bool = False) -> np.ndarray:
    """Pixel positions ``(x, y)`` of 3-D points in the camera's frame (``cv2.projectPoints``).

    Parameters
    ----------
    points : (N, 3) ndarray
        Points in metres, ``Z > 0``.
    camera : CameraModel
    distorted : bool
        Apply the lens distortion (positions in a raw image).

    Returns
    -------
    (N, 2) float64 ndarray
        ``(x, y)`` = (column, row), pixels.

    Examples
    --------
    >>> cam = CameraModel(np.array([[100., 0, 2], [0, 100., 2], [0, 0, 1]]), np.zeros(5), (5, 5))
    >>> project_points(np.array([[0.04, 0.0, 2.0]]), cam).tolist()
    [[4.0, 2.0]]
    """
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    if pts.shape[0] == 0:
        return np.zeros((0, 2))
    dist = camera.dist if (distorted and camera.has_distortion) else None
    out, _ = cv2.projectPoints(pts.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), camera.K, dist)
    return out.reshape(-1, 2)


def depth_to_points(
    depth: np.ndarray,
    camera: CameraModel,
    *,
    rgb: np.ndarray | None = None,
    depth_units: float | None = None,
    inverse_scale: float | None = None,
    distorted: bool = False,
    stride: int = 1,
) -> tuple[np.ndarray, np.ndarray | None]:
    """A colored point cloud of a depth map, in its camera's frame.

    Parameters
    ----------
    depth : (rows, cols) ndarray
        Depth on the camera's pixel grid (for a refined map: the color
        camera's), any units; invalid pixels give no point.
    camera : CameraModel
        The camera of ``depth``; its ``image_size`` must match the depth's shape.
    rgb : (rows, cols, 3) ndarray, optional
        Color of each pixel (uint8, uint16 or float in [0, 1]).
    depth_units, inverse_scale : float
        Exactly one (see the module docstring).
    distorted : bool
        ``depth`` is a raw (not undistorted) image of a camera with distortion.
    stride : int
        Keep every ``stride``-th row and column (thinner clouds).

    Returns
    -------
    points : (N, 3) float32 ndarray
        ``(X, Y, Z)`` in metres: X right, Y down, Z forward (OpenCV).
    colors : (N, 3) uint8 ndarray or None
        RGB per point (None without ``rgb``).

    Raises
    ------
    ValueError
        Shapes that do not match the camera, no conversion to metres.

    Examples
    --------
    >>> cam = CameraModel(np.array([[10., 0, 1.5], [0, 10., 1.5], [0, 0, 1]]), np.zeros(5), (4, 4))
    >>> pts, _ = depth_to_points(np.full((4, 4), 2000, np.uint16), cam, depth_units=0.001)
    >>> pts.shape, pts[0].tolist()
    ((16, 3), [-0.30000001192092896, -0.30000001192092896, 2.0])
    """
    z = depth_to_metres(depth, depth_units=depth_units, inverse_scale=inverse_scale)
    if z.shape != camera.shape:
        raise ValueError(
            f"depth has shape {z.shape} but the camera's images are {camera.shape} (rows, cols); "
            "give the camera of this depth map (for a refined map, the color camera)."
        )
    if isinstance(stride, bool) or not isinstance(stride, (int, np.integer)) or stride < 1:
        raise ValueError(f"stride must be an integer >= 1; got {stride!r}.")
    colors = None
    if rgb is not None:
        from .._validate import check_rgb

        rgb = check_rgb(rgb, "rgb")
        if rgb.shape[:2] != z.shape:
            raise ValueError(f"rgb has shape {rgb.shape[:2]} but depth has {z.shape}; they must match.")
        colors = _to_uint8(rgb)
    rows, cols = np.mgrid[0:z.shape[0]:stride, 0:z.shape[1]:stride]
    zs = z[rows, cols]
    keep = np.isfinite(zs)
    points = backproject(cols[keep], rows[keep], zs[keep], camera, distorted=distorted).astype(np.float32)
    if colors is not None:
        colors = np.ascontiguousarray(colors[rows[keep], cols[keep]])
    return points, colors



def color_grid_points(
    depth: np.ndarray,
    rgb: np.ndarray,
    camera: CameraModel,
    *,
    depth_units: float | None = None,
    inverse_scale: float | None = None,
    raw_grid: bool = False,
    color_undistorted: bool = False,
    stride: int = 1,
) -> tuple[np.ndarray, np.ndarray]:
    """The colored point cloud of a depth map on a color camera's grid (``depthrefine export-ply``).

    Parameters
    ----------
    depth : (rows, cols) ndarray
        Depth on the color camera's grid, any units (e.g. the output of ``run``).
    rgb : (rows, cols, 3) ndarray
        The color image: raw, unless ``color_undistorted``.
    camera : CameraModel
        The color camera.
    depth_units, inverse_scale : float
        Exactly one (see the module docstring).
    raw_grid : bool
        ``depth`` and ``rgb`` lie on the raw (distorted) grid: back-project
        through the lens distortion. Default: ``depth`` lies on the
        undistorted grid, as ``align`` and ``run`` write it, and ``rgb`` is
        undistorted to match (for a camera with distortion).
    color_undistorted : bool
        ``rgb`` is undistorted already (with the default ``raw_grid=False``).
    stride : int
        Keep every ``stride``-th row and column.

    Returns
    -------
    points : (N, 3) float32 ndarray
        Metres in the color camera's frame: X right, Y down, Z forward.
    colors : (N, 3) uint8 ndarray

    Examples
    --------
    >>> cam = CameraModel(np.array([[10., 0, 1.5], [0, 10., 1.5], [0, 0, 1]]), np.zeros(5), (4, 4))
    >>> pts, colors = color_grid_points(np.full((4, 4), 2000, np.uint16), np.zeros((4, 4, 3), np.uint8), cam,
    ...                                 depth_units=0.001)
    >>> pts.shape, colors.shape
    ((16, 3), (16, 3))
    """
    distorted = camera.has_distortion and raw_grid
    if camera.has_distortion and not raw_grid:
        if not color_undistorted:
            from .undistort import undistort_image

            rgb = undistort_image(rgb, camera)
        camera = camera.without_distortion()
    return depth_to_points(depth, camera, rgb=rgb, depth_units=depth_units, inverse_scale=inverse_scale,
                           distorted=distorted, stride=stride)

def _to_uint8(rgb: np.ndarray) -> np.ndarray:
    if rgb.dtype == np.uint8:
        return rgb
    if rgb.dtype == np.uint16:
        return (rgb >> 8).astype(np.uint8)
    return np.floor(np.clip(rgb, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)
