"""Board calibration of the depth camera and of a depth + color rig (spec step 1).

The thesis (3.2.1) calibrates the ToF camera's lens distortion from
checkerboard images of its intensity channel with the Matlab Camera
Calibration Toolbox; the same parameters undistort the depth map, because
depth and intensity share one viewpoint. OpenCV's ``calibrateCamera`` fits the
same pinhole + radial/tangential model. For the calibrated alignment (spec
step 3, "beyond the thesis") ``stereoCalibrate`` gives the rotation and
translation from the depth camera to the color camera.

Everything here is pure: board views in, :class:`~depthrefine.rig.camera.CameraModel` /
:class:`~depthrefine.rig.camera.StereoRig` out; the conventions (``K``, ``dist``, ``image_size``,
``board`` and the rig's direction) are those of :mod:`depthrefine.rig.camera`. Files are read
and written by :mod:`depthrefine.io`.

``board`` is a :class:`~depthrefine.rig.boards.Board` (checkerboard or ChArUco), or for a
checkerboard ``(cols, rows)`` inner corners with ``square_size`` in metres. The lens model is
OpenCV's ``(k1, k2, p1, p2, k3)`` with ``k3`` held at 0 unless ``estimate_k3``; ``rational=True``
fits the rational model ``(k1, k2, p1, p2, k3, k4, k5, k6)`` of wide-angle lenses (Azure Kinect).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from .._lazy import cv2
from .._validate import is_int
from ._names import LENS_MODELS, MIN_VIEWS, RECOMMENDED_VIEWS
from .boards import MIN_VIEW_CORNERS, Board, BoardView, detect_board, usable
from .camera import CameraModel, StereoRig

__all__ = [
    "MIN_VIEWS",
    "LENS_MODELS",
    "RECOMMENDED_VIEWS",
    "CalibrationFit",
    "StereoFit",
    "lens_model",
    "as_board",
    "fit_camera",
    "fit_stereo",
    "calibrate_from_views",
    "calibrate_from_corners",
    "calibrate_camera",
    "calibrate_stereo_from_views",
    "calibrate_stereo_from_corners",
    "calibrate_stereo",
]


def as_board(board: Board | tuple[int, int], square_size: float | None = None) -> Board:
    """A :class:`Board`; ``(cols, rows)`` inner corners with ``square_size`` make a checkerboard."""
    if isinstance(board, Board):
        if square_size is not None and not math.isclose(square_size, board.square_size):
            raise ValueError(f"square_size {square_size} differs from the board's {board.square_size}; give one.")
        return board
    if square_size is None:
        raise TypeError("a checkerboard given as (cols, rows) needs square_size (metres).")
    return Board.checkerboard(board, square_size)


def lens_model(*, estimate_k3: bool = False, rational: bool = False) -> str:
    """The name in :data:`LENS_MODELS` of the model these options fit.

    Examples
    --------
    >>> lens_model(), lens_model(estimate_k3=True), lens_model(rational=True)
    ('plain', 'k3', 'rational')
    """
    return "rational" if rational else ("k3" if estimate_k3 else "plain")


@dataclass(frozen=True, eq=False)
class CalibrationFit:
    """A single-camera calibration with what it rests on: the views and their reprojection residuals.

    Attributes
    ----------
    camera : CameraModel
        The fitted camera (``camera.rms``: RMS over all corners, pixels).
    views : tuple of BoardView
        The views fitted, in order.
    residuals : tuple of (N_i, 2) float64 ndarray
        Per view, each corner's reprojection minus its detection ``(x, y)``, pixels.
    model : str
        The lens model fitted (a key of :data:`LENS_MODELS`).
    """

    camera: CameraModel
    views: tuple[BoardView, ...]
    residuals: tuple[np.ndarray, ...]
    model: str = "plain"

    @property
    def view_rms(self) -> np.ndarray:
        """(V,) RMS reprojection error of each view, pixels."""
        return np.array([math.sqrt(float(np.mean(np.sum(r * r, axis=1)))) if r.size else 0.0
                         for r in self.residuals])

    @property
    def recommended_views(self) -> int:
        """Views below which this model's fit is unstable (:data:`RECOMMENDED_VIEWS`)."""
        return RECOMMENDED_VIEWS[self.model]


