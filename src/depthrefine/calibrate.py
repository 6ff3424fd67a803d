"""Checkerboard calibration of the depth camera and of a depth + color rig (spec step 1).

The thesis (3.2.1) calibrates the ToF camera's lens distortion from
checkerboard images of its intensity channel with the Matlab Camera
Calibration Toolbox; the same parameters undistort the depth map, because
depth and intensity share one viewpoint. OpenCV's ``calibrateCamera`` fits the
same pinhole + radial/tangential model. For the calibrated alignment (spec
step 3, "beyond the thesis") ``stereoCalibrate`` gives the rotation and
translation from the depth camera to the color camera.

Everything here is pure: images in, :class:`CameraModel` / :class:`StereoRig`
out. Files are read and written by :mod:`depthrefine.io`.

Conventions
-----------
- ``K`` is OpenCV's 3x3 intrinsic matrix in pixels, pixel centres at integer
  coordinates (the centre of the top-left pixel is ``(0, 0)``).
- ``dist`` holds distortion coefficients in OpenCV order
  ``(k1, k2, p1, p2[, k3[, k4, k5, k6 ...]])``.
- ``image_size`` is ``(width, height)``, as OpenCV and the JSON files give it;
  array shapes are ``(rows, cols)`` as everywhere else.
- ``board`` is ``(cols, rows)``: the number of *inner* corners across and
  down, as OpenCV counts them; ``square_size`` is the side of one square in
  metres, so a rig's translation ``t`` is in metres.
- A rig maps a point from the depth camera's frame to the color camera's:
  ``X_color = R @ X_depth + t``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping, Sequence

import cv2
import numpy as np

__all__ = [
    "CameraModel",
    "StereoRig",
    "MIN_VIEWS",
    "board_points",
    "to_gray8",
    "find_board_corners",
    "calibrate_from_corners",
    "calibrate_camera",
    "calibrate_stereo_from_corners",
    "calibrate_stereo",
]

#: Fewest board views a calibration accepts. Zhang's method needs three
#: views of a plane for the five intrinsic parameters; 10-20 views that
#: cover the whole image give a good distortion estimate.
MIN_VIEWS = 3

_SUBPIX_CRITERIA = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 50, 1e-4)


# ----------------------------------------------------------------------------
# Models
# ----------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class CameraModel:
    """A calibrated pinhole camera with lens distortion (OpenCV model).

    Attributes
    ----------
    K : (3, 3) float64 ndarray
        Intrinsic matrix ``[[fx, 0, cx], [0, fy, cy], [0, 0, 1]]``, pixels.
    dist : (n,) float64 ndarray
        Distortion coefficients in OpenCV order (n = 4, 5, 8, 12 or 14;
        all zeros for a distortion-free lens).
    image_size : (int, int)
        ``(width, height)`` of the images the model describes, pixels.
    rms : float or None
        RMS reprojection error of the calibration, pixels (None if unknown).

    Examples
    --------
    >>> cam = CameraModel(np.array([[100., 0, 31.5], [0, 100., 23.5], [0, 0, 1]]), np.zeros(5), (64, 48))
    >>> cam.shape, cam.focal
    ((48, 64), (100.0, 100.0))
    >>> cam.resized((24, 32)).K[0].tolist()
    [50.0, 0.0, 15.5]
    """

    K: np.ndarray
    dist: np.ndarray
    image_size: tuple[int, int]
    rms: float | None = None

    def __post_init__(self) -> None:
        K = _matrix("K", self.K, (3, 3))
        if not (K[0, 0] > 0 and K[1, 1] > 0 and K[2, 2] == 1 and K[1, 0] == 0 and K[2, 0] == 0 and K[2, 1] == 0):
            raise ValueError(
                f"K must be [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] with fx, fy > 0; got {K.tolist()}."
            )
        if K[0, 1] != 0:
            raise ValueError(
                f"K has a skew K[0][1] = {K[0, 1]:g}, which OpenCV's projection and undistortion ignore; "
                "set it to 0 (recalibrate without skew: cv2.calibrateCamera never estimates one)."
            )
        dist = np.array(self.dist if self.dist is not None else [], dtype=np.float64).ravel()
        if dist.size == 0:
            dist = np.zeros(5)
        if dist.size not in (4, 5, 8, 12, 14) or not np.isfinite(dist).all():
            raise ValueError(
                f"dist must hold 4, 5, 8, 12 or 14 finite coefficients (OpenCV order k1, k2, p1, p2, k3, ...); "
                f"got {dist.size}."
            )
        size = self.image_size
        if (isinstance(size, (str, bytes)) or not hasattr(size, "__len__") or len(size) != 2
                or not all(_is_int(v) and v > 0 for v in size)):
            raise ValueError(f"image_size must be two positive integers (width, height); got {size!r}.")
        rms = self.rms
        if rms is not None:
            if isinstance(rms, bool) or not isinstance(rms, (int, float, np.floating)) or not math.isfinite(rms):
                raise TypeError(f"rms must be a finite number of pixels or None; got {rms!r}.")
            rms = float(rms)
        K.flags.writeable = False
        dist.flags.writeable = False
        object.__setattr__(self, "K", K)
        object.__setattr__(self, "dist", dist)
        object.__setattr__(self, "image_size", (int(size[0]), int(size[1])))
        object.__setattr__(self, "rms", rms)

    @property
    def shape(self) -> tuple[int, int]:
        """``(rows, cols)`` of the camera's images."""
        return self.image_size[1], self.image_size[0]

    @property
    def focal(self) -> tuple[float, float]:
        """``(fx, fy)`` in pixels."""
        return float(self.K[0, 0]), float(self.K[1, 1])

    @property
    def has_distortion(self) -> bool:
        """True if any distortion coefficient is non-zero."""
        return bool(np.any(self.dist != 0))

    def without_distortion(self) -> "CameraModel":
        """The same camera with zero distortion (the model of an undistorted image)."""
        return CameraModel(self.K, np.zeros(5), self.image_size, self.rms)

    def resized(self, shape: tuple[int, int]) -> "CameraModel":
        """The model of this camera's images resampled to ``shape = (rows, cols)``.

        Pixel areas are kept aligned (OpenCV ``resize``): a pixel centre ``u``
        moves to ``(u + 0.5) * scale - 0.5``. Distortion is unchanged (it acts
        on normalized coordinates).
        """
        rows, cols = int(shape[0]), int(shape[1])
        if rows < 1 or cols < 1:
            raise ValueError(f"shape must be two positive sizes (rows, cols); got {shape}.")
        sx, sy = cols / self.image_size[0], rows / self.image_size[1]
        K = self.K.copy()
        K[0, :] *= sx
        K[1, :] *= sy
        K[0, 2] = (self.K[0, 2] + 0.5) * sx - 0.5
        K[1, 2] = (self.K[1, 2] + 0.5) * sy - 0.5
        return CameraModel(K, self.dist, (cols, rows), self.rms)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict with the keys ``K``, ``dist``, ``image_size``, ``rms``."""
        return {
            "K": self.K.tolist(),
            "dist": self.dist.tolist(),
            "image_size": list(self.image_size),
            "rms": self.rms,
        }

    @classmethod
    def from_dict(cls, mapping: Mapping[str, Any], *, source: str = "camera") -> "CameraModel":
        """Build from a mapping with the keys of :meth:`to_dict` (``rms`` optional)."""
        if not isinstance(mapping, Mapping):
            raise TypeError(f"{source} must be a table with keys K, dist, image_size; got {type(mapping).__name__}.")
        missing = [k for k in ("K", "dist", "image_size") if k not in mapping]
        if missing:
            raise ValueError(f"{source} lacks key(s) {', '.join(missing)}; a camera needs K, dist and image_size.")
        try:
            return cls(K=mapping["K"], dist=mapping["dist"], image_size=tuple(mapping["image_size"]),
                       rms=mapping.get("rms"))
        except (TypeError, ValueError) as exc:
            raise type(exc)(f"{source}: {exc}") from None


@dataclass(frozen=True, eq=False)
class StereoRig:
    """A depth camera and a color camera with the rigid motion between them.

    Attributes
    ----------
    depth_camera, color_camera : CameraModel
        Intrinsics and distortion of each camera.
    R : (3, 3) float64 ndarray
        Rotation from the depth camera's frame to the color camera's.
    t : (3,) float64 ndarray
        Translation, metres: ``X_color = R @ X_depth + t``.
    rms : float or None
        RMS reprojection error of the stereo calibration, pixels.

    Examples
    --------
    >>> cam = CameraModel(np.diag([100., 100., 1.]), np.zeros(5), (64, 48))
    >>> rig = StereoRig(cam, cam, np.eye(3), np.array([-0.05, 0, 0]))
    >>> rig.color_centre.tolist(), rig.rotation_degrees
    ([0.05, 0.0, 0.0], 0.0)
    """

    depth_camera: CameraModel
    color_camera: CameraModel
    R: np.ndarray
    t: np.ndarray
    rms: float | None = None

    def __post_init__(self) -> None:
        for name in ("depth_camera", "color_camera"):
            if not isinstance(getattr(self, name), CameraModel):
                raise TypeError(f"{name} must be a CameraModel; got {type(getattr(self, name)).__name__}.")
        R = _matrix("R", self.R, (3, 3))
        if np.abs(R.T @ R - np.eye(3)).max() > 1e-4 or np.linalg.det(R) < 0:
            raise ValueError(f"R must be a rotation matrix (orthonormal, det +1); got {R.tolist()}.")
        t = _matrix("t", np.asarray(self.t, dtype=np.float64).ravel(), (3,))
        rms = None if self.rms is None else float(self.rms)
        R.flags.writeable = False
        t.flags.writeable = False
        object.__setattr__(self, "R", R)
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "rms", rms)

    @property
    def color_centre(self) -> np.ndarray:
        """Position of the color camera's centre in the depth camera's frame, metres."""
        return -self.R.T @ self.t

    @property
    def rotation_degrees(self) -> float:
        """Angle of the rotation between the cameras, degrees (0 for a parallel rig)."""
        cos = (np.trace(self.R) - 1.0) / 2.0
        return float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict: ``depth_camera``, ``color_camera``, ``R``, ``t`` (metres), ``rms``."""
        return {
            "depth_camera": self.depth_camera.to_dict(),
            "color_camera": self.color_camera.to_dict(),
            "R": self.R.tolist(),
            "t": self.t.tolist(),
            "rms": self.rms,
        }

    @classmethod
    def from_dict(cls, mapping: Mapping[str, Any], *, source: str = "rig") -> "StereoRig":
        """Build from a mapping with the keys of :meth:`to_dict` (``rms`` optional)."""
        if not isinstance(mapping, Mapping):
            raise TypeError(f"{source} must be a table; got {type(mapping).__name__}.")
        missing = [k for k in ("depth_camera", "color_camera", "R", "t") if k not in mapping]
        if missing:
            raise ValueError(
                f"{source} lacks key(s) {', '.join(missing)}; a rig needs depth_camera, color_camera, R and t "
                "(as written by `depthrefine calibrate-stereo`)."
            )
        depth = CameraModel.from_dict(mapping["depth_camera"], source=f"{source}: depth_camera")
        color = CameraModel.from_dict(mapping["color_camera"], source=f"{source}: color_camera")
        try:
            return cls(depth, color, np.asarray(mapping["R"], dtype=np.float64),
                       np.asarray(mapping["t"], dtype=np.float64), mapping.get("rms"))
        except (TypeError, ValueError) as exc:
            raise type(exc)(f"{source}: {exc}") from None


