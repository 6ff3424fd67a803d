"""Faults on a real Dask cluster (issue 21): a ``dask scheduler`` and two ``dask worker`` processes on loopback.

- a worker killed (SIGKILL) mid-run: its frames are recomputed on the other, every frame is written and
  byte-identical to a run without faults, exit 0;
- the scheduler killed mid-run: one line, exit 1, ``batch.json`` true to the files (the same command
  resumes: tests/test_batch_job.py);
- Ctrl-C (SIGINT to the process group, as a terminal sends it, with the command's own local cluster):
  one line, exit 130, ``batch.json`` true to the files.

Each test starts its own processes (a few seconds) and runs a method that sleeps 0.25 s per frame, so
that there is a middle of the run to hit. Marked ``cluster`` (they run by default).
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

from depthrefine.bench.synthetic import make_sequence
from depthrefine.io import depth_to_dtype, write_depth, write_rgb
from depthrefine.methods.registry import refine

distributed = pytest.importorskip("distributed")

pytestmark = pytest.mark.cluster

SRC = Path(__file__).resolve().parents[1] / "src"
N_FRAMES = 14

#: The command with a slow copy of gbp (0.25 s per frame); its workers unpickle the method by value. Where
#: BATCH_TEST_MARKS names a folder, each frame leaves <pid>-<depth sum>.started and .done there.
RUNNER = textwrap.dedent("""
    import os, sys, time
    from pathlib import Path
    from depthrefine.cli import main
    from depthrefine.methods.registry import get_method, register_method

    gbp = get_method("gbp")

    def slow_gbp(depth_lr, rgb_hr, *, params=None, progress=None):
        marks = os.environ.get("BATCH_TEST_MARKS")
        mark = Path(marks, f"{os.getpid()}-{int(depth_lr.sum())}") if marks else None
        if mark:
            mark.with_suffix(".started").touch()
        time.sleep(0.25)
        out = gbp.func(depth_lr, rgb_hr, params=params, progress=progress)
        if mark:
            mark.with_suffix(".done").touch()
        return out

    register_method("slow_gbp", slow_gbp, params_type=gbp.params_type)
    if __name__ == "__main__":
        sys.exit(main(sys.argv[1:]))
""")


def _env() -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(SRC) + os.pathsep + env.get("PYTHONPATH", "")
    return env


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Cluster:
    """``dask scheduler`` and ``dask worker`` processes (no nanny: a killed worker stays dead) on 127.0.0.1."""

    def __init__(self, workers: int = 2, marks: Path | None = None):
        port = _free_port()
        self.address = f"tcp://127.0.0.1:{port}"
        env = _env() | ({"BATCH_TEST_MARKS": str(marks)} if marks else {})
        quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL, "env": env}
        self.scheduler = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host",
                                           "127.0.0.1", "--port", str(port), "--dashboard-address", ":0",
                                           "--no-show"], **quiet)
        self.workers = [subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", self.address,
                                          "--nthreads", "1", "--no-nanny", "--host", "127.0.0.1", "--no-dashboard"],
                                         **quiet) for _ in range(workers)]
        from distributed import Client

        try:
            with Client(self.address, timeout="60s") as client:
                client.wait_for_workers(workers, timeout=60)
        except BaseException:
            self.stop()
            raise

    def stop(self) -> None:
        for proc in [*self.workers, self.scheduler]:
            if proc.poll() is None:
                proc.kill()
            proc.wait(10)


@pytest.fixture
def cluster(tmp_path):
    """A scheduler and two workers; each frame a worker starts and ends leaves a mark in tmp_path/marks."""
    (tmp_path / "marks").mkdir()
    c = Cluster(marks=tmp_path / "marks")
    yield c
    c.stop()


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    """A folder of N_FRAMES frames, the runner, and the bytes each output must have (written here, no cluster)."""
    root = tmp_path_factory.mktemp("faults")
    seq = make_sequence(N_FRAMES, (48, 64), 4, seed=11)
    (root / "seq" / "depth").mkdir(parents=True)
    (root / "seq" / "color").mkdir()
    (root / "expected").mkdir()
    for i, f in enumerate(seq):
        write_depth(root / "seq" / "depth" / f"{i:04d}.png", f.depth_lr)
        write_rgb(root / "seq" / "color" / f"{i:04d}.png", f.rgb_hr)
        write_depth(root / "expected" / f"{i:04d}.png",
                    depth_to_dtype(refine(f.depth_lr, f.rgb_hr, method="gbp"), np.uint16))
    (root / "runner.py").write_text(RUNNER)
    return root


@pytest.fixture
def start():
    """``start(recording, out, *options)``: the command in a new process group, stopped at the test's end."""
    started: list[subprocess.Popen] = []

    def run(recording: Path, out: Path, *extra: str) -> subprocess.Popen:
        cmd = [sys.executable, str(recording / "runner.py"), "batch", str(recording / "seq"), "-o", str(out),
               "--method", "slow_gbp", "--frames-per-task", "1", *extra]
        proc = subprocess.Popen(cmd, env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                start_new_session=True)
        started.append(proc)
        return proc

    yield run
    for proc in started:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()


