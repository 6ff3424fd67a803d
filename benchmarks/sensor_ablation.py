"""Where gbp loses to the weighted median under a simulated sensor: each part of the simulation turned off in turn.

The ``sensor`` protocol's input (``depthrefine.bench.sensor.simulate_sensor``)
is rebuilt for every Park scene (tuning and test) at the scales given, with
the model's parameters as they are and with one part of the simulation off
at a time (the depth camera beside the color camera, the footprint wider
than the pixel, the calibration error, the noise, the dark dropouts); then
with the input's holes filled from the truth (each hole pixel the mean of
the truth over its block), and with the weighted-median peer's result put in
place of gbp's in the band of gbp's large input jumps (``--band-median``).
Printed per variant: the mean RMSE of gbp, of the protocol-tuned ``wmf``
peer, and their ratio (below 1: gbp ahead). gbp runs with its defaults, its
input's reprojection unsaid (as when ``docs/tuning.md``'s table was made);
``--reprojected`` tells it, as the bench now does::

    python benchmarks/sensor_ablation.py                     # iToF, x4 and x8
    python benchmarks/sensor_ablation.py --model dtof --scales 4,8,16 --band-median
    python benchmarks/sensor_ablation.py --reprojected
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

import numpy as np

#: The parts of the simulation turned off one at a time: name -> the model fields that do it.
PARTS_OFF = {
    "no baseline (the depth camera at the color camera)": {"baseline_mm": 0.0},
    "footprint of one pixel": {"footprint": 1.0},
    "no calibration error": {"misregistration": 0.0},
    "no noise": {"noise_mm_at_1m": 0.0},
    "no dark dropouts": {"dark_low": 0.0, "dark_high": 0.0},
    "footprint of one pixel and no baseline": {"footprint": 1.0, "baseline_mm": 0.0},
}


def _holes_from_truth(depth_lr: np.ndarray, truth: np.ndarray, scale: int) -> np.ndarray:
    """``depth_lr`` with each invalid pixel the mean of the valid truth over its block."""
    h, w = depth_lr.shape
    blocks = truth[: h * scale, : w * scale].reshape(h, scale, w, scale).transpose(0, 2, 1, 3).reshape(h, w, -1)
    with np.errstate(invalid="ignore"):
        means = np.nanmean(blocks, axis=2)
    return np.where(np.isfinite(depth_lr) & (depth_lr > 0), depth_lr, means).astype(np.float32)


def main(argv: list[str] | None = None) -> int:
    import warnings

    import cv2

    from depthrefine.bench.metrics import rmse
    from depthrefine.bench.protocols import load_cases
    from depthrefine.bench.sensor import SENSOR_MODELS, SENSOR_PEER_PARAMS, sensor_seed, simulate_sensor
    from depthrefine.methods.gbp import GbpParams, upsample_gbp
    from depthrefine.methods.gbp.measure import measure_input
    from depthrefine.methods.peers import WeightedMedianParams, upsample_wmf
    from depthrefine._validate import as_depth

    default = Path(__file__).resolve().parents[1].parent / "shared" / "data"
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", type=Path, default=default, help="benchmark data folder (default: ../shared/data)")
    parser.add_argument("--model", choices=sorted(SENSOR_MODELS), default="itof")
    parser.add_argument("--scales", default="4,8", help="comma-separated scales (default 4,8)")
    parser.add_argument("--reprojected", action="store_true",
                        help="tell gbp its input is reprojected (GbpParams.reprojected), as the bench does")
    parser.add_argument("--band-median", action="store_true",
                        help="also: the weighted median in the band of gbp's large input jumps, gbp elsewhere")
    args = parser.parse_args(argv)
    scales = tuple(int(s) for s in args.scales.split(","))
    model = SENSOR_MODELS[args.model]
    wmf = WeightedMedianParams(**SENSOR_PEER_PARAMS["wmf"])
    told = GbpParams(reprojected=True) if args.reprojected else None
    cases = [c for c in load_cases(args.data, "park", scales)]
    if not cases:
        print(f"no Park scenes under {args.data}; give --data", file=sys.stderr)
        return 2
    variants: dict[str, list[tuple[float, float]]] = {}
    for case in cases:
        truth = np.where(np.isfinite(case.depth_gt), case.depth_gt, 0.0)
        seed = sensor_seed(case.scene, model.name, case.scale)
        for name, fields in {"as in the protocol": {}, **PARTS_OFF}.items():
            depth_lr = simulate_sensor(truth, case.rgb_hr, scale=case.scale, seed=seed,
                                       model=dataclasses.replace(model, **fields))
            gbp = upsample_gbp(depth_lr, case.rgb_hr, params=told)
            peer = upsample_wmf(depth_lr, case.rgb_hr, params=wmf)
            variants.setdefault(name, []).append((rmse(gbp, case.depth_gt), rmse(peer, case.depth_gt)))
            if fields:
                continue
            filled = _holes_from_truth(depth_lr, case.depth_gt, case.scale)
            variants.setdefault("holes filled from the truth", []).append(
                (rmse(upsample_gbp(filled, case.rgb_hr, params=told), case.depth_gt),
                 rmse(upsample_wmf(filled, case.rgb_hr, params=wmf), case.depth_gt)))
            if args.band_median:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    band_lr = measure_input(as_depth(depth_lr), case.rgb_hr).large_jumps
                band = cv2.resize(band_lr.astype(np.uint8), gbp.shape[::-1], interpolation=cv2.INTER_NEAREST) > 0
                variants.setdefault("wmf in gbp's large-jump band, gbp elsewhere", []).append(
                    (rmse(np.where(band, peer, gbp), case.depth_gt), rmse(peer, case.depth_gt)))
        print(f"  {case.scene} x{case.scale} done", file=sys.stderr, flush=True)
    print(f"sensor model {model.name}, Park scenes {sorted({c.scene for c in cases})}, x{args.scales}: mean RMSE")
    print(f"{'variant':<52} {'gbp':>7} {'wmf':>7} {'gbp/wmf':>8}")
    for name, scores in variants.items():
        g, w = np.mean(scores, axis=0)
        print(f"{name:<52} {g:7.3f} {w:7.3f} {g / w:8.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
