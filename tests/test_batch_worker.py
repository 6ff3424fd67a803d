"""What a batch task sets in its worker process (issue 21, "each worker uses its share of the cores"): glibc's
allocator thresholds while tasks run in a process that Dask started with ``MALLOC_TRIM_THRESHOLD_``.

The kernel-thread caps are tested through a job in tests/test_batch_job.py.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from depthrefine.batch import _worker

SRC = Path(__file__).resolve().parents[1] / "src"


def glibc() -> bool:
    try:
        return os.confstr("CS_GNU_LIBC_VERSION").startswith("glibc")
    except (AttributeError, ValueError):
        return False


#: Minor page faults of 20 allocations of a 2 MiB array (each page touched), outside a task, inside one, and
#: after the task's thresholds were restored.
FAULTS = textwrap.dedent("""
    import resource, time
    import numpy as np
    from depthrefine.batch import _worker

    _worker.ALLOCATOR_IDLE = 0.05

    def faults():
        before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
        for _ in range(20):
            a = np.empty(2 << 20, np.uint8)  # below 4 MiB: numpy asks for no huge pages
            a[::4096] = 1
            del a
        return resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before

    outside = faults()
    with _worker.task_settings(1):
        faults()  # the heap grows once
        inside = faults()
    time.sleep(0.5)
    print(outside, inside, faults())
""")


@pytest.mark.skipif(not glibc(), reason="glibc's allocator only")
def test_a_task_keeps_arrays_on_the_heap_in_a_process_dask_started_with_malloc_trimming():
    env = {**os.environ, "MALLOC_TRIM_THRESHOLD_": "65536",
           "PYTHONPATH": os.pathsep.join([str(SRC), os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run([sys.executable, "-c", FAULTS], env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    outside, inside, after = (int(v) for v in done.stdout.split())
    pages = 20 * (2 << 20) // 4096
    assert outside > pages / 2          # each array a fresh mmap: every page faults in
    assert inside < outside / 10        # on the heap: the pages stay
    assert after > pages / 2            # the process's own thresholds are back


class Recorder:
    """A stand-in for glibc's ``mallopt``: records its calls."""

    def __init__(self):
        self.calls = []

    def __call__(self, param, value):
        self.calls.append((param, value))
        return 1


@pytest.fixture
def mallopt(monkeypatch):
    recorder = Recorder()
    monkeypatch.setattr(_worker, "_glibc_mallopt", lambda: recorder)
    monkeypatch.setattr(_worker, "ALLOCATOR_IDLE", 0.05)
    return recorder


def test_a_process_started_with_dynamic_thresholds_is_left_alone(mallopt, monkeypatch):
    monkeypatch.setattr(_worker, "_start_environment", lambda: {"PATH": "/usr/bin"})
    with _worker.task_settings(1):
        pass
    time.sleep(0.2)
    assert mallopt.calls == []


def test_consecutive_tasks_keep_the_raised_thresholds_and_idle_restores_the_process_s_own(mallopt, monkeypatch):
    monkeypatch.setattr(_worker, "_start_environment", lambda: {"MALLOC_TRIM_THRESHOLD_": "65536"})
    raised = [(_worker.M_MMAP_THRESHOLD, 32 << 20), (_worker.M_TRIM_THRESHOLD, 64 << 20)]
    for _ in range(3):  # one task after another, sooner than ALLOCATOR_IDLE
        with _worker.task_settings(1):
            with _worker.task_settings(1):  # and two at once
                pass
    assert mallopt.calls == raised
    time.sleep(0.3)
    assert mallopt.calls == raised + [(_worker.M_MMAP_THRESHOLD, 128 << 10), (_worker.M_TRIM_THRESHOLD, 65536)]
