"""numba's ``njit`` with an on-disk cache; the split of a kernel's work over threads is :mod:`depthrefine._threads`.

:func:`njit` falls back to in-memory compilation (one warning per process)
when numba finds no writable cache directory. :func:`run_split`,
:func:`threads` and :func:`set_threads` are :mod:`depthrefine._threads`'s,
re-exported for the kernel modules.

:func:`expf32` is ``exp`` of a float32 as glibc computes it (bit for bit on
x86-64 with FMA), written out so that LLVM vectorises it: numba's
``np.exp`` of a float32 calls libm's ``expf`` once per element.

Imported only by the numba kernel modules (``methods/thesis/_jit.py``,
``methods/_wls_jit.py`` and the other ``*_jit.py``, ``_geodesic.py``) when a
method that needs them runs: importing this module imports numba.
"""

from __future__ import annotations

import os
import warnings

import numba
import numpy as np
from numba import types
from numba.extending import intrinsic

from ._threads import run_split, set_threads, threads  # noqa: F401 - re-exported: the kernels' modules use them

__all__ = ["njit", "run_split", "threads", "set_threads", "expf32", "warm_up", "FirstCompileWarning", "cold_kernels",
           "note_first_compile"]

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


@njit
def _first_kernel(x):
    return x + 1


def warm_up(*, skip_blas_check: bool = False) -> None:
    """Make numba ready to run compiled kernels: its first one in a process costs about a second.

    That second is numba setting up its CPU target (importing its own
    implementations, SciPy's BLAS bindings among them) before it loads the
    first kernel from the cache; later kernels load in milliseconds. The
    command line calls this in a thread while it reads the images.

    ``skip_blas_check=True`` is for a process whose compiled code is all
    depthrefine's (the command line): numba's set-up then skips its check
    for SciPy's BLAS, which imports ``scipy.linalg`` (0.3-0.4 s of the
    second); ``np.dot`` and ``np.linalg`` inside numba-compiled functions are
    then unsupported in this process (no depthrefine kernel uses them).
    Once numba's set-up is done (any kernel ran), it changes nothing.
    """
    import sys

    if skip_blas_check and "numba.np.arraymath" not in sys.modules:
        import numba.np.linalg as linalg

        check = getattr(linalg, "ensure_blas", None)
        if check is not None:   # numba.np.arraymath runs it once, when numba's set-up imports it
            def no_blas() -> None:
                raise ImportError("numba's BLAS check skipped (depthrefine's command line)")

            linalg.ensure_blas = no_blas
            try:
                _first_kernel(1)
            finally:
                linalg.ensure_blas = check
            return
    _first_kernel(1)


# ---- exp of a float32, as glibc 2.28+ computes it (sysdeps/ieee754/flt-32/e_expf.c, from ARM's
# optimized-routines; its FMA build, which x86-64 CPUs with FMA run): x * 32 / ln 2 = k + r, the
# result 2**(k / 32) (a table of 32 doubles) times a cubic in r, in double precision.

#: ``asuint64(2**(i / 32)) - (i << 47)`` for i = 0..31 (glibc's ``__exp2f_data.tab``).
_EXP2_TABLE = np.array([
    0x3ff0000000000000, 0x3fefd9b0d3158574, 0x3fefb5586cf9890f, 0x3fef9301d0125b51,
    0x3fef72b83c7d517b, 0x3fef54873168b9aa, 0x3fef387a6e756238, 0x3fef1e9df51fdee1,
    0x3fef06fe0a31b715, 0x3feef1a7373aa9cb, 0x3feedea64c123422, 0x3feece086061892d,
    0x3feebfdad5362a27, 0x3feeb42b569d4f82, 0x3feeab07dd485429, 0x3feea47eb03a5585,
    0x3feea09e667f3bcd, 0x3fee9f75e8ec5f74, 0x3feea11473eb0187, 0x3feea589994cce13,
    0x3feeace5422aa0db, 0x3feeb737b0cdc5e5, 0x3feec49182a3f090, 0x3feed503b23e255d,
    0x3feee89f995ad3ad, 0x3feeff76f2fb5e47, 0x3fef199bdd85529c, 0x3fef3720dcef9069,
    0x3fef5818dcfba487, 0x3fef7c97337b9b5f, 0x3fefa4afa2a490da, 0x3fefd0765b6e4540,
], dtype=np.uint64)
_INV_LN2_32 = float.fromhex("0x1.71547652b82fep+5")     # 32 / ln 2
_SHIFT = float.fromhex("0x1.8p+52")                     # adding it rounds to an integer
_C0, _C1, _C2 = (float.fromhex(h) for h in ("0x1.c6af84b912394p-20", "0x1.ebfce50fac4f3p-13",
                                             "0x1.62e42ff0c52d6p-6"))
