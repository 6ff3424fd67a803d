"""Readers of recordings (issue 21): Azure Kinect .mkv, RealSense bags, bags with camera_info and /tf_static, bare .mcap.

Every recording is written here, small: MKVs with PyAV, bags with rosbags.
The shared Azure Kinect recording (``../shared/data``) is read under the
``shared_data`` marker. The batch itself (rig chain, unpaired in the summary)
is tested in ``test_batch.py``.
"""

from __future__ import annotations

import json
import struct
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import cv2
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from depthrefine.cli import main
from depthrefine.io import InputFileError, open_sequence, read_calibration, read_depth, read_rgb
from depthrefine.rig.formats import rig_from_k4a

from conftest import shared_data_path

av = pytest.importorskip("av")
pytest.importorskip("rosbags")

SRC = Path(__file__).resolve().parents[1] / "src"


# ----------------------------------------------------------------------------
# Azure Kinect .mkv, written with PyAV
# ----------------------------------------------------------------------------


def k4a_calibration() -> dict:
    """A K4A calibration.json (the layout of the device's factory calibration) with made-up numbers."""
    def camera(purpose, size, params, rotation, translation):
        return {"Purpose": purpose, "SensorWidth": size[0], "SensorHeight": size[1],
                "Intrinsics": {"ModelType": "CALIBRATION_LensDistortionModelBrownConrady",
                               "ModelParameters": params},
                "Rt": {"Rotation": rotation, "Translation": translation}}

    rot = Rotation.from_euler("xyz", [5.0, -0.5, 0.2], degrees=True).as_matrix().ravel().tolist()
    return {"CalibrationInformation": {"Cameras": [
        camera("CALIBRATION_CameraPurposeDepth", (1024, 1024),
               [0.51, 0.52, 0.49, 0.49, 0.3, -0.1, 0.01, 0.6, -0.05, 0.001, 0, 0, 1e-5, -2e-5],
               np.eye(3).ravel().tolist(), [0.0, 0.0, 0.0]),
        camera("CALIBRATION_CameraPurposePhotoVideo", (4096, 3072),
               [0.5, 0.51, 0.48, 0.64, 0.08, -0.05, 0.01, 0.0, 0.0, 0.0, 0, 0, 1e-4, 2e-4],
               rot, [-0.032, -0.002, 0.004]),
    ]}}


def _jpeg(rgb: np.ndarray) -> bytes:
    ok, buf = cv2.imencode(".jpg", cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR))
    assert ok
    return buf.tobytes()


