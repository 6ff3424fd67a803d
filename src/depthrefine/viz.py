"""Pictures a user looks at: colorized depth, cluster labels, overlays, comparison figures.

Image functions return RGB uint8 arrays (no file access). Figure functions
build a matplotlib ``Figure`` (Agg, no display needed) that the caller saves;
matplotlib is imported only inside them.
"""

from __future__ import annotations

from typing import Sequence

import cv2
import numpy as np

from ._validate import as_rgb_float

__all__ = [
    "colorize_depth",
    "colorize_labels",
    "blend",
    "overlay_sparse",
    "to_rgb8",
    "comparison_figure",
    "depth_limits",
    "pick_detail",
]

#: Colormap for depth (perceptually uniform); invalid pixels are drawn black.
DEPTH_COLORMAP = cv2.COLORMAP_TURBO


def to_rgb8(rgb: np.ndarray) -> np.ndarray:
    """Any checked color image (uint8, uint16, float in [0, 1]) as RGB uint8."""
    if rgb.dtype == np.uint8:
        return rgb
    return np.clip(as_rgb_float(rgb) * 255.0 + 0.5, 0, 255).astype(np.uint8)


def depth_limits(*depths: np.ndarray) -> tuple[float, float]:
    """Common (min, max) of the finite values of several depth maps, for one color scale."""
    finite = [d[np.isfinite(d)] for d in depths]
    finite = [f for f in finite if f.size]
    if not finite:
        return 0.0, 1.0
    lo = min(float(f.min()) for f in finite)
    hi = max(float(f.max()) for f in finite)
    return (lo, hi) if hi > lo else (lo, lo + 1.0)


def colorize_depth(depth: np.ndarray, *, limits: tuple[float, float] | None = None) -> np.ndarray:
    """Depth (NaN = invalid) as an RGB uint8 image with the turbo colormap.

    Larger values are drawn warmer. Invalid pixels are black.

    Examples
    --------
    >>> colorize_depth(np.array([[1.0, np.nan]], np.float32)).shape
    (1, 2, 3)
    """
    depth = np.asarray(depth, dtype=np.float32)
    lo, hi = depth_limits(depth) if limits is None else limits
    valid = np.isfinite(depth)
    scaled = np.zeros(depth.shape, dtype=np.uint8)
    scaled[valid] = np.clip((depth[valid] - lo) / max(hi - lo, 1e-12) * 255.0 + 0.5, 0, 255).astype(np.uint8)
    rgb = cv2.cvtColor(cv2.applyColorMap(scaled, DEPTH_COLORMAP), cv2.COLOR_BGR2RGB)
    rgb[~valid] = 0
    return rgb


def colorize_labels(labels: np.ndarray, patch_index: np.ndarray | None = None) -> np.ndarray:
    """Cluster labels as distinct colors; with ``patch_index``, neighbouring patches differ too.

    Examples
    --------
    >>> colorize_labels(np.array([[0, 1], [1, 2]])).shape
    (2, 2, 3)
    """
    ids = labels.astype(np.int64)
    if patch_index is not None:
        ids = ids + (int(ids.max()) + 1 if ids.size else 1) * patch_index.astype(np.int64)
    # A fixed, well-spread palette: golden-ratio hues, alternating lightness.
    n = int(ids.max()) + 1 if ids.size else 1
    hues = (np.arange(n) * 0.618033988749895) % 1.0
    hsv = np.stack([hues * 179, np.full(n, 200), np.where(np.arange(n) % 2, 170, 245)], axis=1)
    palette = cv2.cvtColor(hsv.astype(np.uint8)[None], cv2.COLOR_HSV2RGB)[0]
    return palette[ids]


def blend(depth_rgb: np.ndarray, rgb: np.ndarray, alpha: float = 0.5) -> np.ndarray:
    """Alpha-blend a colorized depth map over the color image (thesis Figs. 22, 42)."""
    color = to_rgb8(rgb)
    return cv2.addWeighted(depth_rgb, alpha, color, 1.0 - alpha, 0.0)


