"""``depthrefine demo [-o DIR]``: the methods on the shipped Middlebury scene, as in the thesis's Fig. 47.

The scenes are computed by :mod:`depthrefine.bench.demo`; this module writes and prints.
"""

from __future__ import annotations

import argparse
import json
import sys

from ..io._names import SAMPLE_SCALES, SCENES
from ..methods._names import DEFAULT_METHOD
from ._common import add_overwrite, progress_bar


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "demo",
        help="run the methods on a shipped scene and write a comparison figure: Middlebury 2005 Art (default) "
             "or, with --scene, a real Azure Kinect or iPhone LiDAR capture",
        description=(
            "Refine the shipped Middlebury 2005 Art scene (noisy low-resolution disparity of Park et al.) "
            "with bilinear interpolation, the OpenCV peers (jbf, guided, fgs, wmf), the thesis method and "
            f"the default method ({DEFAULT_METHOD}), and write a figure like the thesis's Fig. 47: color, "
            "input, bilinear, the best peer on this scene, the thesis method, the default method and the "
            "ground truth, each titled with its RMSE, with the same zoomed detail under each and one "
            "colorbar; plus the RMSE of every method and the default method's result."
        ),
    )
    p.add_argument("-o", "--output", default="depthrefine-demo", metavar="DIR",
                   help="output folder (default: ./depthrefine-demo)")
    p.add_argument("--scale", type=int, default=8, choices=SAMPLE_SCALES,
                   help="art: upsampling factor (default: 8)")
    p.add_argument("--scene", choices=SCENES, default="art",
                   help="art (default): Middlebury 2005 Art with ground truth; mug: a real Azure Kinect capture "
                        "through the whole rig chain (factory calibration import, reprojection, refinement); "
                        "bookshelf: a real iPhone LiDAR frame refined x7.5")
    add_overwrite(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..bench.demo import run_demo
    from ..io import atomic_directory, write_depth, write_figure, write_ply, write_rgb, write_rig

    with atomic_directory(args.output, overwrite=args.overwrite) as tmp:
        demo = run_demo(args.scene, scale=args.scale, progress_bar=progress_bar)
        for name, figure in demo.figures.items():
            write_figure(tmp / name, figure)
        for name, (depth, dtype) in demo.depth_maps.items():
            write_depth(tmp / name, depth, dtype=dtype)
        for name, rgb in demo.images.items():
            write_rgb(tmp / name, rgb)
        if demo.rig is not None:
            write_rig(tmp / "rig.json", demo.rig[0], extra=demo.rig[1])
        if demo.cloud is not None:
            points, colors, comments = demo.cloud
            write_ply(tmp / "cloud.ply", points, colors, comments=comments)
        (tmp / "demo.json").write_text(json.dumps(demo.record, indent=2) + "\n", encoding="utf-8")
    for line in demo.lines:
        print(line.replace("wrote ", f"wrote {args.output}/", 1) if line.startswith("wrote") else line)
    print(f"data: {demo.citation}", file=sys.stderr)
    return 0
