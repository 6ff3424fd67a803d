"""Where a calibration's board corners fell in the image, and how well the fit reproduces them.

A lens model is only constrained where the board was seen: distortion
fitted from corners that all lie in the image's centre is a guess in its
corners. :func:`coverage_grid` counts the corners of all views in a grid of
cells over the image; :func:`coverage_figure` draws the corners of every
view over the image frame (cells without a corner shaded: unconstrained) and
each corner's reprojection residual as a magnified arrow colored by its
size (``depthrefine calibrate --report DIR``).

Pure: a :class:`~depthrefine.rig.calibrate.CalibrationFit` in, arrays or a
matplotlib ``Figure`` out (matplotlib is imported inside).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Sequence

import numpy as np

if TYPE_CHECKING:
    from .calibrate import CalibrationFit

__all__ = ["COVERAGE_CELLS", "coverage_grid", "uncovered_share", "coverage_figure"]

#: Cells of :func:`coverage_grid` across and down the image.
COVERAGE_CELLS = (8, 6)


def coverage_grid(corners: Sequence[np.ndarray], image_size: tuple[int, int], *,
                  cells: tuple[int, int] = COVERAGE_CELLS) -> np.ndarray:
    """Corners per cell of a ``cells = (across, down)`` grid over a ``(width, height)`` image.

    Parameters
    ----------
    corners : sequence of (N, 2) ndarray
        Each view's corners ``(x, y)``, pixels.
    image_size : (int, int)
        ``(width, height)``.
    cells : (int, int)

    Returns
    -------
    (down, across) int64 ndarray

    Examples
    --------
    >>> coverage_grid([np.array([[1.0, 1.0], [99.0, 49.0]])], (100, 50), cells=(2, 1)).tolist()
    [[1, 1]]
    """
    width, height = image_size
    across, down = cells
    points = np.concatenate([np.asarray(c, np.float64).reshape(-1, 2) for c in corners]) if len(corners) else \
        np.zeros((0, 2))
    col = np.clip((points[:, 0] + 0.5) * across // width, 0, across - 1).astype(np.int64)
    row = np.clip((points[:, 1] + 0.5) * down // height, 0, down - 1).astype(np.int64)
    return np.bincount(row * across + col, minlength=across * down).reshape(down, across)


def uncovered_share(fit: CalibrationFit, *, cells: tuple[int, int] = COVERAGE_CELLS) -> float:
    """The share of the image's cells (:func:`coverage_grid`) holding no corner of any view."""
    grid = coverage_grid([v.corners for v in fit.views], fit.camera.image_size, cells=cells)
    return float((grid == 0).mean())


def coverage_figure(fit: CalibrationFit, *, names: Sequence[str] | None = None, title: str | None = None,
                    cells: tuple[int, int] = COVERAGE_CELLS):
    """Corners of all views over the image frame, and their reprojection residuals.

    Parameters
    ----------
    fit : CalibrationFit
    names : sequence of str, optional
        A name per view (the legend gives each with its RMS error).
    title : str, optional
    cells : (int, int)
        The grid whose empty cells are shaded.

    Returns
    -------
    matplotlib.figure.Figure
        Two panels (axes labels ``"panel:corners"``, ``"panel:residuals"``)
        and a colorbar of the residuals in pixels (``"colorbar:residual"``).
    """
    import matplotlib
    from matplotlib.colors import Normalize
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch, Rectangle

    width, height = fit.camera.image_size
    names = list(names) if names is not None else [f"view {i + 1}" for i in range(len(fit.views))]
    rms = fit.view_rms
    grid = coverage_grid([v.corners for v in fit.views], (width, height), cells=cells)
    aspect = height / width
    fig = Figure(figsize=(11.0, 5.2 * aspect + 1.6), dpi=110, layout="constrained")
    ax_corners, ax_residuals = fig.subplots(1, 2)
    colors = [matplotlib.colormaps["tab20"](i % 20) for i in range(len(fit.views))]
    across, down = cells
    for ax in (ax_corners, ax_residuals):
        ax.set_xlim(-0.5, width - 0.5)
        ax.set_ylim(height - 0.5, -0.5)
        ax.set_aspect("equal")
        ax.add_patch(Rectangle((-0.5, -0.5), width, height, fill=False, edgecolor="black", linewidth=1.0))
        for r in range(down):
            for c in range(across):
                if grid[r, c] == 0:
                    ax.add_patch(Rectangle((c * width / across - 0.5, r * height / down - 0.5), width / across,
                                           height / down, facecolor=(0.95, 0.55, 0.55, 0.45), edgecolor="none"))
        ax.tick_params(labelsize=7)
    for i, view in enumerate(fit.views):
        ax_corners.plot(view.corners[:, 0], view.corners[:, 1], "o", markersize=2.2, color=colors[i],
                        label=f"{names[i]}: {rms[i]:.2f} px")
    empty = int((grid == 0).sum())
    ax_corners.set_title(f"corners of {len(fit.views)} views ({sum(v.count for v in fit.views)}); "
                         f"{empty} of {grid.size} cells without a corner (shaded)", fontsize=8.5)
    points = np.concatenate([v.corners for v in fit.views]).astype(np.float64)
    residuals = np.concatenate(fit.residuals)
    size = np.linalg.norm(residuals, axis=1)
    largest = float(size.max()) if size.size else 0.0
    gain = _round_gain(0.06 * width / largest) if largest > 0 else 1.0
    norm = Normalize(vmin=0.0, vmax=max(largest, 1e-9))
    arrows = ax_residuals.quiver(points[:, 0], points[:, 1], residuals[:, 0] * gain, residuals[:, 1] * gain,
                                 size, cmap="magma_r", norm=norm, angles="xy", scale_units="xy", scale=1.0,
                                 width=0.0025)
    ax_residuals.set_title(f"reprojection residuals, arrows x{gain:g} (RMS {fit.camera.rms:.3f} px, "
                           f"largest {largest:.2f} px)", fontsize=8.5)
    cbar = fig.colorbar(arrows, ax=ax_residuals, shrink=0.8, aspect=30)
    cbar.set_label("reprojection error (px)", fontsize=8)
    cbar.ax.set_label("colorbar:residual")
    ax_corners.set_label("panel:corners")
    ax_residuals.set_label("panel:residuals")
    handles, labels = ax_corners.get_legend_handles_labels()
    shaded = Patch(facecolor=(0.95, 0.55, 0.55, 0.45), label="no corner: the lens is not constrained here")
    fig.legend(handles=[shaded] + handles[:20], labels=[shaded.get_label()] + labels[:20], loc="outside lower center",
               ncol=min(4, len(handles) + 1), fontsize=7, frameon=False, markerscale=2.5)
    if title:
        fig.suptitle(title, fontsize=10)
    return fig


def _round_gain(gain: float) -> float:
    """The largest of 1, 2, 5, 10, 20, 50 ... not above ``gain`` (at least 1).

    Examples
    --------
    >>> _round_gain(99.0), _round_gain(0.3)
    (50.0, 1.0)
    """
    if gain <= 1:
        return 1.0
    decade = 10.0 ** np.floor(np.log10(gain))
    return float(max(m * decade for m in (1, 2, 5) if m * decade <= gain))