@dataclass(frozen=True, eq=False)
class StereoFit:
    """A rig calibration with its per-pair reprojection errors and the cameras' own fits.

    Attributes
    ----------
    rig : StereoRig
    pair_rms : (P, 2) float64 ndarray
        RMS reprojection error of each pair used, in the depth and the color image, pixels.
    pairs : tuple of int
        Index of each pair used in the given lists (pairs without the board in both are left out).
    depth_fit, color_fit : CalibrationFit or None
        The cameras' fits from the pairs' views (None for a camera whose intrinsics were given).
    """

    rig: StereoRig
    pair_rms: np.ndarray
    pairs: tuple[int, ...]
    depth_fit: CalibrationFit | None = None
    color_fit: CalibrationFit | None = None


def _flags(estimate_k3: bool, rational: bool) -> tuple[int, int]:
    """calibrateCamera flags and the number of distortion coefficients kept."""
    if rational:
        return cv2.CALIB_RATIONAL_MODEL, 8
    return (0 if estimate_k3 else cv2.CALIB_FIX_K3), 5


def _view_points(view: BoardView, board: Board) -> tuple[np.ndarray, np.ndarray]:
    return board.points[view.ids], np.asarray(view.corners, np.float32).reshape(-1, 1, 2)


def fit_camera(
    views: Sequence[BoardView],
    *,
    board: Board,
    image_size: tuple[int, int],
    estimate_k3: bool = False,
    rational: bool = False,
) -> CalibrationFit:
    """Calibrate one camera from board detections (OpenCV ``calibrateCamera``), keeping the residuals.

    Parameters
    ----------
    views : sequence of BoardView
        One per image, from :func:`~depthrefine.rig.boards.detect_board`;
        a ChArUco view may hold any subset of the corners.
    board : Board
    image_size : (int, int)
        ``(width, height)`` of the images.
    estimate_k3 : bool
        Also fit the sixth-order radial term ``k3``. Off by default, as in the
        Camera Calibration Toolbox the thesis used: with few views ``k3``
        over-fits the image corners.
    rational : bool
        Fit the rational model (8 coefficients, ``k3`` included).

    Returns
    -------
    CalibrationFit
        ``camera.dist`` holds ``(k1, k2, p1, p2, k3)`` (or the 8 rational
        coefficients), ``camera.rms`` the RMS reprojection error in pixels;
        ``residuals`` each view's corner residuals.

    Raises
    ------
    ValueError
        Fewer than :data:`MIN_VIEWS` usable views (the message says how many
        corners each view has), or a view with the wrong corners.
    """
    if not isinstance(board, Board):
        raise TypeError(f"board must be a Board; got {type(board).__name__}.")
    views = list(views)
    bad = [i for i, v in enumerate(views) if not usable(v, board)]
    if bad or len(views) < MIN_VIEWS:
        counts = ", ".join(str(v.count if v is not None else 0) for v in views)
        need = ("all " + str(board.points.shape[0]) if board.kind == "checkerboard"
                else f"at least {MIN_VIEW_CORNERS} non-collinear")
        raise ValueError(
            f"calibration needs at least {MIN_VIEWS} views with {need} corners of the {board.describe()}; "
            f"got {len(views)} view(s) with {counts or 'no'} corners ({len(bad)} not usable)."
        )
    width, height = _check_size(image_size)
    flags, n_dist = _flags(estimate_k3, rational)
    obj, img = zip(*(_view_points(v, board) for v in views))
    rms, K, dist, rvecs, tvecs = cv2.calibrateCamera(list(obj), list(img), (width, height), None, None, flags=flags)
    residuals = tuple(
        cv2.projectPoints(o, r, t, K, dist)[0].reshape(-1, 2).astype(np.float64) - i.reshape(-1, 2)
        for o, i, r, t in zip(obj, img, rvecs, tvecs))
    return CalibrationFit(CameraModel(K, dist.ravel()[:n_dist], (width, height), float(rms)), tuple(views),
                          residuals, lens_model(estimate_k3=estimate_k3, rational=rational))


