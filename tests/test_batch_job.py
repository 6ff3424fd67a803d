"""The batch job without a subprocess (issues 19 and 21): BatchJob on an in-process Dask cluster, the rig chain,
the outputs beside each frame, the preview video, and a record that stays true to the files on every exit.

The cluster's workers are threads of the test process (``processes=False``), so a job runs in well under a
second per frame; tests/test_batch.py runs the command on worker processes, tests/test_batch_cluster.py kills
them.
"""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest

from depthrefine.batch import BatchJob, BatchOptions, FramePlan, refine_many, solve_frame
from depthrefine.bench.synthetic import make_sequence
from depthrefine.cli import main
from depthrefine.io import (InputFileError, depth_to_dtype, open_sequence, read_depth, read_ply, read_rgb,
                            scale_to_dtype, write_depth, write_rgb, write_rig)
from depthrefine.methods.registry import METHODS, get_method, refine, register_method
from depthrefine.rig import AlignSettings, CameraModel, StereoRig

distributed = pytest.importorskip("distributed")

#: A small rig: a 48 x 36 depth camera with barrel distortion and a 192 x 144 color camera 5 cm to its right.
DEPTH_CAM = CameraModel(np.array([[40.0, 0, 23.6], [0, 40.2, 17.8], [0, 0, 1]]),
                        np.array([-0.2, 0.04, 0.0, 0.0, 0.0]), (48, 36))
COLOR_CAM = CameraModel(np.array([[165.0, 0, 96.4], [0, 165.5, 71.2], [0, 0, 1]]),
                        np.array([0.03, -0.01, 0.0, 0.0, 0.0]), (192, 144))
RIG = StereoRig(DEPTH_CAM, COLOR_CAM, cv2.Rodrigues(np.array([0.004, -0.01, 0.002]))[0], np.array([-0.05, 0.0, 0.0]))


@pytest.fixture(scope="module")
def client():
    """A Dask cluster in this process: one worker, two threads."""
    import logging

    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=":0",
                      silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
        yield client


@pytest.fixture
def registered():
    """``registered(name, func, **options)``: a method registered for one test only (other tests list them all)."""
    names = []

    def add(name, func, **options):
        register_method(name, func, **options)
        names.append(name)

    yield add
    for name in names:
        METHODS.pop(name, None)


@pytest.fixture(scope="module")
def frames():
    return make_sequence(5, (48, 64), 4, seed=7)


def write_folder(root: Path, pairs) -> Path:
    (root / "depth").mkdir(parents=True)
    (root / "color").mkdir()
    for i, (depth, rgb) in enumerate(pairs):
        write_depth(root / "depth" / f"{i:04d}.png", depth)
        write_rgb(root / "color" / f"{i:04d}.png", rgb)
    return root


