"""Batches (issue 11): refine_many, ``depthrefine batch`` on folders, manifests and ROS bags, resume, bad input.

One real Dask ``LocalCluster`` on loopback (two worker processes) serves the
whole module: the in-process tests hand its client to ``refine_many`` and the
command-line tests give its address with ``--scheduler``, so only the tests
that need their own process start another cluster.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import cv2
import numpy as np
import pytest

from depthrefine.batch import refine_many
from depthrefine.bench.metrics import flicker
from depthrefine.bench.synthetic import make_scene, make_sequence
from depthrefine.cli import main
from depthrefine.io import depth_to_dtype, open_sequence, read_depth, write_depth, write_rgb
from depthrefine.methods.registry import get_method, refine
from depthrefine.methods.thesis.params import ThesisParams

distributed = pytest.importorskip("distributed")
rosbags = pytest.importorskip("rosbags")

SRC = Path(__file__).resolve().parents[1] / "src"
PARAMS = ThesisParams(patches=(2, 2))


@pytest.fixture(scope="module")
def cluster():
    """A LocalCluster on 127.0.0.1 with two one-thread worker processes, shared by the module."""
    import logging

    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=":0",
                      silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
        yield client


@pytest.fixture(scope="module")
def frames():
    """Six 48 x 64 frames (x4, uint16 mm) of a disc moving over a static scene."""
    return make_sequence(6, (48, 64), 4, seed=5)


def _env():
    env = dict(os.environ)
    env["PYTHONPATH"] = str(SRC) + os.pathsep + env.get("PYTHONPATH", "")
    return env


def write_folder(root: Path, frames, *, depth_ext=".png", color_ext=".png") -> Path:
    (root / "depth").mkdir(parents=True)
    (root / "color").mkdir()
    for i, f in enumerate(frames):
        write_depth(root / "depth" / f"{i:04d}{depth_ext}", f.depth_lr)
        write_rgb(root / "color" / f"{i:04d}{color_ext}", f.rgb_hr)
    return root


def expected_file(depth_lr, rgb_hr, method="thesis", params=None):
    """What ``depthrefine refine`` writes for one frame: refine, then the depth's dtype."""
    return depth_to_dtype(refine(depth_lr, rgb_hr, method=method, params=params), depth_lr.dtype)


def run_batch(client, *args) -> int:
    return main(["batch", *map(str, args), "--scheduler", client.scheduler.address])


# ----------------------------------------------------------------------------
# refine_many: the Python API
# ----------------------------------------------------------------------------


def test_refine_many_is_bit_identical_to_refine_and_keeps_input_order(cluster, frames):
    pairs = [(f"f{i}", f.depth_lr, f.rgb_hr) for i, f in enumerate(frames)]
    got = list(refine_many(pairs, method="thesis", params=PARAMS, client=cluster))
    assert [k for k, _ in got] == [k for k, _, _ in pairs]
    for (_, depth, rgb), (_, out) in zip(pairs, got):
        assert out.dtype == np.float32
        assert np.array_equal(out, refine(depth, rgb, method="thesis", params=PARAMS))


def test_refine_many_takes_a_mapping(cluster, frames):
    pairs = {i: (f.depth_lr, f.rgb_hr) for i, f in enumerate(frames[:3])}
    got = dict(refine_many(pairs, method="bilinear", client=cluster))
    assert list(got) == [0, 1, 2]
    assert all(np.array_equal(got[i], refine(*pairs[i], method="bilinear")) for i in pairs)


