"""What a method shows of its steps: named pictures, arrays and record entries.

A method may give its registry entry an ``intermediates`` hook,
``intermediates(depth_lr, rgb_hr, *, params=None, progress=None) ->
(depth_hr, Intermediates)``, whose ``depth_hr`` is bit for bit the method's
output. ``depthrefine refine --save-intermediate DIR`` writes what it returns
(:func:`depthrefine.io.write_intermediates`); a method without the hook
gets the pictures of its result only.

The pictures are described, not drawn (the method needs no plotting): a
``"color"`` image, a ``"labels"`` image drawn with a distinct color per
label, or ``"depth"`` samples drawn over a color image in the result's depth
range and units.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Mapping

if TYPE_CHECKING:
    import numpy as np

__all__ = ["Picture", "Intermediates", "PICTURE_KINDS"]

#: What a :class:`Picture` can show.
PICTURE_KINDS = ("color", "labels", "depth")


@dataclass(frozen=True, eq=False)
class Picture:
    """One picture of an intermediate step.

    Attributes
    ----------
    kind : {"color", "labels", "depth"}
        ``"color"``: ``data`` is an RGB image (any dtype the color input may
        have), written as 8-bit PNG. ``"labels"``: ``data`` is an integer
        label image, drawn with a distinct color per label. ``"depth"``:
        ``data`` is depth in the input's units (NaN = no sample), drawn as
        samples over ``background`` with the result's colorbar.
    data : ndarray
    title : str
        What the picture shows (the title of a ``"depth"`` picture).
    groups : ndarray, optional
        ``"labels"``: an id per pixel of the region its label belongs to, so
        that equal labels of neighbouring regions get different colors.
    background : ndarray, optional
        ``"depth"``: the RGB image under the samples.
    """

    kind: str
    data: np.ndarray
    title: str = ""
    groups: np.ndarray | None = None
    background: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.kind not in PICTURE_KINDS:
            raise ValueError(f"Picture kind must be one of {PICTURE_KINDS}; got {self.kind!r}.")


@dataclass(frozen=True, eq=False)
class Intermediates:
    """A method's intermediate results, by name.

    Attributes
    ----------
    pictures : mapping of str to Picture
        File name (``"cluster_labels.png"``) -> picture.
    arrays : mapping of str to ndarray
        Saved together as ``intermediates.npz`` (none: no file).
    record : mapping of str to value
        JSON-ready entries added to the run's record (``run.json``).

    Examples
    --------
    >>> Intermediates().pictures, Intermediates().arrays
    ({}, {})
    """

    pictures: Mapping[str, Picture] = field(default_factory=dict)
    arrays: Mapping[str, Any] = field(default_factory=dict)
    record: Mapping[str, Any] = field(default_factory=dict)
