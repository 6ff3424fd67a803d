"""Parameters of the thesis refinement, with the thesis values as defaults.

Every number the thesis gives (chapter 4) or the algorithm spec decides
(the design note ``docs/algorithm.md``, steps 4-8) is a field of :class:`ThesisParams`, so a
run is fully described by one frozen, hashable value that can be written next
to its output and read back (:meth:`ThesisParams.to_dict`,
:meth:`ThesisParams.from_dict`).

``RefineParams`` is the old name of :class:`ThesisParams`: it still works for
one release, with a ``DeprecationWarning``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

from ..._lazy import lazy_exports
from ..._validate import check_int, check_number, is_int
from ..params import params_from_mapping, params_to_dict

__all__ = ["ThesisParams", "Rect", "params_from_mapping"]

#: A manual patch: ``(x, y, width, height)`` in color-image pixels
#: (x = column of the top-left corner, y = its row), OpenCV's ``Rect`` order.
Rect = tuple[int, int, int, int]


@dataclass(frozen=True)
class ThesisParams:
    """Parameters of the thesis depth refinement (spec steps 4-8).

    Defaults are the thesis values; the section of the thesis each comes from
    is given in brackets. ``median_size`` and ``patch_layout`` are in color
    pixels, ``expansion`` in depth pixels; depth thresholds are in 8-bit
    "levels" (see ``level_size``).

    Attributes
    ----------
    patches : (int, int)
        Automatic patch grid, ``(across, down)`` [4.2; spec decision 4 x 4].
    patch_layout : tuple of (x, y, width, height), optional
        Manual patch layout in color-image pixels [4.2]. Rectangles are
        snapped to the depth grid (multiples of the scale factor); where two
        overlap the later one wins; together they must cover the image.
        When given, ``patches`` is ignored.
    median_size : int
        Side of the square median filter applied to R, G and B [4.3.1: 7].
    unify_lightness : bool
        Replace L* by the mean L* of its black / color / white class [4.3.2].
    black_bound, white_bound : float
        L* at or below ``black_bound * max_lightness`` is black, at or above
        ``white_bound * max_lightness`` is white [4.3.2, Fig. 32: 20 %, 80 %].
    max_lightness : float
        The "max L*" the bounds refer to [spec decision: 100].
    lightness_weight : float
        Weight of L* in the k-means distance [4.3.2; spec decision: 1].
    n_clusters : int
        k of k-means, per patch [4.3.3: 4].
    kmeans_iterations : int
        Iterations of k-means [4.3.3, left to the user; spec decision: 10].
    correct_depth : bool
        Apply the histogram correction of 4.4.4 (snap rare depths to the
        dominant ones). ``False`` skips it, for analysis; the thesis has it on.
    dominant_fraction : float
        A histogram bin whose count exceeds this fraction of the maximum count
        is dominant too [4.4.4: one half].
    tolerance_levels : float
        A depth within this many levels of a dominant value is kept [4.4.4: 5].
    histogram_bins : int
        Bins of the per-cluster histogram over the valid depth range, for
        input that is not uint8 (uint8 input has one bin per 8-bit level)
        [spec decision: 256].
    level_size : float, optional
        Depth units per level, the unit of ``tolerance_levels``. ``None``
        (default): 1 for uint8 input, otherwise ``(max - min) / 255`` of the
        valid input depths [spec conventions].
    expansion : int
        Depth pixels by which each cluster's samples are dilated before
        interpolation [4.5.2; spec decision: 1].
    """

    patches: tuple[int, int] = (4, 4)
    patch_layout: tuple[Rect, ...] | None = None
    median_size: int = 7
    unify_lightness: bool = True
    black_bound: float = 0.20
    white_bound: float = 0.80
    max_lightness: float = 100.0
    lightness_weight: float = 1.0
    n_clusters: int = 4
    kmeans_iterations: int = 10
    correct_depth: bool = True
    dominant_fraction: float = 0.5
    tolerance_levels: float = 5.0
    histogram_bins: int = 256
    level_size: float | None = None
    expansion: int = 1

    def __post_init__(self) -> None:
        # Normalise sequences (from TOML/JSON lists) to tuples so the value
        # stays hashable, then check every field once, here.
        patches = _int_tuple("patches", self.patches, 2)
        object.__setattr__(self, "patches", patches)
        if min(patches) < 1:
            raise ValueError(f"patches must be two positive counts (across, down); got {patches}.")
        if self.patch_layout is not None:
            layout = tuple(_int_tuple(f"patch_layout[{i}]", r, 4) for i, r in enumerate(self.patch_layout))
            if not layout:
                raise ValueError("patch_layout must hold at least one rectangle (x, y, width, height).")
            for i, (x, y, w, h) in enumerate(layout):
                if w < 1 or h < 1 or x < 0 or y < 0:
                    raise ValueError(
                        f"patch_layout[{i}] = {(x, y, w, h)} is not a rectangle inside the image: "
                        "x and y must be >= 0, width and height >= 1."
                    )
            object.__setattr__(self, "patch_layout", layout)
        check_int("median_size", self.median_size, minimum=1)
        if self.median_size % 2 == 0:
            raise ValueError(f"median_size must be odd (a centred window); got {self.median_size}.")
        check_int("n_clusters", self.n_clusters, minimum=1)
        check_int("kmeans_iterations", self.kmeans_iterations, minimum=0)
        check_int("histogram_bins", self.histogram_bins, minimum=2)
        check_int("expansion", self.expansion, minimum=0)
        for name in ("unify_lightness", "correct_depth"):
            if not isinstance(getattr(self, name), bool):
                raise TypeError(f"{name} must be true or false; got {getattr(self, name)!r}.")
        for name in ("black_bound", "white_bound", "max_lightness", "lightness_weight",
                     "dominant_fraction", "tolerance_levels"):
            check_number(name, getattr(self, name))
        if not 0.0 <= self.black_bound < self.white_bound <= 1.0:
            raise ValueError(
                "black_bound and white_bound must satisfy 0 <= black_bound < white_bound <= 1; "
                f"got {self.black_bound} and {self.white_bound}."
            )
        if self.max_lightness <= 0:
            raise ValueError(f"max_lightness must be > 0; got {self.max_lightness}.")
        if self.lightness_weight < 0:
            raise ValueError(f"lightness_weight must be >= 0; got {self.lightness_weight}.")
        if not 0.0 < self.dominant_fraction <= 1.0:
            raise ValueError(f"dominant_fraction must be in (0, 1]; got {self.dominant_fraction}.")
        if self.tolerance_levels < 0:
            raise ValueError(f"tolerance_levels must be >= 0; got {self.tolerance_levels}.")
        if self.level_size is not None:
            check_number("level_size", self.level_size)
            if self.level_size <= 0:
                raise ValueError(f"level_size must be > 0 depth units (or unset); got {self.level_size}.")

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON/TOML-ready dict (tuples become lists, ``None`` kept): :func:`~depthrefine.methods.params.params_to_dict`."""
        return params_to_dict(self)

    @classmethod
    def from_dict(cls, mapping: Mapping[str, Any], *, source: str = "parameters") -> "ThesisParams":
        """Build from a mapping, rejecting unknown keys with the list of known ones."""
        return params_from_mapping(cls, mapping, source=source)


def _int_tuple(name: str, value: Any, length: int) -> tuple[int, ...]:
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != length:
        raise TypeError(f"{name} must be a list of {length} integers; got {value!r}.")
    if not all(is_int(v) for v in value):
        raise TypeError(f"{name} must hold integers only; got {value!r}.")
    return tuple(int(v) for v in value)


# ``RefineParams``: the old name of ThesisParams, kept for one release (PEP 562).
__getattr__, _ = lazy_exports(__name__, {}, deprecated={
    "RefineParams": ("", "ThesisParams", "depthrefine.ThesisParams (the same class, renamed)")})