def test_small_frames_share_tasks_and_the_last_tasks_of_a_known_length_are_smaller(cluster, monkeypatch):
    """Two one-thread workers; tasks of at most 8 frames (TASK_PIXELS over the frame's pixels)."""
    from depthrefine.batch import _schedule

    sizes = []
    submit = _schedule._submit

    def counting(client, group, *args):
        sizes.append(len(group))
        return submit(client, group, *args)

    monkeypatch.setattr(_schedule, "_submit", counting)
    monkeypatch.setattr(_schedule, "TASK_PIXELS", 8 * 32 * 32)
    pairs = [(i, np.full((8, 8), 100 + i, np.uint16), np.zeros((32, 32, 3), np.uint8)) for i in range(48)]
    got = list(refine_many(pairs, method="nearest", client=cluster))
    assert [(k, float(d[0, 0])) for k, d in got] == [(i, 100.0 + i) for i in range(48)]
    assert sizes == [1, 8, 8, 8, 6, 5, 3, 3, 2, 1, 1, 1, 1]  # the first one frame: its size sets the rest
    sizes.clear()
    assert len(list(refine_many(iter(pairs), method="nearest", client=cluster))) == 48  # no length
    assert sizes == [1, 8, 8, 8, 8, 8, 7]


def test_temporal_warm_start_equals_the_sequential_loop_chunk_by_chunk(cluster, frames):
    pairs = [(i, f.depth_lr, f.rgb_hr) for i, f in enumerate(frames)]
    got = dict(refine_many(pairs, method="thesis", params=PARAMS, client=cluster, temporal=True, chunk=4))
    stateful = get_method("thesis").refine_stateful
    for start in (0, 4):  # chunks [0..3] and [4, 5]: each starts cold
        state = None
        for i in range(start, min(start + 4, len(frames))):
            want, state = stateful(frames[i].depth_lr, frames[i].rgb_hr, params=PARAMS, state=state)
            assert np.array_equal(got[i], want), i
        assert np.array_equal(got[start], refine(frames[start].depth_lr, frames[start].rgb_hr, method="thesis", params=PARAMS))


def test_temporal_without_a_stateful_method_runs_frames_independently(cluster, frames):
    pairs = [(i, f.depth_lr, f.rgb_hr) for i, f in enumerate(frames[:3])]
    assert get_method("bilinear").refine_stateful is None
    for key, out in refine_many(pairs, method="bilinear", client=cluster, temporal=True):
        assert np.array_equal(out, refine(pairs[key][1], pairs[key][2], method="bilinear"))


def test_refine_many_raises_for_a_bad_frame_naming_it(cluster, frames):
    pairs = [("good", frames[0].depth_lr, frames[0].rgb_hr), ("bad", frames[1].depth_lr, frames[1].rgb_hr[:20])]
    got = refine_many(pairs, method="bilinear", client=cluster)
    assert next(got)[0] == "good"
    with pytest.raises(ValueError, match="frame 'bad'"):
        next(got)


def test_the_thesis_warm_start_lowers_flicker_on_a_moving_object():
    """Measured on a generated sequence; the benchmark reports the figures (benchmarks/bench_batch.py)."""
    seq = make_sequence(8, (64, 96), 4, seed=2, color_noise_std=10.0)
    cold = [refine(f.depth_lr, f.rgb_hr, method="thesis") for f in seq]
    warm, state = [], None
    for f in seq:
        out, state = get_method("thesis").refine_stateful(f.depth_lr, f.rgb_hr, params=None, state=state)
        warm.append(out)
    gts = [f.depth_hr_gt for f in seq]
    assert flicker(warm, gts) < flicker(cold, gts)
    assert flicker(gts, gts) == 0.0


# ----------------------------------------------------------------------------
# the command: folders and manifests, resume
# ----------------------------------------------------------------------------


