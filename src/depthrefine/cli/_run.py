"""``depthrefine run`` (raw captures -> refined depth) and ``depthrefine export-ply``."""

from __future__ import annotations

import argparse
import contextlib
import sys
from pathlib import Path
from typing import Any

import numpy as np

from ..align import align_pair, undistort_image
from ..io import (DEPTH_SUFFIXES, ChainSettings, check_output, read_camera, read_chain_settings, read_depth,
                  read_mapping, read_patch_layout, read_rgb, write_chain_settings, write_depth, write_ply)
from ..methods import get_method, refine
from ..params import params_from_mapping
from ..pointcloud import depth_to_points
from ..scale import plan_scale
from . import CliError
from ._align import add_align_options, add_units_options, chain_settings
from ._common import add_depth_options, add_overwrite, add_params_options, params_dict, progress_bar


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "run",
        help="the whole chain on raw captures: undistort, scale, align, refine",
        description=(
            "From a raw depth map and a raw color image of a calibrated rig to a refined depth map on the "
            "color image's grid: undistort both (spec step 1), align the depth with the color camera "
            "(step 3: reproject by default, or the thesis's shift), then refine (the scale step, step 2, "
            "happens there when the color/depth ratio is not an integer). --rig takes the rig file, or a "
            "chain settings file (TOML/JSON) holding the rig, [align] and [refine]; options given here "
            "override the file. The output keeps DEPTH's dtype and units."
        ),
    )
    p.add_argument("depth", metavar="DEPTH", help="raw depth map of the rig's depth camera")
    p.add_argument("color", metavar="COLOR", help="raw color image of the rig's color camera")
    p.add_argument("-o", "--output", required=True, metavar="OUT", help="refined depth (.png, .tif, .npy)")
    p.add_argument("--rig", required=True, metavar="FILE",
                   help="rig file (calibrate-stereo) or chain settings file (TOML/JSON)")
    p.add_argument("--settings", metavar="FILE",
                   help="chain settings file ([align], [refine]) when --rig is a plain rig file")
    add_align_options(p, method_flag="--align")
    add_params_options(p)
    p.set_defaults(method=None)
    p.add_argument("--ply", metavar="FILE", help="also write the refined depth as a colored point cloud (.ply)")
    p.add_argument("--ply-stride", type=int, default=1, metavar="N",
                   help="point cloud: keep every N-th row and column (default 1)")
    p.add_argument("--save-aligned", metavar="FILE",
                   help="also write the aligned low-resolution depth (before refinement)")
    p.add_argument("--save-settings", metavar="FILE",
                   help="also write the chain settings used (rig inline) as JSON, to rerun with --rig FILE")
    add_overwrite(p)
    add_depth_options(p)
    p.set_defaults(func=run_chain)

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


def _refine_params(args: argparse.Namespace, chain: ChainSettings) -> tuple[str, Any]:
    """The refinement method and its parameters: the settings file's, then --params, then options.

    The file's ``[refine.params]`` apply only to the file's method (a
    different ``--method`` starts from its own defaults).
    """
    method = args.method or chain.method or "thesis"
    entry = get_method(method)
    overrides: dict[str, Any] = {}
    if chain.params and method == (chain.method or "thesis"):
        overrides.update(chain.params)
    if args.params:
        overrides.update(read_mapping(args.params, what="parameter"))
    if args.patches is not None:
        overrides["patches"] = args.patches
    if args.patch_file is not None:
        overrides["patch_layout"] = read_patch_layout(args.patch_file)
    if args.clusters is not None:
        overrides["n_clusters"] = args.clusters
    if entry.params_type is None:
        if overrides:
            raise CliError(f"method {method!r} takes no parameters; drop {', '.join(sorted(overrides))}.")
        return method, None
    return method, params_from_mapping(entry.params_type, overrides, source="refinement parameters")


