"""Heavy modules imported on first use, so that ``import depthrefine`` and the CLI start fast.

``from .._lazy import cv2`` gives a stand-in whose first attribute access
imports OpenCV; every later access goes straight to the module. The same for
``scipy.ndimage`` and ``tifffile``, and for ``numpy`` in the two modules the
command line reads to build its parser (:mod:`depthrefine.bench.protocols`,
:mod:`depthrefine.viz`). (matplotlib is imported inside the functions of ``viz``.)

:func:`lazy_exports` does the same for a package's public names (PEP 562):
the package's ``__init__`` lists where each name lives, and a module is
imported when one of its names is first read, so that importing one light
module of a package (the names the command line shows) does not import all
of its siblings.
"""

from __future__ import annotations

import importlib
import warnings
from types import ModuleType
from typing import Any, Callable, Iterable, Mapping

__all__ = ["LazyModule", "lazy_exports", "missing_dependency", "cv2", "ndimage", "numpy", "tifffile"]


class LazyModule:
    """Stand-in for the module ``name``, imported when an attribute is first read.

    Examples
    --------
    >>> math = LazyModule("math")
    >>> math.sqrt(4.0)
    2.0
    """

    __slots__ = ("_name", "_module")

    def __init__(self, name: str):
        self._name = name
        self._module: ModuleType | None = None

    def __getattr__(self, attr: str):
        module = self._module
        if module is None:
            module = self._module = importlib.import_module(self._name)
        return getattr(module, attr)

    def __repr__(self) -> str:
        state = "imported" if self._module is not None else "not imported yet"
        return f"<lazy module {self._name!r}, {state}>"


def lazy_exports(package: str, exports: Mapping[str, Iterable[str]], submodules: Iterable[str] = (), *,
                 deprecated: Mapping[str, tuple[str, str, str]] | None = None) -> tuple[
        Callable[[str], Any], Callable[[], list[str]]]:
    """``__getattr__`` and ``__dir__`` for the package ``package`` (PEP 562).

    ``exports`` maps each module, relative to the package, to the public
    names it defines (``{".methods.registry": ("refine", "METHODS")}``), as
    ``from .methods.registry import refine, METHODS`` would; ``submodules`` are
    the package's modules reachable as attributes (``depthrefine.rig.shift``)
    before anything imported them. A name is imported on first use and then
    cached in the package's namespace, so later reads cost nothing.

    ``deprecated`` maps an old name to ``(module, name, replacement)``: reading
    it gives ``module``'s ``name`` (``module`` relative to the package, ``""``
    for the package itself) after a ``DeprecationWarning`` that names
    ``replacement``; it is not cached (every read warns) and not listed by ``dir``.

    Examples
    --------
    ``depthrefine`` itself is such a package:

    >>> import depthrefine
    >>> depthrefine.__getattr__("ThesisParams").__name__, "ThesisParams" in dir(depthrefine)
    ('ThesisParams', True)
    """
    module = importlib.import_module(package)
    names = {name: source for source, defined in exports.items() for name in defined}
    submodules = tuple(submodules)
    old_names = dict(deprecated or {})

    def __getattr__(name: str) -> Any:
        if name in old_names:
            source, new, replacement = old_names[name]
            warnings.warn(f"{package}.{name} is deprecated and goes in the next release; use {replacement}.",
                          DeprecationWarning, stacklevel=2)
            return getattr(importlib.import_module(source, package) if source else module, new)
        if name in names:
            value = getattr(importlib.import_module(names[name], package), name)
        elif name in submodules:
            value = importlib.import_module(f".{name}", package)
        else:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        setattr(module, name, value)
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(module)) | set(names) | set(submodules))

    return __getattr__, __dir__


cv2 = LazyModule("cv2")
ndimage = LazyModule("scipy.ndimage")
numpy = LazyModule("numpy")
tifffile = LazyModule("tifffile")


#: pip's name of a dependency whose import name differs (:func:`missing_dependency`).
_PIP_NAMES = {"cv2": "opencv-contrib-python-headless", "PIL": "pillow", "distributed": "dask[distributed]",
              "dask": "dask[distributed]", "skimage": "scikit-image", "yaml": "pyyaml"}


def missing_dependency(exc: BaseException) -> str | None:
    """pip's name of the third-party package whose import failed, else None (one of our own modules: a bug).

    Examples
    --------
    >>> missing_dependency(ModuleNotFoundError("No module named 'numba'", name="numba"))
    'numba'
    >>> missing_dependency(ModuleNotFoundError("x", name="cv2.ximgproc"))
    'opencv-contrib-python-headless'
    >>> missing_dependency(ModuleNotFoundError("x", name="depthrefine.nothing")) is None
    True
    """
    if not isinstance(exc, ModuleNotFoundError):
        return None
    package = (exc.name or "").partition(".")[0]
    if not package or package == __name__.partition(".")[0]:
        return None
    return _PIP_NAMES.get(package, package)


def missing_dependency_message(package: str, exc: BaseException) -> str:
    """The one-line advice for a missing third-party package (the CLI and batch print it)."""
    detail = " ".join(str(exc).split()) or type(exc).__name__
    return f"this needs the Python package {package}, which is missing or broken ({detail}); install it: pip install {package}"
