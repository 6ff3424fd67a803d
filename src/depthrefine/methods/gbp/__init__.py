"""Guided back-projection (``gbp``): the default method.

It upsamples a low-resolution depth map ``y`` (``h x w``) to the grid of a
registered color image (``H x W``, any factor) in five steps (a sixth on request), one module each:

1. ``measure``  measure the input once: its noise (in 8-bit levels of its own
   depth range, so one set of defaults serves levels and millimetres),
   whether its pixels are footprint means or point samples, where it shows a
   depth jump, and the guide's own noise (:class:`InputMeasures`);
   ``fattening`` (1b) where the input's jumps sit consistently beyond the color
   edges on every side (a direct-ToF camera's near surface spilling over the
   far one), thin the spilling side by as much; on a reprojected input, move
   the whole map back by the shift its jumps show against the color edges;
2. ``solve``    start from the bicubic enlargement, clipped at the input's jumps;
3. ``solve``    back-project: rounds of "add the enlarged residual ``y - D(x)``,
   smooth with a weighted least-squares solve whose weights fall with the
   color difference and the estimate's own gradient", each held within the
   input's local range;
4. ``solve``    where the input shows no depth edge above its noise, blend in a
   stronger color-guided smoother (noise averaged over color segments);
5. ``trust``    check the guide against the input one octave down and fall back
   to clipped bicubic interpolation where its detail is not confirmed, so a
   guide whose texture is not depth does no harm;
6. ``edges``    (``snap_edges``, off by default) move each large depth jump, within
   two depth pixels, onto the strongest color edge between its surfaces: for
   real sensors whose edges sit off the color edges.

``confidence`` makes its confidence map from these internals
(:func:`upsample_gbp_with_confidence`). ``upsample`` runs the steps in this order (:func:`upsample_gbp`) and holds the
warm start for video (:func:`upsample_gbp_stateful`); ``params`` holds the
knobs (:class:`GbpParams`). Invalid input pixels are filled from the nearest
valid pixel before any interpolation and never pull the result; the output
stays within the input's valid range and is deterministic. How each default
was chosen: ``docs/tuning.md``. The names below are imported on first use, so
that the command line can read gbp's options (``_options``) without numpy.

References
----------
M. Irani, S. Peleg, "Improving resolution by image registration", CVGIP 1991
(back-projection). D. Min, S. Choi, J. Lu, B. Ham, K. Sohn, M. N. Do, "Fast
global image smoothing based on weighted least squares", TIP 2014.
D. L. Donoho, I. M. Johnstone, "Ideal spatial adaptation by wavelet
shrinkage", Biometrika 1994 (noise from the finest wavelet band).
"""

from ..._lazy import lazy_exports

_EXPORTS = {
    ".measure": ("InputMeasures", "block_mean_valid", "estimate_guide_noise", "estimate_noise", "footprint_share"),
    ".params": ("GbpParams",),
    ".trust": ("guide_trust",),
    ".upsample": ("upsample_gbp", "upsample_gbp_stateful"),
    ".confidence": ("upsample_gbp_with_confidence",),
}
__all__ = [name for names in _EXPORTS.values() for name in names]

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, ("measure", "fattening", "solve", "trust", "edges",
                                                         "upsample", "confidence", "params", "fast"))
