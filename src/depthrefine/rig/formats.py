"""Calibrations made by other tools, as :class:`CameraModel` / :class:`StereoRig`.

Pure conversions of already-parsed files (mappings of numbers, lists and
arrays); :func:`depthrefine.io.read_calibration` reads the files.

Azure Kinect (K4A ``calibration.json``, the factory calibration stored on the device)
    ``ModelParameters`` are ``[cx, cy, fx, fy, k1, k2, k3, k4, k5, k6, codx,
    cody, p2, p1]`` normalised by the calibration resolution, pixel ``(0, 0)``
    being the top-left *corner* of the image. A capture mode crops and bins
    the sensor: the Azure Kinect Sensor SDK
    (``src/transformation/mode_specific_calibration.c``) gives each mode a
    calibration resolution, a crop offset and an output size, and
    ``pixel = normalised * calibration_resolution - crop_offset - 0.5``
    (OpenCV's pixel-centre convention). The distortion is OpenCV's rational
    model ``(k1, k2, p1, p2, k3, k4, k5, k6)``. Each camera's ``Rt`` maps the
    reference frame (the depth camera's) into that camera, so depth to color
    is ``X_color = R X_depth + t`` with ``t`` in metres.
OpenCV FileStorage YAML
    ``K`` (3x3), ``dist`` (OpenCV order) and ``img_size`` ``[width, height]``,
    as written by OpenCV calibration scripts (e.g. the Azure Kinect SDK's
    ``calibration_registration`` example). One camera.
ROS ``camera_info`` YAML
    The ``camera_calibration_parsers`` layout (``image_width``,
    ``image_height``, ``camera_matrix``, ``distortion_model``,
    ``distortion_coefficients``) or a dumped ``sensor_msgs/CameraInfo``
    message (``width``, ``height``, ``K``/``k``, ``D``/``d``,
    ``distortion_model``). ``plumb_bob`` and ``rational_polynomial`` map to
    OpenCV's model; ``equidistant`` (fisheye) has no equivalent here. One camera.
RealSense (a ``camera_info`` of the SDK's rosbag recordings)
    ``K`` and ``D`` as in ROS, with the SDK's lens model names: ``Brown Conrady``
    holds OpenCV's ``(k1, k2, p1, p2, k3)`` in that order; ``None``, or any model
    whose coefficients are all 0, is a lens without distortion. The
    extrinsics of each stream (``.../tf/<ref>``) map the reference stream into
    that stream: ``X_stream = R X_ref + t``, metres.
ROS transforms (``/tf_static``)
    Each ``geometry_msgs/TransformStamped`` gives the pose of ``child_frame_id`` in
    ``header.frame_id``: ``X_parent = R X_child + t``, ``R`` from the unit
    quaternion ``(x, y, z, w)``. :func:`rig_from_ros` chains them from the depth
    camera's frame to the color camera's (the ``frame_id`` of each ``camera_info``).
"""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from ._names import CALIBRATION_FORMATS, K4A_COLOR_RESOLUTIONS, K4A_DEPTH_MODES
from .camera import CameraModel, StereoRig

__all__ = [
    "K4A_DEPTH_MODES",
    "K4A_COLOR_RESOLUTIONS",
    "CALIBRATION_FORMATS",
    "calibration_format",
    "k4a_camera",
    "rig_from_k4a",
    "camera_from_opencv",
    "camera_from_ros",
    "camera_from_realsense",
    "rig_from_poses",
    "rig_from_ros",
    "rotation_from_quaternion",
    "transform_between_frames",
]

_K4A_DEPTH = "CALIBRATION_CameraPurposeDepth"
_K4A_COLOR = "CALIBRATION_CameraPurposePhotoVideo"
_ROS_MODELS = {"plumb_bob": (5,), "rational_polynomial": (8,)}


def calibration_format(mapping: Mapping[str, Any]) -> str | None:
    """``"k4a"``, ``"opencv"``, ``"ros"`` or None, from a parsed file's keys."""
    if not isinstance(mapping, Mapping):
        return None
    if "CalibrationInformation" in mapping:
        return "k4a"
    if "distortion_model" in mapping or "camera_matrix" in mapping:
        return "ros"
    if "K" in mapping and "img_size" in mapping:
        return "opencv"
    return None


