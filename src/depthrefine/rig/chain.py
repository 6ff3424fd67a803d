"""The chain: raw captures -> a registered low-resolution depth + color pair.

Two alignments bring the depth map onto the color image's grid, both
returning a *low-resolution* depth map for :func:`depthrefine.refine`, which
spreads depth pixel ``(i, j)`` to color pixel ``(i*s + s//2, j*s + s//2)``:
``shift`` (the thesis, :mod:`depthrefine.rig.shift`) and ``reproject``
(calibrated reprojection, :mod:`depthrefine.rig.reproject`). The chain
undistorts (:mod:`depthrefine.rig.undistort`), aligns, and says what it did.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from .._validate import check_choice, check_depth, check_number, check_rgb
from ._names import ALIGN_METHODS
from .camera import CameraModel, StereoRig, check_camera_shape
from .reproject import align_reproject, reproject_camera
from .shift import (COLOR_SIDES, ENCODINGS, MAX_SHIFT_MISREGISTRATION, align_shift, background_depth, shift_from_rig, shift_misregistration)
from .undistort import undistort_depth, undistort_image

__all__ = ["ALIGN_METHODS", "AlignSettings", "AlignedPair", "align_depth", "align_pair", "unmeasured_on_grid",
           "keep_unmeasured", "unmeasured_along_color", "nearest_on_grid", "upsampling_grid", "refine_pair",
           "reprojected_params"]

#: The smallest factor the refinement of an aligned pair upsamples by (:func:`upsampling_grid`).
MIN_UPSAMPLING = 2
#: :func:`keep_unmeasured` with a color image moves the border of the unmeasured pixels onto the color edges within
#: this many depth pixels on either side (the strip a depth camera leaves empty at an outline: the Azure Kinect
#: 2-3 pixels between a mug and the wall behind it) ...
BORDER_BAND = 2.0
#: ... along paths whose step costs the color difference (8-bit levels, the color blurred by this sigma, px) ...
BORDER_BLUR = 1.0
#: ... plus this many levels.
BORDER_STEP_LEVELS = 2.0


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
    factor : float, optional
        ``reproject``: the rendered grid is the color grid / ``s`` (default:
        :func:`~depthrefine.rig.reproject.default_factor`, the grid at the depth
        camera's resolution).
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
    factor: float | None = None
    radial: bool = False
    undistort_depth: bool = True
    undistort_color: bool = True
    slope: float | None = None
    background: float | None = None
    color_side: str | None = None
    encoding: str | None = None

    def __post_init__(self) -> None:
        check_choice("method", self.method, ALIGN_METHODS)
        if self.depth_units is not None and self.inverse_scale is not None:
            raise ValueError("give either depth_units or inverse_scale, not both.")
        for name in ("depth_units", "inverse_scale", "background"):
            if getattr(self, name) is not None:
                check_number(name, getattr(self, name), positive=True)
        if self.slope is not None:
            check_number("slope", self.slope, nonnegative=True)
        if self.factor is not None and (isinstance(self.factor, bool) or not isinstance(self.factor, (int, float))
                                        or not self.factor >= 1 or self.factor == float("inf")):
            raise ValueError(f"factor must be a number >= 1 (the color grid / the rendered grid); got {self.factor!r}.")
        for name in ("radial", "undistort_depth", "undistort_color"):
            if not isinstance(getattr(self, name), bool):
                raise TypeError(f"{name} must be true or false; got {getattr(self, name)!r}.")
        if self.color_side is not None:
            check_choice("color_side", self.color_side, COLOR_SIDES)
        if self.encoding is not None:
            check_choice("encoding", self.encoding, ENCODINGS)

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
    check_camera_shape(depth_raw.shape, rig.depth_camera, "the depth map")
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
    check_camera_shape(rgb.shape, rig.color_camera, "the color image")
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


def unmeasured_on_grid(depth_lr: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """Where on a ``shape = (rows, cols)`` grid no depth was measured: ``depth_lr``'s invalid pixels, enlarged.

    Each pixel of ``depth_lr`` covers the block of the larger grid it is
    spread over by the refinement (nearest, pixel centres aligned), so a
    pixel is unmeasured when the aligned depth has no value there: outside
    the depth camera's view (the Azure Kinect's NFOV hexagon), invalid in the
    raw map, or hidden from the depth camera (a disocclusion).

    Examples
    --------
    >>> unmeasured_on_grid(np.array([[1.0, np.nan]]), (2, 4)).astype(int).tolist()
    [[0, 0, 1, 1], [0, 0, 1, 1]]
    """
    d = check_depth(depth_lr, "depth_lr").astype(np.float32)
    with np.errstate(invalid="ignore"):
        invalid = ~(np.isfinite(d) & (d > 0))
    return _spread(invalid, shape)


def _spread(mask: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """A (h, w) bool mask of the depth grid spread over a ``shape`` = (rows, cols) grid as the refinement spreads it."""
    import cv2

    rows, cols = int(shape[0]), int(shape[1])
    return cv2.resize(mask.astype(np.uint8), (cols, rows), interpolation=cv2.INTER_NEAREST_EXACT).astype(bool)


def keep_unmeasured(depth_hr: np.ndarray, depth_lr: np.ndarray, *, fill_enclosed: bool = False,
                    rgb_hr: np.ndarray | None = None) -> np.ndarray:
    """``depth_hr`` (float32) with NaN wherever :func:`unmeasured_on_grid` says nothing was measured.

    A refinement fills every pixel; this takes back the depth it invented
    where the sensor saw nothing (``depthrefine run`` does this). With
    ``fill_enclosed`` (``run --fill-holes``), the holes that lie inside one
    measured surface (:func:`depthrefine._fill.enclosed_holes` of
    ``depth_lr``: a dropout on a dark or shiny spot, a thin sliver) keep the
    refinement's depth, which carries that surface on; what lies beyond any
    measurement (outside the view, a shadow beside a depth jump, a large
    unmeasured region) stays unmeasured.

    With ``rgb_hr``, the color image on ``depth_hr``'s grid (``run`` passes
    it), the border of the unmeasured pixels follows the color
    (:func:`unmeasured_along_color`): the depth grid puts it only to a
    depth pixel, and a depth camera leaves empty the pixels that straddle an
    outline (the Azure Kinect 2-3 of them between a mug and the wall behind
    it), so the object's outline lies somewhere in that strip, where the
    color shows it. A pixel the border gives up takes the depth of the
    measured pixel its color joins it to; one it takes becomes unmeasured.
    """
    out = np.array(depth_hr, dtype=np.float32, copy=True)
    lr = check_depth(depth_lr, "depth_lr").astype(np.float32)
    with np.errstate(invalid="ignore"):
        lr[~(lr > 0)] = np.nan
    if fill_enclosed or rgb_hr is not None:
        from .._fill import enclosed_holes

        enclosed = enclosed_holes(lr)
        if fill_enclosed:
            lr[enclosed] = 1.0   # counts as measured: the refinement's depth stays there
    if rgb_hr is not None:
        rgb = check_rgb(rgb_hr, "rgb_hr")
        if rgb.shape[:2] != out.shape[:2]:
            raise ValueError(f"rgb_hr has shape {rgb.shape[:2]}; it must be on depth_hr's grid {out.shape[:2]}.")
    unmeasured = unmeasured_on_grid(lr, out.shape[:2])
    if rgb_hr is not None and unmeasured.any() and not unmeasured.all():
        from .._geodesic import color_step_costs, nearest_seed
        from .._validate import guide_uint8

        costs = color_step_costs(guide_uint8(rgb), blur=BORDER_BLUR, step_levels=BORDER_STEP_LEVELS)
        per_pixel = 0.5 * (out.shape[0] / lr.shape[0] + out.shape[1] / lr.shape[1])
        moved = unmeasured_along_color(unmeasured, costs, BORDER_BAND * per_pixel,
                                       dropouts=_spread(enclosed, out.shape[:2]))
        gained = unmeasured & ~moved
        if gained.any():   # the depth of the measured pixel each one is joined to along the color
            source = nearest_seed(*costs, gained | moved)[gained]
            out[gained] = np.where(source >= 0, out.ravel()[np.maximum(source, 0)], np.nan)
            moved[gained] = source < 0
        unmeasured = moved
    out[unmeasured] = np.nan
    return out


def unmeasured_along_color(unmeasured: np.ndarray, costs: tuple[np.ndarray, np.ndarray], band: float, *,
                           dropouts: np.ndarray | None = None) -> np.ndarray:
    """``unmeasured`` (bool) with its border moved onto the color edges within ``band`` pixels of where it was.

    Each pixel within ``band`` pixels of the border, on either side, takes
    the side of its geodesic nearest pixel outside that strip
    (:func:`depthrefine._geodesic.nearest_seed`, ``costs`` from
    :func:`depthrefine._geodesic.color_step_costs`): the new border falls
    on the strongest color edge across the strip, and where the color is
    flat it stays where it was. Narrower than the strip, a measured part
    keeps its middle line (nothing measured vanishes). ``dropouts`` (bool:
    holes inside one surface, which ``run --fill-holes`` fills, measured or
    not in ``unmeasured``) and the pixels within ``band`` of them keep
    their side. New array.

    Examples
    --------
    >>> from depthrefine._geodesic import color_step_costs
    >>> color = np.zeros((1, 10, 3), np.uint8); color[:, 6:] = 200      # the color edge between columns 5 and 6
    >>> unmeasured = np.arange(10)[None, :] >= 4                           # the depth grid's border at column 4
    >>> moved = unmeasured_along_color(unmeasured, color_step_costs(color, blur=0, step_levels=2), 3)
    >>> moved.astype(int).tolist()
    [[0, 0, 0, 0, 0, 0, 1, 1, 1, 1]]
    """
    import cv2

    from .._geodesic import nearest_seed

    unmeasured = np.asarray(unmeasured)
    if unmeasured.dtype != np.bool_ or unmeasured.ndim != 2:
        raise ValueError(f"unmeasured must be a 2-D bool array; got {unmeasured.dtype} of shape {unmeasured.shape}.")
    if len(costs) != 2 or any(np.shape(c) != unmeasured.shape for c in costs):
        raise ValueError(f"costs must be two arrays of unmeasured's shape {unmeasured.shape} (color_step_costs of the "
                         "color image on its grid).")
    if dropouts is not None and np.shape(dropouts) != unmeasured.shape:
        raise ValueError(f"dropouts has shape {np.shape(dropouts)}; it must be unmeasured's, {unmeasured.shape}.")
    if not unmeasured.any() or unmeasured.all():
        return unmeasured.copy()
    to_unmeasured = cv2.distanceTransform((~unmeasured).astype(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
    to_measured = cv2.distanceTransform(unmeasured.astype(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
    thin_middle = ~unmeasured & (to_unmeasured >= cv2.dilate(to_unmeasured, np.ones((3, 3), np.uint8)))
    strip = (np.where(unmeasured, to_measured, to_unmeasured) <= band) & ~thin_middle
    if dropouts is not None and dropouts.any():
        to_dropout = cv2.distanceTransform((~dropouts).astype(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
        strip &= to_dropout > band
    source = nearest_seed(*costs, strip)
    moved = unmeasured.copy()
    reached = strip & (source >= 0)
    moved[reached] = unmeasured.ravel()[source[reached]]
    return moved


def nearest_on_grid(depth_lr: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """``depth_lr`` (float32) spread over a ``shape = (rows, cols)`` grid by nearest sampling (pixel areas aligned).

    How the refinement places the aligned depth on the color grid, for
    measures that need the two on one grid (:func:`depthrefine.rig.edges.edge_overlap`).

    Examples
    --------
    >>> nearest_on_grid(np.array([[1.0, np.nan]]), (2, 4)).tolist()
    [[1.0, 1.0, nan, nan], [1.0, 1.0, nan, nan]]
    """
    import cv2

    d = check_depth(depth_lr, "depth_lr").astype(np.float32)
    return cv2.resize(d, (int(shape[1]), int(shape[0])), interpolation=cv2.INTER_NEAREST_EXACT)


def upsampling_grid(depth_shape: tuple[int, ...], color_shape: tuple[int, ...]) -> tuple[int, tuple[int, int]]:
    """The integer factor ``s`` a refinement of an aligned pair upsamples by, and its working grid.

    ``s = round(color / depth)`` (mean of rows and columns), at least
    :data:`MIN_UPSAMPLING` when the depth grid is coarser than the color
    image: with the Azure Kinect's ratio 1.21 the method still upsamples
    (x2 onto a color image resized to twice the depth grid) instead of
    rounding to 1, where it would have nothing to do; 1 when the depth is
    on the color grid already (``--factor 1``). The working
    grid is ``s`` times the depth grid; the color image is resized onto it
    (bilinear) unless it is that grid already, and the result resized back
    (nearest), as the refinement's own scale step does for a ratio such as 7.4.

    Examples
    --------
    >>> upsampling_grid((594, 1056), (720, 1280))
    (2, (1188, 2112))
    >>> upsampling_grid((72, 96), (504, 672))
    (7, (504, 672))
    >>> upsampling_grid((720, 1280), (720, 1280))
    (1, (720, 1280))
    """
    ratio = (color_shape[0] / depth_shape[0] + color_shape[1] / depth_shape[1]) / 2.0
    s = max(MIN_UPSAMPLING, int(np.floor(ratio + 0.5))) if ratio > 1.0 + 1e-9 else 1
    return s, (int(depth_shape[0]) * s, int(depth_shape[1]) * s)


def reprojected_params(method, params=None):
    """``params`` of ``method`` with an unsaid ``reprojected`` (None) made True, where the method has it (gbp, gbp-fast).

    The chain reprojected the depth onto the color camera, so it tells the
    method so (:attr:`depthrefine.GbpParams.reprojected`). ``method`` is a
    registered name or a registry entry (``Method``, as a batch's workers
    get it); ``params=None`` stands for the method's defaults. A
    ``reprojected`` already said (True or False) stays; a method without
    that parameter, or ``params`` of another type (``refine`` then says what
    is wrong), gets ``params`` unchanged.

    Examples
    --------
    >>> from depthrefine import GbpParams
    >>> reprojected_params("gbp").reprojected, reprojected_params("bicubic")
    (True, None)
    >>> reprojected_params("gbp", GbpParams(reprojected=False)).reprojected
    False
    """
    import dataclasses

    from ..methods.registry import get_method

    entry = get_method(method) if isinstance(method, str) else method
    if not entry.has_param("reprojected"):
        return params
    kind = entry.params_type
    if params is None:
        return kind(reprojected=True)
    if not isinstance(params, kind) or params.reprojected is not None:
        return params
    return dataclasses.replace(params, reprojected=True)


def refine_pair(depth_lr: np.ndarray, rgb_hr: np.ndarray, *, method: str, params=None,
                progress=None, solve=None, reprojected: bool = True) -> tuple[np.ndarray, str]:
    """Refine an aligned pair onto the color image's grid, the method upsampling by :func:`upsampling_grid`'s ``s``.

    Parameters
    ----------
    depth_lr : (h, w) ndarray
        Aligned depth (:func:`align_pair`), NaN = invalid.
    rgb_hr : (H, W, 3) ndarray
        The color image it was aligned to.
    method, params, progress
        As :func:`depthrefine.refine`; with ``reprojected`` (the default: the
        chain reprojected ``depth_lr``) an unsaid ``reprojected`` in
        ``params`` becomes True (:func:`reprojected_params`), else ``params``
        go as they are.
    solve : callable, optional
        ``solve(depth, rgb) -> depth`` in place of ``refine(depth, rgb, method=method, ...)``
        (a warm start over frames: ``depthrefine batch --temporal``); it
        takes its own parameters (:func:`reprojected_params` for them).

    Returns
    -------
    depth_hr : (H, W) float32 ndarray
    note : str
        What the scale step did, one line for the user.
    """
    import cv2

    from ..methods.registry import refine
    from ..methods.scale import plan_scale

    if solve is None:
        told = reprojected_params(method, params) if reprojected else params

        def solve(depth, rgb):
            return refine(depth, rgb, method=method, params=told, progress=progress)

    rows, cols = rgb_hr.shape[:2]
    s, (work_rows, work_cols) = upsampling_grid(depth_lr.shape, rgb_hr.shape)
    step = plan_scale(depth_lr.shape, rgb_hr.shape)
    if step.factor == s:  # the refinement's own scale step does it (or there is nothing to upsample)
        return solve(depth_lr, rgb_hr), step.describe()
    rgb_work = cv2.resize(np.ascontiguousarray(rgb_hr), (work_cols, work_rows), interpolation=cv2.INTER_LINEAR)
    depth_work = solve(depth_lr, rgb_work)
    depth_hr = cv2.resize(depth_work, (cols, rows), interpolation=cv2.INTER_NEAREST_EXACT)
    ratio = (rows / depth_lr.shape[0] + cols / depth_lr.shape[1]) / 2.0
    return depth_hr, (f"ratio {ratio:.3f}: the method upsampled x{s} onto a {work_cols}x{work_rows} grid (color "
                      f"resized, bilinear) and the result was resized to {cols}x{rows} (nearest)")


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
    notes.append(f"depth reprojected into the color camera ({w}x{h} grid, s = {s:.4g}, z-buffer"
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
            f"--method reproject in run and align) or crop the color image to the depth "
            f"camera's view."
        )
    out = align_shift(depth, slope=slope, background=background, color_side=color_side, encoding=encoding)
    notes.append(f"depth shifted horizontally (thesis eq. 1): k = {slope:.6g}, d_bg = {background:.6g}, "
                 f"color camera on the {color_side}, {encoding} depth")
    return out


_CHAIN_ALIGNERS = {"reproject": _chain_reproject, "shift": _chain_shift}