def calibrate_from_views(
    views: Sequence[BoardView],
    *,
    board: Board,
    image_size: tuple[int, int],
    estimate_k3: bool = False,
    rational: bool = False,
) -> CameraModel:
    """Calibrate one camera from board detections: the camera of :func:`fit_camera`.

    See :func:`fit_camera` for the parameters; use it to get each view's
    reprojection error too.
    """
    return fit_camera(views, board=board, image_size=image_size, estimate_k3=estimate_k3, rational=rational).camera


def calibrate_from_corners(
    corners: Sequence[np.ndarray],
    *,
    board: tuple[int, int],
    square_size: float,
    image_size: tuple[int, int],
    estimate_k3: bool = False,
    rational: bool = False,
) -> CameraModel:
    """Calibrate one camera from checkerboard corners (all corners of each view).

    Parameters
    ----------
    corners : sequence of (N, 2) float32 ndarray
        One array per view, as returned by
        :func:`~depthrefine.rig.boards.find_board_corners`.
    board : (int, int)
        Inner corners ``(cols, rows)``.
    square_size : float
        Side of a square, metres (only the extrinsics depend on it).
    image_size, estimate_k3, rational
        As in :func:`calibrate_from_views`.

    Raises
    ------
    ValueError
        Fewer than :data:`MIN_VIEWS` views, or corner arrays of the wrong size.
    """
    spec = as_board(board, square_size)
    cols, rows = spec.inner_corners
    arrays = [np.asarray(c, dtype=np.float32).reshape(-1, 2) for c in corners]
    if len(arrays) < MIN_VIEWS:
        raise ValueError(
            f"calibration needs the board in at least {MIN_VIEWS} images; got {len(arrays)}. "
            f"Take more views ({RECOMMENDED_VIEWS[lens_model(estimate_k3=estimate_k3, rational=rational)]} or more "
            "covering the whole image for this lens model)."
        )
    for i, v in enumerate(arrays):
        if v.shape[0] != cols * rows:
            raise ValueError(f"view {i} has {v.shape[0]} corners; the board {cols}x{rows} has {cols * rows}.")
    views = [BoardView(np.arange(v.shape[0], dtype=np.int32), v) for v in arrays]
    return calibrate_from_views(views, board=spec, image_size=image_size, estimate_k3=estimate_k3,
                                rational=rational)


def calibrate_camera(
    images: Sequence[np.ndarray],
    *,
    board: Board | tuple[int, int],
    square_size: float | None = None,
    estimate_k3: bool = False,
    rational: bool = False,
) -> CameraModel:
    """Calibrate one camera from images of a board (spec step 1).

    Images in which the board is not found (or, for ChArUco, fewer than
    :data:`~depthrefine.rig.boards.MIN_VIEW_CORNERS` corners) are skipped;
    use :func:`~depthrefine.rig.boards.detect_board` and
    :func:`calibrate_from_views` to learn which. See
    :func:`calibrate_from_views` for the parameters.

    Raises
    ------
    ValueError
        Images of different sizes, or the board found in fewer than
        :data:`MIN_VIEWS` images (the message gives the corners found in each).
    """
    spec = as_board(board, square_size)
    if len(images) == 0:
        raise ValueError("no images given; calibration needs images of the board.")
    size = _common_size(images, "images")
    found = [detect_board(img, spec) for img in images]
    views = [v for v in found if usable(v, spec)]
    if len(views) < MIN_VIEWS:
        missing = [i for i, v in enumerate(found) if not usable(v, spec)]
        raise ValueError(
            f"the {spec.describe()} was found in {len(views)} of {len(images)} images "
            f"(not in images {missing}); corners found per image: {[v.count for v in found]}; "
            f"calibration needs at least {MIN_VIEWS}. Check the board and the images."
        )
    return calibrate_from_views(views, board=spec, image_size=size, estimate_k3=estimate_k3, rational=rational)


