"""numba's ``njit`` with an on-disk cache, falling back to in-memory compilation (one warning per process).

Imported only by the compiled-kernel modules (``methods/thesis/_jit.py``,
``methods/_wls.py``) when a method that needs them runs: importing this
module imports numba.
"""

from __future__ import annotations

import warnings

import numba

__all__ = ["njit"]

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
