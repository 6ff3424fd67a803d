"""``depthrefine bench``: score the methods on data with ground truth, under the published protocols."""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

from .. import __version__
from ..bench.protocols import (PAIRS, PROTOCOLS, TUNING_SCENES, left_out_reason, load_cases, pairs_protocol,
                               register_protocol, tuned_on_scenes)
from ..io._files import InputFileError, atomic_directory, check_output_dir
from ..methods._names import RegisteredMethodNames
from ._common import add_units_option, params_dict

#: The environment variable naming the data folder when ``--data`` is not given.
DATA_ENV = "DEPTHREFINE_DATA"


def checkout_data_dir() -> Path | None:
    """``../shared/data`` beside the source checkout this package runs from (None for an installed wheel)."""
    root = Path(__file__).resolve().parents[3]  # <checkout>/src/depthrefine/cli/bench.py
    return root.parent / "shared" / "data" if (root / "pyproject.toml").is_file() else None


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "bench",
        help="score every method against ground truth under the published protocols",
        description=(
            "Run the methods on data with ground truth (folders laid out as shared/data; a folder with only "
            "some scenes works too), print a table of mean RMSE, and with --report write a folder with "
            "scores.csv, summary.md, figures and index.html."
        ),
    )
    where = p.add_mutually_exclusive_group()
    where.add_argument("--data", metavar="DIR",
                       help=f"folder holding the dataset folders, laid out as shared/data (default: ${DATA_ENV}, "
                            "else ../shared/data beside the source checkout)")
    where.add_argument("--pairs", metavar="DIR",
                       help="score your own data instead: DIR/color/, DIR/input/ (low-resolution depth) and DIR/gt/ "
                            "(ground truth on the color grid), files paired by stem (a.png, a.png, a.png)")
    published = {name: entry for name, entry in PROTOCOLS.items() if name != PAIRS}
    p.add_argument("--protocol", default=None, choices=[*published, "all"],
                   help="; ".join(f"{name}: {entry.title}" for name, entry in published.items())
                        + "; or all (default; not with --pairs)")
    registered = ",".join(RegisteredMethodNames(ordered=True))
    p.add_argument("--methods", metavar="A,B,C",
                   help=f"comma-separated methods (default: all registered: {registered})")
    p.add_argument("--scales", default=None, metavar="4,8,16",
                   help="comma-separated upsampling factors (default: 4,8,16; with --pairs the files give them)")
    add_units_option(p, help="--pairs: the depth's units, a label for the tables and colorbars (e.g. mm); "
                             "no value changes")
    p.add_argument("--invalid", type=float, default=0.0, metavar="V",
                   help="--pairs: the stored value meaning no measurement, in input and gt (default 0; NaN "
                        "always is)")
    p.add_argument("--crop", type=int, default=0, metavar="N",
                   help="--pairs: leave N pixels on each side out of the scores (default 0)")
    p.add_argument("--report", metavar="DIR", help="write the report folder here")
    p.add_argument("--overwrite", action="store_true", help="write into an existing non-empty report folder")
    p.set_defaults(func=run)


def _data_dir(arg: str | None) -> Path:
    """``--data``, else ``$DEPTHREFINE_DATA``, else ``../shared/data`` beside the source checkout."""
    if arg is not None:
        data = Path(arg)
        if not data.is_dir():
            raise InputFileError(f"--data {data} does not exist or is not a folder.")
        return data
    env = os.environ.get(DATA_ENV)
    if env:
        if not Path(env).is_dir():
            raise InputFileError(f"${DATA_ENV} is {env}, which does not exist or is not a folder; "
                                 "fix it or pass --data DIR.")
        return Path(env)
    beside = checkout_data_dir()
    if beside is not None and beside.is_dir():
        return beside
    looked = f"{beside}" if beside is not None else "../shared/data beside a source checkout (this is an installed copy)"
    raise InputFileError(
        f"no --data given, ${DATA_ENV} is not set and {looked} does not exist; pass --data DIR (a folder "
        f"laid out as shared/data), set {DATA_ENV}=DIR, or score your own files with --pairs DIR."
    )


def _methods(arg: str | None) -> list[str]:
    from ..methods.registry import METHODS, get_method

    if arg is None:
        return list(METHODS)
    names = [m.strip() for m in arg.split(",") if m.strip()]
    if not names:
        raise ValueError(f"--methods must name methods such as thesis,bilinear; got {arg!r}.")
    for name in names:
        get_method(name)  # raises with the list of known names
    return list(dict.fromkeys(names))