def _mode(name: Any, table: dict, option: str) -> tuple[str, tuple]:
    key = str(name).upper().replace("K4A_DEPTH_MODE_", "").replace("K4A_COLOR_RESOLUTION_", "")
    if key not in table:
        raise ValueError(f"unknown {option} {name!r}; the Azure Kinect has {', '.join(table)}.")
    return key, table[key]


def k4a_camera(camera: Mapping[str, Any], mode: tuple, *, source: str = "camera") -> CameraModel:
    """One camera of a K4A calibration in one mode (``mode`` is a row of the mode tables).

    Examples
    --------
    >>> cam = {"Intrinsics": {"ModelType": "CALIBRATION_LensDistortionModelBrownConrady",
    ...        "ModelParameters": [0.5, 0.5, 0.5, 0.5] + [0.0] * 10}, "SensorWidth": 1024, "SensorHeight": 1024}
    >>> k4a_camera(cam, K4A_DEPTH_MODES["NFOV_UNBINNED"]).K[:2].tolist()
    [[512.0, 0.0, 319.5], [0.0, 512.0, 331.5]]
    """
    (calib_w, calib_h), (crop_x, crop_y), size = mode
    intrinsics = camera.get("Intrinsics", {})
    model = intrinsics.get("ModelType", "")
    if not str(model).endswith("BrownConrady"):
        raise ValueError(f"{source}: lens model {model!r} is not supported; depthrefine reads the Brown-Conrady "
                         "model of Azure Kinect factory calibrations.")
    p = np.asarray(intrinsics.get("ModelParameters", []), dtype=np.float64)
    if p.size < 14:
        raise ValueError(f"{source}: ModelParameters has {p.size} values; the K4A Brown-Conrady model has 14.")
    if p[10] != 0 or p[11] != 0:
        raise ValueError(f"{source}: centre of distortion (codx, cody) = ({p[10]:g}, {p[11]:g}) is not 0; "
                         "OpenCV's lens model cannot represent it.")
    cx, cy, fx, fy = p[0] * calib_w, p[1] * calib_h, p[2] * calib_w, p[3] * calib_h
    K = np.array([[fx, 0.0, cx - crop_x - 0.5], [0.0, fy, cy - crop_y - 0.5], [0.0, 0.0, 1.0]])
    dist = np.array([p[4], p[5], p[13], p[12], p[6], p[7], p[8], p[9]])
    return CameraModel(K, dist, size)


def _k4a_cameras(mapping: Mapping[str, Any], source: str) -> dict[str, Mapping[str, Any]]:
    info = mapping.get("CalibrationInformation")
    cameras = info.get("Cameras") if isinstance(info, Mapping) else None
    if not isinstance(cameras, list):
        raise ValueError(f"{source}: CalibrationInformation has no Cameras list; is it an Azure Kinect calibration?")
    return {c.get("Purpose"): c for c in cameras if isinstance(c, Mapping)}


def _rt(camera: Mapping[str, Any], source: str) -> tuple[np.ndarray, np.ndarray]:
    rt = camera.get("Rt", {})
    try:
        R = np.asarray(rt["Rotation"], dtype=np.float64).reshape(3, 3)
        t = np.asarray(rt["Translation"], dtype=np.float64).reshape(3)
    except (KeyError, TypeError, ValueError):
        raise ValueError(f"{source}: a camera lacks Rt.Rotation (9 values) or Rt.Translation (3 values).") from None
    return R, t


