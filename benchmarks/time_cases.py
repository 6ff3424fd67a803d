"""Wall time of methods on every benchmark case, per protocol, beside OpenCV-contrib's fast global smoother.

``benchmarks/bench_speed.py`` times the speed targets' fixed inputs (the
thesis geometry, Art x4 / x8 / x16, a Kinect frame); a step whose cost
depends on the input (gbp's step 1b measures more where a cheap check cannot
rule a fattening out) shows only on other inputs. This times each method on
every case of every protocol whose data is present (the best of ``--repeats``
calls per case, the methods alternated case by case so they share the
machine's noise) and prints, per protocol, the summed seconds and each
method's ratio to FGS's (the peer with the protocol's tuned parameters, as
in the bench)::

    python benchmarks/time_cases.py                          # gbp-fast and gbp against FGS
    python benchmarks/time_cases.py --methods gbp-fast --repeats 5
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np


def main(argv: list[str] | None = None) -> int:
    from depthrefine.bench.protocols import PROTOCOLS, load_cases
    from depthrefine.bench.suite import protocol_params
    from depthrefine.methods.registry import refine

    default = Path(__file__).resolve().parents[1].parent / "shared" / "data"
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", type=Path, default=default, help="benchmark data folder (default: ../shared/data)")
    parser.add_argument("--methods", default="gbp-fast,gbp", help="comma-separated methods timed beside fgs")
    parser.add_argument("--repeats", type=int, default=3, help="calls per case and method; the best counts (3)")
    args = parser.parse_args(argv)
    methods = [m for m in args.methods.split(",") if m != "fgs"] + ["fgs"]
    totals: dict[str, dict[str, float]] = {}
    for protocol in PROTOCOLS:
        scales = (4, 8) if protocol == "realtof" else (4, 8, 16)
        cases = load_cases(args.data, protocol, scales)
        if not cases:
            continue
        params = protocol_params(protocol)
        for case in cases:
            for method in methods:   # warm: numba's kernels loaded, OpenCV's buffers sized
                refine(case.depth_lr, case.rgb_hr, method=method, params=params.get(method))
            best = {m: np.inf for m in methods}
            for _ in range(args.repeats):
                for method in methods:
                    start = time.perf_counter()
                    refine(case.depth_lr, case.rgb_hr, method=method, params=params.get(method))
                    best[method] = min(best[method], time.perf_counter() - start)
            row = totals.setdefault(f"{protocol} ({len(cases)} cases)", dict.fromkeys(methods, 0.0))
            for method in methods:
                row[method] += best[method]
        print(f"  {protocol}: {len(cases)} cases timed", file=sys.stderr, flush=True)
    if not totals:
        print(f"no benchmark data under {args.data}; give --data", file=sys.stderr)
        return 2
    print("summed wall seconds per protocol (best of", args.repeats, "calls per case) and the ratio to fgs")
    print(f"{'protocol':<24}" + "".join(f"{m:>20}" for m in methods))
    for name, row in totals.items():
        cells = "".join(f"{row[m]:>11.2f} ({row[m] / row['fgs']:4.1f}x)" for m in methods)
        print(f"{name:<24}{cells}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
