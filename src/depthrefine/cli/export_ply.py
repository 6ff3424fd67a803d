"""``depthrefine export-ply``: a colored point cloud from a depth map on the color camera's grid."""

from __future__ import annotations

import argparse
import sys

from . import CliError
from ._common import add_depth_options, add_overwrite
from ._rig_options import add_units_options, warn_implausible_units


def add_parser(sub: argparse._SubParsersAction) -> None:
    e = sub.add_parser(
        "export-ply",
        help="write a depth map on a color image's grid as a colored point cloud (PLY)",
        description=(
            "Back-project DEPTH (on COLOR's grid, e.g. the output of `run`) with the color camera of --rig and "
            "write the points (metres, the color camera's frame: X right, Y down, Z forward) with their "
            "colors as binary PLY. COLOR is undistorted first when the camera has distortion (as `run` does)."
        ),
    )
    e.add_argument("depth", metavar="DEPTH", help="depth map on the color image's grid")
    e.add_argument("color", metavar="COLOR", help="the color image (raw, as given to `run`)")
    e.add_argument("-o", "--output", required=True, metavar="OUT", help="point cloud (.ply)")
    e.add_argument("--rig", required=True, metavar="FILE",
                   help="rig or chain settings file (its color camera), or a camera file")
    add_units_options(e)
    e.add_argument("--stride", type=int, default=1, metavar="N", help="keep every N-th row and column")
    grid = e.add_mutually_exclusive_group()
    grid.add_argument("--no-undistort", action="store_true",
                      help="COLOR is already undistorted (as in align and run): use it as it is")
    grid.add_argument("--distorted-grid", action="store_true",
                      help="DEPTH and COLOR are on the raw (distorted) color grid: back-project through the "
                           "lens distortion")
    add_overwrite(e)
    add_depth_options(e)
    e.set_defaults(func=run_export_ply)


def run_export_ply(args: argparse.Namespace) -> int:
    from ..io import check_distinct_inputs, check_output, read_camera, read_depth, read_depth_units, read_rgb, write_ply
    from ..rig.pointcloud import color_grid_points

    out = check_output(args.output, overwrite=args.overwrite, suffixes=(".ply",), inputs=(args.depth, args.color))
    check_distinct_inputs(args.depth, args.color)
    if args.stride < 1:
        raise CliError(f"--stride must be >= 1; got {args.stride}.")
    depth_units, inverse_scale = args.depth_units, args.inverse_depth_scale
    if depth_units is None and inverse_scale is None:
        depth_units, inverse_scale = read_depth_units(args.rig)
    if depth_units is None and inverse_scale is None:
        raise CliError("the depth's units are unknown: give --depth-units M (0.001 for uint16 mm) or, for 8-bit "
                       "depth intensity (larger = nearer), --inverse-depth-scale C with metres = C / value.")
    camera = read_camera(args.rig, which="color")
    depth = read_depth(args.depth, saturated_invalid=args.saturated_invalid)
    warn_implausible_units("export-ply", depth, depth_units=depth_units, inverse_scale=inverse_scale)
    rgb = read_rgb(args.color)
    if rgb.shape[:2] != camera.shape:
        raise CliError(f"COLOR is {rgb.shape[1]}x{rgb.shape[0]} but the color camera of {args.rig} was "
                       f"calibrated on {camera.image_size[0]}x{camera.image_size[1]} images.")
    if depth.shape != rgb.shape[:2]:
        raise CliError(f"DEPTH is {depth.shape[1]}x{depth.shape[0]} but COLOR is {rgb.shape[1]}x{rgb.shape[0]}; "
                       "export the refined depth (on the color grid), e.g. the output of `run`.")
    points, colors = color_grid_points(depth, rgb, camera, depth_units=depth_units, inverse_scale=inverse_scale,
                                       raw_grid=args.distorted_grid, color_undistorted=args.no_undistort,
                                       stride=args.stride)
    write_ply(out, points, colors, overwrite=args.overwrite,
              comments=("metres, color camera frame: X right, Y down, Z forward",))
    print(f"wrote {out} ({points.shape[0]} points)", file=sys.stderr)
    return 0
