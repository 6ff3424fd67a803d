"""gbp-fast's figures for a setting: the tuning mean, the test cells against the peers, the CPU time against FGS.

The tuning mean is ``benchmarks/tune_gbp.py``'s (the tuning scenes of ``park``,
``middlebury30`` and ``tof`` at x4, x8, x16; the mean of the three per-scale
means), for ``gbp-fast``. A field of ``GbpFastParams`` is set with
``--set rounds=3``, a constant of ``methods/gbp/fast.py`` with
``--set FINAL_ITERATIONS=3`` (or of gbp's steps: ``--set solve.LAMBDA_FIRST=8``).

``--test`` adds the mean RMSE of every protocol x scale cell over the test
scenes (every protocol whose data is present), beside the best of the peers and
bicubic and beside gbp, read from the ``scores.csv`` of a ``depthrefine bench
--report`` run (``--peers``). ``--time`` adds the CPU seconds per call (all
threads) against FGS's on the thesis geometry and Art x4, alternated in this
process (``benchmarks/bench_speed.py``'s inputs and peer).

Usage::

    python benchmarks/tune_gbp_fast.py                                   # the defaults
    python benchmarks/tune_gbp_fast.py --set rounds=3 --time
    python benchmarks/tune_gbp_fast.py --test --peers /tmp/bench/scores.csv
    python benchmarks/tune_gbp_fast.py --protocols sensor --set lambda_lr=1.0   # the sensor tuning scenes

As the bench, the ``sensor`` protocol's cases make an unsaid ``reprojected`` True (``--set reprojected=false``
keeps it off).
"""

from __future__ import annotations

import argparse
import csv
import importlib
import statistics
import sys
import time
from pathlib import Path

import numpy as np

try:
    from benchmarks.tune_gbp import PROTOCOLS, SCALES, _setting, model_row
except ImportError:  # run as a script from benchmarks/
    from tune_gbp import PROTOCOLS, SCALES, _setting, model_row

#: The peers gbp-fast must beat in every cell (issue 22).
PEERS = ("bicubic", "jbf", "guided", "fgs", "wmf")
ALL_PROTOCOLS = ("park", "middlebury30", "lu", "tof", "realtof", "sensor")


def params_from(settings: list[tuple[str, object]]):
    """``GbpFastParams`` with the fields of ``settings``; the module constants among them are set in place."""
    from depthrefine.methods.gbp import fast

    fields = {}
    for name, value in settings:
        module, _, constant = name.rpartition(".")
        target = importlib.import_module(f"depthrefine.methods.gbp.{module}") if module else fast
        if constant.isupper():
            if not hasattr(target, constant):
                raise SystemExit(f"{target.__name__} has no constant {constant}")
            setattr(target, constant, type(getattr(target, constant))(value))
        else:
            fields[name] = value
    return fast.GbpFastParams(**fields)


def cell_means(data: Path, params, split: str, protocols: tuple[str, ...]) -> dict[tuple[str, int], float]:
    """Mean RMSE of gbp-fast per (protocol, scale) over the scenes of ``split`` (``"tune"`` or ``"test"``).

    A simulated sensor's cells also per model (``("sensor itof", 4)``). As the bench, a protocol of reprojected
    inputs (``sensor``) makes an unsaid ``reprojected`` True.
    """
    from depthrefine.bench.metrics import score
    from depthrefine.bench.protocols import PROTOCOLS as REGISTERED, load_cases
    from depthrefine.methods.gbp.fast import upsample_gbp_fast
    from depthrefine.rig.chain import reprojected_params

    scores: dict[tuple[str, int], list[float]] = {}
    for protocol in protocols:
        scales = (4, 8) if protocol == "realtof" else SCALES
        try:
            cases = load_cases(data, protocol, scales, notes=[])
        except (OSError, ValueError):
            continue
        # as the bench: a protocol of reprojected inputs (sensor) tells the method so (--set reprojected=false is kept)
        told = reprojected_params("gbp-fast", params) if REGISTERED[protocol].reprojected else params
        for case in cases:
            if case.split == split:
                out = upsample_gbp_fast(case.depth_lr, case.rgb_hr, params=told)
                rmse = score(out, case.depth_gt, border=case.border).rmse
                scores.setdefault((protocol, case.scale), []).append(rmse)
                if (row := model_row(protocol, case.scene)) is not None:
                    scores.setdefault((row, case.scale), []).append(rmse)
    return {key: float(np.mean(v)) for key, v in scores.items()}


