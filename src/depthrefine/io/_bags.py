"""ROS bags as sequences: ROS 1 ``.bag``, ROS 2 bags (folder, ``.db3``, bare ``.mcap``), RealSense recordings.

Read with the pure-Python ``rosbags`` package. Depth and color topics hold
``sensor_msgs/Image`` (depth ``16UC1``/``mono16`` in millimetres or
``32FC1`` in metres, as ROS REP 118 defines them; color ``rgb8``, ``bgr8``,
``rgba8``, ``bgra8``, ``mono8`` and their 16-bit forms) or
``sensor_msgs/CompressedImage`` (JPEG or PNG) for color.

- **Topics** are found when the choice is unambiguous: the one depth-like
  image topic (one channel, 16-bit or float; a name with ``depth`` wins over
  others, ``ir``/``infra`` topics never count) and the one color-like topic
  (three or four channels, or compressed; a name with ``color`` or ``rgb``
  wins; a raw topic wins over its ``/compressed`` twin). Otherwise the
  error lists the candidates. RealSense recordings (:mod:`._realsense`) use
  the SDK's topic layout.
- **Calibration**: the first ``sensor_msgs/CameraInfo`` on the sibling
  ``camera_info`` topic of each image topic gives the intrinsics, ``/tf_static``
  the extrinsics between their ``frame_id``s (:func:`~depthrefine.rig.formats.rig_from_ros`).
- **Registered or raw**: depth and color whose headers name different frames
  (and whose depth topic is not an ``aligned`` one) are raw.
- **Time stamps** are read from the header at the start of each serialized
  message, without deserializing the image; a stamp of 0 falls back to the
  recording time.
"""

from __future__ import annotations

import functools
import re
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import check_rgb
from ._files import InputFileError
from ._sequences import Sequence, frame_rate_of, load_in_one_pass, pair_streams

__all__ = ["bag_kind", "open_bag"]

_IMAGE = "sensor_msgs/msg/Image"
_COMPRESSED = "sensor_msgs/msg/CompressedImage"
_CAMERA_INFO = "sensor_msgs/msg/CameraInfo"
_DEPTH_ENCODINGS = ("16uc1", "mono16", "32fc1", "64fc1")
_COLOR_ENCODINGS = ("rgb8", "bgr8", "rgba8", "bgra8", "rgb16", "bgr16", "rgba16", "bgra16", "8uc3")
_NOT_DEPTH = re.compile(r"(^|[/_])(ir|infra\w*|infrared\w*|confidence)([/_]|$)", re.IGNORECASE)
_NO_RIG = "pass --rig rig.json (from `depthrefine calibrate-stereo` or `depthrefine rig import`)"


def bag_kind(p: Path) -> str | None:
    """``"ros1"``, ``"ros2"`` or None (not a bag)."""
    if p.is_file() and p.suffix.lower() == ".bag":
        return "ros1"
    if p.is_dir() and (p / "metadata.yaml").is_file():
        return "ros2"
    if p.is_file() and p.suffix.lower() in (".db3", ".mcap"):
        return "ros2"
    return None


def _target(p: Path) -> Path:
    """What rosbags opens: a bag's folder when its metadata.yaml lists the file given, else the file itself."""
    meta = p.parent / "metadata.yaml"
    if p.is_file() and p.suffix.lower() in (".db3", ".mcap") and meta.is_file():
        try:
            if p.name in meta.read_text(encoding="utf-8", errors="replace"):
                return p.parent
        except OSError:
            pass
    return p


def _reader(p: Path):
    try:
        from rosbags.highlevel import AnyReader
        from rosbags.typesys import Stores, get_typestore
    except ImportError:  # pragma: no cover - a dependency
        raise InputFileError("reading ROS bags needs the rosbags package: pip install rosbags") from None
    return AnyReader([_target(p)], default_typestore=get_typestore(Stores.LATEST))


def _listed(topics: dict[str, str]) -> str:
    return ", ".join(f"{t} ({m})" for t, m in sorted(topics.items())) or "none"


