"""``depthrefine align`` and ``depthrefine undistort``: put a raw depth map on the color grid."""

from __future__ import annotations

import argparse
import dataclasses
import sys
from typing import Any

import numpy as np

from ..align import ALIGN_METHODS, COLOR_SIDES, ENCODINGS, align_depth, undistort_depth, undistort_image
from ..io import (DEPTH_SUFFIXES, ChainSettings, check_output, read_camera, read_chain_settings, read_depth,
                  read_rgb, write_depth, write_rgb)
from . import CliError
from ._common import add_depth_options, add_overwrite


def add_units_options(p: argparse.ArgumentParser) -> None:
    """--depth-units / --inverse-depth-scale: how depth values become metres."""
    units = p.add_mutually_exclusive_group()
    units.add_argument("--depth-units", type=float, metavar="M",
                       help="metres per depth unit, for depth that grows with distance (0.001 for uint16 mm)")
    units.add_argument("--inverse-depth-scale", type=float, metavar="C",
                       help="for 8-bit depth intensity / disparity (larger = nearer): metres = C / value "
                            "(255 at z_min metres: C = 255 * z_min)")


def add_align_options(p: argparse.ArgumentParser, *, method_flag: str) -> None:
    """The alignment options shared by ``align`` and ``run`` (None = take the settings file's value)."""
    p.add_argument(method_flag, dest="align_method", choices=ALIGN_METHODS, default=None,
                   help="alignment: reproject (calibrated, any rig; default) or shift (the thesis's "
                        "horizontal shift: a parallel rig whose color image shows the depth camera's view; "
                        "refused when the background would land more than 1 depth pixel off)")
    add_units_options(p)
    p.add_argument("--factor", type=int, metavar="S",
                   help="reproject: scale factor s, the output is the color grid / s (default: focal-length ratio)")
    p.add_argument("--radial", action="store_true", default=None,
                   help="reproject: the depth is the distance along each ray, not Z")
    p.add_argument("--slope", type=float, metavar="K",
                   help="shift: k, the shift in depth pixels is k * (d - d_bg) for --encoding inverse (k in "
                        "depth pixels per depth unit) and k * (1/D - 1/D_bg) for distance (k in depth pixels "
                        "times depth units); default: from the rig and the depth units")
    p.add_argument("--background", type=float, metavar="D",
                   help="shift: background depth d_bg, which does not move (default: mean of the farther half)")
    p.add_argument("--color-side", choices=COLOR_SIDES, default=None,
                   help="shift: side of the color camera seen from behind (default: from the rig)")
    p.add_argument("--encoding", choices=ENCODINGS, default=None,
                   help="shift: inverse (depth intensity, larger = nearer) or distance (mm, m); default: "
                        "distance with --depth-units, else inverse")
    p.add_argument("--no-undistort", action="store_true",
                   help="the depth map and color image are already undistorted: neither is resampled and "
                        "the depth is aligned to the undistorted color camera")


def chain_settings(args: argparse.Namespace) -> ChainSettings:
    """The chain settings of ``--rig`` (and ``--settings``), with the command-line options on top."""
    base = read_chain_settings(args.rig)
    settings_file = getattr(args, "settings", None)
    if settings_file:
        extra = read_chain_settings(settings_file)
        base = dataclasses.replace(extra, rig=base.rig or extra.rig,
                                   rig_source=base.rig_source if base.rig is not None else extra.rig_source)
    if base.rig is None:
        raise CliError(f"{args.rig} holds no rig; give a rig file from `depthrefine calibrate-stereo`.")
    overrides: dict[str, Any] = {}
    for option, key in (("align_method", "method"), ("factor", "factor"), ("radial", "radial"),
                        ("slope", "slope"), ("background", "background"), ("color_side", "color_side"),
                        ("encoding", "encoding")):
        value = getattr(args, option)
        if value is not None:
            overrides[key] = value
    if args.depth_units is not None:
        overrides.update(depth_units=args.depth_units, inverse_scale=None)
    if args.inverse_depth_scale is not None:
        overrides.update(inverse_scale=args.inverse_depth_scale, depth_units=None)
    if args.no_undistort:
        overrides.update(undistort_depth=False, undistort_color=False)
    try:
        align = dataclasses.replace(base.align, **overrides)
    except (TypeError, ValueError) as exc:
        raise CliError(f"alignment settings: {exc}") from None
    return dataclasses.replace(base, align=align)


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
    add_align_options(p, method_flag="--method")
    add_overwrite(p)
    add_depth_options(p)
    p.set_defaults(func=run_align)

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


def run_align(args: argparse.Namespace) -> int:
    out = check_output(args.output, overwrite=args.overwrite, suffixes=DEPTH_SUFFIXES, inputs=(args.depth, args.rig))
    settings = chain_settings(args)
    depth = read_depth(args.depth, saturated_invalid=args.saturated_invalid)
    _check_png_dtype(out, depth.dtype)
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


def run_undistort(args: argparse.Namespace) -> int:
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
        _check_png_dtype(out, depth.dtype)
        write_depth(out, undistort_depth(depth, camera), dtype=depth.dtype, overwrite=args.overwrite)
    w, h = camera.image_size
    print(f"wrote {out} ({w}x{h}, undistorted with {args.camera})", file=sys.stderr)
    return 0


def _check_png_dtype(out, dtype) -> None:
    if out.suffix.lower() in (".png", ".pgm") and dtype not in (np.uint8, np.uint16):
        raise CliError(f"output {out}: the depth is {dtype}, which {out.suffix} cannot hold; write .tif or .npy.")