def rig_from_k4a(
    mapping: Mapping[str, Any], *, depth_mode: str, color_resolution: str, source: str = "calibration.json"
) -> StereoRig:
    """The depth + color rig of an Azure Kinect calibration in one capture mode.

    Parameters
    ----------
    mapping : mapping
        The parsed ``calibration.json``.
    depth_mode : str
        A key of :data:`K4A_DEPTH_MODES`, e.g. ``"NFOV_UNBINNED"``.
    color_resolution : str
        A key of :data:`K4A_COLOR_RESOLUTIONS`, e.g. ``"720P"``.
    source : str
        The file's name, for messages.

    Returns
    -------
    StereoRig
        Intrinsics of the depth and color images of that mode, ``R, t`` from
        the depth camera to the color camera (metres).

    Raises
    ------
    ValueError
        An unknown mode, a camera missing from the file, a sensor size that
        has no such mode, or a lens model OpenCV cannot represent.
    """
    depth_mode, depth_info = _mode(depth_mode, K4A_DEPTH_MODES, "depth mode")
    color_resolution, color_info = _mode(color_resolution, K4A_COLOR_RESOLUTIONS, "color resolution")
    cameras = _k4a_cameras(mapping, source)
    for purpose, what in ((_K4A_DEPTH, "depth"), (_K4A_COLOR, "color")):
        if purpose not in cameras:
            raise ValueError(f"{source} has no {what} camera (Purpose {purpose}); it cannot give the "
                             f"{depth_mode if what == 'depth' else color_resolution} mode.")
    depth, color = cameras[_K4A_DEPTH], cameras[_K4A_COLOR]
    size_d = (depth.get("SensorWidth"), depth.get("SensorHeight"))
    if size_d != (1024, 1024):
        raise ValueError(f"{source}: the depth camera's calibration is {size_d[0]}x{size_d[1]}, not the 1024x1024 "
                         f"the Azure Kinect SDK needs for depth mode {depth_mode}.")
    width, height = color.get("SensorWidth"), color.get("SensorHeight")
    params = list(color.get("Intrinsics", {}).get("ModelParameters", []))
    if isinstance(width, int) and isinstance(height, int) and width * 9 // 16 == height and len(params) >= 4:
        # Legacy 16:9 calibration: the SDK first re-expresses it on the 4:3 sensor (4096x2304 cropped
        # at y = -384 from 4096x3072), still normalised and corner-based.
        params[1] = (params[1] * 2304 + 384) / 3072
        params[3] = params[3] * 2304 / 3072
        color = {**color, "Intrinsics": {**color["Intrinsics"], "ModelParameters": params}}
    elif not (isinstance(width, int) and isinstance(height, int) and width * 3 // 4 == height):
        raise ValueError(f"{source}: the color camera's calibration is {width}x{height}, neither 4:3 nor 16:9; "
                         f"the Azure Kinect SDK has no {color_resolution} mode for it.")
    depth_cam = k4a_camera(depth, depth_info, source=f"{source}: depth camera")
    color_cam = k4a_camera(color, color_info, source=f"{source}: color camera")
    return rig_from_poses(depth_cam, color_cam, _rt(depth, source), _rt(color, source))


def rig_from_poses(
    depth_camera: CameraModel, color_camera: CameraModel, depth_pose: tuple, color_pose: tuple
) -> StereoRig:
    """The rig of two cameras whose poses map one reference frame into each camera.

    ``depth_pose = (R_d, t_d)`` with ``X_depth = R_d X_ref + t_d``, the same for
    ``color_pose``; the rig's ``R, t`` then map the depth camera into the color camera.

    Examples
    --------
    >>> cam = CameraModel(np.diag([100., 100., 1.]), np.zeros(5), (64, 48))
    >>> rig = rig_from_poses(cam, cam, (np.eye(3), np.zeros(3)), (np.eye(3), np.array([-0.05, 0, 0])))
    >>> rig.t.tolist()
    [-0.05, 0.0, 0.0]
    """
    R_d, t_d = (np.asarray(v, dtype=np.float64) for v in depth_pose)
    R_c, t_c = (np.asarray(v, dtype=np.float64) for v in color_pose)
    # X_color = R_c R_d^T (X_depth - t_d) + t_c.
    R = R_c @ R_d.T
    return StereoRig(depth_camera, color_camera, R, t_c.ravel() - R @ t_d.ravel())


def _numbers(value: Any, name: str, source: str) -> np.ndarray:
    if isinstance(value, Mapping) and "data" in value:
        value = value["data"]
    try:
        arr = np.asarray(value, dtype=np.float64).ravel()
    except (TypeError, ValueError):
        raise ValueError(f"{source}: {name} is not a list of numbers.") from None
    return arr


def camera_from_opencv(mapping: Mapping[str, Any], *, source: str = "camera file") -> CameraModel:
    """One camera from an OpenCV FileStorage calibration (``K``, ``dist``, ``img_size``).

    Examples
    --------
    >>> camera_from_opencv({"K": [[500, 0, 319.5], [0, 500, 239.5], [0, 0, 1]], "dist": [0.1, 0, 0, 0, 0],
    ...                     "img_size": [640, 480]}).image_size
    (640, 480)
    """
    if "img_size" not in mapping:
        raise ValueError(f"{source} has K but no img_size [width, height]; the image size is needed.")
    K = _numbers(mapping["K"], "K", source)
    size = _numbers(mapping["img_size"], "img_size", source)
    if K.size != 9 or size.size != 2:
        raise ValueError(f"{source}: K must hold 9 numbers and img_size 2 (width, height); got {K.size} and {size.size}.")
    dist = _numbers(mapping.get("dist", []), "dist", source)
    try:
        return CameraModel(K.reshape(3, 3), dist, (int(size[0]), int(size[1])))
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{source}: {exc}") from None


def camera_from_ros(mapping: Mapping[str, Any], *, source: str = "camera_info") -> CameraModel:
    """One camera from a ROS ``camera_info`` YAML (either layout, see the module docstring).

    Examples
    --------
    >>> info = {"width": 640, "height": 480, "distortion_model": "plumb_bob", "d": [0.1, 0, 0, 0, 0],
    ...         "k": [500, 0, 319.5, 0, 500, 239.5, 0, 0, 1]}
    >>> camera_from_ros(info).focal
    (500.0, 500.0)
    """
    def first(*keys: str) -> Any:
        for key in keys:
            if key in mapping:
                return mapping[key]
        raise ValueError(f"{source} lacks {' / '.join(keys)}; is it a ROS camera_info file?")

    width = first("image_width", "width")
    height = first("image_height", "height")
    K = _numbers(first("camera_matrix", "K", "k"), "camera_matrix", source)
    dist = _numbers(first("distortion_coefficients", "D", "d"), "distortion_coefficients", source)
    model = str(mapping.get("distortion_model", "plumb_bob"))
    if model not in _ROS_MODELS:
        raise ValueError(f"{source}: distortion_model {model!r} is not supported; depthrefine reads "
                         f"{' and '.join(_ROS_MODELS)} (OpenCV's model).")
    if K.size != 9:
        raise ValueError(f"{source}: camera_matrix must hold 9 numbers; got {K.size}.")
    try:
        return CameraModel(K.reshape(3, 3), dist, (int(width), int(height)))
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{source}: {exc}") from None


#: RealSense lens models (``rs2_distortion`` names) that OpenCV's model holds as they are.
_RS_OPENCV_MODELS = ("Brown Conrady", "None")


def camera_from_realsense(mapping: Mapping[str, Any], *, source: str = "camera_info") -> CameraModel:
    """One stream of a RealSense recording (``width``, ``height``, ``K``, ``D``, ``distortion_model``).

    Examples
    --------
    >>> info = {"width": 640, "height": 480, "distortion_model": "Inverse Brown Conrady", "D": [0.0] * 5,
    ...         "K": [600, 0, 319.5, 0, 600, 239.5, 0, 0, 1]}
    >>> camera_from_realsense(info).has_distortion
    False
    """
    model = str(mapping.get("distortion_model", "None"))
    dist = _numbers(mapping.get("D", mapping.get("d", [])), "D", source)
    if model not in _RS_OPENCV_MODELS and np.any(dist != 0):
        raise ValueError(f"{source}: RealSense lens model {model!r} with coefficients {dist.tolist()} is not "
                         f"OpenCV's model (depthrefine reads {' and '.join(map(repr, _RS_OPENCV_MODELS))}); "
                         "calibrate the cameras with `depthrefine calibrate-stereo` and pass --rig.")
    if model == "None" or not np.any(dist != 0):
        dist = np.zeros(5)
    return camera_from_ros({**mapping, "distortion_model": "plumb_bob", "D": dist[:5] if dist.size > 5 else dist},
                           source=source)


def rotation_from_quaternion(quaternion: Any) -> np.ndarray:
    """The 3x3 rotation of a quaternion ``(x, y, z, w)`` (normalised first; ROS order).

    Examples
    --------
    >>> rotation_from_quaternion([0, 0, np.sin(np.pi / 4), np.cos(np.pi / 4)]).round(6).tolist()
    [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    """
    q = np.asarray(quaternion, dtype=np.float64).ravel()
    norm = np.linalg.norm(q) if q.size == 4 else 0.0
    if not (np.isfinite(norm) and norm > 0):
        raise ValueError(f"a rotation quaternion needs 4 finite numbers (x, y, z, w), not all 0; got {q.tolist()}.")
    x, y, z, w = q / norm
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def transform_between_frames(transforms: list[tuple[str, str, np.ndarray, np.ndarray]], source: str, target: str
                             ) -> tuple[np.ndarray, np.ndarray] | None:
    """``(R, t)`` with ``X_target = R X_source + t``, chained through a tree of transforms; None if unlinked.

    ``transforms`` holds ``(parent, child, R, t)`` with ``X_parent = R X_child + t``
    (a ROS ``TransformStamped``); each may be walked either way.

    Examples
    --------
    >>> tree = [("base", "depth", np.eye(3), np.array([0.0, 0, 0])), ("base", "color", np.eye(3), np.array([0.05, 0, 0]))]
    >>> transform_between_frames(tree, "depth", "color")[1].tolist()
    [-0.05, 0.0, 0.0]
    """
    # Poses of every reachable frame in the source frame: X_source = R X_frame + t.
    poses: dict[str, tuple[np.ndarray, np.ndarray]] = {source: (np.eye(3), np.zeros(3))}
    frontier = [source]
    while frontier and target not in poses:
        frame = frontier.pop(0)
        R_f, t_f = poses[frame]
        for parent, child, R, t in transforms:
            if parent == frame and child not in poses:      # X_frame = R X_child + t
                poses[child] = (R_f @ R, R_f @ t + t_f)
                frontier.append(child)
            elif child == frame and parent not in poses:    # X_parent = R X_frame + t
                poses[parent] = (R_f @ R.T, t_f - R_f @ R.T @ t)
                frontier.append(parent)
    if target not in poses:
        return None
    R_st, t_st = poses[target]                              # X_source = R_st X_target + t_st
    return R_st.T, -R_st.T @ t_st


def rig_from_ros(
    depth_info: Mapping[str, Any],
    color_info: Mapping[str, Any],
    transforms: list[tuple[str, str, np.ndarray, np.ndarray]],
    *,
    source: str = "ROS bag",
    realsense: bool = False,
) -> StereoRig:
    """The rig of a depth and a color ``camera_info`` (with their ``frame_id``) and a tree of transforms.

    Cameras in the same frame (or with empty frame ids) get ``R = I, t = 0``.

    Raises
    ------
    ValueError
        A camera_info that does not convert (see :func:`camera_from_ros`), or
        frames that no chain of ``transforms`` links.
    """
    convert = camera_from_realsense if realsense else camera_from_ros
    depth = convert(depth_info, source=f"{source}: depth camera_info")
    color = convert(color_info, source=f"{source}: color camera_info")
    frames = (str(depth_info.get("frame_id", "")), str(color_info.get("frame_id", "")))
    if frames[0] == frames[1]:
        return StereoRig(depth, color, np.eye(3), np.zeros(3))
    link = transform_between_frames(transforms, *frames)
    if link is None:
        known = sorted({name for parent, child, _, _ in transforms for name in (parent, child)})
        raise ValueError(f"{source}: no chain of /tf_static transforms links the depth frame {frames[0]!r} to the "
                         f"color frame {frames[1]!r} (frames: {', '.join(known) or 'none'}).")
    return StereoRig(depth, color, *link)