# ----------------------------------------------------------------------------
# Board detection
# ----------------------------------------------------------------------------


def board_points(board: tuple[int, int], square_size: float) -> np.ndarray:
    """The inner corners of a checkerboard in its own plane (Z = 0), in OpenCV's order.

    Parameters
    ----------
    board : (int, int)
        Inner corners ``(cols, rows)``.
    square_size : float
        Side of a square, metres.

    Returns
    -------
    (cols * rows, 3) float32 ndarray
        Row by row, ``cols`` corners each: ``(col * size, row * size, 0)``.

    Examples
    --------
    >>> board_points((3, 2), 0.5)[:4].tolist()
    [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.5, 0.0]]
    """
    cols, rows = _check_board(board)
    size = _check_square(square_size)
    grid = np.mgrid[0:rows, 0:cols].astype(np.float32)
    pts = np.zeros((rows * cols, 3), np.float32)
    pts[:, 0] = grid[1].ravel() * size
    pts[:, 1] = grid[0].ravel() * size
    return pts


def to_gray8(image: np.ndarray) -> np.ndarray:
    """An 8-bit gray version of an intensity or color image, for corner detection.

    8-bit images are only converted to gray. 16-bit and float images (ToF
    amplitude) are stretched so that the 0.5th-99.5th percentiles of their
    finite values span 0..255.

    Examples
    --------
    >>> to_gray8(np.array([[0, 1000], [2000, 4000]], np.uint16)).tolist()
    [[0, 64], [128, 255]]
    """
    if not isinstance(image, np.ndarray):
        raise TypeError(f"image must be a numpy array; got {type(image).__name__}.")
    if image.ndim == 3 and image.shape[2] in (3, 4):
        if image.dtype == np.uint8 or image.dtype == np.uint16 or image.dtype == np.float32:
            image = cv2.cvtColor(np.ascontiguousarray(image[:, :, :3]), cv2.COLOR_RGB2GRAY)
        else:
            image = image[:, :, :3].astype(np.float64) @ np.array([0.299, 0.587, 0.114])
    elif image.ndim == 3 and image.shape[2] == 1:
        image = image[:, :, 0]
    if image.ndim != 2:
        raise ValueError(f"image must be (rows, cols) or (rows, cols, 3); got shape {image.shape}.")
    if image.dtype == np.uint8:
        return np.ascontiguousarray(image)
    values = image.astype(np.float64)
    finite = np.isfinite(values)
    if not finite.any():
        raise ValueError("image has no finite pixel.")
    lo, hi = np.percentile(values[finite], [0.5, 99.5])
    if hi <= lo:
        hi = lo + 1.0
    out = np.clip((np.where(finite, values, lo) - lo) * (255.0 / (hi - lo)), 0, 255)
    return np.floor(out + 0.5).astype(np.uint8)


