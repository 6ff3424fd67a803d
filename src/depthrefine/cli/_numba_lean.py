"""numba imported without the optional packages depthrefine's kernels never use (the command line's process).

Importing numba and setting up its CPU target imports, besides numba
itself, optional packages that no depthrefine kernel uses: ``cffi`` with
its C parser (numba's support for cffi functions; 50-70 ms) and PyYAML (to
read a ``.numba_config.yaml`` in the working directory; 15-55 ms). In a
process whose compiled code is all depthrefine's, :func:`import_numba_lean`
imports numba with those two absent; numba's BLAS check, which imports
SciPy's linear algebra, is skipped by
``depthrefine._numba.warm_up(skip_blas_check=True)``.
``python benchmarks/bench_startup.py --first-call`` measures what it saves.

This module imports nothing heavy: the ``refine`` command calls it, in its
own process only, before numba is imported.
"""

from __future__ import annotations

import contextlib
import os
import sys
from typing import Iterator

__all__ = ["import_numba_lean"]

#: The numba configuration file numba reads from the working directory (with PyYAML).
NUMBA_CONFIG_FILE = ".numba_config.yaml"


@contextlib.contextmanager
def _absent(names: list[str]) -> Iterator[None]:
    """Within the block, importing any of ``names`` not imported yet raises ImportError; afterwards it works again."""
    blocked = [name for name in names if name not in sys.modules]
    for name in blocked:
        sys.modules[name] = None  # type: ignore[assignment]  # the import system's "known to be absent"
    try:
        yield
    finally:
        for name in blocked:
            if name in sys.modules and sys.modules[name] is None:
                del sys.modules[name]


def import_numba_lean() -> None:
    """Import numba (and the module that would import cffi) without cffi, and without PyYAML unless it is needed.

    For a process that runs only depthrefine's compiled kernels: numba's
    cffi support is off in it. PyYAML stays importable for numba when a
    ``.numba_config.yaml`` lies in the working directory (numba reads it on
    import). A no-op once numba is imported. Afterwards both packages import
    as usual for any other code.
    """
    if "numba" in sys.modules:
        return
    names = ["cffi"] if os.path.exists(NUMBA_CONFIG_FILE) else ["cffi", "yaml"]
    with _absent(names):
        import numba  # noqa: F401
        import numba.core.typing.cffi_utils  # noqa: F401  # numba's set-up imports it: with cffi absent here
