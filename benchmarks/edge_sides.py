"""Which side of a depth jump: how much of gbp's error that decision holds, and how well the color makes it.

Within ``R`` depth pixels of each large jump of the input (``gbp.edges.jump_band``'s
test: a (2R+1)x(2R+1) input range above 8 noise sigmas and 8 % of the depth range,
where the jump map shows a discontinuity), every color pixel lies on one side of
the jump or the other: its value below or above the middle of the input's
(4R+1)x(4R+1) range (the low side is the nearer in depth, the farther in disparity). On the tuning scenes of ``park``, ``middlebury30``, ``tof``
and ``sensor`` (gbp's output as the bench makes it: told the input is reprojected
on ``sensor``), per protocol (``sensor`` per model) and scale, it prints:

- ``band=truth``: gbp's RMSE with the band replaced by the ground truth (what any
  change confined to the band could give at most), relative to gbp's;
- ``sides``: gbp's RMSE when every band pixel gbp puts on the wrong side takes
  the truth's side and that side's depth (its nearest pixel outside the jump's
  own ramp, where gbp's output spans under half a jump over the pixel's
  half-depth-pixel neighbourhood): what a perfect side decision gives;
  ``sides, ramps``: the same, every pixel on a ramp (mixed values) re-set too;
- ``gbp``: the share of band pixels gbp's output puts on the truth's side;
- for two color-based decisions, the share of the band pixels they move to the
  other side, and the share of those moves that are right (their precision: a
  decision helps only where it is above one half):
  ``geodesic``: the side of the geodesic nearest pixel outside the band (the cost
  of a step its color difference plus 2 levels, the guide blurred by 1 px:
  ``--snap-edges``'s decision); ``color``: the side whose local mean color
  (Gaussian, sigma R depth pixels, over the pixels outside the band) is three
  times closer; ``both``: moved only where the two agree.

Run (about 3 min)::

    PYTHONPATH=src python benchmarks/edge_sides.py [--radius 2]
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

PROTOCOLS = ("park", "middlebury30", "tof", "sensor")
SCALES = (4, 8, 16)
#: The local mean color of one side must be this many times closer than the other's to move a pixel.
COLOR_MARGIN = 3.0


def band_sides(out: np.ndarray, depth_lr: np.ndarray, rgb: np.ndarray, radius: int) -> dict:
    """The band around the input's large jumps on the color grid, the middle depth, gbp's sides and its ramps."""
    import cv2

    from depthrefine._validate import as_depth, check_rgb, guide_uint8
    from depthrefine.methods.gbp.edges import SNAP_SIGMAS, SNAP_SPAN
    from depthrefine.methods.gbp.measure import measure_input
    from depthrefine.methods.gbp.solve import resize

    guide = guide_uint8(check_rgb(rgb))
    m = measure_input(as_depth(depth_lr), guide)
    shape = out.shape
    scale = 0.5 * (shape[0] / m.depth.shape[0] + shape[1] / m.depth.shape[1])
    step = max(SNAP_SIGMAS * m.sigma, SNAP_SPAN * m.span)     # jump_band's large jump
    band_k, side_k = np.ones((2 * radius + 1,) * 2, np.uint8), np.ones((4 * radius + 1,) * 2, np.uint8)
    spread = cv2.dilate(m.filled, band_k) - cv2.erode(m.filled, band_k)
    band = resize(((spread > step) & (m.jump >= 0.5)).astype(np.uint8), shape, cv2.INTER_NEAREST) > 0
    middle = 0.5 * (resize(cv2.erode(m.filled, side_k), shape, cv2.INTER_NEAREST)
                    + resize(cv2.dilate(m.filled, side_k), shape, cv2.INTER_NEAREST))
    size = 2 * int(math.ceil(0.5 * scale)) + 1
    ramp_k = np.ones((size, size), np.uint8)
    settled = (cv2.dilate(out, ramp_k) - cv2.erode(out, ramp_k)) <= 0.5 * step
    return {"band": band, "middle": middle, "low": out < middle, "settled": settled, "guide": guide,
            "scale": scale}


def with_sides(out: np.ndarray, b: dict, low: np.ndarray, *, ramps: bool) -> np.ndarray:
    """``out`` with the band's pixels on the sides ``low`` gives (and, with ``ramps``, its mixed pixels re-set)."""
    from scipy import ndimage

    move = b["band"] & ((low != b["low"]) | (~b["settled"] if ramps else False))
    result = out.copy()
    for side in (True, False):
        pool = (b["low"] == side) & b["settled"] & ~move
        target = move & (low == side)
        if pool.any() and target.any():
            rows, cols = ndimage.distance_transform_edt(~pool, return_distances=False, return_indices=True)
            result[target] = out[rows, cols][target]
    return result