def run(args: argparse.Namespace) -> int:
    from ..bench import report

    methods = _methods(args.methods)
    if args.report:
        check_output_dir(args.report, overwrite=args.overwrite, what="report folder")
    if args.pairs is not None:
        cases, skipped = _pair_cases(args)
    else:
        for option in ("units", "crop"):
            if getattr(args, option) not in (None, 0):
                raise ValueError(f"--{option} is for --pairs DIR (the published protocols fix their own).")
        if args.invalid != 0:
            raise ValueError("--invalid is for --pairs DIR (the published protocols fix their own).")
        cases, skipped = _protocol_cases(args)
    scales = tuple(sorted({case.scale for case in cases}))
    if args.report:
        with atomic_directory(args.report, overwrite=args.overwrite) as tmp:
            rows = _run(cases, methods, scales, tmp, skipped)
    else:
        rows = _run(cases, methods, scales, None, skipped)
    print(report.terminal_table(rows), end="")
    if args.report:
        print(f"wrote {Path(args.report) / 'index.html'} (and scores.csv, summary.md, figures)", file=sys.stderr)
    return 0


def _pair_cases(args: argparse.Namespace):
    """The cases of ``--pairs DIR``: one per triplet, at the scale its files give."""
    if args.protocol is not None or args.scales is not None:
        raise ValueError("--pairs DIR takes neither --protocol nor --scales: the triplets are the protocol and "
                         "their files give the scales.")
    folder = Path(args.pairs)
    if not folder.is_dir():
        raise InputFileError(f"--pairs {folder} does not exist or is not a folder.")
    register_protocol(pairs_protocol(folder, units=args.units, invalid=args.invalid, crop=args.crop), replace=True)
    skipped: list[str] = []
    cases = load_cases(folder, PAIRS, (), notes=skipped)
    for note in skipped:
        print(f"depthrefine bench: note: {note}", file=sys.stderr)
    return cases, skipped


def _protocol_cases(args: argparse.Namespace):
    """The cases of the published protocols under ``--data`` (or its default)."""
    from ..bench.runner import DEFAULT_SCALES, parse_scales

    scales = parse_scales(args.scales if args.scales is not None else ",".join(map(str, DEFAULT_SCALES)))
    data = _data_dir(args.data)
    protocol = args.protocol or "all"
    protocols = [p for p in PROTOCOLS if p != PAIRS] if protocol == "all" else [protocol]
    if protocol == "all":
        folders = {p: PROTOCOLS[p].folder for p in protocols}
        present = [p for p in protocols if (data / folders[p]).is_dir() or data.name == folders[p]]
        if not present:
            raise InputFileError(f"{data} holds none of the dataset folders "
                                 f"{sorted(set(folders.values()))}; pass --data DIR laid out as shared/data.")
        for name in protocols:
            if name not in present:
                print(f"depthrefine bench: note: {data} has no {folders[name]}/; "
                      f"skipping the {name} protocol.", file=sys.stderr)
        protocols = present
    cases = []
    skipped: list[str] = []
    for name in protocols:
        if len(protocols) == 1:
            cases += load_cases(data, name, scales, notes=skipped)
            continue
        try:
            cases += load_cases(data, name, scales, notes=skipped)
        except InputFileError as exc:  # --protocol all: one unusable dataset does not stop the others
            skipped.append(f"{name}: skipped the whole protocol: {exc}")
    for note in skipped:
        print(f"depthrefine bench: note: {note}", file=sys.stderr)
    if not cases:
        raise InputFileError(f"{data}: no usable case in any protocol (see the notes above); "
                             "lay it out as shared/data (e.g. middlebury2005_park/<scene>/color.png, gt_disp.png).")
    return cases, skipped


def protocol_params(protocol: str) -> dict:
    """``{method: params}`` a protocol tuned for itself (``Protocol.method_params``); the defaults for the rest."""
    from ..methods.registry import get_method

    entry = PROTOCOLS.get(protocol)
    tuned = entry.method_params if entry is not None else {}
    return {m: get_method(m).params_type(**fields) for m, fields in tuned.items()}


#: With --pairs, a figure for at most this many triplets.
MAX_PAIR_FIGURES = 12


def _run(cases, methods, scales, folder: Path | None, skipped=()):
    """Run case by case (results kept only for the figure of that case), writing the report into ``folder``."""
    from tqdm import tqdm

    from ..bench import report
    from ..bench.runner import run_benchmark

    figure_scale = 8 if 8 in scales else max(scales)
    total = len(cases) * len(methods)
    rows = []
    figures: list[tuple[str, str]] = []
    bar = tqdm(total=total, desc="bench", unit="run", disable=not sys.stderr.isatty(), leave=False)
    try:
        for case in cases:
            bar.set_postfix_str(f"{case.protocol} {case.scene} x{case.scale}")
            offset = bar.n
            if case.protocol == PAIRS:
                want = folder is not None and len(figures) < MAX_PAIR_FIGURES
            else:
                want = folder is not None and case.scale == figure_scale
            result = run_benchmark([case], methods, params=protocol_params(case.protocol), keep=(lambda c: want),
                                   progress=lambda done, _total: bar.update(offset + done - bar.n))
            rows += result.rows
            if want:
                name = f"fig_{case.protocol}_{case.scene}_x{case.scale}.png"
                fig = report.scene_figure(case, result.kept[case.key],
                                          rmse={r.method: r.rmse for r in result.rows})
                fig.savefig(folder / name)
                split = " (a tuning scene of the peers)" if case.split == "tune" else ""
                figures.append((f"{case.protocol} · {case.scene} · ×{case.scale}{split}", name))
    finally:
        bar.close()
    if folder is not None:
        _write_report(folder, rows, methods, figures, skipped)
    return rows