def find_board_corners(image: np.ndarray, board: tuple[int, int]) -> np.ndarray | None:
    """Find a checkerboard's inner corners to sub-pixel accuracy.

    Parameters
    ----------
    image : (rows, cols) or (rows, cols, 3) ndarray
        Intensity (any dtype) or RGB image.
    board : (int, int)
        Inner corners ``(cols, rows)``.

    Returns
    -------
    (cols * rows, 2) float32 ndarray or None
        Corner positions ``(x, y)`` = (column, row) in pixels, in
        :func:`board_points` order, the first corner being the one nearest
        the image's top-left; ``None`` if the board is not found.
    """
    cols, rows = _check_board(board)
    gray = to_gray8(image)
    flags = cv2.CALIB_CB_ADAPTIVE_THRESH | cv2.CALIB_CB_NORMALIZE_IMAGE
    found, corners = cv2.findChessboardCorners(gray, (cols, rows), flags=flags)
    if found:
        corners = corners.reshape(-1, 2).astype(np.float32)
        step = _corner_spacing(corners, cols, rows)
        half = int(np.clip(np.floor(step * 0.4), 2, 11))
        refined = cv2.cornerSubPix(gray, corners.reshape(-1, 1, 2).copy(), (half, half), (-1, -1),
                                   _SUBPIX_CRITERIA)
        corners = refined.reshape(-1, 2)
    else:
        found, corners = cv2.findChessboardCornersSB(gray, (cols, rows), flags=cv2.CALIB_CB_ACCURACY)
        if not found:
            return None
        corners = corners.reshape(-1, 2).astype(np.float32)
    # OpenCV's order is defined up to a half turn of the board: put the first
    # corner top-left so that two cameras of an upright rig agree.
    if corners[0].sum() > corners[-1].sum():
        corners = corners[::-1].copy()
    return np.ascontiguousarray(corners, dtype=np.float32)


