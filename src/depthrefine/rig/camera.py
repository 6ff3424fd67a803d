"""Camera models: a pinhole camera with lens distortion, and a depth + color rig.

What :mod:`depthrefine.rig.calibrate` fits and the rest of the rig uses. Pure data
classes; files are read and written by :mod:`depthrefine.io`.

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
from typing import Any, Mapping

import numpy as np

from .._validate import is_int

__all__ = ["CameraModel", "StereoRig", "check_camera_shape"]


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
                or not all(is_int(v) and v > 0 for v in size)):
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


def check_camera_shape(shape: tuple[int, ...], camera: CameraModel, name: str) -> None:
    """Refuse an image whose size is not the one ``camera`` was calibrated on."""
    if tuple(shape[:2]) != camera.shape:
        w, h = camera.image_size
        raise ValueError(
            f"{name} is {shape[1]}x{shape[0]} (width x height) but the camera was calibrated on {w}x{h} "
            "images; use the camera file of this camera at this resolution."
        )
