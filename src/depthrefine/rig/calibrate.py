"""Checkerboard calibration of the depth camera and of a depth + color rig (spec step 1).

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
"""

from __future__ import annotations

from typing import Any, Sequence

import cv2
import numpy as np

from .._validate import is_int
from .boards import _check_board, board_points, find_board_corners
from .camera import CameraModel, StereoRig

__all__ = [
    "MIN_VIEWS",
    "calibrate_from_corners",
    "calibrate_camera",
    "calibrate_stereo_from_corners",
    "calibrate_stereo",
]

#: Fewest board views a calibration accepts. Zhang's method needs three
#: views of a plane for the five intrinsic parameters; 10-20 views that
#: cover the whole image give a good distortion estimate.
MIN_VIEWS = 3



def calibrate_from_corners(
    corners: Sequence[np.ndarray],
    *,
    board: tuple[int, int],
    square_size: float,
    image_size: tuple[int, int],
    estimate_k3: bool = False,
) -> CameraModel:
    """Calibrate one camera from detected board corners (OpenCV ``calibrateCamera``).

    Parameters
    ----------
    corners : sequence of (N, 2) float32 ndarray
        One array per view, as returned by :func:`find_board_corners`.
    board : (int, int)
        Inner corners ``(cols, rows)``.
    square_size : float
        Side of a square, metres (only the extrinsics depend on it).
    image_size : (int, int)
        ``(width, height)`` of the images.
    estimate_k3 : bool
        Also fit the sixth-order radial term ``k3``. Off by default, as in the
        Camera Calibration Toolbox the thesis used: with few views ``k3``
        over-fits the image corners.

    Returns
    -------
    CameraModel
        ``dist`` holds ``(k1, k2, p1, p2, k3)``; ``rms`` the RMS reprojection
        error in pixels.

    Raises
    ------
    ValueError
        Fewer than :data:`MIN_VIEWS` views, or corner arrays of the wrong size.
    """
    cols, rows = _check_board(board)
    views = [np.asarray(c, dtype=np.float32).reshape(-1, 2) for c in corners]
    if len(views) < MIN_VIEWS:
        raise ValueError(
            f"calibration needs the board in at least {MIN_VIEWS} images; got {len(views)}. "
            "Take more views (10-20 covering the whole image are best)."
        )
    for i, v in enumerate(views):
        if v.shape[0] != cols * rows:
            raise ValueError(f"view {i} has {v.shape[0]} corners; the board {cols}x{rows} has {cols * rows}.")
    width, height = _check_size(image_size)
    obj = board_points(board, square_size)
    flags = 0 if estimate_k3 else cv2.CALIB_FIX_K3
    rms, K, dist, _, _ = cv2.calibrateCamera(
        [obj] * len(views), [v.reshape(-1, 1, 2) for v in views], (width, height), None, None, flags=flags
    )
    return CameraModel(K, dist.ravel()[:5], (width, height), float(rms))


