"""Pixel-exact depth pictures: a crop of a depth map (and its color image) at a chosen scale.

:func:`depthrefine.viz.depth_figure` draws the whole map fitted into a
figure a few hundred pixels wide, which is too small to judge an edge.
:func:`pixel_figure` draws a window of it with every panel pixel placed by
``Figure.figimage`` (no resampling by matplotlib): ``scale`` output pixels
per pixel of the finer of the two images, enlarged by nearest neighbour (so
the pixels stay visible) or reduced by an area mean (depth: over its valid
pixels only). The rules of :mod:`depthrefine.viz` hold: viridis for depth,
a colorbar in the depth's units with arrows where the window goes beyond
the range, pixels without a measurement gray and named in a legend.
"""

from __future__ import annotations

import math

from ._lazy import cv2, numpy as np

__all__ = ["check_crop", "crop_windows", "pixel_figure"]

#: Pixels of the figure around the panels: title and captions above, legend below, colorbar right.
_TOP, _BOTTOM, _SIDE, _GAP, _BAR, _BAR_TEXT = 46, 26, 10, 14, 16, 74


def check_crop(crop: tuple[int, int, int, int] | None, shape: tuple[int, int],
               name: str = "crop") -> tuple[int, int, int, int]:
    """The window ``(x, y, width, height)`` checked against an image of ``shape`` (rows, cols); None: all of it.

    Raises
    ------
    ValueError
        A window of no size or reaching beyond the image (the message gives the image's size).

    Examples
    --------
    >>> check_crop((10, 5, 20, 10), (48, 64)), check_crop(None, (48, 64))
    ((10, 5, 20, 10), (0, 0, 64, 48))
    """
    rows, cols = shape
    if crop is None:
        return 0, 0, cols, rows
    x, y, w, h = (int(v) for v in crop)
    if w < 1 or h < 1 or x < 0 or y < 0 or x + w > cols or y + h > rows:
        raise ValueError(f"{name} {x},{y},{w},{h} (X,Y,WIDTH,HEIGHT) must lie inside the {cols}x{rows} depth map: "
                         f"0 <= X, X + WIDTH <= {cols}, 0 <= Y, Y + HEIGHT <= {rows}.")
    return x, y, w, h


def crop_windows(crop: tuple[int, int, int, int], depth_shape: tuple[int, int], color_shape: tuple[int, int] | None
                 ) -> tuple[tuple[int, int, int, int], tuple[int, int, int, int] | None]:
    """The window of the depth map and the same field of view in the color image, as ``(row0, row1, col0, col1)``.

    Examples
    --------
    >>> crop_windows((10, 5, 20, 10), (48, 64), (96, 128))
    ((5, 15, 10, 30), (10, 30, 20, 60))
    """
    x, y, w, h = crop
    rows, cols = depth_shape
    depth_window = (y, y + h, x, x + w)
    if color_shape is None:
        return depth_window, None
    fr, fc = color_shape[0] / rows, color_shape[1] / cols
    r0, c0 = int(math.floor(y * fr + 1e-9)), int(math.floor(x * fc + 1e-9))
    r1 = max(r0 + 1, min(color_shape[0], int(math.ceil((y + h) * fr - 1e-9))))
    c1 = max(c0 + 1, min(color_shape[1], int(math.ceil((x + w) * fc - 1e-9))))
    return depth_window, (r0, r1, c0, c1)


