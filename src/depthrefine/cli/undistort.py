"""``depthrefine undistort``: remove the lens distortion from a depth map or an image."""

from __future__ import annotations

import argparse
import sys

from . import CliError
from ._common import add_depth_options, add_overwrite


def add_parser(sub: argparse._SubParsersAction) -> None:
    u = sub.add_parser(
        "undistort",
        help="remove the lens distortion from a depth map or an image (camera file)",
        description=(
            "Undistort IMAGE with a camera file (from `calibrate`; a rig file gives its depth camera, or its "
            "color camera with --color). Depth maps are resampled with the nearest pixel, so two surfaces' "
            "depths never blend and invalid pixels (0) stay invalid; --intensity resamples bilinearly."
        ),
    )
    u.add_argument("image", metavar="IMAGE", help="depth map (default) or intensity/color image (--intensity)")
    u.add_argument("--camera", required=True, metavar="FILE", help="camera, rig or chain settings file")
    u.add_argument("--color", action="store_true", help="from a rig file, use the color camera")
    u.add_argument("--intensity", action="store_true",
                   help="IMAGE is an intensity or color image: bilinear sampling, written as RGB (PNG/TIFF)")
    u.add_argument("-o", "--output", required=True, metavar="OUT", help="output file")
    add_overwrite(u)
    add_depth_options(u)
    u.set_defaults(func=run_undistort)


def run_undistort(args: argparse.Namespace) -> int:
    from ..io import (DEPTH_SUFFIXES, check_depth_format, check_output, read_camera, read_depth, read_rgb,
                      write_depth, write_rgb)
    from ..rig.undistort import undistort_depth, undistort_image

    out = check_output(args.output, overwrite=args.overwrite, inputs=(args.image, args.camera))
    camera = read_camera(args.camera, which="color" if args.color else "depth")
    if args.intensity:
        if out.suffix.lower() not in (".png", ".tif", ".tiff"):
            raise CliError(f"output {out}: write an undistorted image as .png or .tif.")
        write_rgb(out, undistort_image(read_rgb(args.image), camera), overwrite=args.overwrite)
    else:
        if out.suffix.lower() not in DEPTH_SUFFIXES:
            raise CliError(f"output {out}: unknown depth format; use one of {', '.join(DEPTH_SUFFIXES)}.")
        depth = read_depth(args.image, saturated_invalid=args.saturated_invalid)
        check_depth_format(out, depth.dtype)
        write_depth(out, undistort_depth(depth, camera), dtype=depth.dtype, overwrite=args.overwrite)
    w, h = camera.image_size
    print(f"wrote {out} ({w}x{h}, undistorted with {args.camera})", file=sys.stderr)
    return 0
