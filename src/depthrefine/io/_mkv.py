"""Azure Kinect recordings (``k4arecorder``'s ``.mkv``) as sequences, demultiplexed with PyAV.

The Azure Kinect Sensor SDK's recording format (docs: "Use Azure Kinect Sensor
SDK to record file format", and ``src/record``):

- a Matroska file with video tracks named ``COLOR`` (MJPEG, or raw NV12,
  YUY2 or BGRA, per ``K4A_COLOR_MODE`` such as ``MJPG_720P``), ``DEPTH`` and
  ``IR`` (FOURCC ``b16g``: 16-bit, big-endian; depth in millimetres, 0 = no
  measurement) and an ``IMU`` track;
- tags: ``K4A_DEPTH_MODE`` (``NFOV_UNBINNED`` ...) on the depth track,
  ``K4A_START_OFFSET_NS`` (added to every time stamp of the file gives the
  device time stamp) and ``K4A_DEPTH_DELAY_NS`` (depth captured that long
  after color) on the file;
- the attachment ``calibration.json``: the device's factory calibration,
  which :func:`~depthrefine.rig.formats.rig_from_k4a` turns into the rig of the
  recording's depth mode and color resolution.

Only packets are read: depth is the packet's bytes, color is decoded with
OpenCV (MJPEG as ``cv2.imdecode`` does for a JPEG file, so a frame equals the
same JPEG written out and read with :func:`~depthrefine.io.read_rgb`). Depth
and color are not registered: a recording is always raw.
"""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

from ._files import InputFileError
from ._sequences import Sequence, frame_rate_of, load_in_one_pass, pair_streams

__all__ = ["is_mkv", "open_mkv"]

_EBML_MAGIC = b"\x1a\x45\xdf\xa3"
#: Raw color layouts of the recorder: bytes per pixel (NV12: 1.5).
_RAW_COLOR = {"NV12": Fraction(3, 2), "YUY2": Fraction(2), "BGRA": Fraction(4)}
_COLOR_FORMATS = ("MJPG", *_RAW_COLOR)


def is_mkv(p: Path) -> bool:
    """True for a ``.mkv`` file or any file that starts like Matroska (EBML)."""
    if not p.is_file():
        return False
    if p.suffix.lower() == ".mkv":
        return True
    try:
        with open(p, "rb") as fh:
            return fh.read(4) == _EBML_MAGIC
    except OSError:
        return False


def _open(p: Path):
    try:
        import av
    except ImportError:  # pragma: no cover - a dependency
        raise InputFileError("reading Azure Kinect recordings needs PyAV: pip install av") from None
    try:
        return av.open(str(p))
    except (av.FFmpegError, OSError, ValueError) as exc:
        raise InputFileError(f"Azure Kinect recording {p} cannot be read ({exc}); it is truncated, damaged or not "
                             "a Matroska file.") from None


def _tracks(container) -> dict[str, Any]:
    """Video streams by track name (``COLOR``, ``DEPTH``, ``IR``), from the title or the K4A track tag."""
    out = {}
    for stream in container.streams.video:
        meta = {k.upper(): v for k, v in stream.metadata.items()}
        name = str(meta.get("TITLE", "")).upper()
        for tag in ("COLOR", "DEPTH", "IR"):
            if f"K4A_{tag}_TRACK" in meta:
                name = tag
        if name:
            out.setdefault(name, stream)
    return out