def write_mkv(path: Path, *, depth_frames=(), color_frames=(), depth_ms=(), color_ms=(), color_format="MJPG",
              calibration: dict | None = None, depth_mode="NFOV_2X2BINNED", color_mode="MJPG_720P",
              start_offset_ns=336_277_000, depth_delay_ns=0, fps=30) -> Path:
    """An Azure Kinect-style recording: COLOR (MJPEG or raw NV12), DEPTH (b16g), tags, calibration attachment.

    FFmpeg's Matroska muxer stores raw video only as a Video-for-Windows track with an empty FOURCC
    (``allow_raw_vfw``), so the FOURCCs the Azure Kinect recorder writes (``b16g``, ``NV12``) are set
    in the track headers afterwards (no CRC-32 elements are written, so the file stays valid).
    """
    tb = Fraction(1, 1000)
    out = av.open(str(path), "w", format="matroska", options={"allow_raw_vfw": "1", "write_crc32": "0"})
    out.metadata["title"] = "Azure Kinect"
    out.metadata["K4A_START_OFFSET_NS"] = str(start_offset_ns)
    out.metadata["K4A_DEPTH_DELAY_NS"] = str(depth_delay_ns)
    patches = []
    color = None
    if color_frames:
        ch, cw = color_frames[0].shape[:2]
        if color_format == "MJPG":
            color = out.add_mux_stream("mjpeg", width=cw, height=ch, rate=fps)
        else:  # frames given as the recorder's bytes: NV12 is (h * 3 / 2, w)
            ch = ch * 2 // 3 if color_format == "NV12" else ch
            color = out.add_stream("rawvideo", rate=fps)
            color.width, color.height, color.pix_fmt = cw, ch, "gray16be"
            patches.append((cw, ch, 16, {"NV12": 12, "YUY2": 16, "BGRA": 32}[color_format], color_format.encode()))
        color.metadata["title"] = "COLOR"
        color.metadata["K4A_COLOR_MODE"] = color_mode
        color.time_base = tb
    depth = None
    if depth_frames:
        dh, dw = depth_frames[0].shape
        depth = out.add_stream("rawvideo", rate=fps)
        depth.width, depth.height, depth.pix_fmt = dw, dh, "gray16be"
        depth.metadata["title"] = "DEPTH"
        depth.metadata["K4A_DEPTH_MODE"] = depth_mode
        depth.time_base = depth.codec_context.time_base = tb  # millisecond stamps as given
        patches.append((dw, dh, 16, 16, b"b16g"))
    if calibration is not None:
        out.add_attachment("calibration.json", "application/octet-stream", json.dumps(calibration).encode())
    events = [(t, "depth", f) for t, f in zip(depth_ms, depth_frames)] + \
             [(t, "color", f) for t, f in zip(color_ms, color_frames)]
    for t, role, frame in sorted(events, key=lambda e: (e[0], e[1])):
        if role == "color":
            data = _jpeg(frame) if color_format == "MJPG" else frame.tobytes()
            packet = av.Packet(data)
            packet.stream, packet.pts, packet.dts, packet.time_base = color, t, t, tb
            out.mux(packet)
        else:
            vf = av.VideoFrame.from_ndarray(frame.astype(np.uint16), format="gray16be")
            vf.pts, vf.time_base = t, tb
            for packet in depth.encode(vf):
                out.mux(packet)
    if depth is not None:
        for packet in depth.encode():
            out.mux(packet)
    out.close()
    data = path.read_bytes()
    for w, h, bits, new_bits, fourcc in patches:  # BITMAPINFOHEADER: top-down, no FOURCC -> the recorder's
        old = struct.pack("<IiiHHI", 40, w, -h, 1, bits, 0)
        assert data.count(old) == 1
        data = data.replace(old, struct.pack("<IiiHH", 40, w, h, 1, new_bits) + fourcc)
    path.write_bytes(data)
    return path


def _depth(i: int, shape=(288, 320)) -> np.ndarray:
    rng = np.random.default_rng(i)
    d = rng.integers(300, 4000, size=shape).astype(np.uint16)
    d[:5] = 0  # no measurement
    return d


def _color(i: int, shape=(720, 1280)) -> np.ndarray:
    yy, xx = np.mgrid[0:shape[0], 0:shape[1]]
    return np.stack([(xx + 40 * i) % 256, yy % 256, np.full(shape, 60 * i % 256)], axis=2).astype(np.uint8)


def test_mkv_frames_stamps_and_factory_calibration(tmp_path):
    calib = k4a_calibration()
    depth = [_depth(i) for i in range(4)]
    color = [_color(i) for i in range(4)]
    ms = [0, 33, 67, 100]
    mkv = write_mkv(tmp_path / "rec.mkv", depth_frames=depth, color_frames=color, depth_ms=ms, color_ms=ms,
                    calibration=calib)
    seq = open_sequence(mkv)
    assert seq.kind == "k4a" and seq.raw and seq.depth_units == 0.001 and seq.frame_rate == 30
    stamps = [t * 1_000_000 + 336_277_000 for t in ms]  # file time + K4A_START_OFFSET_NS = device time
    assert [f.stamp_ns for f in seq.frames] == stamps and [f.key for f in seq.frames] == [str(t) for t in stamps]
    assert all(f.suffix == ".png" and f.problem is None for f in seq.frames) and seq.unpaired == []
    want = rig_from_k4a(calib, depth_mode="NFOV_2X2BINNED", color_resolution="720P")
    assert np.array_equal(seq.rig.depth_camera.K, want.depth_camera.K)
    assert np.array_equal(seq.rig.color_camera.dist, want.color_camera.dist)
    assert np.array_equal(seq.rig.R, want.R) and np.array_equal(seq.rig.t, want.t)
    info = seq.describe()
    assert info["rig"]["depth"] == "320x288" and info["rig"]["color"] == "1280x720" and info["unpaired"] == 0
    assert "calibration.json" in info["rig"]["source"]
    got = list(seq.load(seq.frames))
    assert [f.key for f, _ in got] == [f.key for f in seq.frames]
    for i, (_, (d, rgb)) in enumerate(got):
        assert d.dtype == np.uint16 and np.array_equal(d, depth[i])
        decoded = cv2.cvtColor(cv2.imdecode(np.frombuffer(_jpeg(color[i]), np.uint8), cv2.IMREAD_UNCHANGED),
                               cv2.COLOR_BGR2RGB)
        assert rgb.dtype == np.uint8 and np.array_equal(rgb, decoded)
    # a later span alone (the reader seeks), and the same frames again: identical
    tail = list(seq.load(seq.frames[2:]))
    assert [f.key for f, _ in tail] == [f.key for f in seq.frames[2:]]
    assert all(np.array_equal(a[1][0], b[1][0]) and np.array_equal(a[1][1], b[1][1]) for a, b in zip(tail, got[2:]))


