"""The Azure Kinect mug through the chain: how far the depth's outline lies from the color edges.

The shipped capture (``depthrefine.io.load_capture("mug")``, factory
calibration) is aligned two ways and refined with bicubic and the default
method:

- ``s = 1`` (``--factor 1``, the chain before it upsampled): the depth
  reprojected straight onto the 1280x720 color grid, so the refinement has
  nothing to upsample;
- the default: reprojected onto a grid at the depth camera's resolution
  (1056x594, ``s = 1.21``), which the method upsamples x2 onto a 2112x1188
  working grid, resized back to 1280x720.

For each result it prints :func:`depthrefine.rig.edges.edge_overlap` (the
outline of the pixels nearer than 600 mm next to pixels farther than
1000 mm; the median distance of its pixels to the nearest Canny edge of
the color image, and the share within 2 px) and the mean distance, and
with ``--figure FILE`` writes the mug's handle zoomed, the refined depth
with the color edges drawn on it, bicubic beside the default method::

    PYTHONPATH=src python benchmarks/mug_edges.py --figure docs/rig_mug_upsampling.png
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from depthrefine.bench.demo import MUG_FAR_MM, MUG_NEAR_MM
from depthrefine.io import load_capture, read_calibration
from depthrefine.methods.registry import DEFAULT_METHOD
from depthrefine.rig.chain import AlignSettings, align_pair, keep_unmeasured, nearest_on_grid, refine_pair
from depthrefine.rig.edges import color_edges, depth_silhouette, edge_overlap

#: (row0, row1, col0, col1) of the zoom: the mug's handle and right side against the far wall.
ZOOM = (400, 640, 470, 730)


def outline_distances(depth: np.ndarray, rgb: np.ndarray) -> np.ndarray:
    """Distance (px) of every outline pixel of ``depth`` to the nearest color edge."""
    import cv2

    silhouette = depth_silhouette(depth, near=MUG_NEAR_MM, far=MUG_FAR_MM)
    return cv2.distanceTransform((~color_edges(rgb)).astype(np.uint8), cv2.DIST_L2, 5)[silhouette]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--methods", default=f"bicubic,{DEFAULT_METHOD}")
    parser.add_argument("--figure", help="write the zoomed comparison here (PNG)")
    args = parser.parse_args(argv)
    capture = load_capture("mug")
    rig, _ = read_calibration(capture.calibration, depth_mode="NFOV_UNBINNED", color_resolution="720P")
    methods = [m for m in args.methods.split(",") if m]
    panels = []
    print(f"{'chain':28s} {'result':10s} {'median px':>9s} {'<= 2 px':>8s} {'mean px':>8s} {'pixels':>7s}")
    for label, factor in (("s = 1 (before)", 1), ("depth resolution (after)", None)):
        pair = align_pair(capture.depth, capture.rgb, rig,
                          settings=AlignSettings(depth_units=capture.depth_units, factor=factor))
        results = {"aligned": nearest_on_grid(pair.depth_lr, pair.rgb_hr.shape[:2])}
        for method in methods:
            t0 = time.perf_counter()
            depth_hr, note = refine_pair(pair.depth_lr, pair.rgb_hr, method=method)
            results[method] = keep_unmeasured(depth_hr, pair.depth_lr)
            print(f"  ({method}: {time.perf_counter() - t0:.1f} s; {note})", file=sys.stderr)
        for name, depth in results.items():
            fit = edge_overlap(depth, pair.rgb_hr, near=MUG_NEAR_MM, far=MUG_FAR_MM)
            mean = float(outline_distances(depth, pair.rgb_hr).mean())
            print(f"{label:28s} {name:10s} {fit.median_px:9.2f} {fit.fraction:8.0%} {mean:8.2f} {fit.pixels:7d}  "
                  f"(grid {pair.depth_lr.shape[1]}x{pair.depth_lr.shape[0]})")
            if name != "aligned":
                panels.append((f"{label}: {name}", depth, pair.rgb_hr))
    if args.figure:
        _figure(panels, args.figure)
        print(f"wrote {args.figure}", file=sys.stderr)
    return 0


def _figure(panels, path: str) -> None:
    from matplotlib.figure import Figure

    r0, r1, c0, c1 = ZOOM
    ncols = len(panels) // 2
    fig = Figure(figsize=(3.6 * ncols, 2 * 3.6), dpi=130, layout="constrained")
    axes = fig.subplots(2, ncols, squeeze=False)
    for ax, (title, depth, rgb) in zip(axes.ravel(), panels):
        crop = depth[r0:r1, c0:c1]
        ax.imshow(np.ma.masked_invalid(crop), cmap="gray", vmin=200, vmax=2300, interpolation="nearest")
        edges = np.ma.masked_where(~color_edges(rgb)[r0:r1, c0:c1], np.ones(crop.shape))
        ax.imshow(edges, cmap="autumn", vmin=0, vmax=2, interpolation="nearest")
        ax.set_title(title, fontsize=8)
        ax.set_axis_off()
    fig.suptitle(f"Azure Kinect mug, rows {r0}-{r1}, cols {c0}-{c1}: the refined depth (gray, 200-2300 mm;\n"
                 "white: no measurement) with the color image's Canny edges (orange)", fontsize=8)
    fig.savefig(path)


if __name__ == "__main__":
    sys.exit(main())