def fit_stereo(
    depth_views: Sequence[BoardView | None],
    color_views: Sequence[BoardView | None],
    *,
    board: Board,
    depth_size: tuple[int, int],
    color_size: tuple[int, int],
    depth_camera: CameraModel | None = None,
    color_camera: CameraModel | None = None,
    estimate_k3: bool = False,
    rational: bool = False,
) -> StereoFit:
    """Calibrate a depth + color rig from board detections in pairs of images, keeping the per-pair errors.

    Parameters
    ----------
    depth_views, color_views : sequences of BoardView or None
        Detections of pair ``i`` in each camera (``None`` or unusable where
        the board was not found). A ChArUco pair uses the corners found in
        both images.
    board : Board
        Its ``square_size`` in metres gives ``t`` in metres.
    depth_size, color_size : (int, int)
        ``(width, height)`` of each camera's images.
    depth_camera, color_camera : CameraModel, optional
        Known intrinsics (e.g. from ``depthrefine calibrate``); otherwise each
        camera is calibrated from all its own views first.
    estimate_k3, rational
        As in :func:`calibrate_from_views`.

    Returns
    -------
    StereoFit
        ``rig.R``, ``rig.t`` from ``stereoCalibrate`` with the intrinsics
        held fixed; the RMS error of each pair used; the cameras' own fits.

    Raises
    ------
    ValueError
        Lists of different lengths, or fewer than :data:`MIN_VIEWS` pairs with
        the board found in both images.
    """
    if not isinstance(board, Board):
        raise TypeError(f"board must be a Board; got {type(board).__name__}.")
    if len(depth_views) != len(color_views):
        raise ValueError(
            f"got {len(depth_views)} depth views and {len(color_views)} color views; "
            "give the images in pairs (the same board pose in both, in the same order)."
        )
    pairs, used = [], []
    for index, (d, c) in enumerate(zip(depth_views, color_views)):
        if not (usable(d, board) and usable(c, board)):
            continue
        common, d_idx, c_idx = np.intersect1d(d.ids, c.ids, assume_unique=True, return_indices=True)
        both = (BoardView(common.astype(np.int32), d.corners[d_idx]), BoardView(common.astype(np.int32), c.corners[c_idx]))
        if usable(both[0], board):
            pairs.append(both)
            used.append(index)
    if len(pairs) < MIN_VIEWS:
        raise ValueError(
            f"the board was found in both images of {len(pairs)} pairs; a stereo calibration needs at "
            f"least {MIN_VIEWS}. Take more pairs with the board visible to both cameras."
        )
    fit = dict(board=board, estimate_k3=estimate_k3, rational=rational)
    depth_fit = color_fit = None
    if depth_camera is None:
        depth_fit = fit_camera([d for d in depth_views if usable(d, board)], image_size=depth_size, **fit)
        depth_camera = depth_fit.camera
    if color_camera is None:
        color_fit = fit_camera([c for c in color_views if usable(c, board)], image_size=color_size, **fit)
        color_camera = color_fit.camera
    obj = [board.points[d.ids] for d, _ in pairs]
    rms, *_, R, T, _, _, _, _, pair_rms = cv2.stereoCalibrateExtended(
        obj,
        [d.corners.reshape(-1, 1, 2) for d, _ in pairs],
        [c.corners.reshape(-1, 1, 2) for _, c in pairs],
        depth_camera.K.copy(), depth_camera.dist.copy(), color_camera.K.copy(), color_camera.dist.copy(),
        _check_size(depth_size), None, None, flags=cv2.CALIB_FIX_INTRINSIC,
    )
    rig = StereoRig(depth_camera, color_camera, R, T.ravel(), float(rms))
    return StereoFit(rig, np.asarray(pair_rms, np.float64).reshape(-1, 2), tuple(used), depth_fit, color_fit)


