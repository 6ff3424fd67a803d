"""``depthrefine show DEPTH [COLOR] -o PNG``: look at any depth file, with a colorbar."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .. import viz
from ._confidence import read_shown_confidence
from ._common import add_depth_options, add_overwrite, add_units_option, depth_units_label, parse_range
from ._picture_options import add_picture_options, check_window, picture_options


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "show",
        help="draw a depth file as a picture with a colorbar (beside its color image)",
        description=(
            "Draw DEPTH (8/16-bit PNG, float TIFF or .npy; 0, NaN = no measurement, drawn gray) with the "
            f"{viz.DEPTH_COLORMAP} colormap and a colorbar in its units, beside COLOR when given, and write "
            "the picture as PNG."
        ),
    )
    p.add_argument("depth", metavar="DEPTH", help="depth map (any resolution)")
    p.add_argument("color", metavar="COLOR", nargs="?", help="color image to show beside it (optional)")
    p.add_argument("-o", "--output", required=True, metavar="PNG", help="the picture (.png)")
    add_units_option(p)
    p.add_argument("--range", type=parse_range, metavar="MIN,MAX",
                   help="the colorbar's range, in the depth's units (default: the map's own min and max); "
                        "give the same range to compare several pictures")
    p.add_argument("--confidence", metavar="FILE",
                   help="also draw this confidence map (refine/run --confidence: .tif, .npy or 16-bit .png) beside "
                        "the depth, on its own 0..1 colorbar")
    add_picture_options(p)
    add_overwrite(p)
    add_depth_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from .._validate import as_depth
    from ..io import check_distinct_inputs, check_output, read_depth, read_rgb, write_figure

    inputs = (args.depth,) + ((args.color,) if args.color else ()) + ((args.confidence,) if args.confidence else ())
    out = check_output(args.output, overwrite=args.overwrite, suffixes=(".png",), inputs=inputs)
    if args.color:
        check_distinct_inputs(args.depth, args.color)
    raw = read_depth(args.depth, saturated_invalid=args.saturated_invalid)
    rgb = read_rgb(args.color) if args.color else None
    depth = as_depth(raw, name=f"depth file {args.depth}")
    check_window(args, depth.shape)
    confidence = read_shown_confidence(args.confidence, depth.shape) if args.confidence else None
    fig = viz.depth_figure(depth, rgb, units=depth_units_label(args.units, raw.dtype), title=Path(args.depth).name,
                           limits=args.range, confidence=confidence, **picture_options(args))
    write_figure(out, fig, overwrite=args.overwrite)
    print(f"wrote {out}", file=sys.stderr)
    return 0
