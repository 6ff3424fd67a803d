"""What a batch task sets in its worker process while it runs, and restores after the last task there.

- **Kernel threads**: the compiled kernels' (:func:`depthrefine._threads.set_threads`) and
  OpenCV's (``cv2.setNumThreads``), capped at the worker's share of its
  machine's cores: the cores divided by the Dask threads of all workers on
  that machine, at least 1. Two one-thread workers on two cores run one
  kernel thread each instead of two each (which oversubscribed the cores).
- **glibc's allocator thresholds**: Dask starts its worker processes with
  ``MALLOC_TRIM_THRESHOLD_=65536`` (``distributed.nanny.pre-spawn-environ``,
  so that freed memory goes back to the system at once). Any such variable
  turns off glibc's dynamic thresholds, so every array above 128 KiB is a
  fresh ``mmap`` whose pages fault in, zero-filled, on first touch, and go
  back at ``free``: a 640x480 ``gbp`` frame then cost 80 instead of 48 ms of
  CPU, 28 ms of it in the kernel (``benchmarks/bench_batch.py --overheads``). While a task runs, arrays up to 32 MiB
  come from the heap and stay there for the next frame (``mallopt``:
  ``M_MMAP_THRESHOLD`` 32 MiB, ``M_TRIM_THRESHOLD`` 64 MiB, what glibc's
  dynamic rule reaches by itself); the process's own values come back two
  seconds after the last task ended, and glibc trims the heap as the worker
  wants. A process that started with glibc's dynamic thresholds (none of
  these variables in ``/proc/self/environ``) is left alone, as is any other
  C library.

The results do not depend on either setting.
"""

from __future__ import annotations

import contextlib
import os
import threading
import time
from collections.abc import Iterator, Mapping
from typing import Any

__all__ = ["worker_share", "task_settings", "allocator_values"]

#: ``mallopt`` parameters (glibc's malloc.h).
M_TRIM_THRESHOLD = -1
M_MMAP_THRESHOLD = -3
#: glibc's defaults for both thresholds.
GLIBC_DEFAULT_THRESHOLD = 128 * 1024
#: While a task runs: arrays up to this size come from the heap (glibc's largest mmap threshold on 64 bits) ...
TASK_MMAP_THRESHOLD = 32 * 1024 * 1024
#: ... and the heap's top is given back above this (twice the mmap threshold, as glibc's dynamic rule keeps it).
TASK_TRIM_THRESHOLD = 2 * TASK_MMAP_THRESHOLD
#: Environment variables with which glibc starts a process on fixed thresholds (each turns the dynamic rule off).
_STATIC_VARIABLES = ("MALLOC_TRIM_THRESHOLD_", "MALLOC_MMAP_THRESHOLD_", "MALLOC_TOP_PAD_", "MALLOC_MMAP_MAX_")
_STATIC_TUNABLES = ("glibc.malloc.trim_threshold", "glibc.malloc.mmap_threshold", "glibc.malloc.top_pad",
                    "glibc.malloc.mmap_max")