def _first(reader, topic: str):
    """The first message on ``topic``, deserialized, or None."""
    conns = [c for c in reader.connections if c.topic == topic]
    for conn, _, raw in reader.messages(connections=conns):
        return reader.deserialize(raw, conn.msgtype)
    return None


def _stamp(raw: bytes, logtime: int, big_endian_cdr: bool) -> int:
    """The header stamp at the start of a serialized Image/CompressedImage (ROS 1 or CDR), else ``logtime``."""
    sec, nsec = np.frombuffer(bytes(raw[4:12]), dtype=">u4" if big_endian_cdr else "<u4") if len(raw) >= 12 else (0, 0)
    ns = int(sec) * 1_000_000_000 + int(nsec)
    return ns if ns > 0 else int(logtime)


def open_bag(p: Path, kind: str, depth_topic: str | None, color_topic: str | None, max_dt: float) -> Sequence:
    """Pair the depth and color frames of a bag (see the module docstring)."""
    from . import _realsense

    try:
        with _reader(p) as reader:
            topics = {c.topic: c.msgtype for c in reader.connections}
            realsense = _realsense.streams(topics)
            for name, topic in (("--depth-topic", depth_topic), ("--color-topic", color_topic)):
                if topic is not None and topic not in topics:
                    raise InputFileError(f"ROS bag {p} has no topic {topic!r} ({name}); its topics: {_listed(topics)}.")
                if topic is not None and topics[topic] not in (_IMAGE, _COMPRESSED):
                    raise InputFileError(f"ROS bag {p}: topic {topic} holds {topics[topic]}; {name} needs "
                                         "sensor_msgs/Image or sensor_msgs/CompressedImage.")
            firsts: dict[str, Any] = {}
            depth_topic, color_topic = _choose_topics(reader, p, topics, depth_topic, color_topic, realsense, firsts)
            stamps: dict[str, list] = {depth_topic: [], color_topic: []}
            seen: dict[tuple[str, int], int] = {}
            big = reader.is2 and any(_cdr_big_endian(reader, t) for t in stamps)
            conns = [c for c in reader.connections if c.topic in stamps]
            for conn, logtime, raw in reader.messages(connections=conns):
                k = seen.get((conn.topic, logtime), 0)
                seen[(conn.topic, logtime)] = k + 1
                stamps[conn.topic].append((_stamp(raw, logtime, big), (conn.topic, int(logtime), k)))
            first_depth, first_color = (firsts.get(t) or _first(reader, t) for t in (depth_topic, color_topic))
            if realsense:
                calib = _realsense.calibration(reader, p, topics, depth_topic, color_topic)
            else:
                calib = _ros_calibration(reader, p, topics, depth_topic, color_topic, first_depth, first_color)
    except InputFileError:
        raise
    except Exception as exc:  # noqa: BLE001 - any failure of the bag reader is a bad bag
        raise InputFileError(f"ROS bag {p} cannot be read ({type(exc).__name__}: {exc}).") from None
    for topic in (depth_topic, color_topic):
        if not stamps[topic]:
            raise InputFileError(f"ROS bag {p}: topic {topic} holds no messages; nothing to refine.")
    encoding = str(getattr(first_depth, "encoding", "")).lower()
    suffix = ".tif" if encoding in ("32fc1", "64fc1") else ".png"
    try:
        frames, unpaired = pair_streams(stamps[depth_topic], stamps[color_topic], max_dt, names=(depth_topic, color_topic),
                                        suffix=suffix)
    except InputFileError as exc:
        raise InputFileError(f"ROS bag {p}: {exc}") from None
    units = calib.pop("depth_units", None) or (1.0 if suffix == ".tif" else 0.001)
    rate = calib.pop("frame_rate", None) or frame_rate_of([t for t, _ in stamps[depth_topic]])
    return Sequence(p, "realsense" if realsense else kind, frames, topics={"depth": depth_topic, "color": color_topic},
                    folders=(p,) if p.is_dir() else (), depth_units=units, frame_rate=rate, unpaired=unpaired,
                    reader=_load_bag, **calib)


