"""The real-data scenes of ``depthrefine demo``: ``--scene mug`` (Azure Kinect) and ``--scene bookshelf`` (iPhone LiDAR)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from .. import __version__, viz
from ..evaluate import rmse
from ..io import (atomic_directory, load_capture, read_calibration, write_depth, write_figure, write_ply, write_rgb,
                  write_rig)
from ..methods.registry import DEFAULT_METHOD, refine
from ..rig.chain import AlignSettings, align_pair, keep_unmeasured, nearest_on_grid, refine_pair
from ..rig.edges import color_edges, depth_silhouette, edge_overlap
from ..rig.pointcloud import depth_to_points
from ._common import progress_bar

__all__ = ["run_scene", "MUG_NEAR_MM", "MUG_FAR_MM", "MUG_DETAIL"]

#: The mug is at about 256 mm and the wall behind it at 1.5-2.2 m: the silhouette
#: separates pixels nearer than 600 mm from pixels farther than 1000 mm.
MUG_NEAR_MM, MUG_FAR_MM = 600.0, 1000.0
#: (row0, row1, col0, col1) of the mug in the 1280x720 color image.
MUG_DETAIL = (330, 650, 250, 700)


def edges_picture(rgb: np.ndarray, depth: np.ndarray, *, near: float, far: float) -> np.ndarray:
    """The color image darkened, its Canny edges in green and the depth's near-object silhouette in red."""
    out = (viz.to_rgb8(rgb) * 0.6).astype(np.uint8)
    out[color_edges(rgb)] = (0, 255, 0)
    out[depth_silhouette(depth, near=near, far=far)] = (255, 0, 0)
    return out


def _mug(tmp: Path) -> tuple[dict, list[str]]:
    capture = load_capture("mug")
    rig, _ = read_calibration(capture.calibration, depth_mode="NFOV_UNBINNED", color_resolution="720P")
    method = DEFAULT_METHOD
    pair = align_pair(capture.depth, capture.rgb, rig, settings=AlignSettings(depth_units=capture.depth_units))
    update, close = progress_bar(f"demo mug: {method}", enabled=None)
    try:
        refined = keep_unmeasured(refine_pair(pair.depth_lr, pair.rgb_hr, method=method, progress=update)[0],
                                  pair.depth_lr)
    finally:
        close()
    aligned = nearest_on_grid(pair.depth_lr, pair.rgb_hr.shape[:2])  # as the refinement spreads it
    aligned_fit = edge_overlap(aligned, pair.rgb_hr, near=MUG_NEAR_MM, far=MUG_FAR_MM)
    refined_fit = edge_overlap(refined, pair.rgb_hr, near=MUG_NEAR_MM, far=MUG_FAR_MM)
    limits = (150.0, 2300.0)
    fig = viz.comparison_figure(
        pair.rgb_hr,
        [("depth reprojected into the color camera\n(factory calibration)", aligned),
         (f"refined ({method})", refined)],
        units="mm", zoom=MUG_DETAIL, limits=limits, ncols=3,
        title="Azure Kinect (NFOV unbinned 640x576 ToF, 720p color): the whole chain on one real capture",
    )
    write_figure(tmp / "demo_figure.png", fig)
    r0, r1, c0, c1 = MUG_DETAIL
    # The registration check: the reprojected depth's outline (red) on the color edges (green).
    write_rgb(tmp / "edges.png",
              edges_picture(pair.rgb_hr, aligned, near=MUG_NEAR_MM, far=MUG_FAR_MM)[r0:r1, c0:c1])
    write_depth(tmp / "refined.png", refined, dtype=np.uint16)
    write_depth(tmp / "aligned.png", pair.depth_lr, dtype=np.uint16)
    write_rig(tmp / "rig.json", rig, extra={"imported_from": "calibration.json (Azure Kinect factory calibration)",
                                            "depth_mode": "NFOV_UNBINNED", "color_resolution": "720P"})
    points, colors = depth_to_points(refined, pair.camera, rgb=pair.rgb_hr, depth_units=capture.depth_units, stride=2)
    write_ply(tmp / "cloud.ply", points, colors, comments=("depthrefine demo --scene mug, every 2nd row and column",
                                                           "metres, color camera frame: X right, Y down, Z forward"))
    fits = {name: {"fraction_within_2px": round(fit.fraction, 3), "median_px": round(fit.median_px, 2),
                   "silhouette_pixels": fit.pixels} for name, fit in (("aligned", aligned_fit), ("refined", refined_fit))}
    record = {
        "method": method,
        "notes": list(pair.notes),
        "unmeasured_percent": round(100 * float(np.isnan(refined).mean()), 1),
        "edge_overlap": fits,
        "edge_overlap_definition": (f"silhouette: pixels nearer than {MUG_NEAR_MM:g} mm next to pixels farther than "
                                    f"{MUG_FAR_MM:g} mm; distance to the nearest Canny edge of the color image"),
    }
    lines = [f"Azure Kinect mug: depth reprojected with the factory calibration and refined with {method}",
             f"  mug outline vs color edges: aligned {aligned_fit.fraction:.0%} within 2 px (median "
             f"{aligned_fit.median_px:.1f} px), refined {refined_fit.fraction:.0%} (median {refined_fit.median_px:.1f} px)",
             f"  {record['unmeasured_percent']} % of the color image has no depth measurement (left 0)",
             "wrote demo_figure.png, edges.png, refined.png (uint16 mm), aligned.png, rig.json, cloud.ply, demo.json"]
    return record, lines


