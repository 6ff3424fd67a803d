"""``depthrefine demo [-o DIR]``: the thesis method on the shipped Middlebury scene, as in Fig. 47."""

from __future__ import annotations

import argparse
import json
import sys
import time

from .. import __version__, viz
from ..evaluate import rmse
from ..io import SAMPLE_SCALES, atomic_directory, load_sample, sample_folder, write_depth, write_rgb
from ..methods.registry import refine
from ..methods.thesis.params import RefineParams
from ._common import add_overwrite, progress_bar


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "demo",
        help="run the thesis method on the shipped Middlebury 2005 Art scene and write a comparison figure",
        description=(
            "Refine the shipped Middlebury 2005 Art scene (noisy low-resolution disparity of Park et al.) "
            "with the thesis method and write a figure like the thesis's Fig. 47: color, nearest, refined "
            "and ground truth with a zoomed detail, plus the RMSE of each against the ground truth."
        ),
    )
    p.add_argument("-o", "--output", default="depthrefine-demo", metavar="DIR",
                   help="output folder (default: ./depthrefine-demo)")
    p.add_argument("--scale", type=int, default=8, choices=SAMPLE_SCALES, help="upsampling factor (default: 8)")
    add_overwrite(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    with atomic_directory(args.output, overwrite=args.overwrite) as tmp:
        scene = load_sample(args.scale)
        params = RefineParams()
        update, close = progress_bar(f"demo: thesis method x{args.scale}", enabled=None)
        t0 = time.perf_counter()
        try:
            refined = refine(scene.depth_lr, scene.rgb_hr, method="thesis", params=params, progress=update)
        finally:
            close()
        seconds = time.perf_counter() - t0
        nearest = refine(scene.depth_lr, scene.rgb_hr, method="nearest")
        bilinear = refine(scene.depth_lr, scene.rgb_hr, method="bilinear")
        gt = scene.depth_gt.astype("float32")
        scores = {name: round(rmse(depth, gt), 3)
                  for name, depth in (("nearest", nearest), ("bilinear", bilinear), ("thesis", refined))}
        zoom = viz.pick_detail(gt)
        fig = viz.comparison_figure(
            scene.rgb_hr,
            [(f"nearest\nRMSE {scores['nearest']:.2f}", nearest),
             (f"thesis method (refined)\nRMSE {scores['thesis']:.2f}", refined),
             ("ground truth", gt)],
            zoom=zoom,
            title=f"Middlebury 2005 Art, x{args.scale} noisy input (Park et al. 2011); RMSE in disparity levels",
        )
        fig.savefig(tmp / "demo_figure.png")
        write_depth(tmp / "refined.png", refined, dtype=scene.depth_lr.dtype)
        write_depth(tmp / "nearest.png", nearest, dtype=scene.depth_lr.dtype)
        write_rgb(tmp / "refined_blended.png", viz.blend(viz.colorize_depth(refined), scene.rgb_hr))
        record = {
            "depthrefine": __version__,
            "scene": f"{sample_folder()}/noisy_x{args.scale}.png",
            "citation": scene.citation,
            "scale": args.scale,
            "params": params.to_dict(),
            "rmse": scores,
            "seconds_thesis": round(seconds, 3),
            "zoom_rows_cols": list(zoom),
        }
        (tmp / "demo.json").write_text(json.dumps(record, indent=2) + "\n", encoding="utf-8")
    print(f"Middlebury 2005 Art x{args.scale}: RMSE against ground truth (disparity levels)")
    for name, value in scores.items():
        print(f"  {name:9s} {value:6.2f}")
    print(f"thesis method: {seconds:.2f} s; wrote {args.output}/demo_figure.png, refined.png, nearest.png, "
          f"refined_blended.png, demo.json")
    print(f"data: {scene.citation}", file=sys.stderr)
    return 0