def _cdr_big_endian(reader, topic: str) -> bool:
    conns = [c for c in reader.connections if c.topic == topic]
    for _, _, raw in reader.messages(connections=conns):
        return len(raw) > 1 and raw[1] == 0
    return False


# ----------------------------------------------------------------------------
# topics
# ----------------------------------------------------------------------------


def _choose_topics(reader, p: Path, topics: dict[str, str], depth_topic: str | None, color_topic: str | None,
                   realsense: dict | None, firsts: dict) -> tuple[str, str]:
    """The depth and color topics: the ones given, else the only candidates (see the module docstring)."""
    if depth_topic and color_topic:
        return depth_topic, color_topic
    if realsense:
        depth, color = realsense["depth"], realsense["color"]
    else:
        depth, color = _candidates(reader, topics, firsts)
    chosen = []
    for role, given, found, option in (("depth", depth_topic, depth, "--depth-topic"),
                                       ("color", color_topic, color, "--color-topic")):
        if given:
            chosen.append(given)
            continue
        if len(found) == 1:
            chosen.append(found[0][0])
            continue
        if not found:
            raise InputFileError(f"ROS bag {p} has no {role} image topic ({_ROLE_TYPES[role]}); give {option} "
                                 f"(its topics: {_listed(topics)}).")
        listed = ", ".join(f"{t} ({what})" for t, what in found)
        raise InputFileError(f"ROS bag {p} has {len(found)} {role} image topics: {listed}; choose one with {option}.")
    return chosen[0], chosen[1]


_ROLE_TYPES = {"depth": "sensor_msgs/Image 16UC1, mono16 or 32FC1",
               "color": "sensor_msgs/Image rgb8, bgr8, rgba8 or bgra8, or CompressedImage"}


def _candidates(reader, topics: dict[str, str], firsts: dict) -> tuple[list, list]:
    depth, color = [], []
    for topic, msgtype in sorted(topics.items()):
        if msgtype not in (_IMAGE, _COMPRESSED):
            continue
        msg = _first(reader, topic)
        if msg is None:
            continue
        firsts[topic] = msg
        if msgtype == _COMPRESSED:
            fmt = str(msg.format)
            if "compresseddepth" not in fmt.lower():
                color.append((topic, f"CompressedImage {fmt}".strip()))
            continue
        encoding = str(msg.encoding).lower()
        if encoding in _DEPTH_ENCODINGS and not _NOT_DEPTH.search(topic):
            depth.append((topic, msg.encoding))
        elif encoding in _COLOR_ENCODINGS:
            color.append((topic, msg.encoding))
    return _narrow(depth, ("depth",)), _prefer_raw(_narrow(color, ("color", "rgb")))


def _narrow(found: list, words: tuple[str, ...]) -> list:
    named = [item for item in found if any(w in item[0].lower() for w in words)]
    return named if len(found) > 1 and named else found


def _prefer_raw(found: list) -> list:
    raw = [item for item in found if not any(item[0] == other[0] + "/compressed" for other in found)]
    return raw if raw else found


# ----------------------------------------------------------------------------
# calibration: camera_info + /tf_static
# ----------------------------------------------------------------------------


def camera_info_dict(msg) -> dict[str, Any]:
    """A ``sensor_msgs/CameraInfo`` (ROS 1 or 2 field names) as the mapping the rig importers read."""
    def field(*names):
        return next((getattr(msg, n) for n in names if hasattr(msg, n)), None)

    return {"width": int(msg.width), "height": int(msg.height), "K": np.asarray(field("K", "k"), dtype=np.float64),
            "D": np.asarray(field("D", "d"), dtype=np.float64), "distortion_model": str(msg.distortion_model),
            "frame_id": str(getattr(getattr(msg, "header", None), "frame_id", ""))}


