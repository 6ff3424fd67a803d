"""The README's picture of a real iPhone LiDAR frame: color, input, thesis method, default method.

Uses the shipped iPhone LiDAR capture (``depthrefine.io.load_capture("bookshelf")``: 256x192
ARKit depth in mm, registered 1920x1440 RGB frame; ratio 7.5), refines the depth to the color
grid with the thesis method and with the default method, and writes a comparison figure (with
a zoomed detail)::

    python benchmarks/iphone_figure.py [-o docs/iphone_lidar.png]

There is no ground truth: the figure is for looking (patch seams, blocks snapped to a wrong
depth, edges on the color edges or not). The input panel is the depth enlarged by nearest
neighbour, so its pixels show.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import cv2

import depthrefine
from depthrefine import viz
from depthrefine.io import load_capture


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-o", "--output", default="docs/iphone_lidar.png", help="PNG to write")
    ap.add_argument("--width", type=int, default=960, help="color width of the figure's panels (default 960)")
    args = ap.parse_args(argv)
    capture = load_capture("bookshelf")
    depth, rgb = capture.depth, capture.rgb
    results = {}
    for method in ("thesis", depthrefine.DEFAULT_METHOD):
        t0 = time.perf_counter()
        results[method] = depthrefine.refine(depth, rgb, method=method)
        print(f"{method}: {time.perf_counter() - t0:.2f} s", file=sys.stderr)
    nearest = depthrefine.refine(depth, rgb, method="nearest")
    # a smaller figure: every panel resized to --width (nearest for depth, area for color)
    h = round(rgb.shape[0] * args.width / rgb.shape[1])
    small = lambda d: cv2.resize(d, (args.width, h), interpolation=cv2.INTER_NEAREST)  # noqa: E731
    color = cv2.resize(rgb, (args.width, h), interpolation=cv2.INTER_AREA)
    panels = [(f"input {depth.shape[1]}x{depth.shape[0]} (nearest)", small(nearest)),
              ("thesis method (--method thesis)", small(results["thesis"])),
              (f"default method ({depthrefine.DEFAULT_METHOD})", small(results[depthrefine.DEFAULT_METHOD]))]
    zoom = viz.pick_detail(small(results[depthrefine.DEFAULT_METHOD]))
    fig = viz.comparison_figure(color, panels, units="mm", zoom=zoom, ncols=4,
                                limits=viz.depth_limits(depth.astype("float32")),
                                title="Real iPhone LiDAR frame (PromptDA example, Apache-2.0), x7.5 to 1920x1440; "
                                      "depth in mm, no ground truth")
    fig.savefig(args.output, dpi=90)
    print(f"wrote {args.output} ({Path(args.output).stat().st_size // 1024} kB)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
