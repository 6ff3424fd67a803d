"""The frames of a batch's preview video: color | input | refined, one fixed depth scale and its colorbar.

Pure functions on arrays (the video file is :class:`depthrefine.io.VideoWriter`'s).
The panels use :func:`depthrefine.viz.colorize_depth`, so the video has the
colormap and the gray of "no measurement" of every other depth picture.
"""

from __future__ import annotations

import numpy as np

from .._lazy import cv2
from ..viz import INVALID_COLOR, colorize_depth, to_rgb8

__all__ = ["preview_limits", "preview_frame", "units_label"]

#: Largest panel width of a preview frame, pixels (three panels and the colorbar fit 2048).
PANEL_WIDTH = 640
#: Height of the title band and width of the colorbar band, pixels.
_TITLE = 28
_BAR = 96


def preview_limits(depths: list[np.ndarray]) -> tuple[float, float]:
    """The fixed depth range of a video: the 1st to 99th percentile of the valid values of ``depths``.

    Examples
    --------
    >>> preview_limits([np.arange(1, 102, dtype=np.float32)])
    (2.0, 100.0)
    """
    values = [d[np.isfinite(d)] for d in (np.asarray(d, dtype=np.float32) for d in depths)]
    values = np.concatenate([v for v in values if v.size] or [np.zeros(0, np.float32)])
    if not values.size:
        return 0.0, 1.0
    lo, hi = (float(v) for v in np.percentile(values, [1, 99]))
    return (lo, hi) if hi > lo else (lo, lo + 1.0)


def units_label(depth_units: float | None) -> str:
    """The colorbar's label for depth of ``depth_units`` metres per unit (None: the values as stored).

    Examples
    --------
    >>> units_label(0.001), units_label(1.0), units_label(None)
    ('mm', 'm', 'as stored')
    """
    if depth_units is None:
        return "as stored"
    named = {0.001: "mm", 0.01: "cm", 1.0: "m", 0.0001: "0.1 mm"}
    return named.get(float(depth_units), f"x{depth_units:g} m")


def preview_frame(rgb: np.ndarray, depth_in: np.ndarray, depth_out: np.ndarray, *,
                  limits: tuple[float, float], units: str, method: str) -> np.ndarray:
    """One video frame: the color image, the input depth and the refined depth side by side, and a colorbar.

    Parameters
    ----------
    rgb : (H, W, 3) ndarray
        The color image the refined depth lies on.
    depth_in : (h, w) float ndarray
        The (aligned) input depth, NaN = invalid; shown enlarged (nearest).
    depth_out : (H, W) float ndarray
        The refined depth, NaN = no measurement.
    limits : (float, float)
        The depth range of the colormap (the same for every frame of a video).
    units, method : str
        The colorbar's label and the refined panel's title.

    Returns
    -------
    (rows, cols, 3) uint8 ndarray
        Even width and height (as video encoders need).

    Examples
    --------
    >>> f = preview_frame(np.zeros((40, 60, 3), np.uint8), np.ones((10, 15)), np.ones((40, 60)),
    ...                   limits=(0.0, 2.0), units="m", method="gbp")
    >>> f.shape, f.dtype
    ((68, 276, 3), dtype('uint8'))
    """
    rows, cols = depth_out.shape[:2]
    scale = min(1.0, PANEL_WIDTH / cols)
    size = (max(2, int(round(cols * scale))), max(2, int(round(rows * scale))))
    color = cv2.resize(to_rgb8(rgb), size, interpolation=cv2.INTER_AREA)
    given = cv2.resize(np.asarray(depth_in, np.float32), size, interpolation=cv2.INTER_NEAREST)
    refined = cv2.resize(np.asarray(depth_out, np.float32), size, interpolation=cv2.INTER_NEAREST)
    panels = [color, colorize_depth(given, limits=limits), colorize_depth(refined, limits=limits)]
    titles = ["color", "input", f"refined ({method})"]
    width, height = size
    frame = np.full((height + _TITLE, 3 * width + _BAR, 3), 255, np.uint8)
    for i, (panel, title) in enumerate(zip(panels, titles)):
        frame[_TITLE:, i * width:(i + 1) * width] = panel
        _text(frame, title, (i * width + 6, _TITLE - 9))
    _colorbar(frame[_TITLE:, 3 * width:], limits, units)
    rows_out, cols_out = frame.shape[:2]
    return np.ascontiguousarray(frame[:rows_out - rows_out % 2, :cols_out - cols_out % 2])


def _colorbar(band: np.ndarray, limits: tuple[float, float], units: str) -> None:
    """Into ``band``: the units, a vertical colorbar (high values on top) with three ticks, the gray of "none"."""
    height = band.shape[0]
    top, bottom = 20, max(21, height - 20)
    lo, hi = limits
    ramp = np.linspace(hi, lo, bottom - top, dtype=np.float32)[:, None].repeat(14, axis=1)
    band[top:bottom, 8:22] = colorize_depth(ramp, limits=limits)
    for value in (hi, (lo + hi) / 2, lo):
        y = int(round(top + (hi - value) / (hi - lo) * (bottom - top - 1)))
        band[y, 22:27] = 0
        _text(band, f"{value:.4g}", (29, y + 4), scale=0.35)
    _text(band, units, (4, 13), scale=0.35)
    if height >= bottom + 14:
        band[bottom + 6:bottom + 14, 8:22] = INVALID_COLOR
        _text(band, "none", (29, bottom + 14), scale=0.35)


def _text(image: np.ndarray, text: str, origin: tuple[int, int], *, scale: float = 0.5) -> None:
    cv2.putText(image, text, origin, cv2.FONT_HERSHEY_SIMPLEX, scale, (0, 0, 0), 1, cv2.LINE_AA)