def test_folder_batch_writes_every_frame_like_refine(cluster, frames, tmp_path, capsys):
    src = write_folder(tmp_path / "seq", frames)
    out = tmp_path / "out"
    assert run_batch(cluster, src, "-o", out, "--method", "thesis", "--patches", "2x2") == 0
    for i, f in enumerate(frames):
        written = read_depth(out / f"{i:04d}.png")
        assert written.dtype == np.uint16
        assert np.array_equal(written, expected_file(f.depth_lr, f.rgb_hr, params=PARAMS))
    record = json.loads((out / "batch.json").read_text())
    assert record["method"] == "thesis" and record["params"]["patches"] == [2, 2]
    assert record["complete"] and record["counts"] == {"done": len(frames)}
    assert [r["key"] for r in record["frames"]] == [f"{i:04d}" for i in range(len(frames))]
    assert all(r["seconds"] > 0 for r in record["frames"])
    err = capsys.readouterr().err
    assert f"batch: {len(frames)} frames: {len(frames)} refined, 0 already done, 0 failed" in err


def test_manifest_paths_are_relative_to_it_and_float_depth_stays_float(cluster, frames, tmp_path):
    data = tmp_path / "data"
    data.mkdir()
    rows = ["depth,color"]
    for i, f in enumerate(frames[:3]):
        metres = (f.depth_lr.astype(np.float32) / 1000).astype(np.float32)
        write_depth(data / f"d{i}.tif", metres)
        write_rgb(data / f"c{i}.png", f.rgb_hr)
        rows.append(f"data/d{i}.tif,data/c{i}.png")
    (tmp_path / "list.csv").write_text("\n".join(rows) + "\n")
    out = tmp_path / "out"
    assert run_batch(cluster, tmp_path / "list.csv", "-o", out, "--method", "bilinear") == 0
    for i, f in enumerate(frames[:3]):
        metres = read_depth(data / f"d{i}.tif")
        written = read_depth(out / f"d{i}.tif")
        assert written.dtype == np.float32
        assert np.array_equal(written, expected_file(metres, f.rgb_hr, method="bilinear"))


def test_a_second_run_skips_done_frames_and_rewrites_none(cluster, frames, tmp_path, capsys):
    src = write_folder(tmp_path / "seq", frames)
    out = tmp_path / "out"
    assert run_batch(cluster, src, "-o", out, "--method", "bilinear") == 0
    (out / "0002.png").unlink()
    (out / ".0004.x1y2.png").write_bytes(b"half a file")  # what a kill during a write leaves
    before = {p.name: (p.stat().st_ino, p.stat().st_mtime_ns) for p in out.glob("[0-9]*.png")}
    capsys.readouterr()
    assert run_batch(cluster, src, "-o", out, "--method", "bilinear") == 0
    after = {p.name: (p.stat().st_ino, p.stat().st_mtime_ns) for p in out.glob("[0-9]*.png")}
    assert {k: v for k, v in after.items() if k != "0002.png"} == before
    assert np.array_equal(read_depth(out / "0002.png"),
                          expected_file(frames[2].depth_lr, frames[2].rgb_hr, method="bilinear"))
    assert not list(out.glob(".*"))
    assert "1 refined, 5 already done, 0 failed" in capsys.readouterr().err
    # other settings in the same folder: refused, nothing touched
    assert run_batch(cluster, src, "-o", out, "--method", "bicubic") == 2
    assert "holds a batch run with other method" in capsys.readouterr().err
    assert {p.name: (p.stat().st_ino, p.stat().st_mtime_ns) for p in out.glob("[0-9]*.png")} == after


def test_temporal_resume_recomputes_the_chunk_start_but_writes_only_missing_frames(cluster, frames, tmp_path):
    src = write_folder(tmp_path / "seq", frames)
    out = tmp_path / "out"
    args = (src, "-o", out, "--temporal", "--chunk", "3", "--method", "thesis", "--patches", "2x2")
    assert run_batch(cluster, *args) == 0
    full = {p.name: read_depth(p) for p in out.glob("[0-9]*.png")}
    (out / "0001.png").unlink()
    (out / "0005.png").unlink()
    kept = (out / "0000.png").stat().st_mtime_ns
    assert run_batch(cluster, *args) == 0
    assert (out / "0000.png").stat().st_mtime_ns == kept
    assert all(np.array_equal(read_depth(out / name), full[name]) for name in full)


