"""Hole filling shared by the methods and the rig: nearest valid pixel.

It sits below both, so that neither imports the other for it.
"""

from __future__ import annotations

import numpy as np

__all__ = ["fill_invalid_nearest", "enclosed_holes", "fill_smooth"]


def fill_invalid_nearest(depth: np.ndarray) -> np.ndarray:
    """Replace NaN pixels by the value of the nearest valid pixel (new array).

    Examples
    --------
    >>> fill_invalid_nearest(np.array([[1, np.nan, np.nan, 4]], np.float32)).tolist()
    [[1.0, 1.0, 4.0, 4.0]]
    """
    valid = np.isfinite(depth)
    if valid.all():
        return depth.copy()
    from scipy import ndimage   # only for holes: importing it costs about half a second

    ir, ic = ndimage.distance_transform_edt(~valid, return_distances=False, return_indices=True)  # no float64 map
    return depth[ir, ic]


#: An unmeasured pixel is inside a surface when a measured pixel lies within this share of the image's larger side
#: in each of the four directions (left, right, up, down) ...
ENCLOSED_REACH = 0.1
#: ... and those four depths span at most this share of their median (one surface: a mug's curvature across an
#: ink drawing spans 1-2 %, the two sides of a depth jump tens of %).
ENCLOSED_SPREAD = 0.05
#: A sliver of unmeasured pixels between enclosed ones is enclosed too when every pixel of it has enclosed or
#: measured pixels within this many pixels each way, spanning at most ``ENCLOSED_SPREAD`` there.
SLIVER_REACH = 3
#: An enclosed pixel with unmeasured, not enclosed pixels within this many pixels on two opposite sides lies on a
#: thin line the rays found through a hole that is not one surface's (the wall seen through a mug's handle): out.
LINE_REACH = 2


def enclosed_holes(depth: np.ndarray) -> np.ndarray:
    """The unmeasured pixels that lie inside one measured surface: where that surface goes on.

    An invalid pixel (NaN) counts when, looking left, right, up and down, a
    measured pixel lies within 10 % of the image's larger side each way, and
    those four depths span at most 5 % of their median: the same surface
    surrounds it. A dark drawing on a mug, a dropout on a dark or shiny spot,
    a thin sliver: enclosed. The outside of the Azure Kinect's NFOV hexagon
    (nothing beyond it), a shadow beside a depth jump (near on one side, far
    on the other), a large unmeasured region: not. Inside a hole that one
    surface frames but that is not that surface's (the wall seen through a
    mug's handle), the rays of a few rows and columns meet only the frame:
    such lines, at most ``2 * LINE_REACH - 1`` pixels thick between
    unmeasured pixels that are not enclosed, are not enclosed either
    (:func:`_without_lines`, last). A thin group of unmeasured
    pixels between enclosed ones that the four rays miss (a ray that meets a
    measured speck inside a wide hole, or reaches just beyond 10 %) is
    enclosed with them when the pixels around it are one surface
    (:func:`_slivers`).

    Examples
    --------
    >>> d = np.full((30, 30), 100.0); d[3:5, 3:5] = np.nan; d[0, 0] = np.nan
    >>> int(enclosed_holes(d).sum()), bool(enclosed_holes(d)[0, 0])
    (4, False)
    """
    invalid = ~np.isfinite(depth)
    if not invalid.any():
        return invalid
    reach = ENCLOSED_REACH * max(depth.shape)
    rows = np.asarray(depth)
    values = _rays(rows, reach)                              # the depth seen each way, NaN beyond reach
    complete = np.isfinite(values).all(axis=0)
    with np.errstate(invalid="ignore"):
        low, high, middle = _range_and_median(values)        # in the memory of values but one map
        del values
        spread = np.subtract(high, low, out=high)
        one_surface = spread <= np.multiply(np.abs(middle, out=low), ENCLOSED_SPREAD, out=low)
        del low, high, spread
    enclosed = invalid & complete & one_surface
    del complete, one_surface
    surface = np.where(enclosed, middle, depth)
    del middle      # (the rays' memory goes: the peak of a large input's step 1, docs/speed.md)
    return _without_lines(invalid, enclosed | _slivers(depth, enclosed, surface))


