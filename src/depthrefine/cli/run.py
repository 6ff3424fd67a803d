"""``depthrefine run``: raw captures -> refined depth (undistort, scale, align, refine), optionally a PLY."""

from __future__ import annotations

import argparse
import contextlib
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..methods._names import DEFAULT_METHOD, RegisteredMethodNames
from ..rig._names import ALIGN_METHODS
from . import CliError
from ._rig_options import add_align_options, chain_settings, warn_implausible_units
from ._confidence import (add_confidence_options, apply_min_confidence, check_confidence_output, confidence_note,
                          refine_pair_maybe_confident)
from ._common import (add_deprecated_alias, add_depth_options, add_output_format_options, add_overwrite,
                      add_params_options, build_params, output_depth, params_dict, progress_bar)
from ._picture_options import add_preview_option, check_window, write_preview

if TYPE_CHECKING:
    from ..io import ChainSettings

#: What --save-color writes.
COLOR_SUFFIXES = (".png", ".jpg", ".jpeg", ".tif", ".tiff")


class _AlignMethod(argparse.Action):
    """``run --method``: the alignment method; a refinement method's name (the old meaning) still works.

    Before ``--method`` named the alignment method in ``run`` as it does in
    ``align``, it named the refinement method. The two sets of names do not
    overlap, so an old command line keeps working, with a note.
    """

    def __call__(self, parser, namespace, values, option_string=None):
        if values in ALIGN_METHODS:
            namespace.align_method = values
        elif values in RegisteredMethodNames():
            print(f"depthrefine: note: run {option_string} {values} for the refinement method is deprecated; "
                  f"use --refine-method {values} ({option_string} is the alignment method: "
                  f"{', '.join(ALIGN_METHODS)}).", file=sys.stderr)
            namespace.method = values
        else:
            parser.error(f"argument {option_string}: invalid choice: {values!r} (the alignment method: choose "
                         f"from {', '.join(ALIGN_METHODS)}; the refinement method is --refine-method)")


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "run",
        help="the whole chain on raw captures: undistort, scale, align, refine",
        description=(
            "From a raw depth map and a raw color image of a calibrated rig to a refined depth map on the "
            "color image's grid: undistort both (spec step 1), align the depth with the color camera "
            "(step 3: reproject by default, onto a grid at the depth camera's resolution, or the thesis's "
            "shift), then refine: the method upsamples by an integer factor of at least 2 (the scale step, "
            "step 2: the color image is resized onto that grid when the ratio is not an integer and the "
            "result resized back). --rig takes the rig file, or a chain settings file (TOML/JSON) holding the "
            "rig, [align] and [refine]; options given here override the file. The output keeps DEPTH's dtype "
            "and units unless --output-dtype/--output-scale say otherwise (float32 .tif/.npy keeps the "
            "refined depth's fractions)."
        ),
    )
    p.add_argument("depth", metavar="DEPTH", help="raw depth map of the rig's depth camera")
    p.add_argument("color", metavar="COLOR", help="raw color image of the rig's color camera")
    p.add_argument("-o", "--output", required=True, metavar="OUT", help="refined depth (.png, .tif, .npy)")
    p.add_argument("--rig", required=True, metavar="FILE",
                   help="rig file (calibrate-stereo) or chain settings file (TOML/JSON)")
    p.add_argument("--settings", metavar="FILE",
                   help="chain settings file ([align], [refine]) when --rig is a plain rig file")
    add_align_options(p, method_action=_AlignMethod)
    add_deprecated_alias(p, "--align", new="--method", dest="align_method", choices=ALIGN_METHODS)
    add_params_options(p, method_flag="--refine-method", method_help=(
        f"refinement method, as refine --method (default: the settings file's [refine] method, else "
        f"{DEFAULT_METHOD}); --method is the alignment method here, as in align"))
    p.set_defaults(method=None)
    p.add_argument("--fill-holes", action="store_true",
                   help="fill the holes that lie inside one measured surface (a dropout on a dark or shiny spot) "
                        "with the refinement's depth; what lies beyond any measurement (outside the depth "
                        "camera's view, hidden from it) stays invalid (0), as do all holes by default (their "
                        "border follows the color edges within 2 depth pixels, so a strip that narrow between "
                        "two surfaces goes to them). Also fill_holes = true in the settings file's [refine]")
    p.add_argument("--ply", metavar="FILE", help="also write the refined depth as a colored point cloud (.ply)")
    p.add_argument("--stride", type=int, default=1, metavar="N",
                   help="point cloud (--ply): keep every N-th row and column (default 1), as export-ply --stride")
    add_deprecated_alias(p, "--ply-stride", new="--stride", dest="stride", type=int)
    add_output_format_options(p)
    add_confidence_options(p)
    p.add_argument("--save-aligned", metavar="FILE",
                   help="also write the aligned low-resolution depth (before refinement)")
    p.add_argument("--save-color", metavar="FILE",
                   help="also write the color image the result lies on (undistorted when the color lens has "
                        "distortion; .png, .jpg or .tif), so that the two overlay pixel for pixel")
    p.add_argument("--save-settings", metavar="FILE",
                   help="also write the chain settings used (rig inline) as JSON, to rerun with --rig FILE")
    add_preview_option(p)
    add_overwrite(p)
    add_depth_options(p)
    p.set_defaults(func=run_chain)