def _write_report(folder: Path, rows, methods, figures, skipped=()) -> None:
    from ..bench import report
    from ..methods.peers import fast_bilateral_solver_status
    from ..methods.registry import get_method

    params_used = {m: params_dict(get_method(m).default_params()) for m in methods}
    own = [p for p in TUNING_SCENES if PROTOCOLS[p].method_params]  # protocols that tune the peers for themselves
    tuned = ", ".join(f"{p}: {', '.join(tuned_on_scenes(p))}" for p in TUNING_SCENES
                      if tuned_on_scenes(p) and p not in own)
    left_out = "; ".join(f"{p} {s} ({left_out_reason(p, s)})" for p, scenes in TUNING_SCENES.items() for s in scenes)
    present = {r.protocol for r in rows}
    notes = [
        f"The OpenCV peers (jbf, guided, fgs, wmf) use parameters tuned with benchmarks/tune_peers.py on "
        f"{tuned}. Every mean leaves out these scenes: {left_out}. The thesis method runs with its thesis "
        "defaults.",
    ]
    for p in (p for p in own if p in present):
        fields = "; ".join(f"{m}: " + ", ".join(f"{k} = {v}" for k, v in f.items())
                           for m, f in PROTOCOLS[p].method_params.items() if m in methods)
        notes.append(f"On the {p} protocol the peers use parameters tuned on its own tuning scenes "
                     f"({', '.join(tuned_on_scenes(p))}; benchmarks/tune_peers.py --protocol {p}): {fields}.")
    if "gbp" in methods:
        notes.append("gbp's defaults were chosen on the same tuning scenes, except hole_margin and local_range "
                     "(picked with the realtof Kinect capture in view) and point_lambda (picked on generated "
                     "point-sampled scenes; no benchmark input is point-sampled); the lu scores were seen while "
                     "the defaults were explored; see docs/bench.md.")
    if "lu" in present:
        notes.append("The tuning set was revised after the lu results had been seen (noise-free middlebury30 "
                     "scenes were added when the Park-only tuning oversmoothed lu at x16), so lu is not a clean "
                     "hold-out.")
    if "sensor" in present:
        notes.append("The sensor protocol's input is simulated with our own sensor models (a depth camera beside "
                     "the color camera, its footprint read as an iToF or a dToF pixel, noise, dark dropouts, a "
                     "calibration error, reprojected with the rig chain; fixed seeds; see docs/bench.md): it is "
                     "not a published protocol. Its scenes are <scene>-<model>; each model is its own column.")
    if "tof" in present:
        notes.append("The tof protocol's input is simulated with our own sensor model (footprint integration, "
                     "noise growing with distance, dropouts on dark surfaces, 8-bit quantisation, fixed seed; see "
                     "docs/bench.md): it is not a published protocol.")
    if "bicubic" in methods:
        notes.append("bicubic is OpenCV INTER_CUBIC, not the PIL bicubic of the READMEs' sanity rows (see "
                     "docs/bench.md).")
    if PAIRS in present:
        notes.append(f"{PAIRS}: {PROTOCOLS[PAIRS].title}; the scale of each triplet is the ratio of its grids.")
    notes.append("Times are wall-clock seconds per image on this machine (shared, so noisy): compare ratios "
                 "within a run.")
    reason = fast_bilateral_solver_status()
    if reason:
        notes.append(f"The fast bilateral solver is not benchmarked: {reason}")
    notes += [f"Skipped (missing or unusable input): {s}" for s in skipped]
    plot = "rmse_vs_scale.png"
    report.rmse_scale_figure(rows).savefig(folder / plot)
    (folder / "scores.csv").write_text(report.csv_text(rows), encoding="utf-8")
    (folder / "summary.md").write_text(
        report.summary_markdown(rows, params_used=params_used, notes=notes, figures=figures, plot=plot),
        encoding="utf-8")
    (folder / "index.html").write_text(
        report.html_page(rows, params_used=params_used, notes=notes, figures=figures, plot=plot),
        encoding="utf-8")
    (folder / "run.json").write_text(json.dumps({"depthrefine": __version__, "methods": methods,
                                                 "params": params_used}, indent=2) + "\n", encoding="utf-8")