def worker_share(share: Mapping[str, int]) -> int:
    """This worker's share of its machine's cores: the cores over the Dask threads on the machine, at least 1.

    ``share`` maps a host to the Dask threads of all workers there; outside
    a Dask worker, all cores.
    """
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    try:
        from distributed import get_worker
        from distributed.comm import get_address_host

        worker = get_worker()
        threads = share.get(get_address_host(worker.address), worker.state.nthreads)
    except (ImportError, ValueError, AttributeError):  # not on a worker (called directly)
        return cores
    return max(1, cores // max(1, threads))


def allocator_values(environ: Mapping[str, str]) -> tuple[int, int] | None:
    """``(mmap threshold, trim threshold)`` a glibc process started with ``environ`` has, or ``None`` if dynamic.

    glibc fixes both thresholds when any ``MALLOC_*_`` threshold variable
    (or a ``glibc.malloc`` threshold tunable) is set; those not given keep
    their defaults (128 KiB).

    Examples
    --------
    >>> allocator_values({"MALLOC_TRIM_THRESHOLD_": "65536"})
    (131072, 65536)
    >>> allocator_values({"GLIBC_TUNABLES": "glibc.malloc.mmap_threshold=1048576"})
    (1048576, 131072)
    >>> allocator_values({"PATH": "/usr/bin"}) is None
    True
    """
    tunables = dict(item.partition("=")[::2] for item in environ.get("GLIBC_TUNABLES", "").split(":") if item)
    if not any(name in environ for name in _STATIC_VARIABLES) and not any(t in tunables for t in _STATIC_TUNABLES):
        return None

    def value(variable: str, tunable: str) -> int:
        text = environ.get(variable, tunables.get(tunable, ""))
        try:
            return int(text, 0)
        except ValueError:
            return GLIBC_DEFAULT_THRESHOLD

    return (value("MALLOC_MMAP_THRESHOLD_", "glibc.malloc.mmap_threshold"),
            value("MALLOC_TRIM_THRESHOLD_", "glibc.malloc.trim_threshold"))


def _glibc_mallopt() -> Any:
    """glibc's ``mallopt`` (a ctypes function), or ``None`` on another C library or platform."""
    try:
        if not os.confstr("CS_GNU_LIBC_VERSION").startswith("glibc"):
            return None
        import ctypes

        mallopt = ctypes.CDLL(None).mallopt
    except (AttributeError, ValueError, OSError):
        return None
    mallopt.argtypes = (ctypes.c_int, ctypes.c_int)
    mallopt.restype = ctypes.c_int
    return mallopt


#: Seconds without a task after which the allocator's own thresholds come back (a batch's next task comes sooner).
ALLOCATOR_IDLE = 2.0

#: Tasks inside :func:`task_settings` in this process, and what to restore when the last one leaves.
_lock = threading.Lock()
_idle = threading.Condition(_lock)
_users = 0
_before: dict[str, Any] = {}
#: The raised allocator thresholds (mallopt, values to restore), when the last task ended, the thread that
#: restores them (its process id: a forked child starts its own).
_raised: tuple[Any, tuple[int, int]] | None = None
_ended = 0.0
_restorer_pid: int | None = None


@contextlib.contextmanager
def task_settings(threads: int) -> Iterator[None]:
    """Kernel threads capped at ``threads`` and heap-friendly allocator thresholds while tasks run here.

    Counted, so that tasks on several threads of one process (a threaded
    worker, or workers in the caller's own process) restore the settings
    only when the last one leaves: the kernel threads at once, the
    allocator's thresholds after :data:`ALLOCATOR_IDLE` seconds without a
    task (restored after each task, the heap a task leaves would go back to
    the system before the next task, which would fault it in again).
    """
    global _users, _raised, _ended
    import cv2

    from .. import _threads

    with _lock:
        if _users == 0:
            _before.clear()
            _before["kernels"] = _threads.set_threads(threads)
            _before["cv2"] = cv2.getNumThreads()
            if _raised is None:
                _raised = _raise_thresholds()
                if _raised is not None:
                    _start_restorer()
        else:
            _threads.set_threads(threads)
        cv2.setNumThreads(threads)
        _users += 1
    try:
        yield
    finally:
        with _lock:
            _users -= 1
            if _users == 0:
                _threads.set_threads(_before["kernels"])
                cv2.setNumThreads(_before["cv2"])
                _ended = time.monotonic()
                _idle.notify_all()


def _start_restorer() -> None:
    """Start this process's thread that restores the allocator's thresholds when tasks stop (under ``_lock``)."""
    global _restorer_pid
    if _restorer_pid != os.getpid():
        _restorer_pid = os.getpid()
        threading.Thread(target=_restore_when_idle, name="depthrefine-allocator", daemon=True).start()


def _restore_when_idle() -> None:
    """Forever: once no task has run for :data:`ALLOCATOR_IDLE` seconds, the process's own thresholds."""
    global _raised
    with _lock:
        while True:
            if _raised is None or _users:
                _idle.wait()
                continue
            left = _ended + ALLOCATOR_IDLE - time.monotonic()
            if left > 0:
                _idle.wait(left)
                continue
            _restore_thresholds(_raised)
            _raised = None


def _start_environment() -> dict[str, str]:
    """The environment this process started with (what glibc read), not ``os.environ`` as changed since.

    A process that started a Dask ``LocalCluster`` has Dask's variables in
    its ``os.environ`` (the nanny sets them before it spawns a worker) but
    its allocator runs on what it started with. Empty where ``/proc`` is not.
    """
    try:
        with open("/proc/self/environ", "rb") as f:
            data = f.read()
    except OSError:
        return {}
    items = (item.decode("utf-8", "surrogateescape").partition("=") for item in data.split(b"\0") if item)
    return {name: value for name, _, value in items}


def _raise_thresholds() -> tuple[Any, tuple[int, int]] | None:
    """Set the task's thresholds if this process runs glibc on fixed ones; return (mallopt, values to restore)."""
    values = allocator_values(_start_environment())
    mallopt = _glibc_mallopt() if values is not None else None
    if mallopt is None:
        return None
    if not (mallopt(M_MMAP_THRESHOLD, TASK_MMAP_THRESHOLD) and mallopt(M_TRIM_THRESHOLD, TASK_TRIM_THRESHOLD)):
        mallopt(M_MMAP_THRESHOLD, values[0])  # refused (another word size): the process's own values
        mallopt(M_TRIM_THRESHOLD, values[1])
        return None
    return mallopt, values


def _restore_thresholds(raised: tuple[Any, tuple[int, int]] | None) -> None:
    if raised is not None:
        mallopt, (mmap_threshold, trim_threshold) = raised
        mallopt(M_MMAP_THRESHOLD, mmap_threshold)
        mallopt(M_TRIM_THRESHOLD, trim_threshold)