#: Beyond these, glibc's special cases: overflow (inf), underflow (0), and the band where it returns the
#: smallest subnormal instead of computing (its errno path).
_EXP_OVERFLOW = np.float32(float.fromhex("0x1.62e42ep6"))
_EXP_UNDERFLOW = np.float32(float.fromhex("-0x1.9fe368p6"))
_EXP_MAY_UNDERFLOW = np.float32(float.fromhex("-0x1.9d1d9ep6"))
_EXP_TINY = np.float32(np.float32(float.fromhex("0x1.4p-75")) * np.float32(float.fromhex("0x1.4p-75")))


@intrinsic
def _fma(typingctx, a, b, c):
    """``a * b + c`` rounded once (LLVM's ``llvm.fma.f64``), for float64 arguments."""
    def codegen(context, builder, signature, args):
        from llvmlite import ir
        from numba.core import cgutils

        double = ir.DoubleType()
        fma = cgutils.get_or_insert_function(builder.module, ir.FunctionType(double, [double] * 3), "llvm.fma.f64")
        return builder.call(fma, args)
    return types.float64(types.float64, types.float64, types.float64), codegen


@intrinsic
def _double_bits(typingctx, x):
    """The bits of a float64 as a uint64."""
    def codegen(context, builder, signature, args):
        from llvmlite import ir

        return builder.bitcast(args[0], ir.IntType(64))
    return types.uint64(types.float64), codegen


@intrinsic
def _bits_double(typingctx, x):
    """The float64 of a uint64's bits."""
    def codegen(context, builder, signature, args):
        from llvmlite import ir

        return builder.bitcast(args[0], ir.DoubleType())
    return types.float64(types.uint64), codegen


@njit(inline="always")
def expf32(x):
    """``exp(x)`` of a float32 ``x``, a float32 equal to glibc's ``expf`` (its FMA build) for every input.

    Branch-free on the common path, so loops over it vectorise (numba's
    ``np.exp`` calls libm once per element); the special cases (overflow,
    underflow, NaN) are selected after. Checked against numba's ``np.exp``
    (glibc 2.36 on an x86-64 CPU with FMA) on all 2**32 float32 values. On
    any machine the result is the same, while libm's ``expf`` differs between
    libm builds and CPUs.
    """
    xd = np.float64(x)
    shifted = _fma(_INV_LN2_32, xd, _SHIFT)
    k = _double_bits(shifted)
    kd = shifted - _SHIFT
    r = _fma(_INV_LN2_32, xd, -kd)
    scale = _bits_double(_EXP2_TABLE[k & np.uint64(31)] + (k << np.uint64(47)))
    cubic = _fma(_fma(r, _C0, _C1), r * r, _fma(r, _C2, 1.0))
    out = np.float32(cubic * scale)
    if x < _EXP_MAY_UNDERFLOW:
        out = _EXP_TINY
    if x < _EXP_UNDERFLOW:
        out = np.float32(0.0)
    if x > _EXP_OVERFLOW:
        out = np.float32(np.inf)
    if x != x:
        out = x + x
    return out
