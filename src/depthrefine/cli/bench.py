"""``depthrefine bench``: score the methods on data with ground truth, under the published protocols."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from .. import __version__
from ..bench.protocols import PROTOCOLS, TUNING_SCENES, left_out_reason, load_cases, tuned_on_scenes
from ..bench.runner import DEFAULT_SCALES, parse_scales, run_benchmark
from ..io import InputFileError, atomic_directory, check_output_dir
from ..methods.registry import METHODS, get_method
from ..methods.peers import fast_bilateral_solver_status
from ..bench import report
from ._common import params_dict

#: Where ``--data`` points when it is not given (relative to the current folder).
DEFAULT_DATA = Path("..") / "shared" / "data"


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
    p.add_argument("--data", metavar="DIR",
                   help=f"folder holding the dataset folders (default: {DEFAULT_DATA} if present)")
    p.add_argument("--protocol", default="all", choices=[*PROTOCOLS, "all"],
                   help="; ".join(f"{name}: {entry.title}" for name, entry in PROTOCOLS.items())
                        + "; or all (default)")
    p.add_argument("--methods", metavar="A,B,C",
                   help=f"comma-separated methods (default: all registered: {','.join(METHODS)})")
    p.add_argument("--scales", default=",".join(map(str, DEFAULT_SCALES)), metavar="4,8,16",
                   help="comma-separated upsampling factors (default: 4,8,16)")
    p.add_argument("--report", metavar="DIR", help="write the report folder here")
    p.add_argument("--overwrite", action="store_true", help="write into an existing non-empty report folder")
    p.set_defaults(func=run)


def _data_dir(arg: str | None) -> Path:
    if arg is not None:
        data = Path(arg)
        if not data.is_dir():
            raise InputFileError(f"--data {data} does not exist or is not a folder.")
        return data
    if DEFAULT_DATA.is_dir():
        return DEFAULT_DATA
    raise InputFileError(
        f"no --data given and {DEFAULT_DATA} (relative to the current folder {Path.cwd()}) does not exist; "
        "pass --data DIR, a folder laid out as shared/data."
    )


def _methods(arg: str | None) -> list[str]:
    if arg is None:
        return list(METHODS)
    names = [m.strip() for m in arg.split(",") if m.strip()]
    if not names:
        raise ValueError(f"--methods must name methods such as thesis,bilinear; got {arg!r}.")
    for name in names:
        get_method(name)  # raises with the list of known names
    return list(dict.fromkeys(names))


def run(args: argparse.Namespace) -> int:
    methods = _methods(args.methods)
    scales = parse_scales(args.scales)
    data = _data_dir(args.data)
    if args.report:
        check_output_dir(args.report, overwrite=args.overwrite, what="report folder")
    protocols = list(PROTOCOLS) if args.protocol == "all" else [args.protocol]
    if args.protocol == "all":
        folders = {p: PROTOCOLS[p].folder for p in protocols}
        present = [p for p in protocols if (data / folders[p]).is_dir() or data.name == folders[p]]
        if not present:
            raise InputFileError(f"{data} holds none of the dataset folders "
                                 f"{sorted(set(folders.values()))}; pass --data DIR laid out as shared/data.")
        for protocol in protocols:
            if protocol not in present:
                print(f"depthrefine bench: note: {data} has no {folders[protocol]}/; "
                      f"skipping the {protocol} protocol.", file=sys.stderr)
        protocols = present
    cases = []
    skipped: list[str] = []
    for protocol in protocols:
        if len(protocols) == 1:
            cases += load_cases(data, protocol, scales, notes=skipped)
            continue
        try:
            cases += load_cases(data, protocol, scales, notes=skipped)
        except InputFileError as exc:  # --protocol all: one unusable dataset does not stop the others
            skipped.append(f"{protocol}: skipped the whole protocol: {exc}")
    for note in skipped:
        print(f"depthrefine bench: note: {note}", file=sys.stderr)
    if not cases:
        raise InputFileError(f"{data}: no usable case in any protocol (see the notes above); "
                             "lay it out as shared/data (e.g. middlebury2005_park/<scene>/color.png, gt_disp.png).")

    if args.report:
        with atomic_directory(args.report, overwrite=args.overwrite) as tmp:
            rows = _run(cases, methods, scales, tmp, skipped)
    else:
        rows = _run(cases, methods, scales, None, skipped)
    print(report.terminal_table(rows), end="")
    if args.report:
        print(f"wrote {Path(args.report) / 'index.html'} (and scores.csv, summary.md, figures)", file=sys.stderr)
    return 0


def _run(cases, methods, scales, folder: Path | None, skipped=()):
    """Run case by case (results kept only for the figure of that case), writing the report into ``folder``."""
    from tqdm import tqdm

    figure_scale = 8 if 8 in scales else max(scales)
    total = len(cases) * len(methods)
    rows = []
    figures: list[tuple[str, str]] = []
    bar = tqdm(total=total, desc="bench", unit="run", disable=not sys.stderr.isatty(), leave=False)
    try:
        for case in cases:
            bar.set_postfix_str(f"{case.protocol} {case.scene} x{case.scale}")
            offset = bar.n
            want = folder is not None and case.scale == figure_scale
            result = run_benchmark([case], methods, keep=(lambda c: want),
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
    params_used = {m: params_dict(get_method(m).default_params()) for m in methods}
    tuned = ", ".join(f"{p}: {', '.join(tuned_on_scenes(p))}" for p in TUNING_SCENES if tuned_on_scenes(p))
    left_out = "; ".join(f"{p} {s} ({left_out_reason(p, s)})" for p, scenes in TUNING_SCENES.items() for s in scenes)
    notes = [
        f"The OpenCV peers (jbf, guided, fgs, wmf) use parameters tuned with benchmarks/tune_peers.py on "
        f"{tuned}. Every mean leaves out these scenes: {left_out}. The thesis method runs with its thesis "
        "defaults.",
        "The tuning set was revised after the lu results had been seen (noise-free middlebury30 scenes were "
        "added when the Park-only tuning oversmoothed lu at x16), so lu is not a clean hold-out.",
        "The tof protocol's input is simulated with our own sensor model (footprint integration, noise growing "
        "with distance, dropouts on dark surfaces, 8-bit quantisation, fixed seed; see docs/bench.md): "
        "it is not a published protocol.",
        "bicubic is OpenCV INTER_CUBIC, not the PIL bicubic of the READMEs' sanity rows (see docs/bench.md).",
        "Times are wall-clock seconds per image on this machine (shared, so noisy): compare ratios within a run.",
    ]
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
