"""The thesis method's intermediates hook: its steps as pictures and arrays (``refine --save-intermediate``)."""

from __future__ import annotations

from typing import Callable

import numpy as np

from ..intermediates import Intermediates, Picture
from .params import ThesisParams
from .refine import refine_with_intermediates

__all__ = ["thesis_intermediates"]


def thesis_intermediates(
    depth_lr: np.ndarray,
    rgb_hr: np.ndarray,
    *,
    params: ThesisParams | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> tuple[np.ndarray, Intermediates]:
    """:func:`~.refine.refine_with_intermediates`, as the registry's ``intermediates`` hook.

    Returns
    -------
    depth_hr : (H, W) float32 ndarray
        :func:`~.refine.refine_thesis`'s output, bit for bit.
    intermediates : Intermediates
        Pictures: the median-filtered color (``color_filtered.png``), the
        cluster labels (``cluster_labels.png``), the depth samples and the
        corrected samples over the filtered color (``sparse_depth_over_color.png``,
        ``corrected_depth_over_color.png``); arrays: ``labels``,
        ``patch_index``, ``labels_lr``, ``corrected_lr``, ``lab_unified``,
        ``patches``; record: ``level_size`` and ``patches``.

    Examples
    --------
    >>> depth = np.full((4, 4), 30, np.uint8)
    >>> rgb = np.zeros((8, 8, 3), np.uint8)
    >>> depth_hr, steps = thesis_intermediates(depth, rgb, params=ThesisParams(patches=(2, 2)))
    >>> sorted(steps.pictures), steps.record["patches"][0]
    (['cluster_labels.png', 'color_filtered.png', 'corrected_depth_over_color.png', 'sparse_depth_over_color.png'], [0, 4, 0, 4])
    """
    result = refine_with_intermediates(depth_lr, rgb_hr, params=params, progress=progress)
    work_rgb = result.rgb_filtered
    pictures = {
        "color_filtered.png": Picture("color", work_rgb, "median-filtered color (step 4.3.1)"),
        "cluster_labels.png": Picture("labels", result.labels, "cluster labels, per patch (4.3.3)",
                                      groups=result.patch_index),
        "sparse_depth_over_color.png": Picture("depth", result.sparse_depth,
                                               "depth samples over the filtered color (step 5)", background=work_rgb),
        "corrected_depth_over_color.png": Picture("depth", result.corrected_sparse, "corrected depth samples (step 6)",
                                                  background=work_rgb),
    }
    arrays = dict(labels=result.labels, patch_index=result.patch_index, labels_lr=result.labels_lr,
                  corrected_lr=result.corrected_lr, lab_unified=result.lab_unified,
                  patches=np.array(result.patches, dtype=np.int32))
    record = dict(level_size=result.level_size, patches=[list(p) for p in result.patches])
    return result.depth_hr, Intermediates(pictures=pictures, arrays=arrays, record=record)