def _resize_depth(depth: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """``depth`` at ``size = (cols, rows)``: nearest when enlarging, valid-pixel area mean when reducing."""
    cols, rows = size
    if cols >= depth.shape[1] and rows >= depth.shape[0]:
        return cv2.resize(depth, size, interpolation=cv2.INTER_NEAREST)
    valid = np.isfinite(depth)
    total = cv2.resize(np.where(valid, depth, 0).astype(np.float32), size, interpolation=cv2.INTER_AREA)
    share = cv2.resize(valid.astype(np.float32), size, interpolation=cv2.INTER_AREA)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(share >= 0.5, total / share, np.nan).astype(np.float32)


def _resize_color(rgb8: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    cols, rows = size
    enlarge = cols >= rgb8.shape[1] and rows >= rgb8.shape[0]
    return cv2.resize(rgb8, size, interpolation=cv2.INTER_NEAREST if enlarge else cv2.INTER_AREA)


def pixel_figure(depth: np.ndarray, rgb: np.ndarray | None = None, *, units: str, title: str | None = None,
                 limits: tuple[float, float] | None = None, crop: tuple[int, int, int, int] | None = None,
                 scale: float = 1.0, confidence: np.ndarray | None = None):
    """A window of ``depth`` (beside the same window of ``rgb``), ``scale`` figure pixels per image pixel.

    Parameters
    ----------
    depth : (H, W) ndarray
        NaN = no measurement.
    rgb : (h, w, 3) ndarray, optional
        Any resolution: the same field of view is shown, at the same size as the depth panel.
    units : str
        For the colorbar's label.
    title : str, optional
    limits : (min, max), optional
        The colorbar's range (default: the window's own min and max).
    crop : (x, y, width, height), optional
        The window, in ``depth``'s pixels (default: the whole map).
    scale : float
        Figure pixels per pixel of the finer image's window (> 0); 1 is its own resolution.
    confidence : (H, W) ndarray, optional
        A confidence map in [0, 1] on ``depth``'s grid: the same window drawn
        to the right of the depth, with its own colorbar (``"colorbar:confidence"``).

    Returns
    -------
    matplotlib.figure.Figure
        The panels are figure images (``fig.images``) of exactly the window's
        size times ``scale``; the colorbar's axes has the label ``"colorbar:depth"``.

    Examples
    --------
    >>> d = np.arange(64, dtype=np.float32).reshape(8, 8)
    >>> fig = pixel_figure(d, units="m", crop=(2, 2, 4, 3), scale=10)
    >>> fig.images[0].get_array().shape[:2]
    (30, 40)
    """
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    from .viz import CONFIDENCE_COLORMAP, DEPTH_COLORMAP, INVALID_COLOR, INVALID_LABEL, _extend, depth_limits, to_rgb8

    if not (isinstance(scale, (int, float)) and math.isfinite(scale) and scale > 0):
        raise ValueError(f"scale must be a positive number of figure pixels per image pixel; got {scale!r}.")
    depth = np.asarray(depth, dtype=np.float32)
    x, y, w, h = check_crop(crop, depth.shape)
    (r0, r1, c0, c1), color_window = crop_windows((x, y, w, h), depth.shape, None if rgb is None else rgb.shape[:2])
    part = depth[r0:r1, c0:c1]
    color = None
    if rgb is not None:
        cr0, cr1, cc0, cc1 = color_window
        color = to_rgb8(rgb[cr0:cr1, cc0:cc1])
    finest = max(w, color.shape[1] if color is not None else 0)
    ratio = finest / w
    out_w = max(1, int(round(w * ratio * scale)))
    out_h = max(1, int(round(h * ratio * scale)))
    lo, hi = limits if limits is not None else depth_limits(part)
    norm = Normalize(vmin=lo, vmax=hi)
    cmap = colormaps[DEPTH_COLORMAP]
    shown = _resize_depth(part, (out_w, out_h))
    painted = (cmap(norm(np.nan_to_num(shown, nan=lo)))[..., :3] * 255 + 0.5).astype(np.uint8)
    painted[~np.isfinite(shown)] = INVALID_COLOR
    panels = []
    if color is not None:
        zoom = out_w / color.shape[1]
        panels.append((_resize_color(color, (out_w, out_h)), f"color {color.shape[1]}x{color.shape[0]} at x{zoom:.3g}"))
    valid = 100.0 * float(np.isfinite(part).mean()) if part.size else 0.0
    panels.append((painted, f"depth {w}x{h} at x{scale * ratio:.3g}, {valid:.1f}% measured"))
    bars = [("depth", norm, cmap, f"depth ({units})" if units else "depth", _extend([part], lo, hi))]
    if confidence is not None:
        trusted = np.asarray(confidence, dtype=np.float32)[r0:r1, c0:c1]
        confidence_map = colormaps[CONFIDENCE_COLORMAP]
        shaded = _resize_depth(trusted, (out_w, out_h))
        panels.append(((confidence_map(np.clip(np.nan_to_num(shaded), 0.0, 1.0))[..., :3] * 255 + 0.5)
                       .astype(np.uint8), f"confidence, median {float(np.median(trusted)):.2f}"))
        bars.append(("confidence", Normalize(vmin=0.0, vmax=1.0), confidence_map,
                     "confidence (1 = most trusted)", "neither"))

    width = (_SIDE + len(panels) * out_w + (len(panels) - 1) * _GAP + _GAP
             + len(bars) * (_BAR + _BAR_TEXT) + (len(bars) - 1) * _GAP)
    height = _TOP + out_h + _BOTTOM
    dpi = 100
    fig = Figure(figsize=(width / dpi, height / dpi), dpi=dpi)
    for i, (image, caption) in enumerate(panels):
        left = _SIDE + i * (out_w + _GAP)
        fig.figimage(image, xo=left, yo=_BOTTOM, origin="upper", resize=False)
        fig.text(left / width, (_BOTTOM + out_h + 4) / height, caption, fontsize=8, va="bottom", ha="left")
    bar_left = _SIDE + len(panels) * (out_w + _GAP)
    for kind, bar_norm, bar_cmap, label, extend in bars:
        cax = fig.add_axes((bar_left / width, _BOTTOM / height, _BAR / width, out_h / height), label=f"colorbar:{kind}")
        bar = fig.colorbar(ScalarMappable(norm=bar_norm, cmap=bar_cmap), cax=cax, extend=extend)
        bar.set_label(label, fontsize=8)
        bar.ax.tick_params(labelsize=7)
        bar_left += _BAR + _BAR_TEXT + _GAP
    if not np.isfinite(part).all():
        swatch = Patch(facecolor=tuple(c / 255.0 for c in INVALID_COLOR), edgecolor="black", linewidth=0.5,
                       label=INVALID_LABEL)
        fig.legend(handles=[swatch], loc="lower left", bbox_to_anchor=(_SIDE / width, 0), fontsize=7, frameon=False,
                   borderaxespad=0.2)
    window = f"x {x}-{x + w}, y {y}-{y + h} of {depth.shape[1]}x{depth.shape[0]}"
    fig.suptitle(f"{title}: {window}" if title else window, fontsize=9, y=1 - 4 / height, va="top")
    return fig
