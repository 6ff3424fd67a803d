"""``depthrefine demo [-o DIR]``: the methods on the shipped Middlebury scene, as in the thesis's Fig. 47."""

from __future__ import annotations

import argparse
import json
import sys
import time

from .. import __version__, viz
from ..io._names import SAMPLE_SCALES, SCENES
from ..methods._names import DEFAULT_METHOD
from ._common import add_overwrite, params_dict, progress_bar

#: The OpenCV peers the demo compares; the figure shows the best of them on the scene.
PEERS = ("jbf", "guided", "fgs", "wmf")
#: Units of the shipped scene's depth.
UNITS = "disparity levels"


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


def demo_panels(results: dict[str, object], scores: dict[str, float], *, scale: int,
                default: str = DEFAULT_METHOD) -> tuple[list[tuple[str, object]], str]:
    """The demo figure's depth panels (title with RMSE, depth) and the best peer's name.

    ``results`` holds ``nearest`` (the input enlarged), ``bilinear``, the
    peers of :data:`PEERS` that ran, ``thesis``, ``default`` and ``ground
    truth``; ``scores`` their RMSE.
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


def run(args: argparse.Namespace) -> int:
    if args.scene != "art":
        from ._demo_scenes import run_scene

        return run_scene(args)
    from ..evaluate import rmse
    from ..io import atomic_directory, load_sample, sample_folder, write_depth, write_figure
    from ..methods.registry import METHODS, refine

    default = DEFAULT_METHOD
    names = list(dict.fromkeys(["nearest", "bilinear", *[m for m in PEERS if m in METHODS], "thesis", default]))
    with atomic_directory(args.output, overwrite=args.overwrite) as tmp:
        scene = load_sample(args.scale)
        gt = scene.depth_gt.astype("float32")
        results: dict[str, object] = {}
        seconds: dict[str, float] = {}
        for name in names:
            update, close = progress_bar(f"demo: {name} x{args.scale}", enabled=None)
            t0 = time.perf_counter()
            try:
                results[name] = refine(scene.depth_lr, scene.rgb_hr, method=name, progress=update)
            finally:
                close()
            seconds[name] = time.perf_counter() - t0
        scores = {name: round(rmse(depth, gt), 3) for name, depth in results.items()}
        results["ground truth"] = gt
        panels, best = demo_panels(results, scores, scale=args.scale, default=default)
        zoom = viz.pick_detail(gt)
        fig = viz.comparison_figure(
            scene.rgb_hr, panels, units=UNITS, zoom=zoom, limits=viz.depth_limits(gt),
            ncols=(len(panels) + 2) // 2,  # color + panels in two rows
            title=f"Middlebury 2005 Art, ×{args.scale} noisy input (Park et al. 2011); RMSE against the "
                  f"ground truth in {UNITS}",
        )
        write_figure(tmp / "demo_figure.png", fig)
        refined = results[default]
        write_depth(tmp / "refined.png", refined, dtype=scene.depth_lr.dtype)
        write_figure(tmp / "refined_blended.png", viz.figure_grid(
            [[viz.Panel(f"{default}: depth over the color image", refined, "blend", background=scene.rgb_hr)]],
            units=UNITS, limits=viz.depth_limits(gt), panel_width=6.0))
        record = {
            "depthrefine": __version__,
            "scene": f"{sample_folder()}/noisy_x{args.scale}.png",
            "citation": scene.citation,
            "scale": args.scale,
            "default_method": default,
            "best_peer": best,
            "params": {name: params_dict(METHODS[name].default_params()) for name in names},
            "rmse": scores,
            "seconds": {name: round(t, 3) for name, t in seconds.items()},
            "zoom_rows_cols": list(zoom),
        }
        (tmp / "demo.json").write_text(json.dumps(record, indent=2) + "\n", encoding="utf-8")
    print(f"Middlebury 2005 Art x{args.scale}: RMSE against ground truth ({UNITS})")
    for name, value in scores.items():
        notes = [n for n, on in (("input", name == "nearest"), ("best peer", name == best),
                                 ("default", name == default)) if on]
        print(f"  {name:9s} {value:6.2f}  {seconds[name]:6.2f} s" + (f"  ({', '.join(notes)})" if notes else ""))
    print(f"wrote {args.output}/demo_figure.png, refined.png ({default}), refined_blended.png, demo.json")
    print(f"data: {scene.citation}", file=sys.stderr)
    return 0
