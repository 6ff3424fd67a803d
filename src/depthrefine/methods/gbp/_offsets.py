"""The per-pixel search of step 1b (a compiled kernel): how far the color edge lies from each depth jump pixel.

Imported only when gbp runs. The kernel is the C one when built
(:mod:`depthrefine._native`), else numba's (:mod:`._offsets_jit`). One pass over the jump band,
no image-sized temporaries; its rows are shared out over threads
(:func:`~depthrefine._threads.run_split`) and the results gathered in row
order, so the offsets are those of a sequential pass, whatever the threads.
"""

from __future__ import annotations

import numpy as np

from ..._native import kernels
from ..._threads import run_split

__all__ = ["jump_offsets"]


def jump_offsets(band: np.ndarray, magnitude: np.ndarray, gx: np.ndarray, gy: np.ndarray, edges: np.ndarray,
                 reach: int, peak_ratio: float) -> tuple[np.ndarray, np.ndarray]:
    """At each pixel of ``band`` on the ridge of the depth gradient, the offset of the strongest color edge along it.

    ``magnitude``, ``gx``, ``gy``: the depth gradient (float32, the grid of
    ``band``); ``edges``: the guide's gradient magnitude. The profile of
    ``edges`` is sampled at ``-reach .. reach`` pixels along the depth
    gradient; its peak counts when it is inside the profile and holds more
    than ``peak_ratio`` times the profile's mean. Returns the offsets (pixels
    of the grid, sub-pixel by a parabola through the peak, positive along
    the gradient) and the gradient's angles (radians), float64.
    """
    per_row = np.count_nonzero(band, axis=1)
    row_start = np.concatenate([[0], np.cumsum(per_row)[:-1]]).astype(np.int64)
    offsets, angles = np.empty(int(per_row.sum())), np.empty(int(per_row.sum()))
    found = np.zeros(band.shape[0], np.int64)
    search = kernels(__package__ + "._offsets_jit").search
    run_split(search, band.shape[0], band, magnitude, gx, gy, edges, int(reach), float(peak_ratio), row_start,
              offsets, angles, found)
    # row by row, in the order of a sequential pass: the same arrays however the rows were shared out
    keep = np.repeat(row_start - np.concatenate([[0], np.cumsum(found)[:-1]]), found) + np.arange(found.sum())
    return offsets[keep], angles[keep]
