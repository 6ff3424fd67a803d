"""gbp's compiled kernels between two grids: the guided x2 enlargement, clips to bounds on the input's grid.

- :func:`guided_enlarge`: joint bilateral x2 enlargement of the reduced
  rounds' estimate (:func:`depthrefine.methods.gbp.solve.back_project`);
- :func:`clip_nearest`, :func:`clip_toward`: a clip to per-pixel bounds
  that live on the input's grid (their nearest-neighbour enlargement,
  without its image-sized arrays).

Imported only when gbp runs. The kernels are the C ones when built, else
numba's (:mod:`._resample_jit`), as for :mod:`._wls`.
"""

from __future__ import annotations

import numpy as np

from .._native import kernels
from .._threads import run_split
from .._validate import check_number
from ._wls import _check_in_place, _color_lut, _guide, _parallel

__all__ = ["guided_enlarge", "clip_nearest", "clip_toward"]


def _kernels():
    """The C kernels when built (:mod:`depthrefine._native`), else numba's (:mod:`._resample_jit`)."""
    return kernels(__package__ + "._resample_jit")


def guided_enlarge(x: np.ndarray, small_guide: np.ndarray, guide: np.ndarray, sigma_color: float) -> np.ndarray:
    """Enlarge ``x`` x2 to ``guide``'s grid, each pixel from the small pixels whose color is like its own.

    Joint bilateral upsampling (Kopf et al. 2007) on the bilinear footprint:
    each output pixel is the mean of its four nearest ``x`` pixels weighted
    by their bilinear weights (9, 3, 3, 1 sixteenths) times
    ``exp(-|dc| / sigma_color)``, ``|dc|`` the distance of the output
    pixel's color in ``guide`` to the small pixel's color in ``small_guide``
    (its 2x2 block's mean, say); where all four are far off, the bilinear
    enlargement. ``x`` and ``small_guide`` are on the grid of
    ``ceil(H / 2) x ceil(W / 2)`` pixels, small pixel ``q`` centred between
    output pixels ``2q`` and ``2q + 1``; the guides are (H, W, 3) uint8.

    Examples
    --------
    >>> guide = np.zeros((4, 8, 3), np.uint8); guide[:, 3:] = 255       # the edge inside small column 1
    >>> small = np.zeros((2, 4, 3), np.uint8); small[:, 1] = 128; small[:, 2:] = 255
    >>> x = np.array([[0, 50, 100, 100]] * 2, np.float32)
    >>> guided_enlarge(x, small, guide, 16.0)[0].round(1).tolist()
    [0.0, 0.0, 0.0, 100.0, 100.0, 100.0, 100.0, 100.0]
    """
    import cv2

    small_guide, guide = _guide(small_guide), _guide(guide)
    x = np.ascontiguousarray(x, dtype=np.float32)
    (H, W), (h, w) = guide.shape[:2], x.shape
    if small_guide.shape[:2] != (h, w) or (h, w) != (-(-H // 2), -(-W // 2)) or guide.shape[2] != 3 \
            or small_guide.shape[2] != 3:
        raise ValueError(f"x and small_guide must be of the guide's grid halved, {(-(-H // 2), -(-W // 2))}, "
                         f"the guides of 3 channels; got {x.shape}, {small_guide.shape} and {guide.shape}.")
    lut = _color_lut(3, check_number("sigma_color", sigma_color, positive=True))
    out = np.empty((H, W), np.float32)
    run_split(_kernels().enlarge_rows, H, x, *cv2.split(small_guide), guide, lut, out, parallel=_parallel(out.shape))
    return out


def clip_nearest(x: np.ndarray, low: float, high: float, lower: np.ndarray, upper: np.ndarray, rows: np.ndarray,
                 cols: np.ndarray) -> None:
    """Clip ``x`` in place to ``[low, high]``, then pixel ``(i, j)`` to ``[lower[rows[i], cols[j]], upper[...]]``.

    One pass: the bounds ``lower``, ``upper`` stay on their own (small)
    grid, ``rows`` and ``cols`` (int32) map ``x``'s rows and columns to
    theirs. ``x`` is a C-contiguous float32 array without NaN.

    Examples
    --------
    >>> x = np.arange(6, dtype=np.float32).reshape(2, 3)
    >>> clip_nearest(x, 0.5, 4.5, np.full((1, 2), 1, np.float32), np.array([[3, 9]], np.float32),
    ...              np.zeros(2, np.int32), np.array([0, 0, 1], np.int32)); x.tolist()
    [[1.0, 1.0, 2.0], [3.0, 3.0, 4.5]]
    """
    _check_in_place(x, "clipped")
    if x.shape != (len(rows), len(cols)):
        raise ValueError(f"rows and cols must map x's {x.shape} rows and columns; got {len(rows)} and {len(cols)}.")
    lower = np.ascontiguousarray(lower, dtype=np.float32)
    upper = np.ascontiguousarray(upper, dtype=np.float32)
    rows = np.ascontiguousarray(rows, dtype=np.int32)
    cols = np.ascontiguousarray(cols, dtype=np.int32)
    run_split(_kernels().clip_rows, x.shape[0], x, np.float32(low), np.float32(high), lower, upper, rows, cols,
              parallel=_parallel(x.shape))


def clip_toward(x: np.ndarray, weight: np.ndarray, lower: np.ndarray, upper: np.ndarray, rows: np.ndarray,
                cols: np.ndarray) -> None:
    """Move ``x`` in place toward its clip to the bounds of :func:`clip_nearest` by ``weight`` (0: stay, 1: clip).

    ``x <- x + weight * (clip(x) - x)`` with float32 operations in that
    order; ``weight`` is an array of ``x``'s shape.

    Examples
    --------
    >>> x = np.array([[0.0, 5.0, 10.0]], np.float32)
    >>> clip_toward(x, np.array([[1.0, 1.0, 0.5]], np.float32), np.full((1, 1), 2, np.float32),
    ...             np.full((1, 1), 6, np.float32), np.zeros(1, np.int32), np.zeros(3, np.int32)); x.tolist()
    [[2.0, 5.0, 8.0]]
    """
    _check_in_place(x, "changed")
    if x.shape != (len(rows), len(cols)) or weight.shape != x.shape:
        raise ValueError(f"weight must be of x's shape {x.shape} and rows, cols map its rows and columns; got "
                         f"{weight.shape}, {len(rows)} and {len(cols)}.")
    run_split(_kernels().clip_toward_rows, x.shape[0], x, np.ascontiguousarray(weight, dtype=np.float32),
              np.ascontiguousarray(lower, dtype=np.float32), np.ascontiguousarray(upper, dtype=np.float32),
              np.ascontiguousarray(rows, dtype=np.int32), np.ascontiguousarray(cols, dtype=np.int32),
              parallel=_parallel(x.shape))