def calibrate_stereo_from_views(
    depth_views: Sequence[BoardView | None],
    color_views: Sequence[BoardView | None],
    *,
    board: Board,
    depth_size: tuple[int, int],
    color_size: tuple[int, int],
    depth_camera: CameraModel | None = None,
    color_camera: CameraModel | None = None,
    estimate_k3: bool = False,
    rational: bool = False,
) -> StereoRig:
    """Calibrate a depth + color rig from board detections in pairs of images: the rig of :func:`fit_stereo`.

    See :func:`fit_stereo` for the parameters; use it to get each pair's
    reprojection error too.
    """
    return fit_stereo(depth_views, color_views, board=board, depth_size=depth_size, color_size=color_size,
                      depth_camera=depth_camera, color_camera=color_camera, estimate_k3=estimate_k3,
                      rational=rational).rig


def calibrate_stereo_from_corners(
    depth_corners: Sequence[np.ndarray | None],
    color_corners: Sequence[np.ndarray | None],
    *,
    board: tuple[int, int],
    square_size: float,
    depth_size: tuple[int, int],
    color_size: tuple[int, int],
    depth_camera: CameraModel | None = None,
    color_camera: CameraModel | None = None,
    estimate_k3: bool = False,
    rational: bool = False,
) -> StereoRig:
    """Calibrate a depth + color rig from checkerboard corners seen by both cameras.

    ``depth_corners[i]`` and ``color_corners[i]`` are the corners of pair
    ``i`` (:func:`~depthrefine.rig.boards.find_board_corners`, ``None`` where
    not found); ``board`` is ``(cols, rows)`` inner corners. See
    :func:`calibrate_stereo_from_views` for the rest.
    """
    spec = as_board(board, square_size)

    def view(c: np.ndarray | None) -> BoardView | None:
        if c is None:
            return None
        c = np.asarray(c, np.float32).reshape(-1, 2)
        return BoardView(np.arange(c.shape[0], dtype=np.int32), c)

    return calibrate_stereo_from_views(
        [view(c) for c in depth_corners], [view(c) for c in color_corners], board=spec, depth_size=depth_size,
        color_size=color_size, depth_camera=depth_camera, color_camera=color_camera, estimate_k3=estimate_k3,
        rational=rational,
    )


def calibrate_stereo(
    depth_images: Sequence[np.ndarray],
    color_images: Sequence[np.ndarray],
    *,
    board: Board | tuple[int, int],
    square_size: float | None = None,
    depth_camera: CameraModel | None = None,
    color_camera: CameraModel | None = None,
    estimate_k3: bool = False,
    rational: bool = False,
) -> StereoRig:
    """Calibrate a depth + color rig from pairs of board images.

    ``depth_images[i]`` (the ToF camera's intensity image) and
    ``color_images[i]`` show the same board pose. See
    :func:`calibrate_stereo_from_views` for the parameters and errors.
    """
    spec = as_board(board, square_size)
    depth_size = _common_size(depth_images, "depth_images")
    color_size = _common_size(color_images, "color_images")
    return calibrate_stereo_from_views(
        [detect_board(img, spec) for img in depth_images],
        [detect_board(img, spec) for img in color_images],
        board=spec, depth_size=depth_size, color_size=color_size,
        depth_camera=depth_camera, color_camera=color_camera, estimate_k3=estimate_k3, rational=rational,
    )


def _check_size(size: Any) -> tuple[int, int]:
    if (not hasattr(size, "__len__") or len(size) != 2 or not all(is_int(v) and v > 0 for v in size)):
        raise ValueError(f"image size must be two positive integers (width, height); got {size!r}.")
    return int(size[0]), int(size[1])


def _common_size(images: Sequence[np.ndarray], name: str) -> tuple[int, int]:
    shapes = {tuple(np.shape(img)[:2]) for img in images}
    if not shapes:
        raise ValueError(f"{name} is empty.")
    if len(shapes) > 1:
        raise ValueError(f"{name} have different sizes {sorted(shapes)} (rows, cols); one camera gives one size.")
    rows, cols = shapes.pop()
    return int(cols), int(rows)


