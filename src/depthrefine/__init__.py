"""depthrefine: refine a low-resolution ToF depth map with a high-resolution color image.

The main entry point is :func:`refine`::

    import depthrefine
    depth_hr = depthrefine.refine(depth_lr, rgb_hr)                 # guided back-projection ("gbp")
    depth_hr = depthrefine.refine(depth_lr, rgb_hr, method="thesis")  # the thesis method, as specified
    depth_hr = depthrefine.refine(depth_lr, rgb_hr, method="bilinear")
    depth_hr, confidence = depthrefine.refine_with_confidence(depth_lr, rgb_hr)  # 1 = most trusted

Subpackages, one per domain (the README's "Architecture" section draws the flow):

- ``methods``   the registry :func:`refine` looks up, and one module per method family:
                ``baselines``, ``peers`` (OpenCV-contrib filters), ``gbp`` (the default),
                ``thesis`` (chapter 4)
- ``rig``       two cameras to one grid (chapter 3): camera models, calibration,
                undistortion, shift and reprojection alignment, point clouds
- ``bench``     metrics, the simulated ToF sensor, protocols, runner and report
- ``io``        every file format we read and write (the only module that touches files,
                with ``cli``)
- ``cli``       the ``depthrefine`` command, one module per subcommand
- ``batch``     many frames on Dask distributed (one machine or a cluster):
                :func:`batch.refine_many`, and the scheduling of ``depthrefine batch``
- ``viz``       pictures: depth figures with a colorbar (demo, show, report), colorized depth, labels
- ``evaluate``  the public name of the metrics (``bench.metrics``)

Top-level names belong to every method (:func:`refine`, the registry,
:class:`ScaleWarning`) or say their method (:class:`ThesisParams`,
:class:`GbpParams`). The thesis method's own results live with it:
``depthrefine.methods.thesis.refine_with_intermediates`` and ``.Refinement``.
Deprecated for one release (a ``DeprecationWarning`` on use, same objects):
``depthrefine.RefineParams`` (now :class:`ThesisParams`), and
``depthrefine.refine_with_intermediates`` and ``depthrefine.Refinement`` (now
only in ``depthrefine.methods.thesis``).
"""

from ._lazy import lazy_exports

__version__ = "0.1.0"

#: The public names by module, imported on first use (PEP 562), so that
#: ``import depthrefine`` and ``depthrefine --version`` stay fast.
_EXPORTS = {
    ".methods.registry": ("refine", "DEFAULT_METHOD", "METHODS", "Method", "get_method", "register_method"),
    ".methods.thesis.params": ("ThesisParams",),
    ".methods.gbp": ("GbpParams",),
    ".methods.scale": ("ScaleWarning",),
    ".methods.confidence": ("refine_with_confidence",),
}
_SUBPACKAGES = ("methods", "rig", "bench", "io", "cli", "batch", "viz", "evaluate")
#: Old top-level names, each read with a DeprecationWarning until the next release.
_DEPRECATED = {
    "RefineParams": (".methods.thesis.params", "ThesisParams", "depthrefine.ThesisParams (the same class, renamed)"),
    "Refinement": (".methods.thesis.refine", "Refinement",
                   "depthrefine.methods.thesis.Refinement (it belongs to the thesis method)"),
    "refine_with_intermediates": (".methods.thesis.refine", "refine_with_intermediates",
                                  "depthrefine.methods.thesis.refine_with_intermediates (it belongs to the thesis "
                                  "method)"),
}

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, _SUBPACKAGES, deprecated=_DEPRECATED)

__all__ = [
    "refine",
    "refine_with_confidence",
    "ThesisParams",
    "GbpParams",
    "DEFAULT_METHOD",
    "ScaleWarning",
    "METHODS",
    "Method",
    "get_method",
    "register_method",
    "__version__",
]