def _range_and_median(values: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The minimum, maximum and median of four (4, h, w) maps, per pixel, where all four are finite.

    The median of four is the mean of the two middle ones, the larger of the
    pairs' minima and the smaller of their maxima: ``np.median``'s bits (it
    adds the two middle values and halves the sum in their type) without its
    sort of every pixel's four values. Where one is NaN the figures are
    undefined. ``values`` is overwritten: the maximum and the median are
    views of it, the minimum is the one new map.
    """
    v0, v1, v2, v3 = values
    low = np.minimum(v0, v1)
    np.maximum(v0, v1, out=v1)              # v1: the first pair's maximum
    np.minimum(v2, v3, out=v0)              # v0: the second pair's minimum
    np.maximum(v2, v3, out=v3)              # v3: its maximum
    middle = np.maximum(low, v0, out=v2)    # the larger minimum ...
    np.minimum(low, v0, out=low)
    middle += np.minimum(v1, v3, out=v0)    # ... plus the smaller maximum
    middle /= 2
    return low, np.maximum(v1, v3, out=v1), middle


def _without_lines(invalid: np.ndarray, enclosed: np.ndarray) -> np.ndarray:
    """``enclosed`` without its thin lines through holes that are not enclosed (new array).

    An enclosed pixel goes when unmeasured, not enclosed pixels lie within
    :data:`LINE_REACH` pixels both above and below it, or both left and
    right of it; repeated until none goes, so a line up to
    ``2 * LINE_REACH - 1`` pixels thick goes whole. The rim of an enclosed
    hole has such pixels on one side only and stays.
    """
    rows, cols = invalid.shape
    reach = LINE_REACH

    def within(rest: np.ndarray, dr: int, dc: int) -> np.ndarray:
        # whether ``rest`` (padded by ``reach``) holds a pixel 1 to ``reach`` steps of (dr, dc) away
        seen = np.zeros((rows, cols), bool)
        for k in range(1, reach + 1):
            seen |= rest[reach + dr * k:reach + dr * k + rows, reach + dc * k:reach + dc * k + cols]
        return seen

    while True:
        rest = np.pad(invalid & ~enclosed, reach)
        line = enclosed & ((within(rest, -1, 0) & within(rest, 1, 0)) | (within(rest, 0, -1) & within(rest, 0, 1)))
        if not line.any():
            return enclosed
        enclosed = enclosed & ~line


def _slivers(depth: np.ndarray, enclosed: np.ndarray, surface: np.ndarray) -> np.ndarray:
    """The other unmeasured pixels that lie in thin slivers surrounded by ``enclosed`` and measured pixels.

    Over a wide hole in a slanted or curved surface, the four depths a pixel
    sees can span just over :data:`ENCLOSED_SPREAD` where one of its rays
    meets a measured speck inside the hole: such pixels form lines one or
    two pixels wide through the hole. A connected group (8 neighbours) of
    unmeasured, not enclosed pixels joins the enclosed ones when it touches
    one of them, does not touch the image's border, and each of its pixels has, within
    :data:`SLIVER_REACH` pixels, enclosed or measured pixels whose depths
    (``surface``: the median of an enclosed pixel's four, a measured one's
    own) span at most ``ENCLOSED_SPREAD`` of their largest. A strip between
    a near and a far surface, or a group wider than the reach, stays out.
    """
    import cv2

    rest = ~np.isfinite(depth) & ~enclosed
    if not rest.any() or not enclosed.any():
        return np.zeros_like(rest)
    known = np.isfinite(surface)
    window = np.ones((2 * SLIVER_REACH + 1,) * 2, np.uint8)
    low = cv2.erode(np.where(known, surface, np.inf).astype(np.float32, copy=False), window,
                    borderType=cv2.BORDER_REPLICATE)
    high = cv2.dilate(np.where(known, surface, -np.inf).astype(np.float32, copy=False), window,
                      borderType=cv2.BORDER_REPLICATE)
    with np.errstate(invalid="ignore"):
        one_surface = np.isfinite(low) & ((high - low) <= ENCLOSED_SPREAD * np.abs(high))   # finite: known ones near
    count, labels = cv2.connectedComponents(rest.astype(np.uint8), connectivity=8)
    beside = cv2.dilate(enclosed.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
    out = np.bincount(labels[rest & ~one_surface], minlength=count) > 0
    out |= np.bincount(labels[rest & beside], minlength=count) == 0                    # touching no enclosed pixel
    out[np.concatenate([labels[0], labels[-1], labels[:, 0], labels[:, -1]])] = True    # touching the border
    out[0] = True                                                                       # not a group at all
    return ~out[labels]


def _rays(depth: np.ndarray, reach: float) -> np.ndarray:
    """(4, h, w): per pixel, the depth of the nearest valid pixel to its left, right, above and below (itself
    included) within ``reach`` pixels, NaN where none; depthrefine's C kernel over threads for a float32 map
    where it is built, else :func:`_nearest_along` (the same values)."""
    from ._native import c_kernels
    from ._threads import run_split, worth_splitting

    values = np.empty((4, *depth.shape), depth.dtype)
    c = c_kernels()
    if c is not None and depth.dtype == np.float32 and depth.ndim == 2:
        depth = np.ascontiguousarray(depth)
        for direction in range(4):       # along the rows (left, right): parts of the rows; else of the columns
            run_split(c.nearest_seen, depth.shape[0] if direction < 2 else depth.shape[1], depth, reach, direction,
                      values[direction], parallel=worth_splitting(depth.size))
        return values
    values[0] = _nearest_along(depth, reach, axis=1)                              # to the left
    values[1] = _nearest_along(depth[:, ::-1], reach, axis=1)[:, ::-1]            # to the right
    values[2] = _nearest_along(depth, reach, axis=0)                              # above
    values[3] = _nearest_along(depth[::-1], reach, axis=0)[::-1]                  # below
    return values


def _nearest_along(depth: np.ndarray, reach: float, axis: int) -> np.ndarray:
    """Per pixel, the depth of the nearest valid pixel at or before it along ``axis`` (1: to its left, 0: above it)
    within ``reach`` pixels (NaN if none); each line along the axis is one vectorised pass, the image not transposed."""
    n = depth.shape[axis]
    at = np.arange(n, dtype=np.int32).reshape((1, n) if axis == 1 else (n, 1))   # int32: half numpy's default int64
    last = np.maximum.accumulate(np.where(np.isfinite(depth), at, np.int32(-1)), axis=axis)
    found = (last >= 0) & (at - last <= reach)
    picked = np.take_along_axis(depth, np.maximum(last, 0), axis=axis)
    return np.where(found, picked, np.nan)


def fill_smooth(depth: np.ndarray, holes: np.ndarray) -> np.ndarray:
    """``depth`` with the pixels of ``holes`` filled by the smoothest surface through their surroundings (new array).

    Each hole pixel takes the mean of its four neighbours (a discrete Laplace
    equation, solved exactly for all hole pixels at once), the neighbours
    outside the holes holding their own depth: a membrane spanned over the
    hole from its rim. Pixels of ``holes`` with no valid pixel around them
    anywhere stay NaN. ``depth`` is float with NaN where invalid; ``holes``
    must not hold valid pixels' neighbours that are NaN outside ``holes``.

    Examples
    --------
    >>> d = np.array([[1.0, np.nan, np.nan, 4.0]])
    >>> fill_smooth(d, np.isnan(d)).round(3).tolist()
    [[1.0, 2.0, 3.0, 4.0]]
    """
    from scipy import ndimage, sparse
    from scipy.sparse.linalg import spsolve

    out = np.array(depth, dtype=np.float32, copy=True)
    holes = holes & ~np.isfinite(depth)
    n = int(holes.sum())
    if n == 0:
        return out
    rows, cols = depth.shape
    index = np.full(depth.shape, -1, np.int64)
    index[holes] = np.arange(n)
    hr, hc = np.nonzero(holes)
    diagonal = np.zeros(n)
    rhs = np.zeros(n)
    anchored = np.zeros(n, bool)
    pairs_i, pairs_j = [], []
    for dr, dc in ((-1, 0), (1, 0), (0, -1), (0, 1)):
        nr, nc = hr + dr, hc + dc
        inside = (nr >= 0) & (nr < rows) & (nc >= 0) & (nc < cols)
        nr_in, nc_in = nr[inside], nc[inside]
        diagonal[inside] += 1.0
        neighbour = index[nr_in, nc_in]
        unknown = neighbour >= 0
        pairs_i.append(np.nonzero(inside)[0][unknown])
        pairs_j.append(neighbour[unknown])
        known = ~unknown
        value = depth[nr_in[known], nc_in[known]].astype(np.float64)
        ok = np.isfinite(value)
        np.add.at(rhs, np.nonzero(inside)[0][known][ok], value[ok])
        anchored[np.nonzero(inside)[0][known][ok]] = True
        # a NaN neighbour outside the holes counts as absent
        np.subtract.at(diagonal, np.nonzero(inside)[0][known][~ok], 1.0)
    i = np.concatenate(pairs_i)
    j = np.concatenate(pairs_j)
    matrix = sparse.csr_matrix((np.concatenate([diagonal, -np.ones(i.size)]),
                                (np.concatenate([np.arange(n), i]), np.concatenate([np.arange(n), j]))),
                               shape=(n, n))
    # a connected part of the holes with no valid pixel on its rim has nothing to span: it stays NaN
    parts, count = ndimage.label(holes)
    reached_parts = np.concatenate([[False], ndimage.maximum(anchored.astype(np.uint8), parts[hr, hc],
                                                             np.arange(1, count + 1)).astype(bool)])
    reached = reached_parts[parts[hr, hc]]
    solution = np.full(n, np.nan)
    if reached.any():
        solution[reached] = spsolve(matrix[reached][:, reached].tocsc(), rhs[reached])
    out[hr, hc] = solution
    return out