def test_mkv_depth_at_30_color_at_15_leaves_depth_frames_unpaired(tmp_path):
    depth = [_depth(i, (12, 16)) for i in range(6)]
    color = [_color(i, (24, 32)) for i in range(3)]
    mkv = write_mkv(tmp_path / "rates.mkv", depth_frames=depth, color_frames=color, depth_ms=[0, 33, 67, 100, 133, 167],
                    color_ms=[0, 67, 133], start_offset_ns=0)
    seq = open_sequence(mkv)
    assert [f.stamp_ns for f in seq.frames] == [0, 67_000_000, 133_000_000]
    assert [(u["stream"], u["stamp_ns"]) for u in seq.unpaired] == [("depth", 33_000_000), ("depth", 100_000_000),
                                                                    ("depth", 167_000_000)]
    assert seq.unpaired[0]["why"] == "no color frame on COLOR track within 20 ms"
    # a wider window pairs each color frame once, nearest first
    wide = open_sequence(mkv, max_dt=0.05)
    assert len(wide.frames) == 3 and len(wide.unpaired) == 3
    assert "paired with nearer depth frames" in wide.unpaired[0]["why"]
    for frame, (d, rgb) in seq.load(seq.frames):
        assert np.array_equal(d, depth[[0, 67, 133].index(frame.stamp_ns // 1_000_000) * 2])


def test_streams_that_never_meet_are_one_line(tmp_path, capsys):
    mkv = write_mkv(tmp_path / "apart.mkv", depth_frames=[_depth(0, (12, 16))], color_frames=[_color(0, (24, 32))],
                    depth_ms=[0], color_ms=[500], start_offset_ns=0)
    assert main(["batch", str(mkv), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "no depth frame on DEPTH track has a color frame on COLOR track within " \
        "20 ms (depth stamps 0.000 to 0.000 s, color 0.500 to 0.500 s); raise --max-dt" in err


def test_mkv_depth_delay_pairs_depth_with_the_earlier_color_frame(tmp_path):
    # Depth captured 15 ms after color (k4arecorder --depth-delay 15000): nearest stamps would pick the next color.
    depth = [_depth(i, (12, 16)) for i in range(3)]
    color = [_color(i, (24, 32)) for i in range(3)]
    mkv = write_mkv(tmp_path / "delay.mkv", depth_frames=depth, color_frames=color, depth_ms=[15, 48, 82],
                    color_ms=[0, 33, 67], start_offset_ns=0, depth_delay_ns=15_000_000)
    seq = open_sequence(mkv, max_dt=0.005)
    assert [(f.depth, f.color) for f in seq.frames][0] == ("DEPTH track @ 15000000", "COLOR track @ 0")
    assert len(seq.frames) == 3 and seq.unpaired == []


def test_mkv_with_raw_nv12_color(tmp_path):
    h, w = 24, 32
    yuv = cv2.cvtColor(_color(1, (h, w)), cv2.COLOR_RGB2YUV_I420)  # planar 4:2:0 -> NV12 (interleaved chroma)
    y, u, v = yuv[:h], yuv[h:h + h // 4].reshape(-1), yuv[h + h // 4:].reshape(-1)
    nv12 = np.concatenate([y.reshape(-1), np.stack([u, v], axis=1).reshape(-1)]).reshape(h * 3 // 2, w)
    mkv = write_mkv(tmp_path / "nv12.mkv", depth_frames=[_depth(0, (12, 16))], color_frames=[nv12], depth_ms=[0],
                    color_ms=[0], color_format="NV12", color_mode="NV12_720P")
    seq = open_sequence(mkv)
    assert seq.topics["color"] == "COLOR (NV12)"
    (_, (d, rgb)), = seq.load(seq.frames)
    assert rgb.shape == (h, w, 3) and np.array_equal(rgb, cv2.cvtColor(nv12, cv2.COLOR_YUV2RGB_NV12))


def test_mkv_without_calibration_needs_a_rig_file(tmp_path):
    mkv = write_mkv(tmp_path / "nocal.mkv", depth_frames=[_depth(0, (12, 16))], color_frames=[_color(0, (24, 32))],
                    depth_ms=[0], color_ms=[0])
    seq = open_sequence(mkv)  # not an error until a rig is needed
    assert seq.rig is None and seq.raw and len(seq.frames) == 1
    with pytest.raises(InputFileError) as err:
        seq.require_rig()
    message = str(err.value)
    assert "nocal.mkv has no calibration.json attachment" in message and "pass --rig rig.json" in message
    assert "--depth-mode NFOV_2X2BINNED --color-resolution 720P" in message and "\n" not in message


def test_mkv_whose_tracks_do_not_match_the_calibration_mode(tmp_path):
    mkv = write_mkv(tmp_path / "small.mkv", depth_frames=[_depth(0, (12, 16))], color_frames=[_color(0, (24, 32))],
                    depth_ms=[0], color_ms=[0], calibration=k4a_calibration())
    seq = open_sequence(mkv)
    assert seq.rig is None
    assert "DEPTH track is 16x12 but mode NFOV_2X2BINNED of calibration.json gives 320x288" in seq.rig_problem


def test_mkv_without_depth_track_is_one_line(tmp_path, capsys):
    mkv = write_mkv(tmp_path / "color_only.mkv", color_frames=[_color(0, (24, 32))], color_ms=[0])
    assert main(["batch", str(mkv), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "color_only.mkv has no DEPTH track (its video tracks: COLOR (mjpeg))" in err
    assert not (tmp_path / "out").exists()


def test_a_damaged_mkv_is_one_line(tmp_path, capsys):
    bad = tmp_path / "cut.mkv"
    bad.write_bytes(b"\x1a\x45\xdf\xa3" + b"\x00" * 20)
    with pytest.raises(InputFileError, match="cut.mkv cannot be read"):
        open_sequence(bad)


@pytest.mark.shared_data
def test_the_shared_azure_kinect_recording():
    folder = shared_data_path("real_tof", "azure_kinect_mug")
    seq = open_sequence(folder / "recording.mkv")
    assert seq.kind == "k4a" and seq.frame_rate == 5.0 and seq.topics == {"depth": "DEPTH", "color": "COLOR (MJPG)"}
    assert [f.stamp_ns for f in seq.frames] == [800_222_000] and seq.unpaired == []  # device time 800222 us
    want, _ = read_calibration(folder / "calibration.json", depth_mode="NFOV_UNBINNED", color_resolution="720P")
    for a, b in ((seq.rig.depth_camera, want.depth_camera), (seq.rig.color_camera, want.color_camera)):
        assert np.array_equal(a.K, b.K) and np.array_equal(a.dist, b.dist) and a.image_size == b.image_size
    assert np.array_equal(seq.rig.R, want.R) and np.array_equal(seq.rig.t, want.t)
    (_, (depth, rgb)), = seq.load(seq.frames)
    assert np.array_equal(depth, read_depth(folder / "derived" / "depth_640x576_mm.png"))
    assert np.array_equal(rgb, read_rgb(folder / "derived" / "color_1280x720.jpg"))


@pytest.mark.shared_data
def test_refine_given_a_recording_points_to_batch(tmp_path, capsys):
    folder = shared_data_path("real_tof", "azure_kinect_mug")
    mkv = folder / "recording.mkv"
    assert main(["refine", str(mkv), str(folder / "derived" / "color_1280x720.jpg"), "-o", str(tmp_path / "o.png")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert f"is a Matroska recording (.mkv, e.g. Azure Kinect), not an image; refine its frames with " \
           f"`depthrefine batch {mkv} -o OUTDIR`" in err


# ----------------------------------------------------------------------------
# bags written with rosbags
# ----------------------------------------------------------------------------

T0 = 1_700_000_000_000_000_000
PERIOD = 33_333_333


def _store(ros1: bool):
    from rosbags.typesys import Stores, get_typestore, get_types_from_msg

    store = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    store.register(get_types_from_msg("uint32 fps\nstring encoding\nbool is_recommended",
                                      "realsense_msgs/msg/StreamInfo"))
    if "tf2_msgs/msg/TFMessage" not in store.types:  # not in rosbags' ROS 1 store
        store.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", "tf2_msgs/msg/TFMessage"))
    return store


class BagWriter:
    """Messages of the common types into a ROS 1 or ROS 2 bag (rosbags), one connection per topic."""

    def __init__(self, path: Path, *, ros1: bool, mcap: bool = False):
        self.ros1, self.store = ros1, _store(ros1)
        if ros1:
            from rosbags.rosbag1 import Writer
            self.writer = Writer(path)
        else:
            from rosbags.rosbag2 import StoragePlugin, Writer
            self.writer = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP if mcap else StoragePlugin.SQLITE3)
        self.conns = {}

    def __enter__(self):
        self.writer.open()
        return self

    def __exit__(self, *exc):
        self.writer.close()

    def t(self, name):
        return self.store.types[name]

    def header(self, t: int, frame_id: str):
        stamp = self.t("builtin_interfaces/msg/Time")(sec=t // 10**9, nanosec=t % 10**9)
        extra = {"seq": 0} if self.ros1 else {}
        return self.t("std_msgs/msg/Header")(stamp=stamp, frame_id=frame_id, **extra)

    def write(self, topic: str, t: int, msg):
        msgtype = msg.__msgtype__
        if topic not in self.conns:
            self.conns[topic] = self.writer.add_connection(topic, msgtype, typestore=self.store)
        raw = self.store.serialize_ros1(msg, msgtype) if self.ros1 else self.store.serialize_cdr(msg, msgtype)
        self.writer.write(self.conns[topic], t, raw)

    def image(self, topic: str, t: int, array: np.ndarray, encoding: str, frame_id: str):
        h, w = array.shape[:2]
        data = np.frombuffer(np.ascontiguousarray(array).astype(array.dtype.newbyteorder("<")).tobytes(), np.uint8)
        msg = self.t("sensor_msgs/msg/Image")(header=self.header(t, frame_id), height=h, width=w, encoding=encoding,
                                              is_bigendian=0, step=array.strides[0], data=data)
        self.write(topic, t, msg)

    def camera_info(self, topic: str, K, D, size, model: str, frame_id: str, t: int = T0):
        fields = ("D", "K", "R", "P") if self.ros1 else ("d", "k", "r", "p")
        P = np.hstack([np.asarray(K, float).reshape(3, 3), np.zeros((3, 1))]).ravel()
        roi = self.t("sensor_msgs/msg/RegionOfInterest")(x_offset=0, y_offset=0, height=0, width=0, do_rectify=False)
        values = dict(zip(fields, (np.asarray(D, float), np.asarray(K, float).ravel(), np.eye(3).ravel(), P)))
        msg = self.t("sensor_msgs/msg/CameraInfo")(header=self.header(t, frame_id), height=size[1], width=size[0],
                                                   distortion_model=model, binning_x=0, binning_y=0, roi=roi, **values)
        self.write(topic, t, msg)

    def transform(self, translation, quaternion):
        v = self.t("geometry_msgs/msg/Vector3")(x=translation[0], y=translation[1], z=translation[2])
        q = self.t("geometry_msgs/msg/Quaternion")(x=quaternion[0], y=quaternion[1], z=quaternion[2], w=quaternion[3])
        return self.t("geometry_msgs/msg/Transform")(translation=v, rotation=q)


K_DEPTH = [[60.0, 0, 31.5], [0, 60.0, 23.5], [0, 0, 1]]
K_COLOR = [[120.0, 0, 63.5], [0, 121.0, 47.5], [0, 0, 1]]
D_COLOR = [0.05, -0.02, 0.001, -0.0005, 0.003]
OPTICAL = Rotation.from_euler("ZX", [-90, -90], degrees=True).as_quat()  # x, y, z, w: camera_link -> optical


def write_camera_bag(path: Path, *, depth_info=True, mcap=False, n_depth=6, ros1=False) -> list[int]:
    """/camera/depth (16UC1, 30 fps) and /camera/color (rgb8, 15 fps), their camera_info and /tf_static."""
    stamps = []
    with BagWriter(path, ros1=ros1, mcap=mcap) as bag:
        tf = []
        for parent, child, xyz, q in (("camera_link", "camera_depth_frame", (0, 0, 0), (0, 0, 0, 1)),
                                      ("camera_depth_frame", "camera_depth_optical_frame", (0, 0, 0), OPTICAL),
                                      ("camera_link", "camera_color_frame", (0, 0.015, 0.001), (0, 0, 0.0087, 0.99996)),
                                      ("camera_color_frame", "camera_color_optical_frame", (0, 0, 0), OPTICAL)):
            tf.append(bag.t("geometry_msgs/msg/TransformStamped")(header=bag.header(T0, parent), child_frame_id=child,
                                                                    transform=bag.transform(xyz, q)))
        bag.write("/tf_static", T0, bag.t("tf2_msgs/msg/TFMessage")(transforms=tf))
        if depth_info:
            bag.camera_info("/camera/depth/camera_info", K_DEPTH, [0] * 5, (64, 48), "plumb_bob",
                            "camera_depth_optical_frame")
        bag.camera_info("/camera/color/camera_info", K_COLOR, D_COLOR, (128, 96), "plumb_bob",
                        "camera_color_optical_frame")
        for i in range(n_depth):
            t = T0 + i * PERIOD
            stamps.append(t)
            bag.image("/camera/depth/image_rect_raw", t, _depth(i, (48, 64)), "16UC1", "camera_depth_optical_frame")
            if i % 2 == 0:
                bag.image("/camera/color/image_raw", t + 1_000_000, _color(i, (96, 128)), "rgb8",
                          "camera_color_optical_frame")
    return stamps


def _pose(xyz, q) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = Rotation.from_quat(q).as_matrix(), xyz
    return T


@pytest.mark.parametrize("ros1", [False, True], ids=["ros2", "ros1"])
def test_bag_topics_camera_info_and_tf_static_give_the_rig(tmp_path, ros1):
    bag = tmp_path / ("cam.bag" if ros1 else "cam")
    stamps = write_camera_bag(bag, ros1=ros1)
    seq = open_sequence(bag)  # no topic options: one depth-like and one color-like topic
    assert seq.topics == {"depth": "/camera/depth/image_rect_raw", "color": "/camera/color/image_raw"}
    assert seq.kind == ("ros1" if ros1 else "ros2") and seq.raw and seq.depth_units == 0.001 and seq.frame_rate == 30.0
    assert [f.stamp_ns for f in seq.frames] == stamps[::2]
    assert [u["stamp_ns"] for u in seq.unpaired] == stamps[1::2] and {u["stream"] for u in seq.unpaired} == {"depth"}
    # expected extrinsics from the same tree, chained with 4x4 matrices
    link_depth = _pose((0, 0, 0), (0, 0, 0, 1)) @ _pose((0, 0, 0), OPTICAL)
    link_color = _pose((0, 0.015, 0.001), (0, 0, 0.0087, 0.99996)) @ _pose((0, 0, 0), OPTICAL)
    color_from_depth = np.linalg.inv(link_color) @ link_depth
    np.testing.assert_allclose(seq.rig.R, color_from_depth[:3, :3], atol=1e-9)
    np.testing.assert_allclose(seq.rig.t, color_from_depth[:3, 3], atol=1e-9)
    assert np.array_equal(seq.rig.color_camera.K, K_COLOR) and np.array_equal(seq.rig.color_camera.dist, D_COLOR)
    assert seq.rig.depth_camera.image_size == (64, 48) and seq.rig.color_camera.image_size == (128, 96)
    for frame, (d, rgb) in seq.load(seq.frames):
        i = stamps.index(frame.stamp_ns)
        assert np.array_equal(d, _depth(i, (48, 64))) and np.array_equal(rgb, _color(i, (96, 128)))


def test_a_bag_without_camera_info_for_the_depth_topic_needs_a_rig_file(tmp_path):
    bag = tmp_path / "nodepthinfo"
    write_camera_bag(bag, depth_info=False, n_depth=2)
    seq = open_sequence(bag)
    assert seq.rig is None and seq.raw
    with pytest.raises(InputFileError) as err:
        seq.require_rig()
    assert ("has no camera_info for the depth topic /camera/depth/image_rect_raw (looked for "
            "/camera/depth/camera_info)") in str(err.value) and "pass --rig rig.json" in str(err.value)


def test_a_bare_mcap_file_without_metadata_yaml(tmp_path):
    folder = tmp_path / "rec"
    stamps = write_camera_bag(folder, mcap=True, n_depth=2)
    mcap = next(folder.glob("*.mcap"))
    bare = tmp_path / "bare.mcap"
    mcap.rename(bare)
    seq = open_sequence(bare)
    assert seq.kind == "ros2" and [f.stamp_ns for f in seq.frames] == stamps[:1] and seq.rig is not None
    (_, (d, rgb)), = seq.load(seq.frames)
    assert np.array_equal(d, _depth(0, (48, 64)))


def test_ambiguous_topics_are_listed(tmp_path, capsys):
    bag = tmp_path / "two.bag"
    with BagWriter(bag, ros1=True) as w:
        for topic in ("/a/depth/image", "/b/depth/image"):
            w.image(topic, T0, _depth(0, (4, 4)), "16UC1", "d")
        w.image("/c/color/image", T0, _color(0, (8, 8)), "bgr8", "c")
        w.image("/c/ir/image", T0, _depth(1, (4, 4)), "mono16", "ir")  # never a depth candidate
    assert main(["batch", str(bag), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "has 2 depth image topics: /a/depth/image (16UC1), /b/depth/image (16UC1); choose one with " \
           "--depth-topic" in err
    seq = open_sequence(bag, depth_topic="/b/depth/image")  # the color topic is still found
    assert seq.topics == {"depth": "/b/depth/image", "color": "/c/color/image"}


def test_a_raw_topic_wins_over_its_compressed_twin_and_registered_frames_are_not_raw(tmp_path):
    bag = tmp_path / "twins.bag"
    with BagWriter(bag, ros1=True) as w:
        w.image("/cam/aligned_depth_to_color/image_raw", T0, _depth(0, (8, 8)), "16UC1", "cam_color")
        w.image("/cam/color/image_raw", T0, _color(0, (8, 8)), "rgb8", "cam_color")
        jpeg = w.t("sensor_msgs/msg/CompressedImage")(header=w.header(T0, "cam_color"), format="jpeg",
                                                      data=np.frombuffer(_jpeg(_color(0, (8, 8))), np.uint8))
        w.write("/cam/color/image_raw/compressed", T0, jpeg)
    seq = open_sequence(bag)
    assert seq.topics["color"] == "/cam/color/image_raw" and seq.raw is False


# ----------------------------------------------------------------------------
# RealSense SDK recordings (ROS 1, the SDK's topic layout)
# ----------------------------------------------------------------------------

RS = "/device_0/sensor_{s}/{stream}_0"
RS_COLOR_Q = Rotation.from_euler("xyz", [0.3, -0.2, 0.5], degrees=True).as_quat()


def write_realsense_bag(path: Path, *, depth_units=0.0001, camera_info=True) -> list[int]:
    stamps = []
    with BagWriter(path, ros1=True) as bag:
        depth, color = RS.format(s=0, stream="Depth"), RS.format(s=1, stream="Color")
        bag.write("/file_version", 0, bag.t("std_msgs/msg/UInt32")(data=3))
        bag.write("/device_0/sensor_0/option/Depth Units/value", 0, bag.t("std_msgs/msg/Float32")(data=depth_units))
        for prefix, fps in ((depth, 30), (color, 30)):
            bag.write(f"{prefix}/info", 0, bag.t("realsense_msgs/msg/StreamInfo")(fps=fps, encoding="",
                                                                                  is_recommended=True))
        if camera_info:
            bag.camera_info(f"{depth}/info/camera_info", K_DEPTH, [0] * 5, (64, 48), "Brown Conrady", "", 0)
            bag.camera_info(f"{color}/info/camera_info", K_COLOR, D_COLOR, (128, 96), "Brown Conrady", "", 0)
        bag.write(f"{depth}/tf/0", 0, bag.transform((0, 0, 0), (0, 0, 0, 1)))
        bag.write(f"{color}/tf/0", 0, bag.transform((0.015, 0.0002, 0.0003), RS_COLOR_Q))
        for i in range(3):
            t = T0 + i * PERIOD
            stamps.append(t)
            bag.image(f"{depth}/image/data", t, _depth(i, (48, 64)), "mono16", "")
            bag.image(f"{color}/image/data", t + 2_000_000, _color(i, (96, 128)), "rgb8", "")
    return stamps


def test_realsense_recording_without_topic_options(tmp_path):
    bag = tmp_path / "rs.bag"
    write_realsense_bag(bag)
    seq = open_sequence(bag)
    assert seq.kind == "realsense" and seq.raw and len(seq.frames) == 3 and seq.unpaired == []
    assert seq.topics == {"depth": "/device_0/sensor_0/Depth_0/image/data",
                          "color": "/device_0/sensor_1/Color_0/image/data"}
    assert seq.depth_units == pytest.approx(0.0001) and seq.frame_rate == 30.0
    assert np.array_equal(seq.rig.depth_camera.K, K_DEPTH) and not seq.rig.depth_camera.has_distortion
    assert np.array_equal(seq.rig.color_camera.dist, D_COLOR)  # Brown Conrady = OpenCV (k1, k2, p1, p2, k3)
    np.testing.assert_allclose(seq.rig.R, Rotation.from_quat(RS_COLOR_Q).as_matrix(), atol=1e-12)
    np.testing.assert_allclose(seq.rig.t, [0.015, 0.0002, 0.0003])  # .../tf/0: depth (reference) -> color
    for i, (frame, (d, rgb)) in enumerate(seq.load(seq.frames)):
        assert d.dtype == np.uint16 and np.array_equal(d, _depth(i, (48, 64)))
        assert np.array_equal(rgb, _color(i, (96, 128)))


def test_realsense_lens_models():
    from depthrefine.rig.formats import camera_from_realsense

    info = {"width": 64, "height": 48, "K": np.ravel(K_COLOR), "D": D_COLOR}
    assert np.array_equal(camera_from_realsense({**info, "distortion_model": "Brown Conrady"}).dist, D_COLOR)
    assert not camera_from_realsense({**info, "D": [0.0] * 5, "distortion_model": "Inverse Brown Conrady"}) \
        .has_distortion
    with pytest.raises(ValueError, match="lens model 'Inverse Brown Conrady' with coefficients .* is not OpenCV's"):
        camera_from_realsense({**info, "distortion_model": "Inverse Brown Conrady"})


def test_realsense_recording_without_camera_info(tmp_path):
    bag = tmp_path / "rs.bag"
    write_realsense_bag(bag, camera_info=False)
    seq = open_sequence(bag)
    assert seq.rig is None and "has no camera_info for the depth stream" in seq.rig_problem


# ----------------------------------------------------------------------------
# other inputs
# ----------------------------------------------------------------------------


def test_an_input_of_no_known_format_names_every_format(tmp_path, capsys):
    other = tmp_path / "notes.txt"
    other.write_text("hello")
    assert main(["batch", str(other), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert "Azure Kinect recording (.mkv)" in err and ".mcap" in err and len(err.splitlines()) == 1


def test_reading_recordings_is_not_loaded_at_start_up():
    code = ("import sys, depthrefine, depthrefine.io, depthrefine.cli; depthrefine.cli.build_parser(); "
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('av', 'rosbags')))")
    env_path = {"PYTHONPATH": str(SRC)}
    import os

    out = subprocess.run([sys.executable, "-c", code], env={**os.environ, **env_path}, capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "[]"
