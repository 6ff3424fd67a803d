"""RealSense SDK recordings (``rs-record``, the RealSense Viewer): a ROS 1 bag in the SDK's own layout.

Topics (``librealsense``'s ``ros_topic``, file version 3 and later)::

    /device_<d>/sensor_<s>/<Stream>_<i>/image/data         sensor_msgs/Image (Depth: mono16, Color: rgb8, ...)
    /device_<d>/sensor_<s>/<Stream>_<i>/info               realsense_msgs/StreamInfo (fps, encoding)
    /device_<d>/sensor_<s>/<Stream>_<i>/info/camera_info   sensor_msgs/CameraInfo (K, D, lens model name)
    /device_<d>/sensor_<s>/<Stream>_<i>/tf/<ref>           geometry_msgs/Transform: reference stream -> this stream
    /device_<d>/sensor_<s>/option/Depth Units/value        std_msgs/Float32: metres per depth unit

Depth and color come from different sensors, so a recording is always raw
(not registered); its calibration (:func:`calibration`) becomes the
sequence's rig, and the ``Depth Units`` option its depth units.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np

from ._bags import _first, camera_info_dict

__all__ = ["streams", "calibration"]

_STREAM = re.compile(r"^/device_(\d+)/sensor_(\d+)/(Depth|Color)_(\d+)/image/data$")
_NO_RIG = "pass --rig rig.json (from `depthrefine calibrate-stereo`)"


def streams(topics: dict[str, str]) -> dict[str, list[tuple[str, str]]] | None:
    """``{"depth": [(topic, "Depth_0"), ...], "color": [...]}`` of a RealSense recording, else None.

    Examples
    --------
    >>> streams({"/device_0/sensor_0/Depth_0/image/data": "sensor_msgs/msg/Image"})["depth"]
    [('/device_0/sensor_0/Depth_0/image/data', 'Depth_0 of device 0')]
    """
    found: dict[str, list[tuple[str, str]]] = {"depth": [], "color": []}
    for topic in sorted(topics):
        m = _STREAM.match(topic)
        if m:
            found["depth" if m.group(3) == "Depth" else "color"].append(
                (topic, f"{m.group(3)}_{m.group(4)} of device {m.group(1)}"))
    return found if found["depth"] or found["color"] else None


def _prefix(image_topic: str) -> str:
    return image_topic[: -len("/image/data")]


def calibration(reader, p: Path, topics: dict[str, str], depth_topic: str, color_topic: str) -> dict[str, Any]:
    """Rig, depth units and frame rate of a RealSense recording (keyword arguments of :class:`Sequence`)."""
    from ..rig.formats import rig_from_ros, rotation_from_quaternion

    out: dict[str, Any] = {"raw": True}
    device, sensor = depth_topic.split("/")[1:3]
    for name in ("Depth Units", "Depth_Units"):
        option = f"/{device}/{sensor}/option/{name}/value"
        units = _first(reader, option) if option in topics else None
        if units is not None and float(units.data) > 0:
            out["depth_units"] = float(units.data)
            break
    info = f"{_prefix(depth_topic)}/info"
    stream_info = _first(reader, info) if info in topics else None
    if stream_info is not None and float(getattr(stream_info, "fps", 0) or 0) > 0:
        out["frame_rate"] = float(stream_info.fps)
    infos, poses = {}, {}
    for role, topic in (("depth", depth_topic), ("color", color_topic)):
        where = f"{_prefix(topic)}/info/camera_info"
        msg = _first(reader, where) if where in topics else None
        if msg is None:
            out["rig_problem"] = (f"RealSense recording {p} has no camera_info for the {role} stream ({where}); "
                                  f"{_NO_RIG}.")
            return out
        infos[role] = {**camera_info_dict(msg), "frame_id": role}
        refs = {}
        for t in topics:
            if t.startswith(f"{_prefix(topic)}/tf/") and t.rsplit("/", 1)[1].isdigit():
                refs[int(t.rsplit("/", 1)[1])] = t
        poses[role] = refs
    common = sorted(set(poses["depth"]) & set(poses["color"]))
    if not common:
        out["rig_problem"] = (f"RealSense recording {p} has no extrinsics of the depth and color streams to one "
                              f"reference ({_prefix(depth_topic)}/tf/<n> and {_prefix(color_topic)}/tf/<n>); "
                              f"{_NO_RIG}.")
        return out
    transforms = []
    for role in ("depth", "color"):
        tf = _first(reader, poses[role][common[0]])
        tr, q = tf.translation, tf.rotation
        # .../tf/<ref> maps the reference stream into this stream: X_stream = R X_ref + t.
        transforms.append((role, "reference", rotation_from_quaternion([q.x, q.y, q.z, q.w]),
                           np.array([tr.x, tr.y, tr.z], dtype=np.float64)))
    try:
        out["rig"] = rig_from_ros(infos["depth"], infos["color"], transforms, source=f"RealSense recording {p}",
                                  realsense=True)
    except ValueError as exc:
        out["rig_problem"] = str(exc)
        return out
    out["rig_source"] = "the recording's intrinsics and extrinsics (RealSense SDK)"
    return out