SLOW_RUNNER = textwrap.dedent("""
    import sys, time
    from depthrefine.cli import main
    from depthrefine.methods.registry import register_method
    from depthrefine.methods.thesis.params import ThesisParams
    from depthrefine.methods.thesis.refine import refine_thesis

    def slow_thesis(depth_lr, rgb_hr, *, params=None, progress=None):
        time.sleep(0.2)  # long enough to be killed midway
        return refine_thesis(depth_lr, rgb_hr, params=params, progress=progress)

    register_method("slow_thesis", slow_thesis, params_type=ThesisParams)
    sys.exit(main(sys.argv[1:]))
""")


def test_a_run_killed_midway_resumes_and_every_output_matches_refine(cluster, tmp_path):
    seq = make_sequence(12, (32, 48), 4, seed=9)
    src = write_folder(tmp_path / "seq", seq)
    out = tmp_path / "out"
    runner = tmp_path / "runner.py"
    runner.write_text(SLOW_RUNNER)
    cmd = [sys.executable, str(runner), "batch", str(src), "-o", str(out), "--method", "slow_thesis",
           "--frames-per-task", "1", "--scheduler", cluster.scheduler.address]
    proc = subprocess.Popen(cmd, env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 60
    while len(list(out.glob("[0-9]*.png"))) < 3 and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.02)
    proc.send_signal(signal.SIGKILL)
    proc.communicate()
    done_before = {p.name: (p.stat().st_ino, p.stat().st_mtime_ns) for p in out.glob("[0-9]*.png")}
    assert 3 <= len(done_before) < len(seq), "the run was not killed midway"
    resumed = subprocess.run(cmd, env=_env(), capture_output=True, text=True, timeout=120)
    assert resumed.returncode == 0, resumed.stderr
    assert f"{len(done_before)} already done" in resumed.stderr
    for name, stamp in done_before.items():
        p = out / name
        assert (p.stat().st_ino, p.stat().st_mtime_ns) == stamp, f"{name} was rewritten"
    for i, f in enumerate(seq):
        assert np.array_equal(read_depth(out / f"{i:04d}.png"), expected_file(f.depth_lr, f.rgb_hr)), i
    assert not list(out.glob(".*"))
    assert json.loads((out / "batch.json").read_text())["counts"] == {"done": len(seq)}


def test_the_command_starts_its_own_local_cluster(tmp_path, frames):
    src = write_folder(tmp_path / "seq", frames[:2])
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "depthrefine", "batch", str(src), "-o", str(out), "--workers", "1",
                           "--method", "bilinear"], env=_env(), capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stderr.strip().splitlines()  # no Dask chatter, no progress bar off a terminal: one line
    assert len(lines) == 1 and lines[0].startswith("batch: 2 frames: 2 refined, 0 already done, 0 failed")
    assert ", 1 worker)" in lines[0]
    assert json.loads((out / "batch.json").read_text())["scheduler"] == "local"


# ----------------------------------------------------------------------------
# ROS bags, written here with rosbags itself
# ----------------------------------------------------------------------------

T0 = 1_700_000_000_000_000_000
PERIOD = 33_333_333
#: Color stamp minus depth stamp per frame (ns): jitter within 20 ms, and one frame 45 ms off.
JITTER = [3_000_000, -7_000_000, 12_000_000, 0, 45_000_000]


