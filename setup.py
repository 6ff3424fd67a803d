"""Builds gbp's C kernels (src/depthrefine/_native/kernels.c) beside the package; everything else is in pyproject.toml.

The extension is optional: without a C compiler the install goes on and gbp
runs the same kernels through numba (same bits; its first call in a process
is about half a second slower). The build stamps the source's SHA-256 into the
library, so that an editable install whose kernels.c changed since falls back
to numba instead of running a stale build (reinstall to rebuild).
"""

import hashlib
import platform
import sys
from pathlib import Path

from setuptools import Extension, setup

SOURCE = Path("src/depthrefine/_native/kernels.c")


def compile_args() -> list[str]:
    if sys.platform == "win32":
        return ["/O2", "/fp:precise"]
    # no -ffast-math; no a * b + c fused into one rounding (the kernels must give numba's bits); without traps and
    # errno, which change no value, the loops with selections vectorise (LLVM assumes the same for numba)
    args = ["-O3", "-ffp-contract=off", "-fno-fast-math", "-fno-trapping-math", "-fno-math-errno",
            "-fvisibility=hidden"]
    if sys.platform == "linux" and platform.machine() in ("x86_64", "AMD64"):
        args += ["-mavx2", "-mfma"]     # the loader checks /proc/cpuinfo for both before it uses the library
    return args


setup(ext_modules=[Extension(
    "depthrefine._native._kernels",
    sources=[str(SOURCE)],
    define_macros=[("DEPTHREFINE_KERNELS_SOURCE", '"%s"' % hashlib.sha256(SOURCE.read_bytes()).hexdigest())],
    extra_compile_args=compile_args(),
    libraries=[] if sys.platform == "win32" else ["m"],   # atan2f, sqrtf, fma: not only through Python's own libm
    optional=True,
)])
