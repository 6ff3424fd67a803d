"""``depthrefine bench``: score the methods on data with ground truth, under the published protocols.

The work is :mod:`depthrefine.bench.suite`'s; this module parses, prints and writes.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..bench.protocols import PAIRS, PROTOCOLS
from ..bench.suite import DATA_ENV
from ..methods._names import RegisteredMethodNames
from ._common import add_units_option


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


def _note(text: str) -> None:
    print(f"depthrefine bench: note: {text}", file=sys.stderr)


def run(args: argparse.Namespace) -> int:
    from ..bench import report
    from ..bench.runner import DEFAULT_SCALES, parse_scales
    from ..bench.suite import find_data_folder, pair_cases, protocol_cases
    from ..io import atomic_directory, check_output_dir

    methods = _methods(args.methods)
    if args.report:
        check_output_dir(args.report, overwrite=args.overwrite, what="report folder")
    if args.pairs is not None:
        if args.protocol is not None or args.scales is not None:
            raise ValueError("--pairs DIR takes neither --protocol nor --scales: the triplets are the protocol and "
                             "their files give the scales.")
        cases, skipped = pair_cases(args.pairs, units=args.units, invalid=args.invalid, crop=args.crop, note=_note)
    else:
        for option in ("units", "crop"):
            if getattr(args, option) not in (None, 0):
                raise ValueError(f"--{option} is for --pairs DIR (the published protocols fix their own).")
        if args.invalid != 0:
            raise ValueError("--invalid is for --pairs DIR (the published protocols fix their own).")
        scales = parse_scales(args.scales if args.scales is not None else ",".join(map(str, DEFAULT_SCALES)))
        cases, skipped = protocol_cases(find_data_folder(args.data), args.protocol or "all", scales, note=_note)
    if args.report:
        with atomic_directory(args.report, overwrite=args.overwrite) as tmp:
            rows = _run(cases, methods, tmp, skipped)
    else:
        rows = _run(cases, methods, None, skipped)
    print(report.terminal_table(rows), end="")
    if args.report:
        print(f"wrote {Path(args.report) / 'index.html'} (and scores.csv, summary.md, figures)", file=sys.stderr)
    return 0


def _run(cases, methods, folder: Path | None, skipped=()):
    """Run case by case with a progress bar, writing each case's figure and then the report into ``folder``."""
    from tqdm import tqdm

    from ..bench.suite import report_files, run_suite
    from ..io import write_figure

    rows = []
    curves: dict = {}   # the sparsification curves of the confidence maps
    figures: list[tuple[str, str]] = []
    bar = tqdm(total=len(cases) * len(methods), desc="bench", unit="run", disable=not sys.stderr.isatty(),
               leave=False)

    def progress(done: int, _total: int, case: str) -> None:
        bar.set_postfix_str(case, refresh=False)
        bar.update(done - bar.n)

    try:
        for case_rows, figure in run_suite(cases, methods, figures=folder is not None, progress=progress,
                                           curves=curves):
            rows += case_rows
            if figure is not None:
                write_figure(folder / figure.name, figure.figure)
                figures.append((figure.caption, figure.name))
    finally:
        bar.close()
    if folder is not None:
        for name, content in report_files(rows, methods, figures, skipped, curves=curves).items():
            if isinstance(content, str):
                (folder / name).write_text(content, encoding="utf-8")
            else:
                write_figure(folder / name, content)
    return rows