def _refine_params(args: argparse.Namespace, chain: ChainSettings) -> tuple[str, Any]:
    """The refinement method and its parameters: the settings file's, then --params, then options.

    The file's ``[refine.params]`` apply only to the file's method (a
    different ``--refine-method`` starts from its own defaults). The method is
    told the depth was reprojected (:func:`depthrefine.rig.chain.reprojected_params`).
    """
    from ..rig.chain import reprojected_params

    method = args.method or chain.method or DEFAULT_METHOD
    base = chain.params if chain.params and method == (chain.method or DEFAULT_METHOD) else None
    return method, reprojected_params(method, build_params(args, method=method, base=base))


def run_chain(args: argparse.Namespace) -> int:
    import numpy as np

    from ..io import (DEPTH_SUFFIXES, ChainSettings, check_depth_format, check_distinct_inputs, check_output,
                      read_depth, read_rgb, write_chain_settings, write_confidence, write_depth, write_ply, write_rgb)
    from ..methods.confidence import confidence_on_grid
    from ..rig.chain import align_pair, keep_unmeasured
    from ..rig.pointcloud import depth_to_points

    inputs = (args.depth, args.color, args.rig, args.settings)
    out = check_output(args.output, overwrite=args.overwrite, suffixes=DEPTH_SUFFIXES, inputs=inputs)
    check_distinct_inputs(args.depth, args.color)
    extra_outputs = {}
    for flag, path, suffixes in (("--ply", args.ply, (".ply",)), ("--save-aligned", args.save_aligned, DEPTH_SUFFIXES),
                                 ("--save-settings", args.save_settings, (".json",)),
                                 ("--save-color", args.save_color, COLOR_SUFFIXES),
                                 ("--preview", args.preview, (".png",))):
        if path:
            extra_outputs[flag] = check_output(path, overwrite=args.overwrite, suffixes=suffixes, inputs=inputs,
                                               what=f"{flag} file")
    paths = [out.resolve()] + [p.resolve() for p in extra_outputs.values()]
    if len(set(paths)) != len(paths):
        raise CliError("the output files must all be different.")
    confidence_out = check_confidence_output(args, inputs=inputs, taken=(out, *extra_outputs.values()))
    if args.stride < 1:
        raise CliError(f"--stride must be >= 1; got {args.stride}.")
    chain = chain_settings(args)
    align = chain.align
    if args.ply and align.depth_units is None and align.inverse_scale is None:
        raise CliError("--ply needs the depth's units: --depth-units M or --inverse-depth-scale C "
                       "(or depth_units / inverse_scale in the settings file's [align]).")
    method, params = _refine_params(args, chain)

    depth_raw = read_depth(args.depth, saturated_invalid=args.saturated_invalid)
    warn_implausible_units("run", depth_raw, depth_units=align.depth_units, inverse_scale=align.inverse_scale)
    check_depth_format(out, args.output_dtype or depth_raw.dtype)
    if "--save-aligned" in extra_outputs:
        check_depth_format(extra_outputs["--save-aligned"], depth_raw.dtype)
    rgb_raw = read_rgb(args.color)
    pair = align_pair(depth_raw, rgb_raw, chain.rig, settings=align)
    check_window(args, pair.rgb_hr.shape[:2])
    update, close = progress_bar(f"refine ({method})")
    try:
        depth_hr, confidence, scale_note = refine_pair_maybe_confident(args, pair.depth_lr, pair.rgb_hr,
                                                                       method=method, params=params, progress=update)
    finally:
        close()
    fill_holes = args.fill_holes or chain.fill_holes
    depth_hr = keep_unmeasured(depth_hr, pair.depth_lr, fill_enclosed=fill_holes, rgb_hr=pair.rgb_hr)
    if confidence is not None:
        confidence = confidence_on_grid(confidence, depth_hr)   # 0 where the chain left no depth
        confidence_line = confidence_note(confidence, args.min_confidence)
        depth_hr, confidence = apply_min_confidence(depth_hr, confidence, args.min_confidence)
    stored, dtype = output_depth(args, depth_hr, depth_raw.dtype)
    cloud = None
    if args.ply:
        cloud = depth_to_points(depth_hr, pair.camera, rgb=pair.rgb_hr, depth_units=align.depth_units,
                                inverse_scale=align.inverse_scale, distorted=pair.camera.has_distortion,
                                stride=args.stride)

    written: list[Path] = []
    try:
        written.append(write_depth(out, stored, dtype=dtype, overwrite=args.overwrite))
        if confidence_out is not None:
            written.append(write_confidence(confidence_out, confidence, overwrite=args.overwrite))
        if "--save-aligned" in extra_outputs:
            written.append(write_depth(extra_outputs["--save-aligned"], pair.depth_lr, dtype=depth_raw.dtype,
                                       overwrite=args.overwrite))
        if "--save-color" in extra_outputs:
            written.append(write_rgb(extra_outputs["--save-color"], pair.rgb_hr, overwrite=args.overwrite))
        if cloud is not None:
            written.append(write_ply(extra_outputs["--ply"], *cloud, overwrite=args.overwrite,
                                     comments=(f"depthrefine run {Path(args.depth).name} {Path(args.color).name}",
                                               "metres, color camera frame: X right, Y down, Z forward")))
        if "--preview" in extra_outputs:
            written.append(write_preview(args, extra_outputs["--preview"], depth_hr, pair.rgb_hr, title=out.name,
                                         units={0.001: "mm", 0.01: "cm", 1.0: "m"}.get(align.depth_units, "as stored"),
                                         confidence=confidence))
        if "--save-settings" in extra_outputs:
            used = ChainSettings(rig=chain.rig, align=align, method=method, params=params_dict(params),
                                 rig_source=chain.rig_source, fill_holes=fill_holes)
            written.append(write_chain_settings(extra_outputs["--save-settings"], used, overwrite=args.overwrite))
    except BaseException:
        for path in written:  # all or nothing
            with contextlib.suppress(OSError):
                path.unlink()
        raise
    h, w = depth_hr.shape
    notes = list(pair.notes) + [scale_note, f"refined with {method}"]
    notes.append(f"{100 * np.isnan(depth_hr).mean():.1f} % of pixels left unmeasured (0)"
                 + ("" if fill_holes else "; --fill-holes fills those inside a measured surface"))
    print(f"wrote {out} ({w}x{h}, {dtype}): " + "; ".join(notes), file=sys.stderr)
    if confidence is not None:
        print(f"{'wrote ' + str(confidence_out) + ': ' if confidence_out else ''}{confidence_line}", file=sys.stderr)
    if cloud is not None:
        print(f"wrote {extra_outputs['--ply']} ({cloud[0].shape[0]} points)", file=sys.stderr)
    if "--preview" in extra_outputs:
        print(f"wrote {extra_outputs['--preview']}", file=sys.stderr)
    return 0
