"""Leave-out hole filling on the shipped real captures: hide valid depth shaped like real holes, fill, score.

``depthrefine.bench.holes``: the holes inside the measured area of the Azure
Kinect mug (its depth aligned to the color camera by the chain, as ``run``
does: the 1056x594 grid, millimetres) are moved onto valid surface of the
same map (seeded), filled, and scored against the depth that was there.
The iPhone LiDAR bookshelf (256x192, mm) has no holes of its own, so the
mug's hole shapes are placed on it, resized by the ratio of the two maps'
widths (256 / 1056: a hole keeps its share of the field of view). Prints one table
per capture: RMSE and mean absolute error in mm over the hidden pixels::

    PYTHONPATH=src python benchmarks/hole_leaveout.py                       # nearest and inpainting
    PYTHONPATH=src python benchmarks/hole_leaveout.py --methods bicubic,gbp # and refinement methods
"""

from __future__ import annotations

import argparse
import sys
import time

from depthrefine.bench.holes import BASELINE_FILLERS, hole_shapes, leave_out, place_holes, rescale_shapes
from depthrefine.io import load_capture, read_calibration
from depthrefine.rig.chain import AlignSettings, align_pair


def captures():
    """``{name: (depth, rgb)}``: the mug aligned by the chain (factory calibration), the bookshelf as shipped."""
    mug = load_capture("mug")
    rig, _ = read_calibration(mug.calibration, depth_mode="NFOV_UNBINNED", color_resolution="720P")
    pair = align_pair(mug.depth, mug.rgb, rig, settings=AlignSettings(depth_units=mug.depth_units))
    shelf = load_capture("bookshelf")
    return {"mug": (pair.depth_lr, pair.rgb_hr), "bookshelf": (shelf.depth.astype("float32"), shelf.rgb)}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--methods", default="", help="refinement methods to score beside the baselines")
    parser.add_argument("--seed", type=int, default=0, help="seed of the placement")
    parser.add_argument("--min-pixels", type=int, default=2, help="smallest real hole used as a shape")
    args = parser.parse_args(argv)
    fillers = [*BASELINE_FILLERS, *[m for m in args.methods.split(",") if m]]
    data = captures()
    shapes = hole_shapes(data["mug"][0], min_pixels=args.min_pixels)
    print(f"{len(shapes)} hole shapes from the mug's aligned depth (holes inside the measured area, "
          f">= {args.min_pixels} px, {sum(int(s.sum()) for s in shapes)} px in all)")
    source_cols = data["mug"][0].shape[1]
    for name, (depth, rgb) in data.items():
        mine = shapes if name == "mug" else rescale_shapes(shapes, depth.shape[1] / source_cols)
        hidden = place_holes(depth, mine, seed=args.seed)
        print(f"\n{name}: depth {depth.shape[1]}x{depth.shape[0]}, {len(mine)} shapes, {int(hidden.sum())} px hidden "
              f"({100 * hidden.mean():.2f} % of the map)")
        print(f"{'filler':10s} {'RMSE mm':>9s} {'MAE mm':>8s} {'pixels':>7s} {'s':>6s}")
        for filler in fillers:
            t0 = time.perf_counter()
            (score,) = leave_out(depth, rgb, hidden, [filler], reprojected=name == "mug")   # the chain's
            print(f"{score.filler:10s} {score.rmse:9.2f} {score.mae:8.2f} {score.pixels:7d} "
                  f"{time.perf_counter() - t0:6.1f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