def write_bag(path: Path, scenes, *, ros1: bool, jpeg: bool, storage: str = "sqlite3") -> list[int]:
    """A bag with /cam/depth (16UC1) and /cam/color (rgb8 Image or JPEG CompressedImage); the depth stamps."""
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    image, compressed = store.types["sensor_msgs/msg/Image"], store.types["sensor_msgs/msg/CompressedImage"]
    header_t, time_t = store.types["std_msgs/msg/Header"], store.types["builtin_interfaces/msg/Time"]
    serialize = store.serialize_ros1 if ros1 else store.serialize_cdr
    if ros1:
        from rosbags.rosbag1 import Writer
        writer = Writer(path)
    else:
        from rosbags.rosbag2 import StoragePlugin, Writer
        writer = Writer(path, version=9,
                        storage_plugin=StoragePlugin.MCAP if storage == "mcap" else StoragePlugin.SQLITE3)

    def header(t: int, seq: int):
        stamp = time_t(sec=t // 10**9, nanosec=t % 10**9)
        return header_t(seq=seq, stamp=stamp, frame_id="cam") if ros1 else header_t(stamp=stamp, frame_id="cam")

    stamps = []
    with writer:
        depth_conn = writer.add_connection("/cam/depth", image.__msgtype__, typestore=store)
        color_type = compressed if jpeg else image
        color_conn = writer.add_connection("/cam/color", color_type.__msgtype__, typestore=store)
        for i, scene in enumerate(scenes):
            t = T0 + i * PERIOD
            stamps.append(t)
            h, w = scene.depth_lr.shape
            msg = image(header=header(t, i), height=h, width=w, encoding="16UC1", is_bigendian=0, step=2 * w,
                        data=np.frombuffer(scene.depth_lr.astype("<u2").tobytes(), np.uint8))
            writer.write(depth_conn, t, serialize(msg, image.__msgtype__))
            tc = t + JITTER[i]
            if jpeg:
                ok, buf = cv2.imencode(".jpg", cv2.cvtColor(scene.rgb_hr, cv2.COLOR_RGB2BGR))
                msg = compressed(header=header(tc, i), format="jpeg", data=buf.ravel())
            else:
                hh, ww, _ = scene.rgb_hr.shape
                msg = image(header=header(tc, i), height=hh, width=ww, encoding="rgb8", is_bigendian=0, step=3 * ww,
                            data=np.ascontiguousarray(scene.rgb_hr).ravel())
            writer.write(color_conn, tc, serialize(msg, color_type.__msgtype__))
    return stamps


def _bag_scenes():
    return [make_scene((32, 48), 4, n_objects=1, dtype=np.uint16, seed=i) for i in range(len(JITTER))]


@pytest.mark.parametrize("ros1, jpeg, storage", [(False, False, "sqlite3"), (False, True, "mcap"), (True, True, "")],
                         ids=["ros2-db3-rgb8", "ros2-mcap-jpeg", "ros1-jpeg"])
def test_bag_frames_pair_by_nearest_stamp_and_match_refine(cluster, tmp_path, capsys, ros1, jpeg, storage):
    scenes = _bag_scenes()
    bag = tmp_path / ("rec.bag" if ros1 else "rec")
    stamps = write_bag(bag, scenes, ros1=ros1, jpeg=jpeg, storage=storage)
    out = tmp_path / "out"
    status = run_batch(cluster, bag, "-o", out, "--depth-topic", "/cam/depth", "--color-topic", "/cam/color",
                       "--method", "bilinear")
    assert status == 0  # the last depth frame has no color frame within 20 ms: unpaired, not a failure
    unpaired = open_sequence(bag).unpaired
    assert [(u["stream"], u["stamp_ns"]) for u in unpaired] == [("depth", stamps[4]), ("color", stamps[4] + JITTER[4])]
    assert unpaired[0]["why"] == "no color frame on /cam/color within 20 ms"
    for i, scene in enumerate(scenes[:4]):
        rgb = scene.rgb_hr
        if jpeg:  # what the bag holds: the decoded JPEG
            ok, buf = cv2.imencode(".jpg", cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR))
            rgb = cv2.cvtColor(cv2.imdecode(buf, cv2.IMREAD_COLOR), cv2.COLOR_BGR2RGB)
        written = read_depth(out / f"{stamps[i]}.png")
        assert written.dtype == np.uint16
        assert np.array_equal(written, expected_file(scene.depth_lr, rgb, method="bilinear")), i
    record = json.loads((out / "batch.json").read_text())
    assert record["counts"] == {"done": 4}
    assert record["input"]["topics"] == {"depth": "/cam/depth", "color": "/cam/color"}
    assert record["input"]["unpaired"] == 2 and record["input"]["raw"] is False
    # a wider window pairs the last frame too
    assert run_batch(cluster, bag, "-o", tmp_path / "wide", "--depth-topic", "/cam/depth", "--color-topic",
                     "/cam/color", "--method", "bilinear", "--max-dt", "50ms") == 0


