"""How well each method's confidence map ranks its errors, beside the steepness baseline (issue 23).

For every test scene of ``park``, ``middlebury30``, ``lu``, ``tof`` and ``sensor`` at x4,
x8 and x16 (``../shared/data`` or ``--data``), each method runs through
``depthrefine.refine_with_confidence`` and its map is scored by the
sparsification curve (``depthrefine.bench.metrics.sparsification``) against
the baseline ``exp(-g / p90(g))`` on the same output (``steepness_confidence``).
Per protocol, scale and method it prints:

- ``AUSE/RMSE`` and ``base``: the mean relative AUSE of the map and of the baseline;
- ``ratio``: mean AUSE / mean baseline AUSE (the issue's target for gbp: <= 0.6),
  and ``worst``: the largest per-scene ratio;
- ``half`` and ``base half``: mean RMSE of the more confident half over the less
  confident half (target for gbp: <= 0.5);
- with ``--bounds`` (gbp only): the ratio reached by a map that knows the true
  RMS error of each 3x3 / 7x7 window (``bound3``, ``bound7``): what a map as
  smooth as that could reach at best.

Then, for gbp, whether the issue's two targets are met in each row. Usage::

    python benchmarks/confidence_table.py                      # every method (the thesis is slow)
    python benchmarks/confidence_table.py --methods gbp,bicubic,guided --bounds
    python benchmarks/confidence_table.py --csv confidence.csv
    python benchmarks/confidence_table.py --split tune --methods gbp --set NEAR_LENGTH=2.5   # tuning

``--set NAME=VALUE`` sets a constant of ``depthrefine.methods.confidence``
(``FALLBACK_WEIGHT``: of ``depthrefine.methods.gbp.confidence``) for the run:
how the weights were compared with their neighbours on the tuning scenes.
"""

from __future__ import annotations

import argparse
import csv
import sys
import time
from pathlib import Path

import numpy as np

PROTOCOLS = ("park", "middlebury30", "lu", "tof", "sensor")
SCALES = (4, 8, 16)
#: The issue's targets for gbp.
AUSE_TARGET, HALF_TARGET = 0.6, 0.5


def _window_oracle(depth_hr: np.ndarray, depth_gt: np.ndarray, size: int) -> np.ndarray:
    """Minus the true RMS error of each ``size x size`` window: a map that knows the local error."""
    import cv2

    err2 = np.where(np.isfinite(depth_gt) & np.isfinite(depth_hr), (depth_hr - depth_gt) ** 2, 0).astype(np.float32)
    return -cv2.blur(err2, (size, size))


def score_case(case, method: str, bounds: bool, curves: dict | None = None) -> dict:
    import depthrefine
    from depthrefine.bench.metrics import sparsification
    from depthrefine.bench.suite import protocol_params
    from depthrefine.methods.confidence import steepness_confidence

    start = time.perf_counter()
    params = protocol_params(case.protocol).get(method)   # as the bench: the protocol's own parameters
    depth_hr, confidence = depthrefine.refine_with_confidence(case.depth_lr, case.rgb_hr, method=method, params=params)
    seconds = time.perf_counter() - start
    mine = sparsification(depth_hr, case.depth_gt, confidence, border=case.border)
    base = sparsification(depth_hr, case.depth_gt, steepness_confidence(depth_hr), border=case.border)
    if curves is not None:
        curves[case.key + (method,)] = (mine, base)
    row = dict(protocol=case.protocol, scene=case.scene, scale=case.scale, method=method, split=case.split,
               rmse=mine.rmse, ause=mine.ause, ause_baseline=base.ause, half=mine.half_ratio,
               half_baseline=base.half_ratio, seconds=seconds)
    if bounds:
        for size in (3, 7):
            oracle = sparsification(depth_hr, case.depth_gt, _window_oracle(depth_hr, case.depth_gt, size),
                                    border=case.border)
            row[f"ause_bound{size}"] = oracle.ause
    return row


def summarize(rows: list[dict], bounds: bool) -> list[dict]:
    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        groups.setdefault((r["protocol"], r["scale"], r["method"]), []).append(r)
    out = []
    for (protocol, scale, method), sel in groups.items():
        base = np.mean([r["ause_baseline"] for r in sel])
        line = dict(protocol=protocol, scale=scale, method=method, n=len(sel),
                    rel=np.mean([r["ause"] / r["rmse"] for r in sel]),
                    rel_base=np.mean([r["ause_baseline"] / r["rmse"] for r in sel]),
                    ratio=np.mean([r["ause"] for r in sel]) / base,
                    worst=max(r["ause"] / r["ause_baseline"] for r in sel),
                    half=np.mean([r["half"] for r in sel]), half_base=np.mean([r["half_baseline"] for r in sel]))
        if bounds and "ause_bound3" in sel[0]:
            line["bound3"] = np.mean([r["ause_bound3"] for r in sel]) / base
            line["bound7"] = np.mean([r["ause_bound7"] for r in sel]) / base
        out.append(line)
    return out