def info_topic(image_topic: str) -> str:
    """The ``camera_info`` topic beside an image topic (``/cam/color/image_raw`` -> ``/cam/color/camera_info``).

    Examples
    --------
    >>> info_topic("/cam/color/image_raw/compressed")
    '/cam/color/camera_info'
    """
    base = image_topic[: -len("/compressed")] if image_topic.endswith("/compressed") else image_topic
    return base.rsplit("/", 1)[0] + "/camera_info"


def _ros_calibration(reader, p: Path, topics: dict[str, str], depth_topic: str, color_topic: str,
                     first_depth, first_color) -> dict[str, Any]:
    frame_of = [str(getattr(getattr(m, "header", None), "frame_id", "")) for m in (first_depth, first_color)]
    raw = bool(frame_of[0] and frame_of[1] and frame_of[0] != frame_of[1] and "aligned" not in depth_topic.lower())
    infos = {}
    for role, topic, image in (("depth", depth_topic, first_depth), ("color", color_topic, first_color)):
        where = info_topic(topic)
        if topics.get(where) != _CAMERA_INFO or (msg := _first(reader, where)) is None:
            return {"raw": raw, "rig_problem": f"ROS bag {p} has no camera_info for the {role} topic {topic} (looked "
                                               f"for {where}), so its cameras are not calibrated; {_NO_RIG}."}
        info = camera_info_dict(msg)
        info["frame_id"] = info["frame_id"] or frame_of[0 if role == "depth" else 1]
        size = _image_size(image)
        if size is not None and size != (info["width"], info["height"]):
            return {"raw": raw, "rig_problem": f"ROS bag {p}: camera_info {where} is for {info['width']}x"
                                               f"{info['height']} images but {topic} holds {size[0]}x{size[1]}; "
                                               f"{_NO_RIG}."}
        infos[role] = info
    from ..rig.formats import rig_from_ros

    try:
        rig = rig_from_ros(infos["depth"], infos["color"], tf_static(reader, topics), source=f"ROS bag {p}")
    except ValueError as exc:
        return {"raw": raw, "rig_problem": f"{exc} {_NO_RIG[0].upper()}{_NO_RIG[1:]}."}
    return {"raw": raw, "rig": rig, "rig_source": f"camera_info of {depth_topic} and {color_topic}, /tf_static"}


def _image_size(msg) -> tuple[int, int] | None:
    return (int(msg.width), int(msg.height)) if msg is not None and hasattr(msg, "width") else None


def tf_static(reader, topics: dict[str, str]) -> list[tuple[str, str, np.ndarray, np.ndarray]]:
    """Every transform on ``/tf_static`` as ``(parent, child, R, t)`` (see :func:`~depthrefine.rig.formats.transform_between_frames`)."""
    from ..rig.formats import rotation_from_quaternion

    if "/tf_static" not in topics:
        return []
    out = []
    conns = [c for c in reader.connections if c.topic == "/tf_static"]
    for conn, _, raw in reader.messages(connections=conns):
        for ts in reader.deserialize(raw, conn.msgtype).transforms:
            tr, q = ts.transform.translation, ts.transform.rotation
            out.append((str(ts.header.frame_id).lstrip("/"), str(ts.child_frame_id).lstrip("/"),
                        rotation_from_quaternion([q.x, q.y, q.z, q.w]), np.array([tr.x, tr.y, tr.z], dtype=np.float64)))
    return out


# ----------------------------------------------------------------------------
# decoding
# ----------------------------------------------------------------------------


def _load_bag(seq: Sequence, frames: list):
    """Decode ``frames`` in one pass over the span of the bag they cover."""
    def messages(refs: set):
        start = min(ref[1] for ref in refs)
        stop = max(ref[1] for ref in refs) + 1
        seen: dict[tuple[str, int], int] = {}
        with _reader(seq.source) as reader:
            conns = [c for c in reader.connections if c.topic in (seq.topics["depth"], seq.topics["color"])]
            for conn, logtime, raw in reader.messages(connections=conns, start=start, stop=stop):
                k = seen.get((conn.topic, logtime), 0)
                seen[(conn.topic, logtime)] = k + 1
                ref = (conn.topic, int(logtime), k)
                if ref in refs:
                    yield ref, functools.partial(reader.deserialize, raw, conn.msgtype)

    def decode(role: str, message, where: str):
        msg = message()
        return _decode_depth(msg, where) if role == "depth" else _decode_color(msg, where)

    return load_in_one_pass(frames, messages, decode, f"ROS bag {seq.source}")