def test_float_depth_in_metres_from_a_bag(cluster, tmp_path):
    """32FC1 depth (metres, NaN = no measurement) comes out as float32 TIFF."""
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    image = store.types["sensor_msgs/msg/Image"]
    scene = make_scene((32, 48), 4, n_objects=1, dtype=np.float32, seed=1)
    depth = scene.depth_lr.copy()
    depth[0, 0] = np.nan
    bag = tmp_path / "metric"
    with Writer(bag, version=9) as writer:
        d_conn = writer.add_connection("/d", image.__msgtype__, typestore=store)
        c_conn = writer.add_connection("/c", image.__msgtype__, typestore=store)
        h, w = depth.shape
        hh, ww, _ = scene.rgb_hr.shape
        d = image(header=store.types["std_msgs/msg/Header"](stamp=store.types["builtin_interfaces/msg/Time"](
            sec=5, nanosec=0), frame_id=""), height=h, width=w, encoding="32FC1", is_bigendian=0, step=4 * w,
            data=np.frombuffer(depth.astype("<f4").tobytes(), np.uint8))
        c = image(header=d.header, height=hh, width=ww, encoding="bgr8", is_bigendian=0, step=3 * ww,
                  data=np.ascontiguousarray(scene.rgb_hr[:, :, ::-1]).ravel())
        writer.write(d_conn, 5 * 10**9, store.serialize_cdr(d, image.__msgtype__))
        writer.write(c_conn, 5 * 10**9, store.serialize_cdr(c, image.__msgtype__))
    out = tmp_path / "out"
    assert run_batch(cluster, bag, "-o", out, "--depth-topic", "/d", "--color-topic", "/c",
                     "--method", "bilinear") == 0
    written = read_depth(out / f"{5 * 10**9}.tif")
    assert written.dtype == np.float32
    assert np.array_equal(written, expected_file(depth, scene.rgb_hr, method="bilinear"))


# ----------------------------------------------------------------------------
# bad input: one line, or a per-frame failure; nothing lost
# ----------------------------------------------------------------------------


