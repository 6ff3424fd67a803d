"""``depthrefine rig import``: a rig or camera file from another tool's calibration."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from ..rig._names import CALIBRATION_FORMATS, K4A_COLOR_RESOLUTIONS, K4A_DEPTH_MODES
from ._common import add_overwrite, add_shared_options


if TYPE_CHECKING:
    from ..rig.camera import CameraModel


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "rig",
        help="rig files from other tools: `rig import FILE -o rig.json`",
        description="Work with rig files. `depthrefine rig import --help` for the one subcommand.",
    )
    rig_sub = p.add_subparsers(dest="rig_command", metavar="SUBCOMMAND", parser_class=type(p))
    rig_sub.required = True
    i = rig_sub.add_parser(
        "import",
        help="convert an Azure Kinect, OpenCV or ROS calibration into a depthrefine rig or camera file",
        description=(
            "Read another tool's calibration and write it as depthrefine JSON. An Azure Kinect calibration.json "
            "(the device's factory calibration, K4A format; give the capture's --depth-mode and "
            "--color-resolution: the SDK's mode-specific crop and scale are applied) gives a rig file (both "
            "cameras, R and t from the depth camera to the color camera) for `run --rig` and `align --rig`. "
            "An OpenCV FileStorage YAML (K, dist, img_size) or a ROS camera_info YAML holds one camera and gives "
            "a camera file for `undistort --camera` and `calibrate-stereo --depth-camera/--color-camera`."
        ),
    )
    i.add_argument("file", metavar="FILE", help="calibration.json (Azure Kinect), or a .yml/.yaml (OpenCV or ROS)")
    i.add_argument("-o", "--output", required=True, metavar="OUT", help="rig or camera file to write (.json)")
    i.add_argument("--depth-mode", metavar="MODE", type=str.upper,
                   help=f"Azure Kinect depth mode: {', '.join(K4A_DEPTH_MODES)}")
    i.add_argument("--color-resolution", metavar="RES", type=str.upper,
                   help=f"Azure Kinect color resolution: {', '.join(K4A_COLOR_RESOLUTIONS)}")
    add_overwrite(i)
    add_shared_options(i)
    i.set_defaults(func=run_import)


def _camera_line(name: str, camera: CameraModel) -> str:
    fx, fy = camera.focal
    w, h = camera.image_size
    return (f"{name} {w}x{h}: fx {fx:.3f}, fy {fy:.3f}, cx {camera.K[0, 2]:.3f}, cy {camera.K[1, 2]:.3f} px, "
            f"{camera.dist.size} distortion coefficients")


def run_import(args: argparse.Namespace) -> int:
    import numpy as np

    from ..io import check_output, read_calibration, write_camera, write_rig
    from ..rig.camera import CameraModel

    out = check_output(args.output, overwrite=args.overwrite, suffixes=(".json",), inputs=(args.file,))
    calibration, kind = read_calibration(args.file, depth_mode=args.depth_mode,
                                         color_resolution=args.color_resolution)
    extra = {"imported_from": Path(args.file).name, "format": CALIBRATION_FORMATS[kind]}
    if isinstance(calibration, CameraModel):
        write_camera(out, calibration, overwrite=args.overwrite, extra=extra)
        print(f"wrote camera file {out}: " + _camera_line("camera", calibration), file=sys.stderr)
        return 0
    extra.update(depth_mode=args.depth_mode, color_resolution=args.color_resolution)
    write_rig(out, calibration, overwrite=args.overwrite, extra=extra)
    print(f"wrote rig file {out}: " + "; ".join([
        _camera_line("depth camera", calibration.depth_camera),
        _camera_line("color camera", calibration.color_camera),
        f"color camera at {np.round(calibration.color_centre, 4).tolist()} m from the depth camera, rotated "
        f"{calibration.rotation_degrees:.2f} deg",
    ]), file=sys.stderr)
    return 0