def raw_frames(n: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """Raw captures of RIG: uint16 mm depth (a box before a wall, a hole) and a smooth color image with a box."""
    out = []
    for i in range(n):
        depth = np.full((36, 48), 1600, np.uint16)
        depth[10:24, 12 + i:28 + i] = 900 + 10 * i
        depth[2:5, 40:44] = 0
        rng = np.random.default_rng(i)
        rgb = cv2.GaussianBlur(rng.integers(0, 255, (144, 192, 3)).astype(np.uint8), (0, 0), 3)
        rgb[40:100, 50 + 4 * i:115 + 4 * i] = (200, 60, 40)
        out.append((depth, rgb))
    return out


def counts_on_disk(outdir: Path) -> tuple[set, set]:
    """(frames whose depth file exists, frames batch.json calls done)."""
    record = json.loads((outdir / "batch.json").read_text())
    on_disk = {r["key"] for r in record["frames"] if (outdir / r["output"]).is_file()}
    done = {r["key"] for r in record["frames"] if r["status"] == "done"}
    return on_disk, done


# ----------------------------------------------------------------------------
# the job object
# ----------------------------------------------------------------------------


def test_a_job_writes_every_frame_and_a_second_job_resumes_it(client, frames, tmp_path):
    src = write_folder(tmp_path / "seq", [(f.depth_lr, f.rgb_hr) for f in frames])
    job = BatchJob(open_sequence(src), tmp_path / "out", BatchOptions(method="gbp"))
    assert job.done_before == set() and job.plan.rig is None
    seen = []
    summary = job.run(client, progress=lambda done, total: seen.append((done, total)))
    assert (summary.frames, summary.refined, summary.already_done, summary.failed) == (5, 5, 0, [])
    assert summary.exit_status == 0 and seen[-1] == (5, 5)
    assert summary.line().startswith("batch: 5 frames: 5 refined, 0 already done, 0 failed in ")
    for i, f in enumerate(frames):
        want = depth_to_dtype(refine(f.depth_lr, f.rgb_hr, method="gbp"), np.uint16)
        assert np.array_equal(read_depth(tmp_path / "out" / f"{i:04d}.png"), want)
    (tmp_path / "out" / "0003.png").unlink()
    again = BatchJob(open_sequence(src), tmp_path / "out", BatchOptions(method="gbp"))
    assert again.done_before == {"0000", "0001", "0002", "0004"}
    summary = again.run(client)
    assert (summary.refined, summary.already_done) == (1, 4)
    record = json.loads((tmp_path / "out" / "batch.json").read_text())
    assert record["complete"] and record["counts"] == {"done": 5} and record["unpaired"] == []


def test_the_worker_sends_back_the_files_bytes_as_the_writers_write_them(client, frames, tmp_path):
    """The frame's files are encoded on the worker (the results are their bytes, not float32 arrays)."""
    from depthrefine.batch import run_frames
    from depthrefine.io import write_confidence

    f = frames[0]
    plan = FramePlan(get_method("gbp"), confidence=True)
    suffixes = {"depth": ".png", "confidence": ".png"}
    [result] = run_frames([("0000", lambda: (f.depth_lr, f.rgb_hr, suffixes))], plan=plan, client=client)
    assert result.output.depth_hr is None and result.output.confidence is None
    want, _ = solve_frame(plan, f.depth_lr, f.rgb_hr)
    write_depth(tmp_path / "d.png", want.depth_hr, dtype=np.uint16)
    write_confidence(tmp_path / "c.png", want.confidence)
    assert result.output.files == {"depth": (tmp_path / "d.png").read_bytes(),
                                   "confidence": (tmp_path / "c.png").read_bytes()}


def test_a_depth_the_output_type_cannot_hold_fails_its_frame_as_bad_input(client, frames, tmp_path):
    src = write_folder(tmp_path / "seq", [(f.depth_lr, f.rgb_hr) for f in frames[:2]])
    options = BatchOptions(method="nearest", output_scale=1000.0, output_dtype="uint16")  # mm x 1000: over 65535
    summary = BatchJob(open_sequence(src), tmp_path / "out", options).run(client)
    assert summary.exit_status == 2 and [k for k, _, bad in summary.failed if bad] == ["0000", "0001"]
    assert "output scale 1000, dtype uint16: depth x 1000 reaches" in summary.failed[0][1]
    on_disk, done = counts_on_disk(tmp_path / "out")
    assert on_disk == done == set()


def test_an_interrupt_leaves_the_record_true_to_the_files_and_the_job_resumes(client, frames, tmp_path):
    src = write_folder(tmp_path / "seq", [(f.depth_lr, f.rgb_hr) for f in frames])
    out = tmp_path / "out"

    def interrupt(done, total):
        if done == 2:
            raise KeyboardInterrupt

    job = BatchJob(open_sequence(src), out, BatchOptions(method="bilinear"))
    with pytest.raises(KeyboardInterrupt):
        job.run(client, progress=interrupt)
    on_disk, done = counts_on_disk(out)
    assert on_disk == done and len(done) == 2
    assert not json.loads((out / "batch.json").read_text())["complete"]
    assert not list(out.glob(".*")) and "2 of 5 frames written" in job.describe_progress()
    summary = BatchJob(open_sequence(src), out, BatchOptions(method="bilinear")).run(client)
    assert (summary.refined, summary.already_done, summary.exit_status) == (3, 2, 0)


def test_a_ctrl_c_that_a_finalizer_dropped_still_stops_the_batch_at_its_next_frame():
    import signal
    import sys

    from depthrefine.cli.batch import _interrupt_latch

    class Released:   # as a Dask future the garbage collector releases while Ctrl-C comes
        def __del__(self):
            signal.raise_signal(signal.SIGINT)
            sum(range(1000))   # the handler runs in here: Python prints its KeyboardInterrupt and drops it

    before, hook = signal.getsignal(signal.SIGINT), sys.unraisablehook
    dropped = []
    sys.unraisablehook = dropped.append   # what Python would print
    try:
        with _interrupt_latch() as check:
            check()                # nothing came yet
            Released()             # the interrupt is dropped, silently ...
            with pytest.raises(KeyboardInterrupt):
                check()            # ... and the latch raises it at the next frame
        assert dropped == []
        assert signal.getsignal(signal.SIGINT) is before and sys.unraisablehook == dropped.append
    finally:
        sys.unraisablehook = hook


def test_unpaired_frames_are_listed_not_failures(client, frames, tmp_path):
    src = write_folder(tmp_path / "seq", [(f.depth_lr, f.rgb_hr) for f in frames[:2]])
    seq = open_sequence(src)
    seq.unpaired = [{"stream": "color", "stamp_ns": 123, "why": "no depth frame within 20 ms"}]
    summary = BatchJob(seq, tmp_path / "out", BatchOptions(method="nearest")).run(client)
    assert summary.exit_status == 0 and summary.unpaired == seq.unpaired
    assert ", 1 unpaired (see batch.json)" in summary.line()
    assert json.loads((tmp_path / "out" / "batch.json").read_text())["unpaired"] == seq.unpaired


def test_a_method_that_fails_a_frame_fails_only_it(client, frames, registered, tmp_path):
    def fragile(depth_lr, rgb_hr, *, params=None, progress=None):
        if depth_lr.flat[0] == frames[1].depth_lr.flat[0]:
            raise RuntimeError("boom")
        return refine(depth_lr, rgb_hr, method="nearest")

    registered("fragile_test", fragile, params_type=None)
    src = write_folder(tmp_path / "seq", [(f.depth_lr, f.rgb_hr) for f in frames[:3]])
    summary = BatchJob(open_sequence(src), tmp_path / "out", BatchOptions(method="fragile_test")).run(client)
    assert summary.exit_status == 1 and [k for k, _, _ in summary.failed] == ["0001"]
    assert "internal error: RuntimeError: boom" in summary.failed[0][1]
    on_disk, done = counts_on_disk(tmp_path / "out")
    assert on_disk == done == {"0000", "0002"}


def test_each_task_caps_the_kernel_threads_at_its_share_and_restores_them(client, registered):
    """One worker with two threads in this process: each task gets max(1, cores // 2) kernel threads."""
    import os

    from depthrefine import _numba

    def probe(depth_lr, rgb_hr, *, params=None, progress=None):
        return np.full(rgb_hr.shape[:2], 100 * _numba.threads() + cv2.getNumThreads(), np.float32)

    registered("threads_probe", probe, params_type=None)
    before = (_numba.threads(), cv2.getNumThreads())
    got = dict(refine_many({0: (np.ones((2, 2)), np.zeros((4, 4, 3), np.uint8))}, method="threads_probe",
                           client=client))
    share = max(1, len(os.sched_getaffinity(0)) // 2)
    assert got[0][0, 0] == 100 * share + share
    assert (_numba.threads(), cv2.getNumThreads()) == before


# ----------------------------------------------------------------------------
# the rig chain and the outputs beside each frame
# ----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def rig_folder(tmp_path_factory):
    root = tmp_path_factory.mktemp("raw")
    write_folder(root / "seq", raw_frames(3))
    write_rig(root / "rig.json", RIG)
    return root


def test_raw_frames_through_batch_rig_equal_run_on_each_frame(client, rig_folder, tmp_path, capsys):
    out = tmp_path / "out"
    common = ["--rig", str(rig_folder / "rig.json"), "--depth-units", "0.001"]
    assert main(["batch", str(rig_folder / "seq"), "-o", str(out), "--method", "gbp", *common,
                 "--scheduler", client.scheduler.address]) == 0
    err = capsys.readouterr().err
    assert "note: chain: color image undistorted (bilinear); depth reprojected into the color camera" in err
    assert "warning" not in err
    for i in range(3):
        single = tmp_path / f"run{i}.png"
        assert main(["run", str(rig_folder / "seq" / "depth" / f"{i:04d}.png"),
                     str(rig_folder / "seq" / "color" / f"{i:04d}.png"), "-o", str(single), "--refine-method", "gbp",
                     *common]) == 0
        assert (out / f"{i:04d}.png").read_bytes() == single.read_bytes(), i
    record = json.loads((out / "batch.json").read_text())
    assert record["rig"]["source"].endswith("rig.json") and record["align"]["depth_units"] == 0.001


def test_implausible_depth_units_are_a_warning_naming_the_units_and_the_median(client, rig_folder, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["batch", str(rig_folder / "seq"), "-o", str(out), "--rig", str(rig_folder / "rig.json"),
                 "--depth-units", "1", "--method", "bilinear", "--scheduler", client.scheduler.address]) == 0
    err = capsys.readouterr().err
    # the wall is 1600 mm away; one warning, before the run's summary line
    assert err.count("warning") == 1 and err.index("depthrefine batch: warning: frame 0000: depth units 1 m per stored "
                                                   "value give a median depth of 1.6 km, outside the 5 cm .. 50 m") \
        < err.index("batch: 3 frames"), err
    assert "give --depth-units 0.001" in err
    job = BatchJob(open_sequence(rig_folder / "seq"), tmp_path / "out2",
                   BatchOptions(method="bilinear", rig=RIG, align=AlignSettings(inverse_scale=1.0)))
    assert job.warnings == ["frame 0000: inverse depth scale 1 (metres = scale / value) give a median depth of 0.625 mm, "
                            "outside the 5 cm .. 50 m a ToF camera measures: the units are probably wrong"]


def test_a_rigs_frames_tell_the_method_they_are_reprojected(rig_folder, tmp_path):
    """With a rig, as run: gbp's unsaid ``reprojected`` becomes True when the frames are solved and in the record;
    a said False stays; registered frames and other methods keep their parameters."""
    from depthrefine.methods.gbp import GbpParams

    gbp = get_method("gbp")
    assert FramePlan(gbp, rig=RIG).told_params() == GbpParams(reprojected=True)
    assert FramePlan(gbp, GbpParams(reprojected=False), rig=RIG).told_params() == GbpParams(reprojected=False)
    assert FramePlan(gbp).told_params() is None and FramePlan(get_method("bilinear"), rig=RIG).told_params() is None
    job = BatchJob(open_sequence(rig_folder / "seq"), tmp_path / "out",
                   BatchOptions(method="gbp", rig=RIG, align=AlignSettings(depth_units=0.001)))
    assert job.settings()["params"]["reprojected"] is True
    depth = read_depth(rig_folder / "seq" / "depth" / "0000.png")
    rgb = read_rgb(rig_folder / "seq" / "color" / "0000.png")
    told, _ = solve_frame(job.plan, depth, rgb)
    kept, _ = solve_frame(FramePlan(gbp, GbpParams(reprojected=False), rig=RIG, align=job.plan.align), depth, rgb)
    assert not np.array_equal(told.depth_hr, kept.depth_hr, equal_nan=True)


def test_the_recordings_own_calibration_and_units_run_the_chain(client, rig_folder, tmp_path):
    seq = open_sequence(rig_folder / "seq")
    seq.rig, seq.raw, seq.depth_units = RIG, True, 0.001  # what a recording reader gives
    job = BatchJob(seq, tmp_path / "out", BatchOptions(method="bilinear"))
    assert job.plan.rig is RIG and job.plan.align.depth_units == 0.001
    assert job.run(client).exit_status == 0
    depth, rgb = raw_frames(1)[0]
    want, _ = solve_frame(FramePlan(get_method("bilinear"), rig=RIG, align=job.plan.align), depth, rgb)
    assert np.array_equal(read_depth(tmp_path / "out" / "0000.png"), depth_to_dtype(want.depth_hr, np.uint16))
    seq.rig = None
    seq.rig_problem = "input seq holds no calibration: pass --rig"
    with pytest.raises(InputFileError, match="holds no calibration: pass --rig"):
        BatchJob(seq, tmp_path / "out2", BatchOptions())


def test_a_rig_of_other_sizes_is_one_line_and_writes_nothing(rig_folder, tmp_path, capsys):
    half = CameraModel(np.array([[20.0, 0, 11.8], [0, 20.1, 8.9], [0, 0, 1]]), DEPTH_CAM.dist, (24, 18))
    small = StereoRig(half, COLOR_CAM, RIG.R, RIG.t)
    write_rig(tmp_path / "small.json", small)
    out = tmp_path / "out"
    assert main(["batch", str(rig_folder / "seq"), "-o", str(out), "--rig", str(tmp_path / "small.json"),
                 "--depth-units", "0.001"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "has a 24x18 depth camera but the depth frames are 48x36 (frame 0000)" in err
    assert not out.exists()
    assert main(["batch", str(rig_folder / "seq"), "-o", str(out), "--rig", str(rig_folder / "rig.json")]) == 2
    assert "needs the depth's units" in capsys.readouterr().err and not out.exists()


def test_color_point_clouds_scaled_output_and_a_preview_video(client, rig_folder, tmp_path, capsys):
    import av

    out, video = tmp_path / "out", tmp_path / "preview.mp4"
    assert main(["batch", str(rig_folder / "seq"), "-o", str(out), "--rig", str(rig_folder / "rig.json"),
                 "--depth-units", "0.001", "--method", "bilinear", "--save-color", "--ply", "--stride", "2",
                 "--output-scale", "0.001", "--output-dtype", "float32", "--video", str(video), "--fps", "12",
                 "--scheduler", client.scheduler.address]) == 0
    assert f"wrote {video}" in capsys.readouterr().err
    depth, rgb = raw_frames(3)[2]
    from depthrefine.rig.chain import AlignSettings

    want, _ = solve_frame(FramePlan(get_method("bilinear"), rig=RIG, align=AlignSettings(depth_units=0.001),
                                    color=True, points=True, stride=2), depth, rgb)
    metres = read_depth(out / "0002.tif")
    assert metres.dtype == np.float32
    assert np.array_equal(metres, depth_to_dtype(scale_to_dtype(want.depth_hr, 0.001, np.float32), np.float32))
    assert np.array_equal(read_rgb(out / "color" / "0002.png"), want.rgb_hr)
    points, colors = read_ply(out / "ply" / "0002.ply")
    assert np.array_equal(points, want.points) and np.array_equal(colors, want.colors)
    record = json.loads((out / "batch.json").read_text())
    assert record["frames"][2]["ply_output"] == "ply/0002.ply" and record["save_color"] and record["ply"]
    with av.open(str(video)) as container:
        stream = container.streams.video[0]
        decoded = [f.to_ndarray(format="rgb24") for f in container.decode(stream)]
        assert len(decoded) == 3 and float(stream.average_rate) == 12.0
    assert decoded[0].shape[1] > 3 * 192  # color | input | refined, and the colorbar
    # the same command again: nothing to do, and the video is not overwritten without --overwrite
    assert main(["batch", str(rig_folder / "seq"), "-o", str(tmp_path / "out2"), "--rig", str(rig_folder / "rig.json"),
                 "--depth-units", "0.001", "--video", str(video)]) == 2
    assert "preview.mp4 exists; pass --overwrite" in capsys.readouterr().err


def test_ply_without_a_rig_and_align_options_without_one_are_refused(frames, tmp_path, capsys):
    src = write_folder(tmp_path / "seq", [(f.depth_lr, f.rgb_hr) for f in frames[:1]])
    assert main(["batch", str(src), "-o", str(tmp_path / "out"), "--ply"]) == 2
    assert "--ply) needs the rig" in capsys.readouterr().err
    assert main(["batch", str(src), "-o", str(tmp_path / "out"), "--depth-units", "0.001"]) == 2
    assert "apply to raw frames of a rig: give --rig" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()