def _wait_for_files(proc: subprocess.Popen, out: Path, n: int, timeout: float = 60) -> None:
    deadline = time.monotonic() + timeout
    while len(list(out.glob("[0-9]*.png"))) < n and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.01)
    assert proc.poll() is None, proc.communicate()
    assert len(list(out.glob("[0-9]*.png"))) >= n, "no frame was written in time"


def _record_is_true_to_the_files(out: Path) -> dict:
    record = json.loads((out / "batch.json").read_text())
    done = {r["output"] for r in record["frames"] if r["status"] == "done"}
    assert done == {p.name for p in out.glob("[0-9]*.png")}
    assert not list(out.glob(".*")), "a temporary file was left"
    return record


def test_a_killed_worker_s_frames_are_recomputed_and_every_output_is_byte_identical(cluster, recording, start,
                                                                                    tmp_path):
    out, marks = tmp_path / "out", tmp_path / "marks"
    victim = cluster.workers[0]
    proc = start(recording, out, "--scheduler", cluster.address)
    _wait_for_files(proc, out, 2)
    deadline = time.monotonic() + 30  # kill the worker in the middle of a frame
    while time.monotonic() < deadline:
        busy = [p.stem for p in marks.glob(f"{victim.pid}-*.started") if not p.with_suffix(".done").exists()]
        if busy:
            break
        time.sleep(0.005)
    victim.send_signal(signal.SIGKILL)
    assert busy, "the worker never started a frame"
    _, err = proc.communicate(timeout=120)
    assert victim.wait(10) == -signal.SIGKILL
    assert proc.returncode == 0, err
    assert err.strip().splitlines()[0].startswith(f"batch: {N_FRAMES} frames: {N_FRAMES} refined, 0 already done, "
                                                  "0 failed")
    frame = busy[0].split("-", 1)[1]  # the frame the killed worker was computing: done by the other one
    assert not (marks / f"{busy[0]}.done").exists()
    assert list(marks.glob(f"{cluster.workers[1].pid}-{frame}.done"))
    for i in range(N_FRAMES):
        name = f"{i:04d}.png"
        assert (out / name).read_bytes() == (recording / "expected" / name).read_bytes(), name
    assert _record_is_true_to_the_files(out)["counts"] == {"done": N_FRAMES}


def test_a_killed_scheduler_is_one_line_exit_1_and_the_record_is_true(cluster, recording, start, tmp_path):
    out = tmp_path / "out"
    proc = start(recording, out, "--scheduler", cluster.address)
    _wait_for_files(proc, out, 3)
    cluster.scheduler.send_signal(signal.SIGKILL)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 1, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and f"lost the connection to the Dask scheduler at {cluster.address}" in lines[0], err
    assert "run the same command again (with a running scheduler) to resume" in lines[0]
    record = _record_is_true_to_the_files(out)
    assert 3 <= record["counts"]["done"] < N_FRAMES and not record["complete"]
    assert all((out / r["output"]).read_bytes() == (recording / "expected" / r["output"]).read_bytes()
               for r in record["frames"] if r["status"] == "done")


def test_ctrl_c_is_one_line_exit_130_with_the_local_cluster_silent(recording, start, tmp_path):
    out = tmp_path / "out"
    proc = start(recording, out, "--workers", "1")
    _wait_for_files(proc, out, 2, timeout=90)
    os.killpg(proc.pid, signal.SIGINT)  # as a terminal's Ctrl-C: the command and its worker processes
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("depthrefine batch: interrupted; "), err
    assert "run the same command again to resume" in lines[0]
    assert not _record_is_true_to_the_files(out)["complete"]
