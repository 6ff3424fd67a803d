"""Plain Python threads for compiled kernels that release the GIL: :func:`run_split`, :func:`threads`.

:func:`run_split` runs a compiled kernel (numba's or depthrefine's C ones,
:mod:`depthrefine._native`) over contiguous parts of its rows or columns in
plain Python threads rather than numba's ``parallel=True`` pool: numba's pool
is not safe to enter from two Python threads at once (its ``workqueue`` layer
aborts the process: "Terminating: Nested parallel kernel launch detected")
nor from a process forked after the pool started (GNU OpenMP kills the child:
"fork() called from a process already using GNU OpenMP"), and OpenMP's
spinning threads slowed ``gbp`` two-fold on a loaded machine.

Imports no numba: the C kernels run without it.
"""

from __future__ import annotations

import os
import sys
import threading
from concurrent.futures import ThreadPoolExecutor
from typing import Callable

__all__ = ["run_split", "threads", "set_threads", "worth_splitting", "PARALLEL_PIXELS"]

#: Work on images of fewer pixels runs in the calling thread: starting the workers costs more than a small
#: image's whole pass.
PARALLEL_PIXELS = 1 << 16


def _default_threads() -> int:
    """numba's ``NUMBA_NUM_THREADS``: the environment variable, else the CPUs this process may run on."""
    numba = sys.modules.get("numba")
    if numba is not None:       # numba's own setting (a program may have changed it)
        return max(1, int(numba.config.NUMBA_NUM_THREADS))
    value = os.environ.get("NUMBA_NUM_THREADS", "").strip()
    if value:
        try:
            return max(1, int(value))
        except ValueError:
            pass
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:      # not on Linux
        return max(1, os.cpu_count() or 1)


#: The worker threads of :func:`run_split`, per process (a forked child starts its own).
_pool: ThreadPoolExecutor | None = None
_pool_pid: int | None = None
_pool_lock = threading.Lock()


#: The cap :func:`set_threads` put on :func:`threads` (None: no cap).
_thread_cap: int | None = None


def threads() -> int:
    """How many threads :func:`run_split` uses: ``NUMBA_NUM_THREADS`` (default: the number of CPUs), or the cap
    of :func:`set_threads`."""
    if _thread_cap is not None:
        return _thread_cap
    return _default_threads()


def set_threads(count: int | None) -> int | None:
    """Cap the threads of this process's kernels at ``count`` (None: lift the cap); return the previous cap.

    For a process that shares the machine's cores with others, e.g. one of
    several Dask workers (``depthrefine.batch`` gives each its share). The
    results do not depend on it (:func:`run_split` cuts work into parts whose
    bits do not depend on the cut).

    Examples
    --------
    >>> previous = set_threads(1); threads()
    1
    >>> set_threads(previous)
    1
    """
    global _thread_cap
    previous = _thread_cap
    _thread_cap = None if count is None else max(1, int(count))
    return previous


def worth_splitting(pixels: int) -> bool:
    """Whether a kernel pass over an image of ``pixels`` pixels pays for its threads (:data:`PARALLEL_PIXELS`).

    Examples
    --------
    >>> worth_splitting(1280 * 720), worth_splitting(64 * 64)
    (True, False)
    """
    return pixels >= PARALLEL_PIXELS


def _workers(count: int) -> ThreadPoolExecutor:
    global _pool, _pool_pid
    with _pool_lock:
        if _pool is None or _pool_pid != os.getpid():
            _pool = ThreadPoolExecutor(max_workers=count, thread_name_prefix="depthrefine-kernel")
            _pool_pid = os.getpid()
        return _pool


def run_split(kernel: Callable[..., None], n: int, *args, parallel: bool = True) -> None:
    """``kernel(*args, k0, k1)`` over ``range(n)`` cut into contiguous parts, one per thread.

    ``kernel`` is a compiled kernel (``nogil``) that works on the part
    ``k0:k1`` of its arrays in place, independently of the other parts, so
    the result has the same bits however ``n`` is cut. The calling thread
    runs the first part; the others run on a small pool of worker threads
    (plain Python threads, not numba's ``parallel=True`` pool: numba's pool
    cannot be entered by two Python threads at once under its ``workqueue``
    layer, and GNU OpenMP's spinning threads, its default layer here,
    slowed ``gbp`` two-fold on a loaded machine). Any number of threads may
    call this at once; a forked child starts its own workers. With
    ``parallel=False`` (or one thread, or ``n < 2``) the whole range runs
    in the calling thread.
    """
    parts = min(n, threads()) if parallel else 1
    if parts <= 1:
        kernel(*args, 0, n)
        return
    bounds = [n * k // parts for k in range(parts + 1)]
    pool = _workers(parts - 1)
    futures = [pool.submit(kernel, *args, bounds[k], bounds[k + 1]) for k in range(1, parts)]
    try:
        kernel(*args, bounds[0], bounds[1])
    finally:
        for future in futures:
            future.result()
