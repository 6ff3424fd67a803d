"""The folder of ``refine --save-intermediate``: the result's pictures, a method's intermediates, the run record."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from ._images import write_figure, write_rgb

if TYPE_CHECKING:
    from ..methods.intermediates import Intermediates

__all__ = ["write_intermediates"]


def write_intermediates(folder: str | os.PathLike, intermediates: Intermediates | None, *, depth_hr: np.ndarray,
                        rgb_hr: np.ndarray, record: Mapping[str, Any], units: str, factor: float = 1.0) -> Path:
    """Write the result and a method's intermediates as pictures, and the run's record, into ``folder``.

    Always: ``result_colorized.png`` and ``result_blended.png`` (``depth_hr``
    over ``rgb_hr``), one depth range and colorbar in ``units`` for every
    depth picture; then each of ``intermediates.pictures`` under its name,
    its ``arrays`` as ``intermediates.npz`` and ``run.json``: ``record`` with
    ``intermediates.record`` added.

    Parameters
    ----------
    folder : path
        An existing folder (the caller makes it atomic).
    intermediates : Intermediates or None
        From the method's ``intermediates`` hook; None for a method without one.
    depth_hr : (H, W) float ndarray
        The result as written (after ``--output-scale``).
    rgb_hr : (H, W, 3) ndarray
        The color image.
    record : mapping
        The run's record (JSON-ready).
    units : str
        The depth's units, for the colorbars.
    factor : float
        ``--output-scale``: the intermediates' depth pictures are multiplied by
        it, so they are drawn in the units of the result.

    Returns
    -------
    Path
        ``folder``.
    """
    from .. import viz

    folder = Path(folder)
    limits = viz.depth_limits(depth_hr)

    def depth_picture(name: str, panel) -> None:
        write_figure(folder / name, viz.figure_grid([[panel]], units=units, limits=limits, panel_width=6.0))

    depth_picture("result_colorized.png", viz.Panel("result", depth_hr, "depth"))
    depth_picture("result_blended.png", viz.Panel("result over the color image", depth_hr, "blend", background=rgb_hr))
    record = dict(record)
    if intermediates is not None:
        for name, picture in intermediates.pictures.items():
            if picture.kind == "color":
                write_rgb(folder / name, viz.to_rgb8(picture.data))
            elif picture.kind == "labels":
                write_rgb(folder / name, viz.colorize_labels(picture.data, picture.groups))
            else:
                depth_picture(name, viz.Panel(picture.title, picture.data * factor, "samples",
                                              background=picture.background))
        if intermediates.arrays:
            np.savez_compressed(folder / "intermediates.npz", **intermediates.arrays)
        record.update(intermediates.record)
    (folder / "run.json").write_text(json.dumps(record, indent=2) + "\n", encoding="utf-8")
    return folder
