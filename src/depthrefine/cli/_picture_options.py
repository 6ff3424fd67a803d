"""The picture options of ``show`` and ``--preview`` (refine, run): --crop, --scale, --full, defined once."""

from __future__ import annotations

import argparse
import math
import re
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np

__all__ = ["parse_crop", "parse_scale", "add_picture_options", "add_preview_option", "picture_options",
           "check_window", "write_preview"]


def parse_crop(text: str) -> tuple[int, int, int, int]:
    """``"100,50,320,240"`` -> ``(100, 50, 320, 240)``: X,Y of the top-left pixel, WIDTH,HEIGHT."""
    m = re.fullmatch(r"\s*(\d+)\s*,\s*(\d+)\s*,\s*(\d+)\s*,\s*(\d+)\s*", text)
    if not m or int(m.group(3)) < 1 or int(m.group(4)) < 1:
        raise argparse.ArgumentTypeError(
            "expected X,Y,WIDTH,HEIGHT in pixels (top-left corner, then size > 0) such as 800,600,320,240; "
            f"got {text!r}")
    return tuple(int(g) for g in m.groups())  # type: ignore[return-value]


def parse_scale(text: str) -> float:
    """``"4"``, ``"0.5"`` -> figure pixels per image pixel (> 0, at most 64)."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and 0 < value <= 64):
        raise argparse.ArgumentTypeError(f"expected figure pixels per image pixel, 0 < F <= 64, such as 4 or 0.5; "
                                         f"got {text!r}")
    return value


def add_picture_options(parser: argparse.ArgumentParser, *, what: str = "the picture") -> None:
    """``--crop X,Y,W,H`` and ``--scale F`` / ``--full`` (mutually exclusive)."""
    parser.add_argument("--crop", type=parse_crop, metavar="X,Y,W,H",
                        help=f"{what}: only this window of the depth map, in its pixels (top-left X,Y, then width and "
                             "height); the color image shows the same field of view. Without --scale it is enlarged "
                             "by a whole factor (at most 16) to about 800 pixels wide, pixel for pixel")
    size = parser.add_mutually_exclusive_group()
    size.add_argument("--scale", type=parse_scale, metavar="F",
                      help=f"{what}: F picture pixels per image pixel (of the finer of depth and color), e.g. 4 to "
                           "see single pixels, 0.5 for half size; default: fitted to about 460 pixels per panel")
    size.add_argument("--full", action="store_true",
                      help=f"{what}: at the image's own resolution (--scale 1)")


def add_preview_option(parser: argparse.ArgumentParser) -> None:
    """``--preview PNG`` with the picture options (for commands that write a depth map)."""
    parser.add_argument("--preview", metavar="PNG",
                        help="also write a picture of the result (colorbar in the depth's units) beside the color "
                             "image (and its confidence map, with --confidence or --min-confidence)")
    add_picture_options(parser, what="--preview")


def picture_options(args: argparse.Namespace) -> dict[str, Any]:
    """``crop`` and ``scale`` for :func:`depthrefine.viz.depth_figure` from --crop, --scale, --full."""
    if getattr(args, "preview", "unset") is None and (args.crop or args.scale or args.full):
        given = [flag for flag, value in (("--crop", args.crop), ("--scale", args.scale), ("--full", args.full))
                 if value]
        raise ValueError(f"{' and '.join(given)} set the --preview picture; add --preview PNG.")
    return {"crop": args.crop, "scale": 1.0 if args.full else args.scale}


def check_window(args: argparse.Namespace, shape: tuple[int, int]) -> None:
    """Check --crop (and that the picture options come with --preview) against the picture's grid, before any work."""
    from .._picture import check_crop

    options = picture_options(args)
    if options["crop"] is not None:
        check_crop(options["crop"], shape, name="--crop")


def write_preview(args: argparse.Namespace, path: Path, depth: np.ndarray, rgb: np.ndarray, *, units: str,
                  title: str, confidence: np.ndarray | None = None) -> Path:
    """Draw ``depth`` beside ``rgb`` (and its ``confidence`` map, when given) as --crop / --scale / --full say and
    write it to ``path`` (--preview)."""
    from .. import viz
    from ..io import write_figure

    fig = viz.depth_figure(depth, rgb, units=units, title=title, confidence=confidence, **picture_options(args))
    return write_figure(path, fig, overwrite=args.overwrite)