def peer_means(scores_csv: Path) -> dict[tuple[str, int, str], float]:
    """Mean test RMSE per (protocol, scale, method) of a ``depthrefine bench --report`` run."""
    acc: dict[tuple[str, int, str], list[float]] = {}
    with open(scores_csv, newline="") as fh:
        for row in csv.DictReader(fh):
            if row["split"] == "test":
                acc.setdefault((row["protocol"], int(row["scale"]), row["method"]), []).append(float(row["rmse"]))
    return {key: float(np.mean(v)) for key, v in acc.items()}


def cpu_against_fgs(params, repeats: int = 7) -> dict[str, tuple[float, float]]:
    """CPU seconds per call of gbp-fast and of the FGS peer (medians, alternated) on two of bench_speed's inputs."""
    try:
        from benchmarks.bench_speed import ART, INPUTS, THESIS, fgs_peer
    except ImportError:
        from bench_speed import ART, INPUTS, THESIS, fgs_peer
    from depthrefine.methods.gbp.fast import upsample_gbp_fast

    out = {}
    for name in (THESIS, ART[0]):
        depth, rgb = INPUTS[name]()
        upsample_gbp_fast(depth, rgb, params=params)
        fgs_peer(depth, rgb)
        ours, peer = [], []
        for _ in range(repeats):
            t0 = time.process_time()
            upsample_gbp_fast(depth, rgb, params=params)
            ours.append(time.process_time() - t0)
            t0 = time.process_time()
            fgs_peer(depth, rgb)
            peer.append(time.process_time() - t0)
        out[name] = (statistics.median(ours), statistics.median(peer))
    return out


def main(argv: list[str] | None = None) -> int:
    default = Path(__file__).resolve().parents[1].parent / "shared" / "data"
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument("--data", type=Path, default=default, help="benchmark data folder")
    parser.add_argument("--set", dest="settings", type=_setting, action="append", default=[], metavar="NAME=VALUE",
                        help="a GbpFastParams field, or a CONSTANT of methods/gbp/fast.py (module.CONSTANT for "
                             "gbp's steps); repeatable")
    parser.add_argument("--protocols", type=lambda text: tuple(text.split(",")), default=PROTOCOLS, metavar="A,B",
                        help="the protocols whose tuning scenes make the tuning mean (each one's cells are printed)")
    parser.add_argument("--test", action="store_true", help="also the test cells of every protocol")
    parser.add_argument("--peers", type=Path, help="scores.csv of a depthrefine bench --report run (with --test)")
    parser.add_argument("--time", action="store_true", help="also the CPU time per call against FGS's")
    args = parser.parse_args(argv)
    params = params_from(args.settings)
    label = ", ".join(f"{n}={v}" for n, v in args.settings) or "defaults"
    t0 = time.perf_counter()
    means = cell_means(args.data, params, "tune", args.protocols)
    per_scale = [np.mean([v for (p, s), v in means.items() if s == scale and p in args.protocols]) for scale in SCALES]
    if args.protocols != PROTOCOLS:
        for name in sorted({p for p, _ in means}):
            print(f"{name:13s} " + " / ".join(f"x{s} {means[name, s]:.4f}" for s in SCALES if (name, s) in means))
    print(f"tuning mean {np.mean(per_scale):.4f}  ({label}; {time.perf_counter() - t0:.0f} s)")
    if args.test:
        test = cell_means(args.data, params, "test", ALL_PROTOCOLS)
        peers = peer_means(args.peers) if args.peers else {}
        worst = 0.0
        for (protocol, scale), value in sorted(test.items()):
            line = f"  {protocol:13s} x{scale:<3d} {value:8.3f}"
            best = [(peers[protocol, scale, m], m) for m in PEERS if (protocol, scale, m) in peers]
            if best:
                rmse, method = min(best)
                worst = max(worst, value / rmse)
                line += f"   best peer {method:8s} {rmse:8.3f} ({value / rmse:.3f}x)"
            if (protocol, scale, "gbp") in peers:
                line += f"   gbp {peers[protocol, scale, 'gbp']:8.3f} ({value / peers[protocol, scale, 'gbp']:.3f}x)"
            print(line)
        if worst:
            print(f"  worst cell against the best peer or bicubic: {worst:.3f}x ({'below' if worst < 1 else 'NOT below'})")
    if args.time:
        for name, (ours, peer) in cpu_against_fgs(params).items():
            print(f"  {name}: {ours * 1e3:.1f} ms CPU, FGS {peer * 1e3:.1f} ms, {ours / peer:.2f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
