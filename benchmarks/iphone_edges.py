"""The real iPhone LiDAR frame: how far the refined depth's near outlines lie from the color edges.

The shipped capture (``depthrefine.io.load_capture("bookshelf")``: 256x192
ARKit depth in mm, its 1920x1440 RGB frame; ratio 7.5) is refined with
bicubic, the default method and the default method with ``--snap-edges``
(``GbpParams(snap_edges=True)``); ``--methods gbp,gbp-fast`` adds gbp-fast with
and without ``--snap-edges``. For each result it prints
:func:`depthrefine.rig.edges.edge_overlap` at three near / far thresholds
(the outline of the pixels nearer than ``near`` next to pixels farther than
``far``: the sofa and the shelves' fronts against the wall; the median
distance of its pixels to the nearest Canny edge of the color image, and
the share within 2 px, and how many outline pixels it counts: only where the
depth falls from below ``near`` to above ``far`` within 8 px, on this frame a
few hundred pixels of the sofa's top-left). With ``--figure FILE`` it writes the sofa's back
against the shelves at full resolution, the color image with the refined
depth's edges (a 3x3 depth range over ``EDGE_MM``) in red, one row per
result::

    PYTHONPATH=src python benchmarks/iphone_edges.py --figure docs/iphone_edges.jpg
    PYTHONPATH=src python benchmarks/iphone_edges.py --methods gbp,gbp-fast
    PYTHONPATH=src python benchmarks/iphone_edges.py --methods gbp,gbp-fast --reprojected

``--reprojected`` tells each method the depth was aligned to the color image by
the camera's SDK, as ARKit's depth is: step 1b then undoes the shift its jumps
show against the color edges.
"""

from __future__ import annotations

import argparse
import functools
import statistics
import sys
import time
from typing import Callable

import numpy as np

import depthrefine
from depthrefine.io import load_capture
from depthrefine.methods.registry import DEFAULT_METHOD
from depthrefine.rig.edges import edge_overlap

#: (near, far) thresholds in mm: the sofa (about 2 m) and the shelves' fronts against the back wall.
THRESHOLDS = ((2100, 2500), (2300, 2700), (2500, 2900))
#: (row0, row1, col0, col1) of the figure: the sofa's back and right side against the shelves.
ZOOM = (300, 700, 0, 720)
#: A depth edge in the figure: the 3x3 range of the refined depth over this many mm.
EDGE_MM = 150.0


def refiners(methods: tuple[str, ...] = (DEFAULT_METHOD,), *, reprojected: bool = False
             ) -> dict[str, Callable[[np.ndarray, np.ndarray], np.ndarray]]:
    """Bicubic, then each of ``methods`` (gbp or gbp-fast) without and with snapped edges: name -> refine call.

    With ``reprojected`` each method is told its input was aligned to the color image by the camera's SDK
    (``--reprojected``), as ARKit's depth is.
    """
    from depthrefine.methods.registry import get_method

    calls = {"bicubic": functools.partial(depthrefine.refine, method="bicubic")}
    told = " --reprojected" if reprojected else ""
    for method in methods:
        params_type = get_method(method).params_type
        for snap in (False, True):
            params = params_type(snap_edges=snap, reprojected=True if reprojected else None)
            name = f"{method}{told}{' --snap-edges' if snap else ''}"
            calls[name] = functools.partial(depthrefine.refine, method=method, params=params)
    return calls


def median_times(calls: dict, depth: np.ndarray, rgb: np.ndarray, repeats: int) -> tuple[dict[str, float], float]:
    """Median wall seconds of each call and of OpenCV's fast global smoother (``bench_speed.fgs_peer``), alternated."""
    from bench_speed import fgs_peer

    times: dict[str, list[float]] = {name: [] for name in calls}
    peer: list[float] = []
    for _ in range(repeats):
        for name, call in calls.items():
            t0 = time.perf_counter()
            call(depth, rgb)
            times[name].append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        fgs_peer(depth, rgb)
        peer.append(time.perf_counter() - t0)
    return {name: statistics.median(v) for name, v in times.items()}, statistics.median(peer)


def figure(rgb: np.ndarray, refined: dict[str, np.ndarray], path: str) -> None:
    """Each result's depth edges in red over the color image, in the :data:`ZOOM` window, one row each."""
    import cv2

    r0, r1, c0, c1 = ZOOM
    rows = []
    for name, depth in refined.items():
        window = np.ascontiguousarray(depth[r0:r1, c0:c1])
        kernel = np.ones((3, 3), np.uint8)
        edges = (cv2.dilate(window, kernel) - cv2.erode(window, kernel)) > EDGE_MM
        picture = rgb[r0:r1, c0:c1].copy()
        picture[edges] = (255, 0, 0)
        cv2.putText(picture, name, (10, 30), cv2.FONT_HERSHEY_SIMPLEX, 0.9, (255, 255, 255), 2, cv2.LINE_AA)
        rows.append(picture)
    if not cv2.imwrite(path, cv2.cvtColor(np.concatenate(rows, axis=0), cv2.COLOR_RGB2BGR)):
        raise OSError(f"could not write {path}")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--methods", default=DEFAULT_METHOD, metavar="A,B",
                    help="methods with a snap_edges knob, each without and with it (default: %(default)s)")
    ap.add_argument("--reprojected", action="store_true",
                    help="tell each method the depth was aligned to the color image by the camera's SDK (ARKit's is)")
    ap.add_argument("--repeats", type=int, default=0, metavar="N",
                    help="also time each result N times, alternated with OpenCV's FGS (median ms and ratio)")
    ap.add_argument("--figure", metavar="FILE", help="also write the zoomed outlines to this picture (.jpg, .png)")
    args = ap.parse_args(argv)
    capture = load_capture("bookshelf")
    calls = refiners(tuple(args.methods.split(",")), reprojected=args.reprojected)
    refined = {name: call(capture.depth, capture.rgb) for name, call in calls.items()}
    times, peer = median_times(calls, capture.depth, capture.rgb, args.repeats) if args.repeats > 0 else ({}, 0.0)
    print("median distance of the near outline to the color edges, px (share within 2 px; outline pixels)"
          + (f"; median ms of {args.repeats} calls (x FGS's {1000 * peer:.0f} ms, alternated)" if times else ""))
    print("| | " + " | ".join(f"{near} / {far} mm" for near, far in THRESHOLDS) + (" | ms |" if times else " |"))
    print("|---|" + "---|" * (len(THRESHOLDS) + bool(times)))
    for name, depth in refined.items():
        cells = []
        for near, far in THRESHOLDS:
            overlap = edge_overlap(depth, capture.rgb, near=near, far=far)
            cells.append(f"{overlap.median_px:.2f} ({overlap.fraction:.0%}; {overlap.pixels})")
        if times:
            cells.append(f"{1000 * times[name]:.0f} ({times[name] / peer:.1f}x)")
        print(f"| {name} | " + " | ".join(cells) + " |", flush=True)
    if args.figure:
        figure(capture.rgb, refined, args.figure)
        print(f"wrote {args.figure}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
