"""The scenes of ``depthrefine demo``: the methods on the shipped data, as figures, files and a record.

- ``art``: Middlebury 2005 Art (Park et al.'s noisy input) refined by
  every compared method and scored against the ground truth, in a figure
  like the thesis's Fig. 47 (:func:`art_demo`);
- ``mug``: a real Azure Kinect capture through the whole rig chain: factory
  calibration, reprojection, refinement, point cloud (:func:`mug_demo`);
- ``bookshelf``: a real iPhone LiDAR frame refined x7.5, with a
  self-benchmark (:func:`bookshelf_demo`).

Each returns a :class:`DemoOutput` (the files by name, the record, the lines
to print); the command writes it.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from .. import __version__, viz
from ..methods._names import DEFAULT_METHOD

__all__ = ["PEERS", "UNITS", "MUG_NEAR_MM", "MUG_FAR_MM", "MUG_DETAIL", "DemoOutput", "demo_panels", "edges_picture",
           "art_demo", "mug_demo", "bookshelf_demo", "point_sampled_params", "run_demo"]

#: The OpenCV peers the Art demo compares; the figure shows the best of them on the scene.
PEERS = ("jbf", "guided", "fgs", "wmf")
#: Units of the Art scene's depth.
UNITS = "disparity levels"

#: The mug is at about 256 mm and the wall behind it at 1.5-2.2 m: the silhouette
#: separates pixels nearer than 600 mm from pixels farther than 1000 mm.
MUG_NEAR_MM, MUG_FAR_MM = 600.0, 1000.0
#: (row0, row1, col0, col1) of the mug in the 1280x720 color image.
MUG_DETAIL = (330, 650, 250, 700)

#: ``progress_bar(description) -> (progress(done, total), close())``: a progress display per refinement.
ProgressBar = Callable[[str], tuple[Callable[[int, int], None], Callable[[], None]]]


@dataclass(frozen=True, eq=False)
class DemoOutput:
    """What a demo scene writes and prints.

    Attributes
    ----------
    figures : dict of str to matplotlib Figure
        PNG figures by file name.
    depth_maps : dict of str to (ndarray, dtype)
        Depth files by name, each with the dtype to store it in.
    images : dict of str to (H, W, 3) uint8 ndarray
        RGB pictures by file name.
    record : dict
        ``demo.json``: the version, the scene, its citation and the figures.
    lines : list of str
        What to print; the line starting with ``"wrote "`` names the files
        relative to the output folder.
    citation : str
        The data's source.
    rig : (StereoRig, dict) or None
        ``rig.json``: the rig and the extra keys to record with it.
    cloud : (points, colors, comments) or None
        ``cloud.ply``.
    """

    figures: dict[str, Any]
    depth_maps: dict[str, tuple[np.ndarray, Any]]
    images: dict[str, np.ndarray]
    record: dict[str, Any]
    lines: list[str]
    citation: str
    rig: tuple[Any, dict[str, Any]] | None = None
    cloud: tuple[np.ndarray, np.ndarray, tuple[str, ...]] | None = field(default=None)


def _refine(depth_lr, rgb_hr, method: str, description: str, progress_bar: ProgressBar | None) -> np.ndarray:
    from ..methods.registry import refine

    update, close = progress_bar(description) if progress_bar is not None else (None, lambda: None)
    try:
        return refine(depth_lr, rgb_hr, method=method, progress=update)
    finally:
        close()


def demo_panels(results: dict[str, object], scores: dict[str, float], *, scale: int,
                default: str = DEFAULT_METHOD) -> tuple[list[tuple[str, object]], str]:
    """The Art figure's depth panels (title with RMSE, depth) and the best peer's name.

    ``results`` holds ``nearest`` (the input enlarged), ``bilinear``, the
    peers of :data:`PEERS` that ran, ``thesis``, ``default`` and ``ground
    truth``; ``scores`` their RMSE. The thesis method has a panel of its own
    (the method the project starts from), beside the default method's.
    """
    peers = [m for m in PEERS if m in scores]
    best = min(peers, key=lambda m: scores[m]) if peers else None

    def titled(caption: str, name: str) -> tuple[str, object]:
        return f"{caption}\nRMSE {scores[name]:.2f}", results[name]

    panels = [titled(f"input ×{scale} (nearest)", "nearest"), titled("bilinear", "bilinear")]
    if best is not None:
        panels.append(titled(f"best peer: {best}", best))
    if default == "thesis":
        panels.append(titled("thesis method (the default)", "thesis"))
    else:
        panels += [titled("thesis method", "thesis"), titled(f"{default} (the default method)", default)]
    panels.append(("ground truth", results["ground truth"]))
    return panels, best or ""


def art_demo(scale: int = 8, *, default: str = DEFAULT_METHOD, progress_bar: ProgressBar | None = None) -> DemoOutput:
    """Middlebury 2005 Art at ``scale``: every compared method, its RMSE and time, the comparison figure."""
    from .metrics import rmse
    from ..io import load_sample, sample_folder
    from ..methods.params import params_to_dict
    from ..methods.registry import METHODS

    names = list(dict.fromkeys(["nearest", "bilinear", *[m for m in PEERS if m in METHODS], "thesis", default]))
    scene = load_sample(scale)
    gt = scene.depth_gt.astype("float32")
    results: dict[str, object] = {}
    seconds: dict[str, float] = {}
    for name in names:
        t0 = time.perf_counter()
        results[name] = _refine(scene.depth_lr, scene.rgb_hr, name, f"demo: {name} x{scale}", progress_bar)
        seconds[name] = time.perf_counter() - t0
    scores = {name: round(rmse(depth, gt), 3) for name, depth in results.items()}
    results["ground truth"] = gt
    panels, best = demo_panels(results, scores, scale=scale, default=default)
    zoom = viz.pick_detail(gt)
    figure = viz.comparison_figure(
        scene.rgb_hr, panels, units=UNITS, zoom=zoom, limits=viz.depth_limits(gt),
        ncols=(len(panels) + 2) // 2,  # color + panels in two rows
        title=f"Middlebury 2005 Art, ×{scale} noisy input (Park et al. 2011); RMSE against the "
              f"ground truth in {UNITS}",
    )
    refined = results[default]
    blended = viz.figure_grid(
        [[viz.Panel(f"{default}: depth over the color image", refined, "blend", background=scene.rgb_hr)]],
        units=UNITS, limits=viz.depth_limits(gt), panel_width=6.0)
    record = {
        "depthrefine": __version__,
        "scene": f"{sample_folder()}/noisy_x{scale}.png",
        "citation": scene.citation,
        "scale": scale,
        "default_method": default,
        "best_peer": best,
        "params": {name: params_to_dict(METHODS[name].default_params()) for name in names},
        "rmse": scores,
        "seconds": {name: round(t, 3) for name, t in seconds.items()},
        "zoom_rows_cols": list(zoom),
    }
    lines = [f"Middlebury 2005 Art x{scale}: RMSE against ground truth ({UNITS})"]
    for name, value in scores.items():
        notes = [n for n, on in (("input", name == "nearest"), ("best peer", name == best),
                                 ("default", name == default)) if on]
        lines.append(f"  {name:9s} {value:6.2f}  {seconds[name]:6.2f} s" + (f"  ({', '.join(notes)})" if notes else ""))
    lines.append(f"wrote demo_figure.png, refined.png ({default}), refined_blended.png, demo.json")
    return DemoOutput(figures={"demo_figure.png": figure, "refined_blended.png": blended},
                      depth_maps={"refined.png": (refined, scene.depth_lr.dtype)}, images={}, record=record,
                      lines=lines, citation=scene.citation)


def edges_picture(rgb: np.ndarray, depth: np.ndarray, *, near: float, far: float) -> np.ndarray:
    """The color image darkened, its Canny edges in green and the depth's near-object silhouette in red."""
    from ..rig.edges import color_edges, depth_silhouette

    out = (viz.to_rgb8(rgb) * 0.6).astype(np.uint8)
    out[color_edges(rgb)] = (0, 255, 0)
    out[depth_silhouette(depth, near=near, far=far)] = (255, 0, 0)
    return out