# sensor_msgs/Image encodings: (dtype, channels, BGR order)
_ENCODINGS = {
    "16uc1": (np.uint16, 1, False), "mono16": (np.uint16, 1, False), "32fc1": (np.float32, 1, False),
    "64fc1": (np.float64, 1, False), "8uc1": (np.uint8, 1, False), "mono8": (np.uint8, 1, False),
    "rgb8": (np.uint8, 3, False), "bgr8": (np.uint8, 3, True), "rgba8": (np.uint8, 4, False),
    "bgra8": (np.uint8, 4, True), "rgb16": (np.uint16, 3, False), "bgr16": (np.uint16, 3, True),
    "rgba16": (np.uint16, 4, False), "bgra16": (np.uint16, 4, True), "8uc3": (np.uint8, 3, True),
}


def _raw_image(msg, where: str) -> tuple[np.ndarray, bool]:
    encoding = str(msg.encoding).lower()
    if encoding not in _ENCODINGS:
        raise InputFileError(f"frame {where} has image encoding {msg.encoding!r}; supported: "
                             f"{', '.join(sorted(_ENCODINGS))}.")
    dtype, channels, bgr = _ENCODINGS[encoding]
    dt = np.dtype(dtype).newbyteorder(">" if msg.is_bigendian else "<")
    h, w, step = int(msg.height), int(msg.width), int(msg.step)
    row_bytes = w * channels * dt.itemsize
    data = np.asarray(msg.data, dtype=np.uint8).ravel()
    if h < 1 or w < 1 or step < row_bytes or data.size < h * step:
        raise InputFileError(f"frame {where} is damaged: {w}x{h} {msg.encoding} with step {step} needs "
                             f"{h * max(step, row_bytes)} bytes, the message has {data.size}.")
    rows = np.ascontiguousarray(data[:h * step].reshape(h, step)[:, :row_bytes])
    arr = rows.view(dt).reshape(h, w, channels).astype(dtype, copy=False)
    return (arr[:, :, 0] if channels == 1 else arr), bgr


def _decode_depth(msg, where: str) -> np.ndarray:
    if not hasattr(msg, "encoding"):
        raise InputFileError(f"depth frame {where} is a CompressedImage ({msg.format!r}); record depth as a raw "
                             "sensor_msgs/Image (16UC1 or 32FC1).")
    depth, _ = _raw_image(msg, where)
    if depth.ndim != 2:
        raise InputFileError(f"depth frame {where} has {depth.shape[2]} channels ({msg.encoding}); depth is one "
                             "channel: 16UC1 (mm) or 32FC1 (m).")
    if depth.dtype == np.float64:
        depth = depth.astype(np.float32)
    return np.ascontiguousarray(depth)


def _decode_color(msg, where: str) -> np.ndarray:
    import cv2

    if hasattr(msg, "encoding"):
        rgb, bgr = _raw_image(msg, where)
        if bgr:
            rgb = rgb[:, :, [2, 1, 0]]
    else:
        buf = np.asarray(msg.data, dtype=np.uint8).ravel()
        img = cv2.imdecode(buf, cv2.IMREAD_UNCHANGED) if buf.size else None
        if img is None:
            raise InputFileError(f"color frame {where} ({msg.format!r}) cannot be decoded; it is damaged or not "
                                 "JPEG/PNG.")
        if img.ndim == 3:
            img = cv2.cvtColor(img, cv2.COLOR_BGRA2RGB if img.shape[2] == 4 else cv2.COLOR_BGR2RGB)
        rgb = img
    try:
        return np.ascontiguousarray(check_rgb(rgb, name=f"color frame {where}"))
    except (TypeError, ValueError) as exc:
        raise InputFileError(str(exc)) from None
