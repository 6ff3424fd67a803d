"""The built-in methods' names and the default method, importable without numpy or OpenCV.

The command line shows these in ``--help`` (``--method`` choices, defaults)
without importing the methods, so that ``depthrefine refine --help`` starts
fast (issue 13); :mod:`.registry` registers exactly these, in this order.
"""

from __future__ import annotations

import importlib
import sys
from typing import TYPE_CHECKING, Iterator

if TYPE_CHECKING:
    from .options import MethodOption

__all__ = ["DEFAULT_METHOD", "BUILTIN_METHODS", "PROBED_METHODS", "COMPILED_METHODS", "NATIVE_METHODS",
           "RegisteredMethodNames", "registered_method_options"]

#: The method of :func:`depthrefine.refine` and of the commands when none is named: guided
#: back-projection, the most accurate method on every benchmark protocol (docs/bench.md).
DEFAULT_METHOD = "gbp"

#: Every built-in method, in the order the registry registers them.
BUILTIN_METHODS = ("thesis", "nearest", "bilinear", "bicubic", "jbf", "guided", "fgs", "wmf", "fbs", "gbp", "gbp-fast")

#: Built-in methods registered only where a check at the registry's import says they work: the fast
#: bilateral solver needs an OpenCV built with Eigen (:func:`~depthrefine.methods.peers.fast_bilateral_solver_status`).
PROBED_METHODS = ("fbs",)

#: The light modules holding the built-in methods' command-line options (an ``OPTIONS`` tuple each); the
#: registry gives each method the same tuple (``Method.options``).
BUILTIN_OPTION_MODULES = {"gbp": "depthrefine.methods.gbp._options",
                          "gbp-fast": "depthrefine.methods.gbp._fast_options",
                          "thesis": "depthrefine.methods.thesis._options"}

#: Built-in methods that run compiled kernels: the command line sets numba up in a thread while it reads the
#: images (:func:`depthrefine._numba.warm_up`), unless the method's kernels are all in depthrefine's C library.
COMPILED_METHODS = ("thesis", "gbp", "gbp-fast")

#: Compiled methods whose kernels depthrefine's C library holds when it is built (:mod:`depthrefine._native`). The
#: thesis method's with its medians of 3x3, 5x5 and 7x7 (the default) on uint8 or uint16 color; another median size
#: runs a numba kernel, which numba then sets up on its first call, not in a thread beside the reading.
NATIVE_METHODS = ("thesis", "gbp", "gbp-fast")

#: Built-in methods that convert the guide to CIE L*a*b* with OpenCV, which builds its conversion tables on the
#: first conversion in a process (about 170 ms of one core): the command line has it done in a thread while it
#: reads the images.
LAB_METHODS = ("thesis",)

_REGISTRY = "depthrefine.methods.registry"


class RegisteredMethodNames:
    """The names of the registered methods, for ``--method`` (``choices``) and ``--help``.

    Listing them (``iter``) reads :data:`~depthrefine.methods.registry.METHODS`
    when the registry is imported already, else :data:`BUILTIN_METHODS`
    without :data:`PROBED_METHODS` (the methods that need no check of the
    installed OpenCV), so ``--help`` imports neither numpy nor OpenCV.
    Asking whether a name is one of them (``in``) imports the registry: a
    command is about to run it.

    Examples
    --------
    >>> names = RegisteredMethodNames()
    >>> "gbp" in names, "no-such-method" in names
    (True, False)
    >>> ("fbs" in names) == ("fbs" in list(names))
    True
    """

    def __init__(self, *, ordered: bool = False):
        self.ordered = ordered  # False: sorted by name (as --method lists them); True: registration order

    def __iter__(self) -> Iterator[str]:
        registry = sys.modules.get(_REGISTRY)
        names = list(registry.METHODS) if registry is not None else [
            m for m in BUILTIN_METHODS if m not in PROBED_METHODS]
        return iter(names if self.ordered else sorted(names))

    def __contains__(self, name: object) -> bool:
        from .registry import METHODS

        return name in METHODS


def registered_method_options() -> dict[str, tuple[MethodOption, ...]]:
    """Each method's own command-line options (``Method.options``), for the parsers of the refining commands.

    Reads :data:`~depthrefine.methods.registry.METHODS` when the registry is
    imported already, else the built-in methods' light option modules
    (:data:`BUILTIN_OPTION_MODULES`), so that ``--help`` imports neither numpy nor OpenCV.
    Methods without options are left out.

    Examples
    --------
    >>> [option.flag for option in registered_method_options()["thesis"]]
    ['--patches', '--patch-file', '--clusters']
    """
    registry = sys.modules.get(_REGISTRY)
    if registry is not None:
        return {name: entry.options for name, entry in registry.METHODS.items() if entry.options}
    return {name: importlib.import_module(module).OPTIONS for name, module in BUILTIN_OPTION_MODULES.items()}