def calibrate_camera(
    images: Sequence[np.ndarray],
    *,
    board: tuple[int, int],
    square_size: float,
    estimate_k3: bool = False,
) -> CameraModel:
    """Calibrate one camera from checkerboard images (spec step 1).

    Images in which the board is not found are skipped; use
    :func:`find_board_corners` and :func:`calibrate_from_corners` to learn
    which. See :func:`calibrate_from_corners` for the parameters.

    Raises
    ------
    ValueError
        Images of different sizes, or the board found in fewer than
        :data:`MIN_VIEWS` images (the message lists the others by index).
    """
    if len(images) == 0:
        raise ValueError("no images given; calibration needs checkerboard images.")
    size = _common_size(images, "images")
    found = [find_board_corners(img, board) for img in images]
    views = [c for c in found if c is not None]
    if len(views) < MIN_VIEWS:
        missing = [i for i, c in enumerate(found) if c is None]
        raise ValueError(
            f"the {board[0]}x{board[1]} board was found in {len(views)} of {len(images)} images "
            f"(not in images {missing}); calibration needs at least {MIN_VIEWS}. "
            "Check --board (inner corners, cols x rows) and the images."
        )
    return calibrate_from_corners(views, board=board, square_size=square_size, image_size=size,
                                  estimate_k3=estimate_k3)


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
) -> StereoRig:
    """Calibrate a depth + color rig from board corners seen by both cameras.

    Parameters
    ----------
    depth_corners, color_corners : sequences of (N, 2) float32 ndarray or None
        Corners of pair ``i`` in each camera (``None`` where not found).
    board, square_size, estimate_k3
        As in :func:`calibrate_from_corners`; ``square_size`` in metres gives
        ``t`` in metres.
    depth_size, color_size : (int, int)
        ``(width, height)`` of each camera's images.
    depth_camera, color_camera : CameraModel, optional
        Known intrinsics (e.g. from ``depthrefine calibrate``); otherwise each
        camera is calibrated from all its own views first.

    Returns
    -------
    StereoRig
        ``R``, ``t`` from ``stereoCalibrate`` with the intrinsics held fixed.

    Raises
    ------
    ValueError
        Lists of different lengths, or fewer than :data:`MIN_VIEWS` pairs with
        the board found in both images.
    """
    if len(depth_corners) != len(color_corners):
        raise ValueError(
            f"got {len(depth_corners)} depth views and {len(color_corners)} color views; "
            "give the images in pairs (the same board pose in both, in the same order)."
        )
    pairs = [(d, c) for d, c in zip(depth_corners, color_corners) if d is not None and c is not None]
    if len(pairs) < MIN_VIEWS:
        raise ValueError(
            f"the board was found in both images of {len(pairs)} pairs; a stereo calibration needs at "
            f"least {MIN_VIEWS}. Take more pairs with the whole board visible to both cameras."
        )
    if depth_camera is None:
        depth_camera = calibrate_from_corners([d for d in depth_corners if d is not None], board=board,
                                              square_size=square_size, image_size=depth_size,
                                              estimate_k3=estimate_k3)
    if color_camera is None:
        color_camera = calibrate_from_corners([c for c in color_corners if c is not None], board=board,
                                              square_size=square_size, image_size=color_size,
                                              estimate_k3=estimate_k3)
    obj = board_points(board, square_size)
    rms, _, _, _, _, R, T, _, _ = cv2.stereoCalibrate(
        [obj] * len(pairs),
        [np.asarray(d, np.float32).reshape(-1, 1, 2) for d, _ in pairs],
        [np.asarray(c, np.float32).reshape(-1, 1, 2) for _, c in pairs],
        depth_camera.K.copy(), depth_camera.dist.copy(), color_camera.K.copy(), color_camera.dist.copy(),
        _check_size(depth_size), flags=cv2.CALIB_FIX_INTRINSIC,
    )
    return StereoRig(depth_camera, color_camera, R, T.ravel(), float(rms))


def calibrate_stereo(
    depth_images: Sequence[np.ndarray],
    color_images: Sequence[np.ndarray],
    *,
    board: tuple[int, int],
    square_size: float,
    depth_camera: CameraModel | None = None,
    color_camera: CameraModel | None = None,
    estimate_k3: bool = False,
) -> StereoRig:
    """Calibrate a depth + color rig from pairs of checkerboard images.

    ``depth_images[i]`` (the ToF camera's intensity image) and
    ``color_images[i]`` show the same board pose. See
    :func:`calibrate_stereo_from_corners` for the parameters and errors.
    """
    depth_size = _common_size(depth_images, "depth_images")
    color_size = _common_size(color_images, "color_images")
    return calibrate_stereo_from_corners(
        [find_board_corners(img, board) for img in depth_images],
        [find_board_corners(img, board) for img in color_images],
        board=board, square_size=square_size, depth_size=depth_size, color_size=color_size,
        depth_camera=depth_camera, color_camera=color_camera, estimate_k3=estimate_k3,
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


