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

Each result is the map ``depthrefine run`` writes (``run --fill-holes``'s
with ``--fill-holes``): the method's output with the unmeasured pixels
taken back, their border following the color
(``rig.chain.keep_unmeasured``).
For each it prints two outlines, each as the median distance of its pixels
to the nearest Canny edge of the color image, the share within 2 px and
the mean:

- ``frame``: :func:`depthrefine.rig.edges.edge_overlap`, the outline of the
  pixels nearer than 600 mm next to pixels farther than 1000 mm; in this
  frame mostly the table's front edge, with the mug's rim and the inside
  of its handle;
- ``mug``: the mug's own outline, the pixels of the mug's depth (nearer than
  400 mm) next to the wall's (beyond 600 mm) or to unmeasured pixels,
  within :data:`TRACE_BAND` px of the mug's silhouette traced by hand
  (``benchmarks/mug_interior.py``).

With ``--figure FILE`` it writes the mug's handle zoomed, the refined depth
with the color edges drawn on it, bicubic beside the default method::

    PYTHONPATH=src python benchmarks/mug_edges.py [--fill-holes] [--figure docs/rig_mug_upsampling.png]
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
from depthrefine.rig.edges import color_edges, depth_silhouette
from mug_interior import MUG_BODY, MUG_HANDLE, MUG_FAR_MM as ON_MUG_MM

#: (row0, row1, col0, col1) of the zoom: the mug's handle and right side against the far wall.
ZOOM = (400, 640, 470, 730)
#: The mug's outline is looked for within this many pixels of its traced silhouette (traced to about 2 px).
TRACE_BAND = 6
#: The handle's traced middle line is drawn this wide for the silhouette's outline, px (the handle is 8-12 px).
HANDLE_TRACE_WIDTH = 10
#: Beyond the mug: the wall, farther than this, mm.
WALL_MM = 600.0


def mug_outline(depth: np.ndarray) -> np.ndarray:
    """The mug's outline in ``depth`` (on the 1280x720 color grid): mug pixels next to the wall or to no depth."""
    import cv2

    traced = np.zeros(depth.shape, np.uint8)
    cv2.fillPoly(traced, [np.array(MUG_BODY, np.int32)], 1)
    cv2.polylines(traced, [np.array(MUG_HANDLE, np.int32)], False, 1, thickness=HANDLE_TRACE_WIDTH)
    square = np.ones((3, 3), np.uint8)
    near_trace = cv2.dilate(traced - cv2.erode(traced, square), np.ones((2 * TRACE_BAND + 1,) * 2, np.uint8)) > 0
    measured = np.isfinite(depth)
    with np.errstate(invalid="ignore"):
        mug = measured & (depth < ON_MUG_MM)
        beyond = ~measured | (depth > WALL_MM)
    return mug & (cv2.dilate(beyond.astype(np.uint8), square) > 0) & near_trace


def outline_distances(outline: np.ndarray, rgb: np.ndarray) -> np.ndarray:
    """Distance (px) of every pixel of ``outline`` (bool) to the nearest color edge of ``rgb``."""
    import cv2

    return cv2.distanceTransform((~color_edges(rgb)).astype(np.uint8), cv2.DIST_L2, 5)[outline]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--methods", default=f"bicubic,{DEFAULT_METHOD}")
    parser.add_argument("--figure", help="write the zoomed comparison here (PNG)")
    parser.add_argument("--fill-holes", action="store_true", help="as run --fill-holes")
    args = parser.parse_args(argv)
    capture = load_capture("mug")
    rig, _ = read_calibration(capture.calibration, depth_mode="NFOV_UNBINNED", color_resolution="720P")
    methods = [m for m in args.methods.split(",") if m]
    panels = []
    print(f"{'chain':26s} {'result':9s} | {'frame: median px':>16s} {'<= 2 px':>7s} {'mean':>5s} {'pixels':>6s} | "
          f"{'mug: median px':>14s} {'<= 2 px':>7s} {'mean':>5s} {'pixels':>6s}")
    for label, factor in (("s = 1 (before)", 1), ("depth resolution (after)", None)):
        pair = align_pair(capture.depth, capture.rgb, rig,
                          settings=AlignSettings(depth_units=capture.depth_units, factor=factor))
        results = {"aligned": nearest_on_grid(pair.depth_lr, pair.rgb_hr.shape[:2])}
        for method in methods:
            t0 = time.perf_counter()
            depth_hr, note = refine_pair(pair.depth_lr, pair.rgb_hr, method=method)
            results[method] = keep_unmeasured(depth_hr, pair.depth_lr, fill_enclosed=args.fill_holes,
                                              rgb_hr=pair.rgb_hr)
            print(f"  ({method}: {time.perf_counter() - t0:.1f} s; {note})", file=sys.stderr)
        for name, depth in results.items():
            figures = []
            for outline, width in ((depth_silhouette(depth, near=MUG_NEAR_MM, far=MUG_FAR_MM), 16),
                                   (mug_outline(depth), 14)):
                distances = outline_distances(outline, pair.rgb_hr)
                figures.append(f"{np.median(distances):{width}.2f} {np.mean(distances <= 2):7.0%} "
                               f"{distances.mean():5.2f} {distances.size:6d}")
            print(f"{label:26s} {name:9s} | {figures[0]} | {figures[1]}  "
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
