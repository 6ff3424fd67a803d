"""Does the Azure Kinect mug's depth outline meet the color edges? With the factory rig, inverted, without extrinsics.

The shipped mug capture (``depthrefine.io.load_capture("mug")``) is aligned
with the factory calibration (``rig import``, NFOV_UNBINNED, 720P), then
refined with each method given (holes kept, as ``run`` does, and filled).
``depthrefine.rig.edges.edge_overlap`` (outline: nearer than 600 mm next to
farther than 1000 mm, against Canny edges of the undistorted color image)
is printed for each map: the share of outline pixels within 2 px of a color
edge and the median distance. The figures of docs/rig.md, step 4 (``benchmarks/mug_edges.py``: before and after
the chain upsampled).

Usage::

    python benchmarks/mug_alignment.py [--methods gbp,thesis]
"""

from __future__ import annotations

import argparse

import numpy as np

NEAR, FAR = 600.0, 1000.0


def main() -> None:
    from depthrefine.io import load_capture, read_calibration, sample_folder
    from depthrefine.rig import StereoRig
    from depthrefine.rig.chain import AlignSettings, align_pair, keep_unmeasured, nearest_on_grid, refine_pair
    from depthrefine.rig.edges import edge_overlap

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--methods", default="gbp,thesis")
    args = parser.parse_args()
    capture = load_capture("mug")
    rig, _ = read_calibration(sample_folder("mug") / "calibration.json", depth_mode="NFOV_UNBINNED",
                              color_resolution="720P")
    settings = AlignSettings(depth_units=0.001)
    rigs = {
        "factory rig": rig,
        "rig inverted (color -> depth used as depth -> color)": StereoRig(rig.depth_camera, rig.color_camera, rig.R.T,
                                                                          -rig.R.T @ rig.t),
        "no extrinsics (R = I, t = 0)": StereoRig(rig.depth_camera, rig.color_camera, np.eye(3), np.zeros(3)),
    }
    print("edge_overlap of the mug's outline: share within 2 px of a color edge, median distance")
    for name, this_rig in rigs.items():
        pair = align_pair(capture.depth, capture.rgb, this_rig, settings=settings)
        fit = edge_overlap(nearest_on_grid(pair.depth_lr, pair.rgb_hr.shape[:2]), pair.rgb_hr, near=NEAR, far=FAR)
        print(f"  aligned, {name}: {100 * fit.fraction:.0f} % within 2 px, median {fit.median_px:.1f} px "
              f"({fit.pixels} outline pixels)")
        if this_rig is not rig:
            continue
        for method in args.methods.split(","):
            dense = refine_pair(pair.depth_lr, pair.rgb_hr, method=method)[0]  # as run does
            for label, depth in (("holes kept (run)", keep_unmeasured(dense, pair.depth_lr, rgb_hr=pair.rgb_hr)),
                                 ("--fill-holes", keep_unmeasured(dense, pair.depth_lr, fill_enclosed=True,
                                                                  rgb_hr=pair.rgb_hr))):
                fit = edge_overlap(depth, pair.rgb_hr, near=NEAR, far=FAR)
                print(f"  refined with {method}, {label}: {100 * fit.fraction:.0f} % within 2 px, median "
                      f"{fit.median_px:.1f} px ({fit.pixels} outline pixels)")


if __name__ == "__main__":
    main()
