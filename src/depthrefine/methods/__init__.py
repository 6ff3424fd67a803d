"""Upsampling methods and the registry that :func:`depthrefine.refine` looks up.

- ``registry``   :data:`METHODS`, :func:`register_method`, :func:`get_method`, :func:`refine`
- ``baselines``  nearest, bilinear, bicubic enlargement
- ``peers``      OpenCV-contrib guided filters as methods: jbf, guided, fgs, wmf (fbs where it works)
- ``confidence`` :func:`refine_with_confidence`: a confidence map for every method (gbp's own, else generic)
- ``scale``      the thesis's scale step for non-integer ratios (applied by every method's caller)
- ``thesis``     the thesis method (chapter 4): parameters, color segmentation, the refinement

A new method is a module here with a function
``func(depth_lr, rgb_hr, *, params=None, progress=None) -> depth_hr`` and one
:func:`register_method` call in ``registry``. The names below are imported on
first use, so the command line can read the method names (``_names``) without
importing the methods.
"""

from .._lazy import lazy_exports

__all__ = ["METHODS", "Method", "get_method", "refine", "register_method", "refine_with_confidence"]

__getattr__, __dir__ = lazy_exports(__name__, {".registry": __all__[:5], ".confidence": __all__[5:]},
                                    ("registry", "baselines", "peers", "gbp", "scale", "thesis", "confidence"))
