"""numba's ``njit`` with an on-disk cache, and the turn to use its thread pool.

:func:`njit` falls back to in-memory compilation (one warning per process)
when numba finds no writable cache directory. :func:`parallel_turn` says
whether the calling thread may launch ``parallel=True`` kernels now: numba's
pool is not safe to enter from two Python threads at once (its ``workqueue``
layer aborts the process: "Terminating: Nested parallel kernel launch
detected") nor from a process forked after the pool started (GNU OpenMP
kills the child: "fork() called from a process already using GNU OpenMP").

Imported only by the compiled-kernel modules (``methods/thesis/_jit.py``,
``methods/_wls.py``) when a method that needs them runs: importing this
module imports numba.
"""

from __future__ import annotations

import contextlib
import os
import threading
import warnings
from typing import Iterator

import numba

__all__ = ["njit", "parallel_turn"]

#: Whether the no-cache warning was given (once per process, not once per kernel).
_warned_no_cache = False


def njit(func=None, /, **options):
    """``numba.njit(cache=True, nogil=True, **options)``; without a writable cache directory, compiled in memory.

    Kernels are compiled on first use and cached on disk (numba falls back to
    a per-user cache directory when the package's own is not writable). They
    release the GIL (``nogil=True``). Usable as ``@njit`` or ``@njit(parallel=True)``.
    """
    def wrap(f):
        global _warned_no_cache
        try:
            return numba.njit(cache=True, nogil=True, **options)(f)
        except RuntimeError:  # numba found no writable cache directory (package and user cache dir)
            if not _warned_no_cache:
                _warned_no_cache = True
                warnings.warn("numba found no writable cache directory: depthrefine's compiled kernels are "
                              "compiled in every new process (seconds); set NUMBA_CACHE_DIR to a writable "
                              "directory.", RuntimeWarning, stacklevel=3)
            return numba.njit(nogil=True, **options)(f)
    return wrap if func is None else wrap(func)


#: Held by the one thread that uses numba's thread pool at a time (:func:`parallel_turn`).
_pool_lock = threading.Lock()
#: True in a process forked from this one: it never uses the pool (:func:`parallel_turn`).
_forked = False


def _after_fork_in_child() -> None:
    global _forked
    _forked = True


if hasattr(os, "register_at_fork"):  # POSIX
    os.register_at_fork(after_in_child=_after_fork_in_child)


@contextlib.contextmanager
def parallel_turn(wanted: bool = True) -> Iterator[bool]:
    """``with parallel_turn() as parallel:``: whether this thread may launch numba's ``parallel=True`` kernels.

    True for one thread at a time (the pool is this thread's until the block
    ends). False when not ``wanted`` (a small image: the pool is left to
    others), without waiting when another thread has the pool, and
    always in a process forked from one that imported this module (the pool's
    threads do not survive a fork): run the serial version of the kernels in
    the calling thread instead. The kernels of depthrefine give the same bits
    either way.
    """
    if not wanted or _forked or not _pool_lock.acquire(blocking=False):
        yield False
        return
    try:
        yield True
    finally:
        _pool_lock.release()
