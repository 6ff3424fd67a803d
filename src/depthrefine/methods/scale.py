"""The scale step (thesis 3.2.2, spec step 2): an integer depth factor.

The refinement places each depth pixel on the color grid ``s`` pixels apart,
so it needs an integer factor ``s``. When the color image covers the depth
map at a non-integer ratio, ``s = round(ratio)`` and the color image is
resized by ``s / ratio`` with bilinear interpolation (thesis: ratio 7.4, so
``s = 7`` and color x0.95, 1760 x 1440 -> 1672 x 1368).

The ratio is measured from the two arrays' shapes, so the color image must
cover the same field of view as the depth map: crop it first (the thesis's
7.4 is the ratio of the scene content; its frames, 1760 / 176, are 10 apart),
or align with :mod:`depthrefine.rig`, which renders the depth on the color
camera's grid.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._lazy import cv2

__all__ = ["ScaleStep", "ScaleWarning", "plan_scale", "resize_color", "MAX_ASPECT_MISMATCH"]

#: Largest relative difference between the row and column ratios that is
#: still taken as one camera pair (beyond it the shapes do not belong together).
MAX_ASPECT_MISMATCH = 0.05


class ScaleWarning(UserWarning):
    """The color/depth ratio is not an integer: the scale step resized the color image.

    Raised by the methods that need an integer factor (``Method.scale_step``:
    the thesis method); the others resize straight to the color grid and do
    not warn.
    """


@dataclass(frozen=True)
class ScaleStep:
    """How a depth map of shape ``depth_shape`` meets a color image of ``color_shape``.

    Attributes
    ----------
    factor : int
        The integer enlargement ``s`` of the depth map.
    ratio : float
        The measured color / depth size ratio (mean of rows and columns).
    work_shape : (int, int)
        ``(rows, cols)`` of the grid the refinement works on: ``s`` times the
        depth shape.
    color_shape : (int, int)
        ``(rows, cols)`` of the color image (and of the final output).
    """

    factor: int
    ratio: float
    work_shape: tuple[int, int]
    color_shape: tuple[int, int]

    @property
    def resizes_color(self) -> bool:
        """True when the color image must be resized (the ratio is not ``s``)."""
        return self.work_shape != self.color_shape

    @property
    def color_scale(self) -> float:
        """The color resize factor ``s / ratio`` (1.0 when none is needed)."""
        return self.factor / self.ratio

    def describe(self, *, direct: bool = False) -> str:
        """One line for the user: what the scale step did.

        ``direct``: for a method that does not take the scale step (it resizes
        straight to the color grid), say so instead.
        """
        h, w = self.color_shape
        wh, ww = self.work_shape
        if not self.resizes_color:
            return f"scale factor {self.factor} (color {w}x{h})"
        if direct:
            return f"ratio {self.ratio:.3f}, resized directly to {w}x{h}"
        return (
            f"non-integer ratio {self.ratio:.3f}: depth enlarged x{self.factor}, color resized "
            f"x{self.color_scale:.3f} ({w}x{h} -> {ww}x{wh}, bilinear) and the result resized "
            f"back to {w}x{h} (nearest)"
        )


def plan_scale(depth_shape: tuple[int, ...], color_shape: tuple[int, ...]) -> ScaleStep:
    """Find the integer factor between a depth map and a color image.

    Parameters
    ----------
    depth_shape : tuple
        Shape of the low-resolution depth map, ``(h, w)``.
    color_shape : tuple
        Shape of the color image, ``(H, W[, 3])``.

    Returns
    -------
    ScaleStep

    Raises
    ------
    ValueError
        If the color image is smaller than the depth map, or the row and
        column ratios differ by more than 5 % (not a registered pair).

    Examples
    --------
    >>> plan_scale((144, 176), (1008, 1232)).factor
    7
    >>> step = plan_scale((144, 176), (1440, 1760))
    >>> step.factor, step.work_shape, round(step.color_scale, 3)
    (10, (1440, 1760), 1.0)
    >>> plan_scale((144, 176), (1066, 1302)).describe()[:24]
    'non-integer ratio 7.400:'
    """
    h, w = int(depth_shape[0]), int(depth_shape[1])
    H, W = int(color_shape[0]), int(color_shape[1])
    ratio_rows, ratio_cols = H / h, W / w
    if ratio_rows < 1 or ratio_cols < 1:
        raise ValueError(
            f"the color image ({W}x{H}) is smaller than the depth map ({w}x{h}); "
            "the color image must be the high-resolution one. Check the argument order (depth first)."
        )
    mismatch = abs(ratio_rows - ratio_cols) / min(ratio_rows, ratio_cols)
    if mismatch > MAX_ASPECT_MISMATCH:
        raise ValueError(
            f"depth ({w}x{h}) and color ({W}x{H}) have different aspect ratios "
            f"(x{ratio_cols:.3f} across, x{ratio_rows:.3f} down); crop them to the same field of view first."
        )
    if H % h == 0 and W % w == 0 and H // h == W // w:
        s = H // h
        return ScaleStep(factor=s, ratio=float(s), work_shape=(H, W), color_shape=(H, W))
    ratio = (ratio_rows + ratio_cols) / 2.0
    s = max(1, int(np.floor(ratio + 0.5)))
    return ScaleStep(factor=s, ratio=ratio, work_shape=(h * s, w * s), color_shape=(H, W))


def resize_color(rgb: np.ndarray, step: ScaleStep) -> np.ndarray:
    """Resize a color image onto the working grid of ``step`` (bilinear, dtype kept)."""
    if not step.resizes_color:
        return rgb
    rows, cols = step.work_shape
    return cv2.resize(rgb, (cols, rows), interpolation=cv2.INTER_LINEAR)


def resize_depth_nearest(depth: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """Resize a depth map to ``shape`` with nearest sampling (never blends two depths)."""
    if depth.shape[:2] == tuple(shape):
        return depth
    return cv2.resize(depth, (shape[1], shape[0]), interpolation=cv2.INTER_NEAREST_EXACT)