def mug_demo(*, method: str = DEFAULT_METHOD, progress_bar: ProgressBar | None = None) -> DemoOutput:
    """The Azure Kinect mug through the whole chain: factory calibration, reprojection, refinement, point cloud."""
    from ..io import load_capture, read_calibration
    from ..rig.chain import AlignSettings, align_pair, keep_unmeasured, nearest_on_grid, refine_pair
    from ..rig.edges import edge_overlap
    from ..rig.pointcloud import depth_to_points

    capture = load_capture("mug")
    rig, _ = read_calibration(capture.calibration, depth_mode="NFOV_UNBINNED", color_resolution="720P")
    pair = align_pair(capture.depth, capture.rgb, rig, settings=AlignSettings(depth_units=capture.depth_units))
    update, close = progress_bar(f"demo mug: {method}") if progress_bar is not None else (None, lambda: None)
    try:  # as run does: the method upsamples the depth-resolution grid (x2 here)
        refined = keep_unmeasured(refine_pair(pair.depth_lr, pair.rgb_hr, method=method, progress=update)[0],
                                  pair.depth_lr, rgb_hr=pair.rgb_hr)
    finally:
        close()
    aligned = nearest_on_grid(pair.depth_lr, pair.rgb_hr.shape[:2])  # as the refinement spreads it
    aligned_fit = edge_overlap(aligned, pair.rgb_hr, near=MUG_NEAR_MM, far=MUG_FAR_MM)
    refined_fit = edge_overlap(refined, pair.rgb_hr, near=MUG_NEAR_MM, far=MUG_FAR_MM)
    figure = viz.comparison_figure(
        pair.rgb_hr,
        [("depth reprojected into the color camera\n(factory calibration)", aligned),
         (f"refined ({method})", refined)],
        units="mm", zoom=MUG_DETAIL, limits=(150.0, 2300.0), ncols=3,
        title="Azure Kinect (NFOV unbinned 640x576 ToF, 720p color): the whole chain on one real capture",
    )
    r0, r1, c0, c1 = MUG_DETAIL
    # The registration check: the reprojected depth's outline (red) on the color edges (green).
    edges = edges_picture(pair.rgb_hr, aligned, near=MUG_NEAR_MM, far=MUG_FAR_MM)[r0:r1, c0:c1]
    points, colors = depth_to_points(refined, pair.camera, rgb=pair.rgb_hr, depth_units=capture.depth_units, stride=2)
    fits = {name: {"fraction_within_2px": round(fit.fraction, 3), "median_px": round(fit.median_px, 2),
                   "silhouette_pixels": fit.pixels} for name, fit in (("aligned", aligned_fit), ("refined", refined_fit))}
    record = {
        "depthrefine": __version__, "scene": "mug", "citation": capture.citation,
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
    return DemoOutput(
        figures={"demo_figure.png": figure},
        depth_maps={"refined.png": (refined, np.uint16), "aligned.png": (pair.depth_lr, np.uint16)},
        images={"edges.png": edges}, record=record, lines=lines, citation=capture.citation,
        rig=(rig, {"imported_from": "calibration.json (Azure Kinect factory calibration)",
                   "depth_mode": "NFOV_UNBINNED", "color_resolution": "720P"}),
        cloud=(points, colors, ("depthrefine demo --scene mug, every 2nd row and column",
                                "metres, color camera frame: X right, Y down, Z forward")))


#: The bookshelf's self-benchmark subsamples the real depth by this factor.
SELF_FACTOR = 4


def point_sampled_params(method: str):
    """``method``'s parameters for a point-sampled input: ``sampling = "point"`` where it has that knob, else None.

    Examples
    --------
    >>> point_sampled_params("gbp").sampling, point_sampled_params("bilinear")
    ('point', None)
    """
    from ..methods.registry import get_method

    entry = get_method(method)
    return entry.params_type(sampling="point") if entry.has_param("sampling") else None


def bookshelf_demo(*, method: str = DEFAULT_METHOD, progress_bar: ProgressBar | None = None) -> DemoOutput:
    """The iPhone LiDAR bookshelf refined x7.5, and a self-benchmark: its depth subsampled x4 and refined back."""
    from .metrics import rmse
    from ..io import load_capture
    from ..methods.registry import refine
    from .._lazy import cv2

    capture = load_capture("bookshelf")
    refined = _refine(capture.depth, capture.rgb, method, f"demo bookshelf: {method}", progress_bar)
    nearest = refine(capture.depth, capture.rgb, method="nearest")
    # Self-benchmark: the real depth subsampled s times further, refined back to its own grid. Depth pixel (i, j)
    # keeps pixel (s*i + s//2, s*j + s//2), where the library places a point sample (docs/algorithm.md 6.1); a method
    # that can be told so (gbp, gbp-fast: sampling) is, as the smooth ARKit map hides it from the input.
    real = capture.depth.astype(np.float32)
    h, w = real.shape
    s = SELF_FACTOR
    low = np.ascontiguousarray(capture.depth[s // 2::s, s // 2::s])
    guide = cv2.resize(capture.rgb, (w, h), interpolation=cv2.INTER_AREA)
    scores = {name: round(rmse(refine(low, guide, method=name, params=point_sampled_params(name)), real), 2)
              for name in ("nearest", "bilinear", method)}
    limits = viz.depth_limits(capture.depth.astype(np.float32))
    figure = viz.comparison_figure(
        capture.rgb, [("input x7.5 (nearest)", nearest), (f"refined ({method})", refined)],
        units="mm", zoom=viz.pick_detail(refined), limits=limits, ncols=3,
        title="iPhone LiDAR 256x192 depth refined to its 1920x1440 RGB frame (x7.5)",
    )
    blended = viz.figure_grid(
        [[viz.Panel(f"{method}: depth over the color image", refined, "blend", background=capture.rgb)]],
        units="mm", limits=limits, panel_width=6.0)
    record = {"depthrefine": __version__, "scene": "bookshelf", "citation": capture.citation,
              "method": method, "ratio": 7.5,
              "self_benchmark": {"what": f"depth subsampled x{s} ({low.shape[1]}x{low.shape[0]}, pixel "
                                         f"({s}i+{s // 2}, {s}j+{s // 2})), refined to {w}x{h} with the RGB "
                                         f"resized to {w}x{h} (gbp and gbp-fast told sampling = 'point'), RMSE in "
                                         f"mm against the real {w}x{h} depth",
                                 "rmse_mm": scores}}
    lines = [f"iPhone LiDAR bookshelf: 256x192 depth refined x7.5 to 1920x1440 with {method}",
             f"  self-benchmark (point samples x{s} further down, refined back up, gbp and gbp-fast told "
             "--sampling point), RMSE against the real depth in mm: "
             + ", ".join(f"{k} {v:.1f}" for k, v in scores.items()),
             "wrote demo_figure.png, refined.png (uint16 mm), refined_blended.png, demo.json"]
    return DemoOutput(figures={"demo_figure.png": figure, "refined_blended.png": blended},
                      depth_maps={"refined.png": (refined, np.uint16)}, images={}, record=record, lines=lines,
                      citation=capture.citation)


def run_demo(scene: str, *, scale: int = 8, progress_bar: ProgressBar | None = None) -> DemoOutput:
    """The demo of ``scene`` (``"art"`` at ``scale``, ``"mug"`` or ``"bookshelf"``)."""
    if scene == "art":
        return art_demo(scale, progress_bar=progress_bar)
    scenes = {"mug": mug_demo, "bookshelf": bookshelf_demo}
    if scene not in scenes:
        raise ValueError(f"unknown demo scene {scene!r}; choose one of art, {', '.join(scenes)}.")
    return scenes[scene](progress_bar=progress_bar)
