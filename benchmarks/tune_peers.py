"""Tune the OpenCV peers' parameters on the benchmark's tuning scenes.

Each peer (``depthrefine.methods.peers``) has a few parameters; this script scores
every combination of a small grid on the tuning scenes of two protocols
(``depthrefine.bench.tuned_on_scenes``): Park's noisy Dolls and Laundry, and
four of the noise-free 30-image Middlebury set (Baby1, Cloth2, Midd1,
Rocks1), at x4, x8 and x16 (the benchmark also leaves out Middlebury_14 and
_18, which are Dolls and Laundry again, but they are not tuned on), and picks the one with the lowest objective:
the mean over the two protocols of the mean RMSE over their cases (so
the noisy and the noise-free case weigh the same). The benchmark then
reports on the other scenes. The chosen values are the defaults of the
params dataclasses in ``peers.py`` (and are listed in ``docs/bench.md``).

Usage::

    python benchmarks/tune_peers.py [--data ../shared/data] [--peers jbf,guided,fgs,wmf] [--output FILE.json]

It prints one line per combination (mean RMSE and edge RMSE over the six
cases, and seconds per image) and the best per peer.

``--protocol sensor`` tunes for one protocol that keeps its own peer parameters
(``Protocol.method_params``; the simulated real sensors of
``depthrefine.bench.sensor``) on that protocol's tuning scenes only (Dolls and
Laundry under both sensor models, 12 cases at x4, x8, x16): the objective is
the mean RMSE over them, and the script prints the ``SENSOR_PEER_PARAMS`` to
store in ``bench/sensor.py``::

    python benchmarks/tune_peers.py --protocol sensor --output sensor_tuning.json
"""

from __future__ import annotations

import argparse
import itertools
import json
import statistics
import sys
import time
from pathlib import Path

from depthrefine.methods import peers
from depthrefine.bench import TUNING_SCENES, mean_or_nan, run_benchmark, tuned_on_scenes
from depthrefine.bench import load_cases

#: The protocols whose tuning scenes are used (one noisy, one noise-free).
TUNING_PROTOCOLS = ("park", "middlebury30")

#: The grids: {method: (params type, {field: values})}.
GRIDS = {
    "jbf": (peers.JointBilateralParams, {"sigma_space_lr": [1.0, 2.0, 4.0], "sigma_color": [0.05, 0.1, 0.2]}),
    "guided": (peers.GuidedParams, {"radius_lr": [0.5, 1.0, 2.0, 4.0], "eps": [1e-3, 1e-2, 3e-2, 1e-1]}),
    "fgs": (peers.FastGlobalSmootherParams, {"lambda_lr": [1.0, 4.0, 16.0, 64.0], "sigma_color": [1.0, 2.0, 4.0, 8.0, 16.0]}),
    "wmf": (peers.WeightedMedianParams, {"radius_lr": [0.5, 1.0, 2.0, 3.0, 4.0], "sigma": [10.0, 25.5, 50.0]}),
}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    default_data = Path(__file__).resolve().parents[1].parent / "shared" / "data"
    parser.add_argument("--data", default=str(default_data), help="folder laid out as shared/data")
    parser.add_argument("--peers", default=",".join(GRIDS), help="comma-separated peers to tune")
    parser.add_argument("--scales", default="4,8,16")
    parser.add_argument("--output", help="write the full grid results as JSON here")
    parser.add_argument("--protocol", help="tune for this protocol alone, on its own tuning scenes (e.g. sensor)")
    parser.add_argument("--grid", help='JSON replacing the grids of some peers, e.g. \'{"fgs": {"lambda_lr": [256], '
                                       '"sigma_color": [1, 2]}}\' (to go past a best value on the edge of a grid)')
    args = parser.parse_args(argv)
    scales = tuple(int(s) for s in args.scales.split(","))
    protocols = (args.protocol,) if args.protocol else TUNING_PROTOCOLS
    cases = [c for p in protocols for c in load_cases(args.data, p, scales)
             if c.scene in tuned_on_scenes(p)]
    if {c.protocol for c in cases} != set(protocols):
        print(f"missing tuning scenes {TUNING_SCENES} under {args.data}", file=sys.stderr)
        return 2
    print(f"tuning on {sorted({(c.protocol, c.scene) for c in cases})} x {scales}: {len(cases)} cases", flush=True)
    results: dict[str, list[dict]] = {}
    best: dict[str, dict] = {}
    grids = {name: (GRIDS[name][0], grid) for name, grid in json.loads(args.grid).items()} if args.grid else {}
    for name in args.peers.split(","):
        params_type, grid = grids.get(name, GRIDS[name])
        results[name] = []
        for values in itertools.product(*grid.values()):
            fields = dict(zip(grid, values))
            params = params_type(**fields)
            t0 = time.perf_counter()
            rows = run_benchmark(cases, [name], params={name: params}).rows
            entry = {
                "params": fields,
                "objective": mean_or_nan(mean_or_nan(r.rmse for r in rows if r.protocol == p)
                                         for p in protocols),
                "rmse_by_protocol": {p: mean_or_nan(r.rmse for r in rows if r.protocol == p)
                                     for p in protocols},
                "rmse": mean_or_nan(r.rmse for r in rows),
                "edge_rmse": mean_or_nan(r.edge_rmse for r in rows),
                "rmse_by_scale": {f"{p} x{s}": mean_or_nan(r.rmse for r in rows if r.scale == s and r.protocol == p)
                                  for p in protocols for s in scales},
                "median_seconds": statistics.median(r.seconds for r in rows),
            }
            results[name].append(entry)
            print(f"{name:7s} {fields} objective {entry['objective']:.4f} "
                  f"{' '.join(f'{p} {v:.4f}' for p, v in entry['rmse_by_protocol'].items())} "
                  f"edge {entry['edge_rmse']:.4f} "
                  f"({time.perf_counter() - t0:.1f} s)", flush=True)
        best[name] = min(results[name], key=lambda e: e["objective"])
        print(f"BEST {name}: {best[name]['params']} objective {best[name]['objective']:.4f}", flush=True)
    if args.protocol:
        print(f"protocol {args.protocol}: method_params = "
              + json.dumps({name: entry["params"] for name, entry in best.items()}), flush=True)
    if args.output:
        Path(args.output).write_text(json.dumps({"cases": [c.key for c in cases], "results": results,
                                                 "best": best}, indent=2) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