def print_table(summary: list[dict], methods: list[str]) -> None:
    header = (f"{'protocol':13s} {'x':>3s} {'method':9s} {'n':>3s} {'AUSE/RMSE':>9s} {'base':>6s} {'ratio':>6s} "
              f"{'worst':>6s} {'half':>6s} {'b.half':>6s} {'bound3':>6s} {'bound7':>6s}")
    print(header)
    print("-" * len(header))
    order = {m: i for i, m in enumerate(methods)}
    for s in sorted(summary, key=lambda s: (PROTOCOLS.index(s["protocol"]) if s["protocol"] in PROTOCOLS else 99,
                                            s["scale"], order.get(s["method"], 99))):
        bound = (f"{s['bound3']:6.2f} {s['bound7']:6.2f}" if "bound3" in s else f"{'':6s} {'':6s}")
        print(f"{s['protocol']:13s} {s['scale']:3d} {s['method']:9s} {s['n']:3d} {s['rel']:9.3f} {s['rel_base']:6.3f} "
              f"{s['ratio']:6.2f} {s['worst']:6.2f} {s['half']:6.3f} {s['half_base']:6.3f} {bound}")


def _set_constant(text: str) -> None:
    import depthrefine.methods.confidence as generic
    import depthrefine.methods.gbp.confidence as gbp

    name, _, value = text.partition("=")
    module = gbp if name == "FALLBACK_WEIGHT" else generic
    if not value or not hasattr(module, name):
        raise SystemExit(f"--set {text}: expected NAME=VALUE with NAME a constant of {module.__name__}")
    setattr(module, name, float(value))


def main(argv: list[str] | None = None) -> int:
    default = Path(__file__).resolve().parents[1].parent / "shared" / "data"
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument("--data", type=Path, default=default, help="benchmark data folder")
    parser.add_argument("--protocols", default=",".join(PROTOCOLS), help="comma-separated protocols")
    parser.add_argument("--scales", default=",".join(map(str, SCALES)), help="comma-separated factors")
    parser.add_argument("--methods", help="comma-separated methods (default: every registered one)")
    parser.add_argument("--split", choices=("test", "tune", "all"), default="test",
                        help="the scenes scored (tune: the tuning scenes the confidence was fitted on)")
    parser.add_argument("--bounds", action="store_true", help="also the local-oracle bounds for gbp")
    parser.add_argument("--csv", type=Path, help="write every per-scene row here")
    parser.add_argument("--plot", type=Path, help="save the mean sparsification curves per protocol here (PNG)")
    parser.add_argument("--set", dest="settings", action="append", default=[], metavar="NAME=VALUE",
                        help="a constant of depthrefine.methods.confidence (or FALLBACK_WEIGHT) for this run")
    args = parser.parse_args(argv)
    for setting in args.settings:
        _set_constant(setting)

    from depthrefine.bench.protocols import load_cases
    from depthrefine.methods.registry import METHODS

    if not args.data.is_dir():
        print(f"data folder {args.data} not found; pass --data", file=sys.stderr)
        return 2
    methods = args.methods.split(",") if args.methods else list(METHODS)
    scales = tuple(int(s) for s in args.scales.split(","))
    rows: list[dict] = []
    curves: dict = {}
    t0 = time.perf_counter()
    for protocol in args.protocols.split(","):
        for case in load_cases(args.data, protocol, scales):
            if args.split != "all" and case.split != args.split:
                continue
            for method in methods:
                rows.append(score_case(case, method, args.bounds and method == "gbp", curves))
            print(f"  {protocol} {case.scene} x{case.scale} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr,
                  flush=True)
    summary = summarize(rows, args.bounds)
    print_table(summary, methods)
    gbp = [s for s in summary if s["method"] == "gbp"]
    if gbp:
        print(f"\ngbp against the targets (ratio <= {AUSE_TARGET}, half <= {HALF_TARGET}):")
        for s in sorted(gbp, key=lambda s: (s["protocol"], s["scale"])):
            print(f"  {s['protocol']:13s} x{s['scale']:<3d} ratio {s['ratio']:.2f} "
                  f"{'met' if s['ratio'] <= AUSE_TARGET else 'NOT met'}; half {s['half']:.3f} "
                  f"{'met' if s['half'] <= HALF_TARGET else 'NOT met'}")
    if args.plot:
        from types import SimpleNamespace

        from depthrefine.bench.confidence_report import sparsification_figure

        cases = [SimpleNamespace(**{k: r[k] for k in ("protocol", "scene", "scale", "method", "split")}) for r in rows]
        sparsification_figure(curves, cases).savefig(args.plot)
    if args.csv:
        with open(args.csv, "w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=list(dict.fromkeys(k for r in rows for k in r)), restval="")
            writer.writeheader()
            writer.writerows(rows)
    print(f"({len(rows)} runs in {time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