def overlay_sparse(sparse_depth: np.ndarray, rgb: np.ndarray, *, limits: tuple[float, float] | None = None,
                   radius: int | None = None) -> np.ndarray:
    """The spread depth samples drawn as colored dots over the color image (Fig. 37a)."""
    color = (to_rgb8(rgb).astype(np.float32) * 0.6).astype(np.uint8)
    valid = np.isfinite(sparse_depth)
    dots = colorize_depth(sparse_depth, limits=limits or depth_limits(sparse_depth))
    if radius is None:
        rows = np.flatnonzero(valid.any(axis=1))
        step = int(np.min(np.diff(rows))) if len(rows) > 1 else 1
        radius = max(0, step // 4)
    if radius > 0:
        size = 2 * radius + 1
        kernel = np.ones((size, size), np.uint8)
        grown = cv2.dilate(valid.astype(np.uint8), kernel) > 0
        dots = cv2.dilate(dots, kernel)
        valid = grown
    out = color.copy()
    out[valid] = dots[valid]
    return out


def comparison_figure(
    rgb: np.ndarray,
    panels: Sequence[tuple[str, np.ndarray]],
    *,
    zoom: tuple[int, int, int, int] | None = None,
    limits: tuple[float, float] | None = None,
    title: str | None = None,
):
    """A figure like the thesis's Fig. 47: the color image and depth panels, each with a zoomed detail.

    Parameters
    ----------
    rgb : (H, W, 3) ndarray
        The color image (first panel).
    panels : sequence of (caption, (H, W) depth)
        Depth maps on the color grid, drawn with one shared color scale.
    zoom : (row0, row1, col0, col1), optional
        The detail region, marked on every panel and shown enlarged below it.
    limits : (min, max), optional
        The depth color scale (default: common range of the panels).
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    limits = limits or depth_limits(*[d for _, d in panels])
    images = [("color", to_rgb8(rgb))] + [(cap, colorize_depth(d, limits=limits)) for cap, d in panels]
    n = len(images)
    rows = 2 if zoom is not None else 1
    h, w = images[0][1].shape[:2]
    fig = Figure(figsize=(3.2 * n, 3.2 * h / w * rows + 0.8), dpi=150, layout="constrained")
    axes = fig.subplots(rows, n, squeeze=False)
    for col, (caption, img) in enumerate(images):
        ax = axes[0, col]
        ax.imshow(img, interpolation="nearest")
        ax.set_title(caption, fontsize=9)
        ax.set_axis_off()
        if zoom is not None:
            r0, r1, c0, c1 = zoom
            ax.add_patch(Rectangle((c0, r0), c1 - c0, r1 - r0, fill=False, edgecolor="white", linewidth=1.2))
            axz = axes[1, col]
            axz.imshow(img[r0:r1, c0:c1], interpolation="nearest")
            axz.set_title(f"detail of {caption.split(chr(10))[0]}", fontsize=8)
            axz.set_axis_off()
    if title:
        fig.suptitle(title, fontsize=10)
    return fig


def pick_detail(depth: np.ndarray, *, size: tuple[int, int] | None = None) -> tuple[int, int, int, int]:
    """The window with the most depth edges, for a zoomed detail: ``(row0, row1, col0, col1)``.

    ``size`` is ``(rows, cols)`` (default: a quarter of each side).
    Deterministic: the first maximum in row-major order wins.

    Examples
    --------
    >>> d = np.zeros((40, 40), np.float32); d[30:, 30:] = 5
    >>> pick_detail(d, size=(10, 10))
    (30, 40, 30, 40)
    """
    depth = np.asarray(depth, dtype=np.float32)
    rows, cols = depth.shape
    h, w = size if size is not None else (max(1, rows // 4), max(1, cols // 4))
    h, w = min(h, rows), min(w, cols)
    filled = np.where(np.isfinite(depth), depth, np.nanmedian(depth) if np.isfinite(depth).any() else 0)
    gy = np.abs(np.diff(filled, axis=0, prepend=filled[:1]))
    gx = np.abs(np.diff(filled, axis=1, prepend=filled[:, :1]))
    edges = (np.maximum(gx, gy) > 0.5 * max(1e-12, float(np.nanstd(filled)) / 4)).astype(np.float32)
    # Sum of edges in every h x w window, anchored at its top-left corner.
    integral = cv2.integral(edges, sdepth=cv2.CV_64F)
    sums = integral[h:, w:] - integral[:-h, w:] - integral[h:, :-w] + integral[:-h, :-w]
    r0, c0 = np.unravel_index(int(np.argmax(sums)), sums.shape)
    return int(r0), int(r0) + h, int(c0), int(c0) + w
