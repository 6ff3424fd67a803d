"""The thesis method (Chen 2014, chapter 4), faithful to the project's design note ``docs/algorithm.md``.

- ``params``    :class:`ThesisParams`, the thesis's parameters and their defaults
- ``segment``   color clustering: 7x7 median, L*a*b* with unified L*, k-means (4.3)
- ``refine``    per patch: sparse depth, histogram correction, per-cluster interpolation (4.4-4.5);
                :func:`refine_with_intermediates` keeps every step's result (:class:`Refinement`)
- ``intermediates``  the registry's hook for ``refine --save-intermediate``: the steps as pictures

The names below are imported on first use, so that the command line can read
the thesis's options (``_options``) without importing numpy. ``RefineParams``
is the old name of :class:`ThesisParams` (deprecated, for one release).
"""

from ..._lazy import lazy_exports

_EXPORTS = {
    ".params": ("ThesisParams",),
    ".refine": ("Refinement", "ScaleWarning", "refine_thesis", "refine_with_intermediates"),
}
__all__ = [name for names in _EXPORTS.values() for name in names]

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, ("params", "segment", "refine", "median", "intermediates"),
                                    deprecated={"RefineParams": (".params", "ThesisParams",
                                                                 "depthrefine.ThesisParams (the same class, renamed)")})