def _bookshelf(tmp: Path) -> tuple[dict, list[str]]:
    import cv2

    capture = load_capture("bookshelf")
    method = DEFAULT_METHOD
    update, close = progress_bar(f"demo bookshelf: {method}", enabled=None)
    try:
        refined = refine(capture.depth, capture.rgb, method=method, progress=update)
    finally:
        close()
    nearest = refine(capture.depth, capture.rgb, method="nearest")
    # Self-benchmark: the real depth subsampled 4 times further, refined back to its own grid.
    real = capture.depth.astype(np.float32)
    h, w = real.shape
    low = np.ascontiguousarray(capture.depth[1::4, 1::4])
    guide = cv2.resize(capture.rgb, (w, h), interpolation=cv2.INTER_AREA)
    scores = {name: round(rmse(refine(low, guide, method=name), real), 2) for name in ("nearest", "bilinear", method)}
    limits = viz.depth_limits(capture.depth.astype(np.float32))
    fig = viz.comparison_figure(
        capture.rgb, [("input x7.5 (nearest)", nearest), (f"refined ({method})", refined)],
        units="mm", zoom=viz.pick_detail(refined), limits=limits, ncols=3,
        title="iPhone LiDAR 256x192 depth refined to its 1920x1440 RGB frame (x7.5)",
    )
    write_figure(tmp / "demo_figure.png", fig)
    write_depth(tmp / "refined.png", refined, dtype=np.uint16)
    write_figure(tmp / "refined_blended.png", viz.figure_grid(
        [[viz.Panel(f"{method}: depth over the color image", refined, "blend", background=capture.rgb)]],
        units="mm", limits=limits, panel_width=6.0))
    record = {"method": method, "ratio": 7.5,
              "self_benchmark": {"what": "depth subsampled x4 (64x48), refined to 256x192 with the RGB resized "
                                         "to 256x192, RMSE in mm against the real 256x192 depth",
                                 "rmse_mm": scores}}
    lines = [f"iPhone LiDAR bookshelf: 256x192 depth refined x7.5 to 1920x1440 with {method}",
             "  self-benchmark (x4 further down and back up), RMSE against the real depth in mm: "
             + ", ".join(f"{k} {v:.1f}" for k, v in scores.items()),
             "wrote demo_figure.png, refined.png (uint16 mm), refined_blended.png, demo.json"]
    return record, lines


_SCENES = {"mug": _mug, "bookshelf": _bookshelf}


def run_scene(args: argparse.Namespace) -> int:
    """``depthrefine demo --scene mug|bookshelf``."""
    with atomic_directory(args.output, overwrite=args.overwrite) as tmp:
        record, lines = _SCENES[args.scene](tmp)
        capture_citation = load_capture(args.scene).citation
        record = {"depthrefine": __version__, "scene": args.scene, "citation": capture_citation, **record}
        (tmp / "demo.json").write_text(json.dumps(record, indent=2) + "\n", encoding="utf-8")
    for line in lines:
        print(line.replace("wrote ", f"wrote {args.output}/", 1) if line.startswith("wrote") else line)
    print(f"data: {capture_citation}", file=sys.stderr)
    return 0
