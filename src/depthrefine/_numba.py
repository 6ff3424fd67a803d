"""numba's ``njit`` with an on-disk cache, and a split of a kernel's work over threads.

:func:`njit` falls back to in-memory compilation (one warning per process)
when numba finds no writable cache directory. :func:`run_split` runs a
compiled kernel over contiguous parts of its rows or columns in plain
Python threads (the kernels release the GIL) rather than numba's
``parallel=True`` pool: numba's pool is not safe to enter from two Python
threads at once (its ``workqueue`` layer aborts the process: "Terminating:
Nested parallel kernel launch detected") nor from a process forked after
the pool started (GNU OpenMP kills the child: "fork() called from a process
already using GNU OpenMP"), and OpenMP's spinning threads slowed ``gbp``
two-fold on a loaded machine.

Imported only by the compiled-kernel modules (``methods/thesis/_jit.py``,
``methods/_wls.py``) when a method that needs them runs: importing this
module imports numba.
"""

from __future__ import annotations

import os
import threading
import warnings
from concurrent.futures import ThreadPoolExecutor
from typing import Callable

import numba

__all__ = ["njit", "run_split", "threads", "FirstCompileWarning", "cold_kernels", "note_first_compile"]

#: Whether the no-cache warning was given (once per process, not once per kernel).
_warned_no_cache = False
#: The kernels made by :func:`njit`, by the module that defines them.
_KERNELS: dict[str, list] = {}


class FirstCompileWarning(UserWarning):
    """The compiled kernels are not in numba's on-disk cache yet: this run compiles them once.

    The command line shows it as ``depthrefine: note: compiling ... once, about N s``.
    """


def njit(func=None, /, **options):
    """``numba.njit(cache=True, nogil=True, **options)``; without a writable cache directory, compiled in memory.

    Kernels are compiled on first use and cached on disk (numba falls back to
    a per-user cache directory when the package's own is not writable). They
    release the GIL (``nogil=True``). Usable as ``@njit`` or ``@njit(parallel=True)``.
    """
    def wrap(f):
        global _warned_no_cache
        try:
            kernel = numba.njit(cache=True, nogil=True, **options)(f)
            _KERNELS.setdefault(f.__module__, []).append(kernel)
            return kernel
        except RuntimeError:  # numba found no writable cache directory (package and user cache dir)
            if not _warned_no_cache:
                _warned_no_cache = True
                warnings.warn("numba found no writable cache directory: depthrefine's compiled kernels are "
                              "compiled in every new process (seconds); set NUMBA_CACHE_DIR to a writable "
                              "directory.", RuntimeWarning, stacklevel=3)
            return numba.njit(nogil=True, **options)(f)
    return wrap if func is None else wrap(func)


def _cached(kernel) -> bool:
    """Whether numba's on-disk cache holds a current entry for ``kernel`` (its index file, same source stamp).

    Reads one small index file; numba's private cache objects are used when
    present, else only the index file's existence counts.
    """
    cache_file = getattr(getattr(kernel, "_cache", None), "_cache_file", None)
    if cache_file is None:
        return False  # compiled in memory: every process compiles
    try:
        return bool(cache_file._load_index())
    except Exception:  # noqa: BLE001 - another numba version: fall back to the file's existence
        return os.path.exists(getattr(cache_file, "_index_path", ""))


def cold_kernels(module: str) -> list[str]:
    """Names of the kernels of ``module`` (made by :func:`njit`) that numba has not cached on disk yet."""
    return [k.__name__ for k in _KERNELS.get(module, ()) if not _cached(k)]


def note_first_compile(module: str, *, what: str, seconds: float) -> None:
    """Warn (:class:`FirstCompileWarning`) when none of ``module``'s kernels is in numba's disk cache yet.

    Called once, where the kernel module is imported (the first use of the
    method in a process). A module none of whose kernels is cached has never
    run here (or its source changed): its first call compiles for about
    ``seconds`` (``benchmarks/first_call.py``), later runs load the kernels
    from the cache. Kernels that only some inputs need compile on their first
    use without a note.
    """
    kernels = _KERNELS.get(module, ())
    if kernels and len(cold_kernels(module)) == len(kernels):
        warnings.warn(f"compiling {what} once, about {seconds:g} s (numba; cached on disk for the next runs)",
                      FirstCompileWarning, stacklevel=3)


#: The worker threads of :func:`run_split`, per process (a forked child starts its own).
_pool: ThreadPoolExecutor | None = None
_pool_pid: int | None = None
_pool_lock = threading.Lock()


def threads() -> int:
    """How many threads :func:`run_split` uses: ``NUMBA_NUM_THREADS`` (default: the number of CPUs)."""
    return max(1, int(numba.config.NUMBA_NUM_THREADS))


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
