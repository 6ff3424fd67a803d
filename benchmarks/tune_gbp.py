"""The tuning-scene mean RMSE of ``gbp``: the figure every default of ``docs/tuning.md`` was chosen by.

Scores ``gbp`` on the tuning scenes of ``park``, ``middlebury30`` and ``tof``
(the scenes every summary leaves out: ``bench.protocols.TUNING_SCENES``) at x4,
x8 and x16 and prints the mean RMSE per protocol and scale, per scale over all
those cases, and the tuning mean (the mean of the three per-scale means). A knob is
set with ``--set iterations=6``; a constant of a step with
``--set solve.LAMBDA_FIRST=8`` (``measure``, ``solve`` or ``trust``: the
modules of ``depthrefine.methods.gbp``), so every default can be compared with
its neighbours::

    python benchmarks/tune_gbp.py                                   # the defaults
    python benchmarks/tune_gbp.py --set lambda_lr=0.045 --set trust.TRUST_FLOOR=0.2
    python benchmarks/tune_gbp.py --protocols sensor                # the simulated sensors' tuning scenes

``--protocols`` scores other protocols' tuning scenes instead (``sensor``:
its four ``<scene>-<model>`` tuning cases, each model's row too, with
``reprojected`` set as the bench sets it there unless ``--set reprojected=...``);
the tuning mean of the defaults
is over the three above. ``--edges`` adds the edge RMSE (a band of 3 px
around the truth's depth edges), the sensor protocol's second target.
"""

from __future__ import annotations

import argparse
import importlib
import sys
import time
from pathlib import Path

import numpy as np

PROTOCOLS = ("park", "middlebury30", "tof")
SCALES = (4, 8, 16)


def _setting(text: str) -> tuple[str, float | int | bool]:
    name, _, value = text.partition("=")
    if not value:
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE; got {text!r}")
    parsed: float | int | bool
    if value.lower() in ("true", "false"):
        parsed = value.lower() == "true"
    else:
        parsed = float(value) if any(c in value for c in ".eE") else int(value)
    return name.strip(), parsed


def model_row(protocol: str, scene: str) -> str | None:
    """``"sensor itof"`` for a simulated sensor's scene ``<scene>-<model>``: its cells are also printed per model."""
    return f"{protocol} {scene.rsplit('-', 1)[1]}" if "-" in scene else None


def tuning_mean(data: Path, settings: list[tuple[str, object]], protocols: tuple[str, ...] = PROTOCOLS,
                edges: bool = False) -> tuple[float, dict[tuple[str, int], float]]:
    """The tuning mean and the mean RMSE per (protocol, scale) and per scale (key ``("all", scale)``).

    With ``edges`` the edge RMSE's means too, under ``(protocol + " edge", scale)``.
    """
    from depthrefine.bench.metrics import score
    from depthrefine.bench.protocols import PROTOCOLS, TUNING_SCENES, load_cases
    from depthrefine.methods.gbp import GbpParams, upsample_gbp
    from depthrefine.rig.chain import reprojected_params

    fields = {}
    for name, value in settings:
        if "." in name:
            module, constant = name.split(".", 1)
            target = importlib.import_module(f"depthrefine.methods.gbp.{module}")
            if not hasattr(target, constant):
                raise SystemExit(f"depthrefine.methods.gbp.{module} has no constant {constant}")
            setattr(target, constant, type(getattr(target, constant))(value))
        else:
            fields[name] = value
    params = GbpParams(**fields)
    scores: dict[tuple[str, int], list[float]] = {}
    for protocol in protocols:
        # as the bench: a protocol of reprojected inputs (sensor) tells gbp so (--set reprojected=false is kept)
        told = reprojected_params("gbp", params) if PROTOCOLS[protocol].reprojected else params
        for case in load_cases(data, protocol, SCALES):
            if case.scene in TUNING_SCENES[protocol]:
                out = upsample_gbp(case.depth_lr, case.rgb_hr, params=told)
                scored = score(out, case.depth_gt, border=case.border)
                scores.setdefault((protocol, case.scale), []).append(scored.rmse)
                scores.setdefault(("all", case.scale), []).append(scored.rmse)
                if (row := model_row(protocol, case.scene)) is not None:
                    scores.setdefault((row, case.scale), []).append(scored.rmse)
                if edges:
                    scores.setdefault((f"{protocol} edge", case.scale), []).append(scored.edge_rmse)
    means = {key: float(np.mean(values)) for key, values in scores.items()}
    return float(np.mean([means["all", s] for s in SCALES])), means


def main(argv: list[str] | None = None) -> int:
    default = Path(__file__).resolve().parents[1].parent / "shared" / "data"
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument("--data", type=Path, default=default, help="benchmark data folder")
    parser.add_argument("--set", dest="settings", type=_setting, action="append", default=[], metavar="NAME=VALUE",
                        help="a GbpParams field, or MODULE.CONSTANT of depthrefine.methods.gbp (repeatable)")
    parser.add_argument("--protocols", type=lambda text: tuple(text.split(",")), default=PROTOCOLS,
                        metavar="A,B", help="the protocols whose tuning scenes are scored")
    parser.add_argument("--edges", action="store_true", help="also the edge RMSE (3 px band around depth edges)")
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    mean, means = tuning_mean(args.data, args.settings, args.protocols, args.edges)
    models = sorted({key for key, _ in means if key.count(" ") == 1 and not key.endswith(" edge")})
    rows = [*args.protocols, *models, *(f"{p} edge" for p in args.protocols if args.edges), "all"]
    for protocol in rows:
        print(f"{protocol:13s} " + " / ".join(f"x{s} {means[protocol, s]:.4f}" for s in SCALES))
    print(f"tuning mean {mean:.4f}  ({', '.join(f'{n}={v}' for n, v in args.settings) or 'defaults'}; "
          f"{time.perf_counter() - t0:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