def _ns(pts: int, time_base: Fraction) -> int:
    return int(pts * time_base.numerator * 1_000_000_000 // time_base.denominator)


def _tag(container, stream, name: str) -> str | None:
    for meta in (stream.metadata, container.metadata):
        for k, v in meta.items():
            if k.upper() == name:
                return str(v)
    return None


def open_mkv(p: Path, max_dt: float) -> Sequence:
    """Pair the depth and color frames of an Azure Kinect recording (see the module docstring)."""
    container = _open(p)
    try:
        tracks = _tracks(container)
        listed = ", ".join(f"{s.metadata.get('title', '#%d' % s.index)} ({s.codec_context.name})"
                           for s in container.streams.video) or "none"
        depth, color = tracks.get("DEPTH"), tracks.get("COLOR")
        if depth is None:
            raise InputFileError(f"Azure Kinect recording {p} has no DEPTH track (its video tracks: {listed}); record "
                                 "with a depth mode such as k4arecorder --depth-mode NFOV_UNBINNED (not OFF or "
                                 "PASSIVE_IR).")
        if color is None:
            raise InputFileError(f"Azure Kinect recording {p} has no COLOR track (its video tracks: {listed}); record "
                                 "with a color mode such as k4arecorder --color-mode 720p (not OFF).")
        depth_mode = _tag(container, depth, "K4A_DEPTH_MODE")
        color_mode = _tag(container, color, "K4A_COLOR_MODE")
        fmt = _color_format(color, color_mode, p)
        offset = int(_tag(container, depth, "K4A_START_OFFSET_NS") or 0)
        delay = int(_tag(container, depth, "K4A_DEPTH_DELAY_NS") or 0)
        stamps: dict[str, list] = {"depth": [], "color": []}
        role_of = {depth.index: "depth", color.index: "color"}
        for packet in container.demux(depth, color):
            if packet.size == 0 or packet.pts is None:
                continue
            role = role_of[packet.stream.index]
            stamps[role].append((_ns(packet.pts, packet.stream.time_base) + offset, (role, int(packet.pts))))
        rate = float(depth.average_rate) if depth.average_rate else None
        rig_kwargs = _calibration(container, p, depth, color, depth_mode, color_mode)
    except InputFileError:
        raise
    except Exception as exc:  # noqa: BLE001 - the demuxer failed: a damaged file
        raise InputFileError(f"Azure Kinect recording {p} cannot be read ({type(exc).__name__}: {exc}); it is "
                             "truncated or damaged.") from None
    finally:
        container.close()
    for role in ("depth", "color"):
        if not stamps[role]:
            raise InputFileError(f"Azure Kinect recording {p}: the {role.upper()} track holds no frames; nothing to "
                                 "refine.")
    # The recorder's depth delay: a depth frame belongs with the color frame `delay` ns before it.
    try:
        frames, unpaired = pair_streams(stamps["depth"], stamps["color"], max_dt, names=("DEPTH track", "COLOR track"),
                                        suffix=".png", color_shift_ns=delay)
    except InputFileError as exc:
        raise InputFileError(f"Azure Kinect recording {p}: {exc}") from None
    return Sequence(p, "k4a", frames, topics={"depth": "DEPTH", "color": f"COLOR ({fmt})"}, depth_units=0.001,
                    frame_rate=rate or frame_rate_of([t for t, _ in stamps["depth"]]), unpaired=unpaired, raw=True,
                    reader=_load_mkv, **rig_kwargs)


def _color_format(color, color_mode: str | None, p: Path) -> str:
    """``MJPG``, ``NV12``, ``YUY2`` or ``BGRA``: from the track's FOURCC, else the color mode tag."""
    tag = str(color.codec_context.codec_tag or "").strip("\x00 ").upper()
    if color.codec_context.name == "mjpeg" or tag == "MJPG":
        return "MJPG"
    if tag in _RAW_COLOR:
        return tag
    prefix = str(color_mode or "").split("_")[0].upper()
    if prefix in _COLOR_FORMATS:
        return prefix
    raise InputFileError(f"Azure Kinect recording {p}: the COLOR track is {color.codec_context.name} "
                         f"(FOURCC {tag or 'none'}, mode {color_mode or 'not tagged'}); the recorder writes MJPG, NV12, "
                         "YUY2 or BGRA.")


def _calibration(container, p: Path, depth, color, depth_mode: str | None, color_mode: str | None) -> dict:
    """``rig`` and ``rig_source``, or ``rig_problem`` (what is missing and what to pass instead)."""
    from ..rig.formats import rig_from_k4a

    resolution = str(color_mode or "").split("_")[-1].upper()
    name = "calibration.json"
    attached = {a.name: a for a in container.streams.attachments}
    for a in attached.values():
        if "K4A_CALIBRATION_FILE" in {k.upper() for k in a.metadata}:
            name = a.name
    command = (f"`depthrefine rig import calibration.json --depth-mode {depth_mode or 'MODE'} --color-resolution "
               f"{resolution or 'RES'} -o rig.json`")
    if name not in attached:
        return {"rig_problem": f"Azure Kinect recording {p} has no {name} attachment (the device's factory "
                               f"calibration); pass --rig rig.json, e.g. from {command} with the device's calibration."}
    source = f"{p}: {name}"
    try:
        data = json.loads(bytes(attached[name].data).decode("utf-8"))
        if not depth_mode or not color_mode:
            raise ValueError(f"{p} has no K4A_DEPTH_MODE or K4A_COLOR_MODE tag, so the capture mode of {name} is "
                             "unknown")
        rig = rig_from_k4a(data, depth_mode=depth_mode, color_resolution=resolution, source=source)
    except (ValueError, UnicodeDecodeError) as exc:
        return {"rig_problem": f"{str(exc).rstrip('.')}; pass --rig rig.json, e.g. from {command}."}
    for camera, stream, what in ((rig.depth_camera, depth, "DEPTH"), (rig.color_camera, color, "COLOR")):
        size = (stream.codec_context.width, stream.codec_context.height)
        if tuple(camera.image_size) != size:
            return {"rig_problem": f"Azure Kinect recording {p}: its {what} track is {size[0]}x{size[1]} but mode "
                                   f"{depth_mode if what == 'DEPTH' else color_mode} of {name} gives "
                                   f"{camera.image_size[0]}x{camera.image_size[1]}; pass --rig rig.json."}
    return {"rig": rig, "rig_source": f"Azure Kinect factory calibration ({name} in the recording; "
                                      f"{depth_mode}, {resolution})"}


def _load_mkv(seq: Sequence, frames: list):
    """Decode ``frames`` from one pass over the span of the file they cover."""
    def messages(refs: set):
        container = _open(seq.source)
        try:
            tracks = _tracks(container)
            depth, color = tracks["DEPTH"], tracks["COLOR"]
            fmt = _color_format(color, _tag(container, color, "K4A_COLOR_MODE"), seq.source)
            shape = {"depth": (depth.codec_context.height, depth.codec_context.width, depth.codec_context.pix_fmt),
                     "color": (color.codec_context.height, color.codec_context.width, fmt)}
            start = min(Fraction(pts) * (depth if role == "depth" else color).time_base for role, pts in refs)
            if start > 0:  # to the cluster before the first wanted packet (every frame is a key frame)
                container.seek(int(start * 1_000_000), backward=True, any_frame=False)
            role_of = {depth.index: "depth", color.index: "color"}
            for packet in container.demux(depth, color):
                if packet.size == 0 or packet.pts is None:
                    continue
                role = role_of[packet.stream.index]
                ref = (role, int(packet.pts))
                if ref in refs:
                    yield ref, (bytes(packet), shape[role])
        finally:
            container.close()

    return load_in_one_pass(frames, messages, _decode, f"Azure Kinect recording {seq.source}")


def _decode(role: str, payload: tuple, where: str) -> np.ndarray:
    data, (h, w, fmt) = payload
    if role == "depth":
        if len(data) != h * w * 2:
            raise InputFileError(f"depth frame {where} is damaged: a {w}x{h} 16-bit frame needs {h * w * 2} bytes, "
                                 f"the packet has {len(data)}.")
        order = "<u2" if fmt == "gray16le" else ">u2"  # b16g: big-endian
        return np.frombuffer(data, dtype=order).reshape(h, w).astype(np.uint16)
    import cv2

    buf = np.frombuffer(data, dtype=np.uint8)
    if fmt == "MJPG":
        img = cv2.imdecode(buf, cv2.IMREAD_UNCHANGED) if buf.size else None  # as read_rgb reads a JPEG file
        if img is None:
            raise InputFileError(f"color frame {where} cannot be decoded; the MJPEG packet is damaged.")
        return cv2.cvtColor(img, cv2.COLOR_GRAY2RGB if img.ndim == 2 else cv2.COLOR_BGR2RGB)
    need = int(h * w * _RAW_COLOR[fmt])
    if buf.size != need:
        raise InputFileError(f"color frame {where} is damaged: a {w}x{h} {fmt} frame needs {need} bytes, the packet "
                             f"has {buf.size}.")
    if fmt == "NV12":
        return cv2.cvtColor(buf.reshape(h * 3 // 2, w), cv2.COLOR_YUV2RGB_NV12)
    if fmt == "YUY2":
        return cv2.cvtColor(buf.reshape(h, w, 2), cv2.COLOR_YUV2RGB_YUY2)
    return np.ascontiguousarray(buf.reshape(h, w, 4)[:, :, 2::-1])