# ----------------------------------------------------------------------------
# Calibration
# ----------------------------------------------------------------------------


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


# ----------------------------------------------------------------------------
# Helpers
# ----------------------------------------------------------------------------


def _is_int(value: Any) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool)


def _matrix(name: str, value: Any, shape: tuple[int, ...]) -> np.ndarray:
    try:
        arr = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a numeric array of shape {shape}; got {value!r}.") from None
    if arr.shape != shape:
        raise ValueError(f"{name} must have shape {shape}; got {arr.shape}.")
    if not np.isfinite(arr).all():
        raise ValueError(f"{name} holds NaN or inf.")
    return arr


def _check_board(board: Any) -> tuple[int, int]:
    if (isinstance(board, (str, bytes)) or not hasattr(board, "__len__") or len(board) != 2
            or not all(_is_int(v) for v in board)):
        raise TypeError(f"board must be two integers (cols, rows) of inner corners; got {board!r}.")
    cols, rows = int(board[0]), int(board[1])
    if cols < 2 or rows < 2:
        raise ValueError(f"board must have at least 2x2 inner corners; got {cols}x{rows}.")
    return cols, rows


def _check_square(square_size: Any) -> float:
    if isinstance(square_size, bool) or not isinstance(square_size, (int, float, np.floating)):
        raise TypeError(f"square_size must be a number (metres); got {square_size!r}.")
    if not (math.isfinite(square_size) and square_size > 0):
        raise ValueError(f"square_size must be > 0 metres; got {square_size}.")
    return float(square_size)


def _check_size(size: Any) -> tuple[int, int]:
    if (not hasattr(size, "__len__") or len(size) != 2 or not all(_is_int(v) and v > 0 for v in size)):
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


def _corner_spacing(corners: np.ndarray, cols: int, rows: int) -> float:
    """Smallest distance between neighbouring corners, pixels."""
    grid = corners.reshape(rows, cols, 2)
    across = np.linalg.norm(np.diff(grid, axis=1), axis=2)
    down = np.linalg.norm(np.diff(grid, axis=0), axis=2)
    return float(min(across.min(), down.min()))