def run_chain(args: argparse.Namespace) -> int:
    inputs = (args.depth, args.color, args.rig, args.settings)
    out = check_output(args.output, overwrite=args.overwrite, suffixes=DEPTH_SUFFIXES, inputs=inputs)
    extra_outputs = {}
    for flag, path, suffixes in (("--ply", args.ply, (".ply",)), ("--save-aligned", args.save_aligned, DEPTH_SUFFIXES),
                                 ("--save-settings", args.save_settings, (".json",))):
        if path:
            extra_outputs[flag] = check_output(path, overwrite=args.overwrite, suffixes=suffixes, inputs=inputs,
                                               what=f"{flag} file")
    paths = [out.resolve()] + [p.resolve() for p in extra_outputs.values()]
    if len(set(paths)) != len(paths):
        raise CliError("the output files must all be different.")
    if args.ply_stride < 1:
        raise CliError(f"--ply-stride must be >= 1; got {args.ply_stride}.")
    chain = chain_settings(args)
    align = chain.align
    if args.ply and align.depth_units is None and align.inverse_scale is None:
        raise CliError("--ply needs the depth's units: --depth-units M or --inverse-depth-scale C "
                       "(or depth_units / inverse_scale in the settings file's [align]).")
    method, params = _refine_params(args, chain)

    depth_raw = read_depth(args.depth, saturated_invalid=args.saturated_invalid)
    for path in [out] + [p for f, p in extra_outputs.items() if f == "--save-aligned"]:
        _check_png_dtype(path, depth_raw.dtype)
    rgb_raw = read_rgb(args.color)
    pair = align_pair(depth_raw, rgb_raw, chain.rig, settings=align)
    step = plan_scale(pair.depth_lr.shape, pair.rgb_hr.shape)
    update, close = progress_bar(f"refine ({method})")
    try:
        depth_hr = refine(pair.depth_lr, pair.rgb_hr, method=method, params=params, progress=update)
    finally:
        close()
    cloud = None
    if args.ply:
        cloud = depth_to_points(depth_hr, pair.camera, rgb=pair.rgb_hr, depth_units=align.depth_units,
                                inverse_scale=align.inverse_scale, distorted=pair.camera.has_distortion,
                                stride=args.ply_stride)

    written: list[Path] = []
    try:
        written.append(write_depth(out, depth_hr, dtype=depth_raw.dtype, overwrite=args.overwrite))
        if "--save-aligned" in extra_outputs:
            written.append(write_depth(extra_outputs["--save-aligned"], pair.depth_lr, dtype=depth_raw.dtype,
                                       overwrite=args.overwrite))
        if cloud is not None:
            written.append(write_ply(extra_outputs["--ply"], *cloud, overwrite=args.overwrite,
                                     comments=(f"depthrefine run {Path(args.depth).name} {Path(args.color).name}",
                                               "metres, color camera frame: X right, Y down, Z forward")))
        if "--save-settings" in extra_outputs:
            used = ChainSettings(rig=chain.rig, align=align, method=method, params=params_dict(params),
                                 rig_source=chain.rig_source)
            written.append(write_chain_settings(extra_outputs["--save-settings"], used, overwrite=args.overwrite))
    except BaseException:
        for path in written:  # all or nothing
            with contextlib.suppress(OSError):
                path.unlink()
        raise
    h, w = depth_hr.shape
    notes = list(pair.notes) + [step.describe(), f"refined with {method}"]
    print(f"wrote {out} ({w}x{h}, {depth_raw.dtype}): " + "; ".join(notes), file=sys.stderr)
    if cloud is not None:
        print(f"wrote {extra_outputs['--ply']} ({cloud[0].shape[0]} points)", file=sys.stderr)
    return 0


def run_export_ply(args: argparse.Namespace) -> int:
    out = check_output(args.output, overwrite=args.overwrite, suffixes=(".ply",), inputs=(args.depth, args.color))
    if args.stride < 1:
        raise CliError(f"--stride must be >= 1; got {args.stride}.")
    depth_units, inverse_scale = args.depth_units, args.inverse_depth_scale
    if depth_units is None and inverse_scale is None:
        chain = read_chain_settings(args.rig) if _is_settings(args.rig) else None
        if chain is not None:
            depth_units, inverse_scale = chain.align.depth_units, chain.align.inverse_scale
    if depth_units is None and inverse_scale is None:
        raise CliError("the depth's units are unknown: give --depth-units M (0.001 for uint16 mm) or, for 8-bit "
                       "depth intensity (larger = nearer), --inverse-depth-scale C with metres = C / value.")
    camera = read_camera(args.rig, which="color")
    depth = read_depth(args.depth, saturated_invalid=args.saturated_invalid)
    rgb = read_rgb(args.color)
    if rgb.shape[:2] != camera.shape:
        raise CliError(f"COLOR is {rgb.shape[1]}x{rgb.shape[0]} but the color camera of {args.rig} was "
                       f"calibrated on {camera.image_size[0]}x{camera.image_size[1]} images.")
    if depth.shape != rgb.shape[:2]:
        raise CliError(f"DEPTH is {depth.shape[1]}x{depth.shape[0]} but COLOR is {rgb.shape[1]}x{rgb.shape[0]}; "
                       "export the refined depth (on the color grid), e.g. the output of `run`.")
    distorted = camera.has_distortion and args.distorted_grid
    if camera.has_distortion and not args.distorted_grid:
        if not args.no_undistort:
            rgb = undistort_image(rgb, camera)
        camera = camera.without_distortion()
    points, colors = depth_to_points(depth, camera, rgb=rgb, depth_units=depth_units, inverse_scale=inverse_scale,
                                     distorted=distorted, stride=args.stride)
    write_ply(out, points, colors, overwrite=args.overwrite,
              comments=("metres, color camera frame: X right, Y down, Z forward",))
    print(f"wrote {out} ({points.shape[0]} points)", file=sys.stderr)
    return 0


def _is_settings(path: str) -> bool:
    data = read_mapping(path, what="rig")
    return any(k in data for k in ("align", "refine", "rig"))


def _check_png_dtype(out: Path, dtype: np.dtype) -> None:
    if out.suffix.lower() in (".png", ".pgm") and dtype not in (np.uint8, np.uint16):
        raise CliError(f"output {out}: the depth is {dtype}, which {out.suffix} cannot hold; write .tif or .npy.")
