"""Thesis 4.5: each cluster's depth samples interpolated on their own, kept on the cluster's own pixels.

The per-cluster bilinear interpolation of :mod:`.refine`'s patches, its
cached axis weights, and the spread of a low-resolution map onto the work
grid for the intermediate pictures.
"""

from __future__ import annotations

import functools

import numpy as np

from ..._lazy import ndimage

__all__ = []


def _interpolate_clusters(corrected, lab_samples, labels, k, s, expansion, keep):
    """Steps 7.1-7.4 for one patch: each pixel interpolated from its own cluster only.

    For cluster ``c``, the valid corrected samples labelled ``c`` are dilated
    by ``expansion`` depth pixels (new positions take the value of the nearest
    cluster-``c`` sample), then interpolated bilinearly on the patch's color
    grid, normalised by the weight of the samples present (so a missing
    neighbour is never averaged in). Each pixel keeps the value of its own
    cluster's map. Returns the combined patch (NaN where a pixel's cluster had
    no sample in reach), if ``keep`` the per-cluster maps, and the count of
    pixels that are not finite.
    """
    from .segment import _kernels

    kernels = _kernels()
    hp, wp = corrected.shape
    valid = np.isfinite(corrected)
    # Cluster c's samples in plane c of (k, hp, wp) masks; one dilation for all planes.
    masks = valid[None] & (lab_samples[None] == np.arange(k, dtype=lab_samples.dtype)[:, None, None])
    grown = masks
    if expansion == 1:   # the default: one pass of a compiled kernel instead of a dilation and a transform per cluster
        values = np.empty(masks.shape)
        grown = np.empty(masks.shape, bool)
        kernels.grow_samples(masks, corrected, values, grown)
    else:
        values = np.where(masks, corrected[None], 0.0)
    if expansion > 1 and masks.any():
        grown = ndimage.binary_dilation(masks, structure=np.ones((1, 3, 3), dtype=bool), iterations=expansion)
        for c in range(k):
            if masks[c].any() and not masks[c].all():  # new positions: the value of the nearest sample
                ir, ic = ndimage.distance_transform_edt(~masks[c], return_distances=False, return_indices=True)
                values[c] = np.where(grown[c], corrected[ir, ic], 0.0)
    weights = grown.astype(np.float64)

    # Bilinear weights along rows and columns; sample i sits at i*s + s//2.
    i0, i1, fr = _axis_weights(labels.shape[0], s, hp)
    j0, j1, fc = _axis_weights(labels.shape[1], s, wp)

    # Where a pixel's four samples are valid and all in its own cluster, the
    # normalised interpolation is plain bilinear interpolation of the samples
    # (``a + f * (b - a)`` keeps a constant exactly constant); other pixels
    # interpolate value x weight and weight of their own cluster (after
    # expansion) and divide, in float64 (num / den of a constant must round
    # back to that constant exactly; float32 gave 3.0000002 for 3 beside a hole).
    below = np.minimum(np.arange(hp) + 1, hp - 1)
    right = np.minimum(np.arange(wp) + 1, wp - 1)
    lab_valid = np.where(valid, lab_samples, -1)
    uniform = ((lab_valid == lab_valid[below]) & (lab_valid == lab_valid[:, right])
               & (lab_valid == lab_valid[below][:, right]))
    cell_label = np.where(uniform, lab_valid, -1).astype(np.int16)
    result = np.empty(labels.shape, dtype=np.float32)
    n_missing = kernels.interpolate_patch(np.where(valid, corrected, 0.0).astype(np.float32), cell_label, labels,
                                          values * weights, weights, i0, i1, fr, j0, j1, fc, result)

    per_cluster = None
    if keep:
        per_cluster = np.full((k,) + labels.shape, np.nan, dtype=np.float32)
        for c in range(k):
            n = np.zeros(labels.shape)
            d = np.zeros(labels.shape)
            for ri, wr in ((i0, 1.0 - fr), (i1, fr)):
                for cj, wc in ((j0, 1.0 - fc), (j1, fc)):
                    wgt = wr[:, None] * wc[None, :] * weights[c][ri[:, None], cj[None, :]]
                    n += wgt * values[c][ri[:, None], cj[None, :]]
                    d += wgt
            with np.errstate(invalid="ignore", divide="ignore"):
                per_cluster[c] = np.where(d > 0, n / d, np.nan)
    return result, per_cluster, n_missing


@functools.lru_cache(maxsize=64)
def _axis_weights(n_hr: int, s: int, n_lr: int):
    """For HR positions 0..n_hr-1: the two neighbouring samples and the weight of the second.

    Cached (patches of one grid share their sizes); the arrays are read-only.
    """
    t = (np.arange(n_hr, dtype=np.float64) - (s // 2)) / s
    i0 = np.clip(np.floor(t).astype(np.intp), 0, n_lr - 1)
    i1 = np.minimum(i0 + 1, n_lr - 1)
    frac = np.clip(t - i0, 0.0, 1.0)
    frac[i1 == i0] = 0.0
    for array in (i0, i1, frac):
        array.setflags(write=False)
    return i0, i1, frac


@functools.lru_cache(maxsize=64)
def _nearest_samples(n_hr: int, s: int, n_lr: int) -> np.ndarray:
    """For HR positions 0..n_hr-1 along one axis: the index of the nearest depth sample (read-only, cached)."""
    index = np.clip(np.floor((np.arange(n_hr) - s // 2) / s + 0.5).astype(np.intp), 0, n_lr - 1)
    index.setflags(write=False)
    return index


def _spread(depth_lr: np.ndarray, s: int, shape: tuple[int, int]) -> np.ndarray:
    """Spreading (4.4.1): depth pixel (i, j) at (i*s + s//2, j*s + s//2), NaN elsewhere."""
    sparse = np.full(shape, np.nan, dtype=np.float32)
    sparse[s // 2::s, s // 2::s] = depth_lr[: len(range(s // 2, shape[0], s)), : len(range(s // 2, shape[1], s))]
    return sparse
