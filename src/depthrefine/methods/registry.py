"""The registry of upsampling methods, and :func:`refine`, which looks them up by name.

Every method has one signature::

    func(depth_lr, rgb_hr, *, params=None, progress=None) -> depth_hr

``params`` is an instance of the method's own frozen parameter dataclass
(``None`` for its defaults; methods without parameters take only ``None``).
The CLI and the benchmark read this registry, so adding a method is one call
to :func:`register_method`. The entry also declares what the layers around a
method need to know of it: its command-line options (:mod:`.options`), an
optional warm start for sequences, an optional hook that shows its steps
(:mod:`.intermediates`), and whether it needs an integer scale factor.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from . import baselines, gbp, peers
from .gbp.fast import GbpFastParams, upsample_gbp_fast
from .._validate import check_pixels
from ._names import DEFAULT_METHOD
from .intermediates import Intermediates
from .options import MethodOption
from .scale import plan_scale
from .gbp._fast_options import OPTIONS as GBP_FAST_OPTIONS
from .gbp._options import OPTIONS as GBP_OPTIONS
from .thesis._options import OPTIONS as THESIS_OPTIONS
from .thesis.intermediates import thesis_intermediates
from .thesis.params import ThesisParams
from .thesis.refine import refine_thesis, refine_thesis_stateful

__all__ = ["Method", "METHODS", "DEFAULT_METHOD", "register_method", "get_method", "refine", "refine_intermediates"]


@dataclass(frozen=True)
class Method:
    """A registered method.

    Attributes
    ----------
    name : str
        The name users pass (``method="thesis"``, ``--method thesis``).
    func : callable
        ``func(depth_lr, rgb_hr, *, params=None, progress=None) -> (H, W) float32``.
    params_type : type or None
        Frozen dataclass of its parameters, or ``None`` if it has none.
    summary : str
        One line for ``--help`` and reports.
    guided : bool
        Whether it uses the color image (False for plain interpolation).
    deterministic : bool
        Whether the same input and parameters always give a bit-identical
        output (the project's rule; False only for a peer whose library
        breaks it, and then said in its summary).
    interpolating : bool
        Whether every output value lies within the range of the valid input
        depths (a convex combination of them, or clipped to their range).
    refine_stateful : callable or None
        Optional warm start for sequences: ``refine_stateful(depth_lr,
        rgb_hr, *, params, state) -> (depth_hr, state)``; ``state=None`` for
        the first frame (then the result must equal ``func``'s), the returned
        state goes with the next frame. ``depthrefine batch --temporal`` and
        :func:`depthrefine.batch.refine_many` (``temporal=True``) use it when
        present; methods without it run frame by frame.
    options : tuple of MethodOption
        The method's own command-line options, each setting one field of
        ``params_type`` (the thesis's ``--patches``, ``--patch-file``,
        ``--clusters``); every refining command adds them under "NAME method
        options". Light: the parsers are built without importing the method.
    intermediates : callable or None
        Optional: ``intermediates(depth_lr, rgb_hr, *, params, progress) ->
        (depth_hr, Intermediates)``, ``depth_hr`` bit for bit ``func``'s;
        ``refine --save-intermediate`` writes what it returns
        (:func:`refine_intermediates`).
    scale_step : bool
        Whether the method works at an integer factor: at a non-integer
        color/depth ratio it resizes the color image first (the scale step of
        :mod:`.scale`) and warns with :class:`~.scale.ScaleWarning`. The others
        resize straight to the color grid.
    confidence : callable or None
        Optional confidence map from the method's own internals:
        ``confidence(depth_lr, rgb_hr, *, params=None, progress=None) ->
        (depth_hr, confidence)``, the depth bit-identical to ``func``'s and
        the confidence float32 in [0, 1] on the same grid (1 = most trusted,
        0 where there is no depth). Methods without it get the generic map of
        :func:`depthrefine.methods.confidence.generic_confidence` (from the
        input's support and the output's local disagreement);
        :func:`depthrefine.refine_with_confidence` picks one or the other.
    """

    name: str
    func: Callable[..., np.ndarray]
    params_type: type | None
    summary: str
    guided: bool = True
    deterministic: bool = True
    interpolating: bool = False
    refine_stateful: Callable[..., tuple[np.ndarray, Any]] | None = None
    options: tuple[MethodOption, ...] = ()
    intermediates: Callable[..., tuple[np.ndarray, Intermediates]] | None = None
    scale_step: bool = False
    confidence: Callable[..., tuple[np.ndarray, np.ndarray]] | None = None

    def default_params(self) -> Any:
        """The method's default parameters (``None`` if it has none)."""
        return None if self.params_type is None else self.params_type()

    def has_param(self, name: str) -> bool:
        """Whether the method's parameters have a field ``name`` (``"reprojected"``, ``"sampling"``)."""
        return name in _param_names(self.params_type)


def _param_names(params_type: type | None) -> set[str]:
    """The field names of a method's parameter dataclass (none without one)."""
    return set() if params_type is None else {f.name for f in dataclasses.fields(params_type)}


METHODS: dict[str, Method] = {}


def register_method(
    name: str,
    func: Callable[..., np.ndarray],
    *,
    params_type: type | None = None,
    summary: str = "",
    guided: bool = True,
    deterministic: bool = True,
    interpolating: bool = False,
    replace: bool = False,
    refine_stateful: Callable[..., tuple[np.ndarray, Any]] | None = None,
    options: tuple[MethodOption, ...] = (),
    intermediates: Callable[..., tuple[np.ndarray, Intermediates]] | None = None,
    scale_step: bool = False,
    confidence: Callable[..., tuple[np.ndarray, np.ndarray]] | None = None,
) -> Method:
    """Add a method to :data:`METHODS` and return its entry (the keywords are :class:`Method`'s attributes).

    Raises ``ValueError`` if ``name`` is taken (unless ``replace=True``), or
    if ``options`` are given without a ``params_type`` having their fields.
    """
    if not isinstance(name, str) or not name or not name.replace("-", "_").replace("_", "a").isalnum():
        raise ValueError(f"method name must be a non-empty word (letters, digits, '-', '_'); got {name!r}.")
    if name in METHODS and not replace:
        raise ValueError(f"a method named {name!r} is already registered; pass replace=True to replace it.")
    options = tuple(options)
    if options:
        fields = _param_names(params_type)
        stray = [option.flag for option in options if not isinstance(option, MethodOption) or option.param not in fields]
        if stray:
            raise ValueError(f"method {name!r}: the options {stray} must be MethodOption instances setting fields of "
                             f"its params_type ({params_type.__name__ if params_type else None}).")
    entry = Method(name=name, func=func, params_type=params_type, summary=summary, guided=guided,
                   deterministic=deterministic, interpolating=interpolating,
                   refine_stateful=refine_stateful, options=options, intermediates=intermediates,
                   scale_step=scale_step, confidence=confidence)
    METHODS[name] = entry
    return entry


def get_method(name: str) -> Method:
    """The registered method called ``name``.

    Raises
    ------
    ValueError
        For an unknown name, listing the known ones.
    """
    try:
        return METHODS[name]
    except (KeyError, TypeError):
        raise ValueError(f"unknown method {name!r}; choose one of {sorted(METHODS)}.") from None


def refine(
    depth_lr: np.ndarray,
    rgb_hr: np.ndarray,
    *,
    method: str = DEFAULT_METHOD,
    params: Any = None,
    progress: Callable[[int, int], None] | None = None,
    max_pixels: int | None = None,
) -> np.ndarray:
    """Upsample ``depth_lr`` to the resolution of ``rgb_hr`` with a registered method.

    Parameters
    ----------
    depth_lr : (h, w) ndarray
        Low-resolution depth in any units (uint8, uint16 or float); 0, NaN,
        inf and negative values mean "no measurement".
    rgb_hr : (H, W, 3) ndarray
        Registered high-resolution color image, RGB order (uint8, uint16, or
        float in [0, 1]).
    method : str
        A key of :data:`METHODS`: ``"gbp"`` (default, guided
        back-projection), ``"thesis"`` (the thesis method, exactly as
        specified), ``"nearest"``, ``"bilinear"``, ``"bicubic"``, the peers
        ``"jbf"``, ``"guided"``, ``"fgs"``, ``"wmf"``, and any later registration.
    params : dataclass, optional
        The method's parameters (:class:`~depthrefine.methods.gbp.GbpParams`
        for ``"gbp"``, :class:`~depthrefine.methods.thesis.params.ThesisParams`
        for ``"thesis"``); ``None`` for its defaults.
    progress : callable, optional
        ``progress(done, total)``, for long runs.
    max_pixels : int, optional
        Refuse a color image of more pixels, before any work. Whatever the
        limit, an image whose estimated peak memory exceeds the machine's
        available memory is refused (``docs/robustness.md``).

    Returns
    -------
    depth_hr : (H, W) float32 ndarray
        Depth on the color image's grid, in the units of ``depth_lr``.

    Raises
    ------
    ValueError, TypeError
        Unknown method, parameters of the wrong type, bad arrays, or an
        image over ``max_pixels`` or the available memory.

    Examples
    --------
    >>> import numpy as np, depthrefine
    >>> depth_lr = np.full((36, 44), 120, np.uint8)
    >>> rgb_hr = np.zeros((144, 176, 3), np.uint8)
    >>> depthrefine.refine(depth_lr, rgb_hr).shape
    (144, 176)
    """
    entry = get_method(method)
    check_call(entry, depth_lr, rgb_hr, params, max_pixels)
    return entry.func(depth_lr, rgb_hr, params=params, progress=progress)


def refine_intermediates(
    depth_lr: np.ndarray,
    rgb_hr: np.ndarray,
    *,
    method: str = DEFAULT_METHOD,
    params: Any = None,
    progress: Callable[[int, int], None] | None = None,
    max_pixels: int | None = None,
) -> tuple[np.ndarray, Intermediates | None]:
    """:func:`refine`, and the method's intermediates when its entry has the hook (else ``None``).

    The depth is :func:`refine`'s, bit for bit; the intermediates are what the
    method's ``intermediates`` hook shows of its steps
    (:class:`~.intermediates.Intermediates`).

    Examples
    --------
    >>> depth_lr = np.full((4, 4), 30, np.uint8)
    >>> rgb_hr = np.zeros((8, 8, 3), np.uint8)
    >>> depth_hr, steps = refine_intermediates(depth_lr, rgb_hr, method="bilinear")
    >>> depth_hr.shape, steps is None
    ((8, 8), True)
    """
    entry = get_method(method)
    check_call(entry, depth_lr, rgb_hr, params, max_pixels)
    if entry.intermediates is None:
        return entry.func(depth_lr, rgb_hr, params=params, progress=progress), None
    return entry.intermediates(depth_lr, rgb_hr, params=params, progress=progress)


def check_call(entry: Method, depth_lr: Any, rgb_hr: Any, params: Any, max_pixels: int | None = None) -> None:
    """The checks :func:`refine` makes before it calls ``entry``'s function (size, shapes, parameter type)."""
    method = entry.name
    if isinstance(rgb_hr, np.ndarray) and rgb_hr.ndim >= 2:
        check_pixels(rgb_hr.shape, max_pixels=max_pixels, name="rgb_hr")
        if isinstance(depth_lr, np.ndarray) and depth_lr.ndim == 2 and min(depth_lr.shape) > 0 < min(rgb_hr.shape[:2]):
            plan_scale(depth_lr.shape, rgb_hr.shape)  # every method: refuse shapes that do not belong together
    if params is not None:
        if entry.params_type is None:
            raise TypeError(f"method {method!r} takes no parameters; pass params=None.")
        if not isinstance(params, entry.params_type):
            owner = [m.name for m in METHODS.values() if m.params_type is not None and isinstance(params, m.params_type)]
            hint = f" {type(params).__name__} are the parameters of method={owner[0]!r}; pass it." if owner else ""
            raise TypeError(
                f"method {method!r} takes params of type {entry.params_type.__name__}; "
                f"got {type(params).__name__}.{hint}"
            )


register_method("thesis", refine_thesis, params_type=ThesisParams, refine_stateful=refine_thesis_stateful,
                options=THESIS_OPTIONS, intermediates=thesis_intermediates, scale_step=True,
                summary="the thesis method: per-patch color k-means, histogram correction, "
                        "per-cluster interpolation (Chen 2014, ch. 4)", interpolating=True)
register_method("nearest", baselines.upsample_nearest, summary="nearest-neighbour enlargement", guided=False,
                interpolating=True)
register_method("bilinear", baselines.upsample_bilinear, summary="bilinear enlargement", guided=False,
                interpolating=True)
register_method("bicubic", baselines.upsample_bicubic, summary="bicubic enlargement", guided=False,
                interpolating=True)
register_method("jbf", peers.upsample_jbf, params_type=peers.JointBilateralParams,
                summary="bilinear, then OpenCV joint bilateral filter guided by the color (Kopf 2007)")
register_method("guided", peers.upsample_guided, params_type=peers.GuidedParams,
                summary="bilinear, then OpenCV guided filter (He 2013)")
register_method("fgs", peers.upsample_fgs, params_type=peers.FastGlobalSmootherParams,
                summary="bilinear, then OpenCV fast global smoother (weighted least squares, Min 2014)")
register_method("wmf", peers.upsample_wmf, params_type=peers.WeightedMedianParams,
                summary="bilinear, then OpenCV weighted median filter (Zhang 2014); not bit-identical from run "
                        "to run (OpenCV 5.0.0's filter)", deterministic=False)
# Only builds of OpenCV with Eigen have a working solver (listed in _names.PROBED_METHODS).
if peers.fast_bilateral_solver_available():
    register_method("fbs", peers.upsample_fbs, params_type=peers.FastBilateralSolverParams,
                    summary="bilinear, then OpenCV fast bilateral solver (Barron 2016)")
register_method("gbp", gbp.upsample_gbp, params_type=gbp.GbpParams, interpolating=True, options=GBP_OPTIONS,
                refine_stateful=gbp.upsample_gbp_stateful, confidence=gbp.upsample_gbp_with_confidence,
                summary="guided back-projection (the default): back-projection with a color-guided smoother, "
                        "noise-adaptive, falling back to bicubic where the guide disagrees with the depth")
register_method("gbp-fast", upsample_gbp_fast, params_type=GbpFastParams, interpolating=True, options=GBP_FAST_OPTIONS,
                summary="gbp for video rates: back-projection on a reduced grid, one edge-aware solve at full "
                        "resolution, the same fallback where the guide disagrees with the depth")