def test_missing_topic_names_the_topics_the_bag_has(tmp_path, capsys):
    bag = tmp_path / "rec"
    write_bag(bag, _bag_scenes()[:1], ros1=False, jpeg=True)
    assert main(["batch", str(bag), "-o", str(tmp_path / "out"), "--depth-topic", "/depth",
                 "--color-topic", "/cam/color"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "has no topic '/depth' (--depth-topic); its topics: /cam/color (sensor_msgs/msg/CompressedImage), " \
           "/cam/depth (sensor_msgs/msg/Image)" in err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("layout, message", [
    ({"depth": [], "color": []}, "holds no depth files"),
    ({"depth": []}, "has no color/ subfolder"),
    ({}, "has no depth/ subfolder"),
])
def test_empty_or_incomplete_folder_is_one_line(tmp_path, capsys, layout, message):
    src = tmp_path / "seq"
    src.mkdir()
    for sub in layout:
        (src / sub).mkdir()
    assert main(["batch", str(src), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err
    assert not (tmp_path / "out").exists()


def test_output_folder_inside_the_input_is_refused(frames, tmp_path, capsys):
    src = write_folder(tmp_path / "seq", frames[:2])
    assert main(["batch", str(src), "-o", str(src / "out")]) == 2
    assert "is inside the input" in capsys.readouterr().err
    assert not (src / "out").exists()


def test_unpaired_stems_and_an_unreadable_frame_fail_alone(cluster, frames, tmp_path, capsys):
    src = write_folder(tmp_path / "seq", frames[:4])
    (src / "color" / "0001.png").unlink()                         # depth without color
    (src / "depth" / "0002.png").write_bytes(b"\x89PNG\r\n\x1a\n")  # unreadable depth
    write_rgb(src / "color" / "0009.png", frames[0].rgb_hr)       # color without depth
    out = tmp_path / "out"
    assert run_batch(cluster, src, "-o", out, "--method", "bilinear") == 2
    err = capsys.readouterr().err
    assert "2 refined, 0 already done, 2 failed" in err
    assert "failed 0001: depth file" in err and "has no color file of stem '0001'" in err
    assert "failed 0002: depth file" in err and "cannot be read" in err
    assert "1 color file(s) with no depth file of the same stem, not used: 0009" in err
    assert sorted(p.name for p in out.glob("[0-9]*.png")) == ["0000.png", "0003.png"]
    statuses = {r["key"]: r["status"] for r in json.loads((out / "batch.json").read_text())["frames"]}
    assert statuses == {"0000": "done", "0001": "failed", "0002": "failed", "0003": "done"}


def test_a_frame_that_fails_inside_the_method_is_reported_with_its_reason(cluster, frames, tmp_path, capsys):
    src = write_folder(tmp_path / "seq", frames[:2])
    write_rgb(src / "color" / "0001.png", frames[1].rgb_hr[:20, :20], overwrite=True)  # not its depth map's size
    out = tmp_path / "out"
    assert run_batch(cluster, src, "-o", out, "--method", "bilinear") == 2
    err = capsys.readouterr().err
    assert "failed 0001:" in err and "0000" not in err.split("failed", 1)[1]
    assert (out / "0000.png").exists() and not (out / "0001.png").exists()


def test_a_folder_that_is_not_a_batch_output_is_not_written_into(frames, tmp_path, capsys):
    src = write_folder(tmp_path / "seq", frames[:1])
    out = tmp_path / "out"
    out.mkdir()
    (out / "mine.txt").write_text("keep")
    assert main(["batch", str(src), "-o", str(out)]) == 2
    assert "not empty and holds no batch.json" in capsys.readouterr().err
    assert sorted(p.name for p in out.iterdir()) == ["mine.txt"]


def test_an_unreachable_scheduler_is_one_line(frames, tmp_path, capsys):
    src = write_folder(tmp_path / "seq", frames[:1])
    assert main(["batch", str(src), "-o", str(tmp_path / "out"), "--scheduler", "tcp://127.0.0.1:9"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "cannot reach the Dask scheduler at tcp://127.0.0.1:9" in err


def test_batch_does_not_load_dask_or_rosbags_at_start_up():
    code = ("import sys, depthrefine, depthrefine.cli; depthrefine.cli.build_parser(); "
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('dask', 'distributed', 'rosbags')))")
    out = subprocess.run([sys.executable, "-c", code], env=_env(), capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_a_scheduler_without_workers_is_one_line(frames, tmp_path, capsys, monkeypatch):
    import logging

    from distributed import LocalCluster

    import depthrefine.batch._schedule

    monkeypatch.setattr(depthrefine.batch._schedule, "_WORKER_WAIT", 1)
    src = write_folder(tmp_path / "seq", frames[:1])
    with LocalCluster(n_workers=0, processes=False, protocol="tcp://", host="127.0.0.1", dashboard_address=":0",
                      silence_logs=logging.ERROR) as empty:
        assert main(["batch", str(src), "-o", str(tmp_path / "out"), "--scheduler", empty.scheduler_address]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "has no workers" in err and "dask worker" in err
