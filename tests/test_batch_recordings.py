"""Recordings through ``depthrefine batch`` (issue 21): the recording's own calibration, units and frame rate run
the rig chain; unpaired frames are listed, not failures. The recordings are written here with the writers of
tests/test_recordings.py (which tests the readers); the shared Azure Kinect capture equals ``run`` on its
extracted frames with the imported factory calibration.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from conftest import shared_data_path
from depthrefine.batch import FramePlan, solve_frame
from depthrefine.cli import main
from depthrefine.io import depth_to_dtype, open_sequence, read_depth
from depthrefine.methods.registry import get_method
from depthrefine.rig.chain import AlignSettings

pytest.importorskip("distributed")
av = pytest.importorskip("av")
pytest.importorskip("rosbags")

from test_recordings import _color, _depth, k4a_calibration, write_camera_bag, write_mkv, write_realsense_bag  # noqa: E402


@pytest.fixture(scope="module")
def address():
    """The scheduler of a Dask cluster in this process (one worker, two threads)."""
    import logging

    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=":0",
                      silence_logs=logging.ERROR) as cluster, Client(cluster):
        yield cluster.scheduler_address


def expected_outputs(seq, method: str) -> dict[str, np.ndarray]:
    """Each frame through the chain with the recording's rig and units, as the batch must write it."""
    plan = FramePlan(get_method(method), rig=seq.rig, align=AlignSettings(depth_units=seq.depth_units))
    out = {}
    for frame, (depth, rgb) in seq.load(seq.frames):
        solved, _ = solve_frame(plan, depth, rgb)
        out[frame.key] = depth_to_dtype(solved.depth_hr, depth.dtype)
    return out


def test_a_realsense_recording_runs_the_chain_with_its_calibration_units_and_rate(address, tmp_path, capsys):
    bag = tmp_path / "rs.bag"
    write_realsense_bag(bag)
    out, video = tmp_path / "out", tmp_path / "rs.mp4"
    assert main(["batch", str(bag), "-o", str(out), "--method", "bilinear", "--video", str(video),
                 "--scheduler", address]) == 0
    assert "note: chain: color image undistorted" in capsys.readouterr().err
    seq = open_sequence(bag)
    for key, want in expected_outputs(seq, "bilinear").items():
        assert np.array_equal(read_depth(out / f"{key}.png"), want), key
    record = json.loads((out / "batch.json").read_text())
    assert record["align"]["depth_units"] == pytest.approx(0.0001) and record["rig"]["source"] == seq.rig_source
    assert [r["stamp_ns"] for r in record["frames"]] == [f.stamp_ns for f in seq.frames]
    with av.open(str(video)) as container:
        stream = container.streams.video[0]
        assert stream.frames == 3 and float(stream.average_rate) == 30.0


def test_a_bag_with_camera_info_and_tf_static_lists_unpaired_depth_frames(address, tmp_path, capsys):
    bag = tmp_path / "cam"
    write_camera_bag(bag)  # depth at 30 fps, color at 15: every other depth frame has no partner
    out = tmp_path / "out"
    assert main(["batch", str(bag), "-o", str(out), "--method", "nearest", "--scheduler", address]) == 0
    err = capsys.readouterr().err
    assert "batch: 3 frames: 3 refined, 0 already done, 0 failed, 3 unpaired (see batch.json)" in err
    record = json.loads((out / "batch.json").read_text())
    assert record["counts"] == {"done": 3} and [u["stream"] for u in record["unpaired"]] == ["depth"] * 3
    seq = open_sequence(bag)
    for key, want in expected_outputs(seq, "nearest").items():
        assert np.array_equal(read_depth(out / f"{key}.png"), want), key


def test_an_azure_kinect_mkv_runs_the_chain_with_its_calibration(address, tmp_path):
    calibration = k4a_calibration()
    depth_camera = calibration["CalibrationInformation"]["Cameras"][0]["Intrinsics"]
    # milder lenses than test_recordings' (whose depth corners reach 40 times a pixel's footprint, which costs
    # the reprojection seconds per frame)
    depth_camera["ModelParameters"][4:10] = [0.2, -0.05, 0.0, 0.2, -0.02, 0.0]
    ms = [0, 33, 67]
    mkv = write_mkv(tmp_path / "rec.mkv", depth_frames=[_depth(i) for i in range(3)],
                    color_frames=[_color(i) for i in range(3)], depth_ms=ms, color_ms=ms, calibration=calibration)
    out = tmp_path / "out"
    assert main(["batch", str(mkv), "-o", str(out), "--method", "nearest", "--save-color", "--scheduler",
                 address]) == 0
    seq = open_sequence(mkv)
    assert seq.raw and seq.rig is not None
    for key, want in expected_outputs(seq, "nearest").items():
        assert np.array_equal(read_depth(out / f"{key}.png"), want), key
        assert (out / "color" / f"{key}.png").is_file()


@pytest.mark.shared_data
def test_the_shared_azure_kinect_recording_equals_run_on_its_extracted_frames(address, tmp_path):
    folder = shared_data_path("real_tof", "azure_kinect_mug")
    assert main(["rig", "import", str(folder / "calibration.json"), "--depth-mode", "NFOV_UNBINNED",
                 "--color-resolution", "720P", "-o", str(tmp_path / "rig.json")]) == 0
    single = tmp_path / "run.png"
    assert main(["run", str(folder / "derived" / "depth_640x576_mm.png"), str(folder / "derived" / "color_1280x720.jpg"),
                 "--rig", str(tmp_path / "rig.json"), "--depth-units", "0.001", "--refine-method", "gbp",
                 "-o", str(single)]) == 0
    out = tmp_path / "out"
    assert main(["batch", str(folder / "recording.mkv"), "-o", str(out), "--method", "gbp",
                 "--scheduler", address]) == 0
    assert (out / "800222000.png").read_bytes() == single.read_bytes()
