"""Heavy modules imported on first use, so that ``import depthrefine`` and the CLI start fast.

``from .._lazy import cv2`` gives a stand-in whose first attribute access
imports OpenCV; every later access goes straight to the module. The same for
``scipy.ndimage`` and ``tifffile``. (matplotlib is imported inside the functions of ``viz``.)
"""

from __future__ import annotations

import importlib
from types import ModuleType

__all__ = ["LazyModule", "cv2", "ndimage", "tifffile"]


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


cv2 = LazyModule("cv2")
ndimage = LazyModule("scipy.ndimage")
tifffile = LazyModule("tifffile")
