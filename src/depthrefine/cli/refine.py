"""``depthrefine refine DEPTH COLOR -o OUT``: refine one depth map."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from .. import __version__
from ..io import (DEPTH_SUFFIXES, check_depth_format, atomic_directory, check_output, check_output_dir, read_depth, read_rgb,
                  write_depth, write_rgb)
from ..methods.registry import get_method, refine
from ..methods.thesis.refine import refine_with_intermediates
from ..methods.scale import plan_scale
from .. import viz
from ._common import (add_depth_options, add_output, add_overwrite, add_params_options, build_params,
                      params_dict, progress_bar)


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "refine",
        help="refine a low-resolution depth map to the color image's resolution",
        description=(
            "Refine DEPTH (8/16-bit PNG, float TIFF or .npy; 0 = no measurement) to the height and width "
            "of COLOR. The output keeps DEPTH's dtype; its format follows OUT's extension."
        ),
    )
    p.add_argument("depth", metavar="DEPTH", help="low-resolution depth map")
    p.add_argument("color", metavar="COLOR", help="registered high-resolution color image")
    add_output(p, help="output depth file (.png, .tif, .npy)")
    add_params_options(p)
    p.add_argument("--save-intermediate", metavar="DIR",
                   help="write the pictures of the intermediate steps (and the parameters) into DIR")
    add_overwrite(p)
    add_depth_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    out = check_output(args.output, overwrite=args.overwrite, suffixes=DEPTH_SUFFIXES,
                       inputs=(args.depth, args.color))
    if args.save_intermediate:
        folder = Path(args.save_intermediate).resolve()
        if out.resolve() == folder:
            raise ValueError(
                f"-o {out} and --save-intermediate {args.save_intermediate} are the same path; "
                "give the intermediate pictures a folder of their own."
            )
        check_output_dir(args.save_intermediate, overwrite=args.overwrite, what="--save-intermediate folder")
    params = build_params(args)  # before reading the images: a bad parameter fails at once
    depth_lr = read_depth(args.depth, saturated_invalid=args.saturated_invalid)
    rgb_hr = read_rgb(args.color)
    check_depth_format(out, depth_lr.dtype)
    step = plan_scale(depth_lr.shape, rgb_hr.shape)
    entry = get_method(args.method)
    update, close = progress_bar(f"refine ({entry.name})")
    try:
        if args.save_intermediate and entry.name == "thesis":
            result = refine_with_intermediates(depth_lr, rgb_hr, params=params, progress=update)
            depth_hr = result.depth_hr
        else:
            result = None
            depth_hr = refine(depth_lr, rgb_hr, method=entry.name, params=params, progress=update)
    finally:
        close()

    # Only the thesis method needs an integer factor; the others resize straight to the color grid.
    scale_note = step.describe() if entry.name == "thesis" or not step.resizes_color else (
        f"ratio {step.ratio:.3f}, resized directly to {rgb_hr.shape[1]}x{rgb_hr.shape[0]}")
    record = {
        "depthrefine": __version__,
        "depth": str(args.depth),
        "color": str(args.color),
        "output": str(out),
        "method": entry.name,
        "params": params_dict(params),
        "scale": scale_note,
        "depth_shape": list(depth_lr.shape),
        "color_shape": list(rgb_hr.shape[:2]),
        "dtype": str(depth_lr.dtype),
    }
    if args.save_intermediate:
        with atomic_directory(args.save_intermediate, overwrite=args.overwrite) as tmp:
            _write_intermediates(tmp, depth_hr, rgb_hr, result, record)
            write_depth(out, depth_hr, dtype=depth_lr.dtype, overwrite=args.overwrite)
    else:
        write_depth(out, depth_hr, dtype=depth_lr.dtype, overwrite=args.overwrite)
    h, w = depth_hr.shape
    if entry.name == "thesis" and step.resizes_color:
        scale_note = f"x{step.factor} after the thesis scale step (see the note above)"
    print(f"wrote {out} ({w}x{h}, {depth_lr.dtype}, method {entry.name}, {scale_note})", file=sys.stderr)
    return 0


def _write_intermediates(folder: Path, depth_hr, rgb_hr, result, record) -> None:
    """The pictures of --save-intermediate, and the run's record as JSON."""
    limits = viz.depth_limits(depth_hr)
    depth_rgb = viz.colorize_depth(depth_hr, limits=limits)
    write_rgb(folder / "result_colorized.png", depth_rgb)
    write_rgb(folder / "result_blended.png", viz.blend(depth_rgb, rgb_hr))
    if result is not None:
        work_rgb = result.rgb_filtered
        write_rgb(folder / "color_filtered.png", viz.to_rgb8(work_rgb))
        write_rgb(folder / "cluster_labels.png", viz.colorize_labels(result.labels, result.patch_index))
        write_rgb(folder / "sparse_depth_over_color.png",
                  viz.overlay_sparse(result.sparse_depth, work_rgb, limits=limits))
        write_rgb(folder / "corrected_depth_over_color.png",
                  viz.overlay_sparse(result.corrected_sparse, work_rgb, limits=limits))
        np.savez_compressed(
            folder / "intermediates.npz",
            labels=result.labels, patch_index=result.patch_index, labels_lr=result.labels_lr,
            corrected_lr=result.corrected_lr, lab_unified=result.lab_unified,
            patches=np.array(result.patches, dtype=np.int32),
        )
        record = dict(record, level_size=result.level_size, patches=[list(p) for p in result.patches])
    (folder / "run.json").write_text(json.dumps(record, indent=2) + "\n", encoding="utf-8")
