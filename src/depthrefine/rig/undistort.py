"""Undistortion of depth maps and images (spec step 1).

Depth is remapped with nearest sampling (a depth value is never blended with
its neighbours across an edge, and an invalid pixel stays invalid); color is
remapped bilinearly.
"""

from __future__ import annotations

import numpy as np

from .._lazy import cv2
from .._validate import as_depth, check_depth
from .camera import CameraModel, check_camera_shape
from .pointcloud import pixel_rays

__all__ = ["undistort_maps", "distort_maps", "undistort_depth", "undistort_image", "distort_depth", "distort_image"]



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
    check_camera_shape(depth.shape, camera, "depth")
    return _remap_depth(depth, undistort_maps(camera))


def undistort_image(image: np.ndarray, camera: CameraModel) -> np.ndarray:
    """Remove the lens distortion from an intensity or color image (bilinear, dtype kept)."""
    check_camera_shape(np.shape(image), camera, "image")
    return _remap_image(image, undistort_maps(camera))


def distort_depth(depth: np.ndarray, camera: CameraModel) -> np.ndarray:
    """Apply the lens distortion to an undistorted depth map (nearest; the inverse of :func:`undistort_depth`)."""
    check_depth(depth, "depth")
    check_camera_shape(depth.shape, camera, "depth")
    return _remap_depth(depth, distort_maps(camera))


def distort_image(image: np.ndarray, camera: CameraModel) -> np.ndarray:
    """Apply the lens distortion to an undistorted image (bilinear; the inverse of :func:`undistort_image`)."""
    check_camera_shape(np.shape(image), camera, "image")
    return _remap_image(image, distort_maps(camera))