def geodesic_sides(b: dict) -> np.ndarray:
    """Each band pixel on the side of its geodesic nearest pixel outside the band (``--snap-edges``'s decision)."""
    import cv2

    from depthrefine._geodesic import color_step_costs, nearest_seed
    from depthrefine.methods.gbp.edges import GUIDE_BLUR, STEP_LEVELS

    color = cv2.GaussianBlur(b["guide"], (0, 0), GUIDE_BLUR).astype(np.float32)
    source = nearest_seed(*color_step_costs(color, blur=0, step_levels=STEP_LEVELS), b["band"])
    low = b["low"]
    return np.where(source >= 0, low.ravel()[np.maximum(source, 0)].reshape(low.shape), low)


def color_sides(b: dict, radius: int) -> np.ndarray:
    """A band pixel moves to the side whose local mean color is :data:`COLOR_MARGIN` times closer than its own's."""
    import cv2

    color = cv2.GaussianBlur(b["guide"], (0, 0), 1.0).astype(np.float32)
    sigma = radius * b["scale"]
    outside = ~b["band"]
    distances, weights = [], []
    for side in (b["low"] & outside, ~b["low"] & outside):
        weight = cv2.GaussianBlur(side.astype(np.float32), (0, 0), sigma)
        mean = np.stack([cv2.GaussianBlur(color[..., c] * side, (0, 0), sigma) for c in range(3)], axis=-1)
        mean /= np.maximum(weight, 1e-6)[..., None]
        distances.append(np.sqrt(np.square(color - mean).sum(axis=-1)))
        weights.append(weight)
    d_low, d_high = distances
    known = (weights[0] > 1e-3) & (weights[1] > 1e-3)
    to_low = known & ~b["low"] & (COLOR_MARGIN * d_low < d_high)
    to_high = known & b["low"] & (COLOR_MARGIN * d_high < d_low)
    return (b["low"] | to_low) & ~to_high


def main(argv: list[str] | None = None) -> int:
    from depthrefine.bench.metrics import score
    from depthrefine.bench.protocols import PROTOCOLS as ALL, TUNING_SCENES, load_cases
    from depthrefine.methods.gbp import GbpParams, upsample_gbp
    from depthrefine.rig.chain import reprojected_params

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", type=Path, default=Path(__file__).resolve().parents[2] / "shared" / "data")
    ap.add_argument("--radius", type=int, default=2, help="the band's half-width, depth pixels (default 2)")
    args = ap.parse_args(argv)
    rows: dict[tuple[str, int], list[list[float]]] = {}
    for protocol in PROTOCOLS:
        params = reprojected_params("gbp", GbpParams()) if ALL[protocol].reprojected else GbpParams()
        for case in load_cases(args.data, protocol, SCALES):
            if case.scene not in TUNING_SCENES[protocol]:
                continue
            out = upsample_gbp(case.depth_lr, case.rgb_hr, params=params)
            truth = case.depth_gt.astype(np.float32)
            b = band_sides(out, case.depth_lr, case.rgb_hr, args.radius)
            band = b["band"]
            truth_low = np.where(np.isfinite(truth), truth, out) < b["middle"]
            rmse = score(out, case.depth_gt, border=case.border).rmse
            perfect = np.where(band & np.isfinite(truth), truth, out)
            row = [score(perfect, case.depth_gt, border=case.border).rmse / rmse]
            row += [score(with_sides(out, b, truth_low, ramps=ramps), case.depth_gt, border=case.border).rmse / rmse
                    for ramps in (False, True)]
            row.append(float((b["low"] == truth_low)[band].mean()) if band.any() else 1.0)
            geodesic, color = geodesic_sides(b), color_sides(b, args.radius)
            both = np.where((geodesic != b["low"]) & (color != b["low"]), color, b["low"])
            for low in (geodesic, color, both):
                moved = band & (low != b["low"])
                row += [moved.sum() / max(band.sum(), 1),
                        float((low == truth_low)[moved].mean()) if moved.any() else float("nan")]
            key = protocol if "-" not in case.scene else f"{protocol} {case.scene.rsplit('-', 1)[1]}"
            rows.setdefault((key, case.scale), []).append(row)
    print(f"band: {args.radius} depth px around the input's large jumps; tuning scenes; RMSE relative to gbp's")
    print("| cell | band=truth | sides | sides, ramps | gbp right | geodesic moves / right | color moves / right "
          "| both moves / right |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for (key, scale), values in rows.items():
        v = np.nanmean(np.array(values, float), axis=0)
        moves = " | ".join(f"{100 * v[4 + 2 * i]:.1f} % / {100 * v[5 + 2 * i]:.0f} %" for i in range(3))
        print(f"| {key} x{scale} | {v[0] - 1:+.0%} | {v[1] - 1:+.0%} | {v[2] - 1:+.0%} | {100 * v[3]:.1f} % | {moves} |",
              flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
