"""``depthrefine align``: put a raw depth map on the color grid (undistort, then shift or reproject)."""

from __future__ import annotations

import argparse
import sys

from ._common import add_depth_options, add_overwrite
from ._rig_options import add_align_options, chain_settings, warn_implausible_units


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "align",
        help="undistort a raw depth map and align it with the color camera (rig file)",
        description=(
            "Undistort DEPTH with the rig's depth camera and align it with the color camera: by reprojection "
            "through the calibrated rig (default; needs --depth-units or --inverse-depth-scale; the output is "
            "on the color image's grid divided by s), or by the thesis's horizontal shift k * (d - d_bg) (the "
            "output stays on the depth map's own grid, which refine stretches over the color image). The "
            "output keeps DEPTH's dtype and units and lines up with the *undistorted* color image: refine it "
            "with `depthrefine refine OUT COLOR`, COLOR being `depthrefine undistort RAW_COLOR --camera RIG "
            "--color --intensity -o COLOR` when the color lens has distortion (`run` does all of this)."
        ),
    )
    p.add_argument("depth", metavar="DEPTH", help="raw depth map of the rig's depth camera")
    p.add_argument("-o", "--output", required=True, metavar="OUT", help="aligned depth (.png, .tif, .npy)")
    p.add_argument("--rig", required=True, metavar="FILE",
                   help="rig file (calibrate-stereo) or chain settings file (TOML/JSON) with the rig")
    add_align_options(p)
    add_overwrite(p)
    add_depth_options(p)
    p.set_defaults(func=run_align)


def run_align(args: argparse.Namespace) -> int:
    from ..io import DEPTH_SUFFIXES, check_depth_format, check_output, read_depth, write_depth
    from ..rig.chain import align_depth

    out = check_output(args.output, overwrite=args.overwrite, suffixes=DEPTH_SUFFIXES, inputs=(args.depth, args.rig))
    settings = chain_settings(args)
    depth = read_depth(args.depth, saturated_invalid=args.saturated_invalid)
    warn_implausible_units("align", depth, depth_units=settings.align.depth_units,
                           inverse_scale=settings.align.inverse_scale)
    check_depth_format(out, depth.dtype)
    depth_lr, notes = align_depth(depth, settings.rig, settings=settings.align)
    write_depth(out, depth_lr, dtype=depth.dtype, overwrite=args.overwrite)
    if settings.rig.color_camera.has_distortion and settings.align.undistort_color:
        notes = list(notes) + [
            "aligned to the undistorted color image: the color lens has distortion, so refine against "
            f"`depthrefine undistort COLOR --camera {args.rig} --color --intensity -o COLOR_UNDISTORTED`"
        ]
    h, w = depth_lr.shape
    print(f"wrote {out} ({w}x{h}, {depth.dtype}): " + "; ".join(notes), file=sys.stderr)
    return 0
