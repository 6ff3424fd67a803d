"""Pictures a user looks at: depth figures with a colorbar, colorized depth, cluster labels.

Every depth picture the package writes is a matplotlib ``Figure`` built by
:func:`figure_grid` (or its shorthands :func:`comparison_figure` and
:func:`depth_figure`), so that it follows one set of rules:

- one perceptually uniform colormap for depth, :data:`DEPTH_COLORMAP`
  (viridis: lightness grows with the value, readable in gray and by
  color-blind readers), and :data:`ERROR_COLORMAP` for error maps;
- the same range on every depth panel of a figure, with one colorbar
  labelled in the depth's units (arrows on the bar when panels go beyond it);
- pixels without a measurement in a neutral gray, :data:`INVALID_COLOR`,
  named in the figure's legend.

The functions are pure: they return arrays or a ``Figure`` (Agg, no display
needed) and the caller writes it. matplotlib is imported only inside them.
Each panel's axes carries its kind as its label (``ax.get_label()`` is
``"panel:depth"``, ``"panel:color"`` ...), so tests can check the arrays,
ranges, titles and colorbars behind a figure without looking at pixels.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

# numpy and OpenCV load on first use, so that the command line can read the names here
# (``depthrefine show --help``) without them (fast start-up).
from ._lazy import cv2, numpy as np

__all__ = [
    "DEPTH_COLORMAP",
    "ERROR_COLORMAP",
    "CONFIDENCE_COLORMAP",
    "INVALID_COLOR",
    "INVALID_LABEL",
    "PANEL_KINDS",
    "Panel",
    "to_rgb8",
    "depth_limits",
    "colorize_depth",
    "colorize_labels",
    "spread_samples",
    "figure_grid",
    "comparison_figure",
    "depth_figure",
    "pick_detail",
]

#: Colormap of every depth picture (matplotlib name; perceptually uniform).
DEPTH_COLORMAP = "viridis"
#: Colormap of error maps (perceptually uniform, distinct from depth's).
ERROR_COLORMAP = "magma"
#: Pixels without a measurement: neutral mid gray (RGB 0..255), in no colormap above.
INVALID_COLOR = (128, 128, 128)
#: The legend entry naming :data:`INVALID_COLOR`.
INVALID_LABEL = "gray: no measurement"
#: Colormap of confidence maps (0..1; perceptually uniform, distinct from depth's and error's).
CONFIDENCE_COLORMAP = "cividis"
#: What a :class:`Panel` can show.
PANEL_KINDS = ("color", "depth", "error", "samples", "blend", "confidence")
#: Kinds drawn with the depth colormap and range.
_DEPTH_KINDS = ("depth", "samples", "blend")
_CV2_COLORMAPS = {"viridis": "COLORMAP_VIRIDIS", "magma": "COLORMAP_MAGMA"}  # names in cv2


@dataclass(frozen=True)
class Panel:
    """One picture of a :func:`figure_grid`.

    Attributes
    ----------
    title : str
        Shown above the panel (put the RMSE here).
    image : ndarray
        ``color``: (H, W, 3) color image; ``depth`` / ``error``: (H, W)
        values, NaN = no measurement; ``samples``: (H, W) sparse depth (NaN
        between samples) drawn as dots over ``background`` dimmed;
        ``blend``: (H, W) depth drawn half-transparent over ``background``;
        ``confidence``: (H, W) values in [0, 1] (1 = most trusted), with their own colorbar.
    kind : str
        One of :data:`PANEL_KINDS`.
    detail : bool
        Show only the figure's zoom window of ``image``, enlarged.
    background : (H, W, 3) ndarray, optional
        The color image under ``samples`` and ``blend``.
    """

    title: str
    image: np.ndarray
    kind: str = "depth"
    detail: bool = False
    background: np.ndarray | None = None

    def __post_init__(self):
        if self.kind not in PANEL_KINDS:
            raise ValueError(f"Panel kind must be one of {PANEL_KINDS}; got {self.kind!r}.")
        if self.kind in ("samples", "blend") and self.background is None:
            raise ValueError(f"a {self.kind!r} panel needs background= (the color image).")


def to_rgb8(rgb: np.ndarray) -> np.ndarray:
    """Any checked color image (uint8, uint16, float in [0, 1]) as RGB uint8."""
    if rgb.dtype == np.uint8:
        return rgb
    from ._validate import as_rgb_float

    return np.clip(as_rgb_float(rgb) * 255.0 + 0.5, 0, 255).astype(np.uint8)


def depth_limits(*depths: np.ndarray) -> tuple[float, float]:
    """Common (min, max) of the finite values of several depth maps, for one color scale.

    Examples
    --------
    >>> depth_limits(np.array([1.0, np.nan]), np.array([3.0]))
    (1.0, 3.0)
    """
    finite = [d[np.isfinite(d)] for d in (np.asarray(d, dtype=np.float64) for d in depths)]
    finite = [f for f in finite if f.size]
    if not finite:
        return 0.0, 1.0
    lo = min(float(f.min()) for f in finite)
    hi = max(float(f.max()) for f in finite)
    return (lo, hi) if hi > lo else (lo, lo + 1.0)


def colorize_depth(depth: np.ndarray, *, limits: tuple[float, float] | None = None,
                   colormap: str = DEPTH_COLORMAP) -> np.ndarray:
    """Depth (NaN = invalid) as an RGB uint8 image with :data:`DEPTH_COLORMAP`; invalid pixels gray.

    For pictures with a colorbar use :func:`depth_figure`; this is the bare
    image (e.g. for a video frame or an overlay of your own).

    Examples
    --------
    >>> colorize_depth(np.array([[1.0, np.nan]], np.float32))[0, 1].tolist()
    [128, 128, 128]
    """
    if colormap not in _CV2_COLORMAPS:
        raise ValueError(f"colormap must be one of {sorted(_CV2_COLORMAPS)}; got {colormap!r}.")
    depth = np.asarray(depth, dtype=np.float32)
    lo, hi = depth_limits(depth) if limits is None else limits
    valid = np.isfinite(depth)
    scaled = np.zeros(depth.shape, dtype=np.uint8)
    scaled[valid] = np.clip((depth[valid] - lo) / max(hi - lo, 1e-12) * 255.0 + 0.5, 0, 255).astype(np.uint8)
    rgb = cv2.cvtColor(cv2.applyColorMap(scaled, getattr(cv2, _CV2_COLORMAPS[colormap])), cv2.COLOR_BGR2RGB)
    rgb[~valid] = INVALID_COLOR
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


def spread_samples(sparse_depth: np.ndarray, *, radius: int | None = None) -> np.ndarray:
    """Sparse depth samples (NaN between them) grown into square dots, to be seen in a picture.

    ``radius`` defaults to a quarter of the row spacing of the samples. Where
    dots overlap, the larger value wins (deterministic).

    Examples
    --------
    >>> d = np.full((5, 5), np.nan, np.float32); d[2, 2] = 7
    >>> int(np.isfinite(spread_samples(d, radius=1)).sum())
    9
    """
    sparse = np.asarray(sparse_depth, dtype=np.float32)
    valid = np.isfinite(sparse)
    if radius is None:
        rows = np.flatnonzero(valid.any(axis=1))
        step = int(np.min(np.diff(rows))) if len(rows) > 1 else 1
        radius = max(0, step // 4)
    if radius <= 0 or not valid.any():
        return sparse.copy()
    kernel = np.ones((2 * radius + 1, 2 * radius + 1), np.uint8)
    floor = np.float32(np.min(sparse[valid]) - 1.0)
    grown = cv2.dilate(np.where(valid, sparse, floor).astype(np.float32), kernel)
    covered = cv2.dilate(valid.astype(np.uint8), kernel) > 0
    return np.where(covered, grown, np.nan).astype(np.float32)


def _colormap(name: str, *, invalid: tuple[int, int, int] | None):
    """A copy of matplotlib's colormap ``name`` drawing masked pixels as ``invalid`` (None: transparent)."""
    import matplotlib

    bad = (0, 0, 0, 0) if invalid is None else tuple(c / 255.0 for c in invalid) + (1.0,)
    return matplotlib.colormaps[name].with_extremes(bad=bad)


def _crop(array: np.ndarray | None, zoom: tuple[int, int, int, int] | None, detail: bool):
    if array is None or not detail or zoom is None:
        return array
    r0, r1, c0, c1 = zoom
    return array[r0:r1, c0:c1]


def _display_size(image: np.ndarray, max_cols: int) -> np.ndarray:
    """``image`` reduced by a whole factor to at most about ``max_cols`` columns (area average).

    Depth and error maps average only their valid pixels; a reduced pixel is
    invalid when less than half of its block was valid. Drawing a picture
    this size looks the same as the full one and costs a fraction of it.
    """
    factor = image.shape[1] // max(1, max_cols)
    if factor < 2:
        return image
    rows, cols = image.shape[0] // factor, image.shape[1] // factor
    if rows < 1:
        return image
    size = (cols, rows)
    if image.ndim == 3:
        return cv2.resize(to_rgb8(image), size, interpolation=cv2.INTER_AREA)
    values = np.asarray(image, dtype=np.float32)
    valid = np.isfinite(values)
    total = cv2.resize(np.where(valid, values, 0).astype(np.float32), size, interpolation=cv2.INTER_AREA)
    share = cv2.resize(valid.astype(np.float32), size, interpolation=cv2.INTER_AREA)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(share >= 0.5, total / share, np.nan).astype(np.float32)


def _extend(values: list[np.ndarray], lo: float, hi: float) -> str:
    """Colorbar arrows: "min", "max", "both" or "neither", by whether any panel leaves [lo, hi]."""
    below = any(bool((v[np.isfinite(v)] < lo).any()) for v in values)
    above = any(bool((v[np.isfinite(v)] > hi).any()) for v in values)
    return {(False, False): "neither", (True, False): "min", (False, True): "max"}.get((below, above), "both")


def figure_grid(
    rows: Sequence[Sequence[Panel | None]],
    *,
    units: str,
    limits: tuple[float, float] | None = None,
    error_max: float | None = None,
    zoom: tuple[int, int, int, int] | None = None,
    title: str | None = None,
    panel_width: float = 2.6,
    dpi: int = 110,
):
    """A grid of panels with one depth colorbar, one error colorbar and the invalid-pixel legend.

    Parameters
    ----------
    rows : sequence of sequences of Panel or None
        The grid, row by row (None leaves a cell empty; rows may differ in length).
    units : str
        The depth's units, written on the colorbar (e.g. ``"mm"``, ``"disparity levels"``).
    limits : (min, max), optional
        Range of every depth panel (default: the common range of the depth
        panels that are not details). Values beyond it saturate and the
        colorbar shows an arrow.
    error_max : float, optional
        Upper end of the error colorbar (default: the largest error shown).
    zoom : (row0, row1, col0, col1), optional
        The detail window: drawn as a white rectangle outlined in black on the full panels,
        shown enlarged on the ``detail=True`` panels.
    title : str, optional
    panel_width : float
        Width of one column, inches.
    dpi : int

    Returns
    -------
    matplotlib.figure.Figure
        Each panel's axes has the label ``"panel:<kind>"`` (``"panel:<kind>:detail"``
        for details); every depth-kind image shares one ``Normalize`` and the
        depth colorbar is built from it.

    Examples
    --------
    >>> d = np.array([[1.0, 2.0], [np.nan, 4.0]], np.float32)
    >>> fig = figure_grid([[Panel("depth", d)]], units="m")
    >>> fig.axes[0].get_images()[0].get_clim()
    (1.0, 4.0)
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch, Rectangle
    from matplotlib.patheffects import withStroke
    from matplotlib.colors import Normalize

    grid = [list(r) for r in rows]
    cells = [p for r in grid for p in r if p is not None]
    if not cells:
        raise ValueError("figure_grid needs at least one panel.")
    if any(p.detail for p in cells) and zoom is None:
        raise ValueError("detail panels need zoom=(row0, row1, col0, col1).")
    depth_values = [p.image for p in cells if p.kind in _DEPTH_KINDS]
    full_depth = [p.image for p in cells if p.kind in _DEPTH_KINDS and not p.detail] or depth_values
    lo, hi = limits if limits is not None else depth_limits(*full_depth)
    depth_norm = Normalize(vmin=lo, vmax=hi)
    errors = [p.image for p in cells if p.kind == "error"]
    if error_max is None:
        error_max = depth_limits(*errors)[1] if errors else 1.0
    error_norm = Normalize(vmin=0.0, vmax=float(error_max))

    ncols = max(len(r) for r in grid)

    def aspect(p: Panel) -> float:
        h, w = _crop(p.image, zoom, p.detail).shape[:2]
        return h / max(w, 1)

    heights = [max(aspect(p) for p in r if p is not None) if any(p is not None for p in r) else 0.2 for r in grid]
    fig = Figure(figsize=(panel_width * ncols + 1.3, panel_width * sum(heights) + 0.4 * len(grid) + 0.6),
                 dpi=dpi, layout="constrained")
    axes = fig.subplots(len(grid), ncols, squeeze=False, gridspec_kw={"height_ratios": heights})
    depth_axes, error_axes, depth_image, error_image = [], [], None, None
    confidence_axes, confidence_image = [], None
    for i, row in enumerate(grid):
        for j in range(ncols):
            ax = axes[i, j]
            ax.set_axis_off()
            ax.set_xticks([])  # no tick work at layout time (it dominates drawing many panels)
            ax.set_yticks([])
            panel = row[j] if j < len(row) else None
            if panel is None:
                continue
            ax.set_label(f"panel:{panel.kind}" + (":detail" if panel.detail else ""))
            max_cols = int(2 * panel_width * dpi)
            image = _crop(panel.image, zoom, panel.detail)
            background = _crop(panel.background, zoom, panel.detail)
            if panel.kind == "samples" and not panel.detail:
                image = spread_samples(image)
            image = _display_size(image, max_cols)
            background = None if background is None else _display_size(background, max_cols)
            scale = panel.image.shape[1] / image.shape[1] if not panel.detail else 1.0
            nearest = "nearest" if panel.detail else "antialiased"
            if panel.kind == "color":
                ax.imshow(to_rgb8(image), interpolation=nearest)
            elif panel.kind == "error":
                im = ax.imshow(np.ma.masked_invalid(image), cmap=_colormap(ERROR_COLORMAP, invalid=INVALID_COLOR),
                               norm=error_norm, interpolation=nearest)
                error_axes.append(ax)
                error_image = error_image or im
            elif panel.kind == "confidence":
                confidence_image = ax.imshow(image, cmap=CONFIDENCE_COLORMAP, vmin=0.0, vmax=1.0,
                                             interpolation=nearest)
                confidence_axes.append(ax)
            else:
                if panel.kind == "depth":
                    cmap, alpha = _colormap(DEPTH_COLORMAP, invalid=INVALID_COLOR), None
                else:
                    dim = 0.6 if panel.kind == "samples" else 1.0
                    ax.imshow((to_rgb8(background).astype(np.float32) * dim).astype(np.uint8), interpolation=nearest)
                    cmap, alpha = _colormap(DEPTH_COLORMAP, invalid=None), (0.5 if panel.kind == "blend" else None)
                im = ax.imshow(np.ma.masked_invalid(image), cmap=cmap, norm=depth_norm, alpha=alpha,
                               interpolation="nearest" if panel.kind == "samples" else nearest)
                depth_axes.append(ax)
                depth_image = depth_image or im
            if zoom is not None and not panel.detail:
                r0, r1, c0, c1 = zoom
                ax.add_patch(Rectangle(((c0 - 0.5) / scale, (r0 - 0.5) / scale), (c1 - c0) / scale, (r1 - r0) / scale,
                                       fill=False, edgecolor="white", linewidth=1.0,
                                       path_effects=[withStroke(linewidth=2.2, foreground="black")]))
            ax.set_title(panel.title, fontsize=8.5)
    # One kind: its bar on the right; depth and error side by side: each bar above its panels.
    several = sum(bool(a) for a in (depth_axes, error_axes, confidence_axes)) > 1
    where = dict(location="top", shrink=0.6, aspect=40, pad=0.01) if several else \
        dict(location="right", shrink=0.8, aspect=30, pad=0.02)
    if depth_image is not None:
        cbar = fig.colorbar(depth_image, ax=depth_axes, **where,
                            extend=_extend(depth_values, lo, hi))
        cbar.set_label(f"depth ({units})" if units else "depth", fontsize=9)
        cbar.ax.set_label("colorbar:depth")
    if error_image is not None:
        cbar = fig.colorbar(error_image, ax=error_axes, **where,
                            extend=_extend(errors, 0.0, float(error_max)))
        cbar.set_label(f"|error| ({units})" if units else "|error|", fontsize=9)
        cbar.ax.set_label("colorbar:error")
    if confidence_image is not None:
        cbar = fig.colorbar(confidence_image, ax=confidence_axes, **where)
        cbar.set_label("confidence (1 = most trusted, 0 = no depth)", fontsize=9)
        cbar.ax.set_label("colorbar:confidence")
    if any(p.kind in ("depth", "error") for p in cells):  # the kinds that draw missing pixels gray
        swatch = Patch(facecolor=tuple(c / 255.0 for c in INVALID_COLOR), edgecolor="black", linewidth=0.5,
                       label=INVALID_LABEL)
        fig.legend(handles=[swatch], loc="outside lower right", fontsize=8, frameon=False)
    if title:
        fig.suptitle(title, fontsize=10)
    return fig


def comparison_figure(
    rgb: np.ndarray,
    panels: Sequence[tuple[str, np.ndarray]],
    *,
    units: str,
    zoom: tuple[int, int, int, int] | None = None,
    limits: tuple[float, float] | None = None,
    title: str | None = None,
    ncols: int = 4,
):
    """The color image and depth panels on one scale, ``ncols`` to a row, each row followed by its details.

    Parameters
    ----------
    rgb : (H, W, 3) ndarray
        The color image (first panel).
    panels : sequence of (title, (H, W) depth)
        Depth maps on the color grid (titles should carry the RMSE).
    units : str
        The depth's units, for the colorbar.
    zoom : (row0, row1, col0, col1), optional
        The detail window, marked on every panel and shown enlarged below it.
    limits : (min, max), optional
        The depth range (default: the common range of the panels).
    title : str, optional
    ncols : int
        Panels per row.

    Returns
    -------
    matplotlib.figure.Figure
        See :func:`figure_grid`.
    """
    if ncols < 1:
        raise ValueError(f"ncols must be >= 1; got {ncols}.")
    items = [Panel("color", rgb, "color")] + [Panel(t, d, "depth") for t, d in panels]
    rows: list[list[Panel | None]] = []
    for start in range(0, len(items), ncols):
        row = items[start:start + ncols]
        rows.append(row)
        if zoom is not None:
            rows.append([Panel(f"detail: {p.title.splitlines()[0]}", p.image, p.kind, detail=True) for p in row])
    return figure_grid(rows, units=units, limits=limits, zoom=zoom, title=title)


def depth_figure(depth: np.ndarray, rgb: np.ndarray | None = None, *, units: str, title: str | None = None,
                 limits: tuple[float, float] | None = None, crop: tuple[int, int, int, int] | None = None,
                 scale: float | None = None, confidence: np.ndarray | None = None):
    """One depth map with its colorbar, beside its color image when given (``show``, ``--preview``).

    Parameters
    ----------
    depth : (H, W) ndarray
        NaN (or 0 read from a file, turned into NaN by the caller) = no measurement.
    rgb : (h, w, 3) ndarray, optional
        Shown to the left, at its own resolution.
    units : str
    title : str, optional
    limits : (min, max), optional
    crop : (x, y, width, height), optional
        Show only this window of ``depth`` (pixels; the color image's same
        field of view beside it), pixel for pixel.
    scale : float, optional
        Figure pixels per pixel of the finer image (1: its own resolution).
        With ``crop`` or ``scale`` the panels are placed pixel-exact
        (:func:`depthrefine._picture.pixel_figure`; ``crop`` alone picks a
        whole scale, at most 16, that makes the window about 800 pixels wide); without
        either, the whole map is fitted into a figure about 460 pixels wide
        per panel.
    confidence : (H, W) ndarray, optional
        A confidence map in [0, 1] on ``depth``'s grid, shown to the right
        with its own colorbar (the same window with ``crop``).

    Returns
    -------
    matplotlib.figure.Figure
    """
    if crop is not None or scale is not None:
        from ._picture import check_crop, pixel_figure

        if scale is None:
            _, _, w, _ = check_crop(crop, np.shape(depth)[:2])
            finest = max(w, round(w * rgb.shape[1] / np.shape(depth)[1])) if rgb is not None else w
            scale = float(max(1, min(16, 800 // max(finest, 1))))
        return pixel_figure(depth, rgb, units=units, title=title, limits=limits, crop=crop, scale=scale,
                            confidence=confidence)
    depth = np.asarray(depth, dtype=np.float32)
    valid = int(np.isfinite(depth).sum())
    caption = f"depth {depth.shape[1]}x{depth.shape[0]}, {100.0 * valid / max(depth.size, 1):.1f}% measured"
    row = ([Panel(f"color {rgb.shape[1]}x{rgb.shape[0]}", rgb, "color")] if rgb is not None else [])
    row.append(Panel(caption, depth, "depth"))
    if confidence is not None:
        confidence = np.asarray(confidence, dtype=np.float32)
        row.append(Panel(f"confidence, median {float(np.median(confidence)):.2f}", confidence, "confidence"))
    return figure_grid([row], units=units, limits=limits, title=title, panel_width=4.2)


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
