"""The benchmark as ``depthrefine bench`` runs it: the data folder, the cases, a run case by case, the report.

:func:`find_data_folder` finds the data (``--data``, ``$DEPTHREFINE_DATA``
or ``../shared/data`` beside a source checkout); :func:`protocol_cases` and
:func:`pair_cases` load the cases of the published protocols or of the
user's own triplets; :func:`run_suite` runs the methods case by case (each
case's results are kept only for its figure); :func:`report_files` gives
the report folder's files (texts and figures) for the caller to write.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterator, Mapping, Sequence

from ..io import InputFileError
from .protocols import PAIRS, PROTOCOLS, TUNING_SCENES, left_out_reason, load_cases, pairs_protocol, \
    register_protocol, tuned_on_scenes

__all__ = ["DATA_ENV", "MAX_PAIR_FIGURES", "CaseFigure", "checkout_data_dir", "find_data_folder", "protocol_cases",
           "pair_cases", "run_suite", "protocol_params", "report_notes", "report_files"]

#: The environment variable naming the data folder when ``--data`` is not given.
DATA_ENV = "DEPTHREFINE_DATA"

#: With ``--pairs``, a figure for at most this many triplets.
MAX_PAIR_FIGURES = 12

#: ``note(text)``: a remark for the user (a skipped scene or protocol).
Note = Callable[[str], None]


def checkout_data_dir() -> Path | None:
    """``../shared/data`` beside the source checkout this package runs from (None for an installed wheel)."""
    root = Path(__file__).resolve().parents[3]  # <checkout>/src/depthrefine/bench/suite.py
    return root.parent / "shared" / "data" if (root / "pyproject.toml").is_file() else None


def find_data_folder(data: str | os.PathLike | None) -> Path:
    """``data`` (``--data``), else ``$DEPTHREFINE_DATA``, else ``../shared/data`` beside the source checkout.

    Raises
    ------
    InputFileError
        The folder named does not exist, or none is given and none is found.
    """
    if data is not None:
        folder = Path(data)
        if not folder.is_dir():
            raise InputFileError(f"--data {folder} does not exist or is not a folder.")
        return folder
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


def protocol_cases(data: Path, protocol: str, scales: tuple[int, ...], *, note: Note = print) -> tuple[list, list[str]]:
    """The cases of a published protocol (or of ``"all"`` of them) under ``data``, and the skipped inputs.

    With ``"all"``, a protocol whose folder is missing is skipped with a
    ``note`` and one that cannot be read is listed among the skipped; the
    skipped inputs are also given to ``note``.

    Raises
    ------
    InputFileError
        ``data`` holds none of the protocols' folders, or no usable case.
    """
    protocols = [p for p in PROTOCOLS if p != PAIRS] if protocol == "all" else [protocol]
    if protocol == "all":
        folders = {p: PROTOCOLS[p].folder for p in protocols}
        present = [p for p in protocols if (data / folders[p]).is_dir() or data.name == folders[p]]
        if not present:
            raise InputFileError(f"{data} holds none of the dataset folders "
                                 f"{sorted(set(folders.values()))}; pass --data DIR laid out as shared/data.")
        for name in protocols:
            if name not in present:
                note(f"{data} has no {folders[name]}/; skipping the {name} protocol.")
        protocols = present
    cases = []
    skipped: list[str] = []
    for name in protocols:
        if len(protocols) == 1:
            cases += load_cases(data, name, scales, notes=skipped)
            continue
        try:
            cases += load_cases(data, name, scales, notes=skipped)
        except InputFileError as exc:  # "all": one unusable dataset does not stop the others
            skipped.append(f"{name}: skipped the whole protocol: {exc}")
    for text in skipped:
        note(text)
    if not cases:
        raise InputFileError(f"{data}: no usable case in any protocol (see the notes above); "
                             "lay it out as shared/data (e.g. middlebury2005_park/<scene>/color.png, gt_disp.png).")
    return cases, skipped


def pair_cases(folder: str | os.PathLike, *, units: str | None = None, invalid: float = 0.0, crop: int = 0,
               note: Note = print) -> tuple[list, list[str]]:
    """The cases of the user's triplets in ``folder`` (the ``pairs`` protocol), one per triplet at its own scale."""
    folder = Path(folder)
    if not folder.is_dir():
        raise InputFileError(f"--pairs {folder} does not exist or is not a folder.")
    register_protocol(pairs_protocol(folder, units=units, invalid=invalid, crop=crop), replace=True)
    skipped: list[str] = []
    cases = load_cases(folder, PAIRS, (), notes=skipped)
    for text in skipped:
        note(text)
    return cases, skipped


@dataclass(frozen=True, eq=False)
class CaseFigure:
    """The figure of one case: its file name in the report, its caption, the matplotlib figure."""

    name: str
    caption: str
    figure: Any


def run_suite(cases: Sequence, methods: Sequence[str], *, figures: bool = True,
              progress: Callable[[int, int, str], None] | None = None,
              curves: dict | None = None) -> Iterator[tuple[list, CaseFigure | None]]:
    """Run ``methods`` on ``cases`` one case at a time: yield each case's rows and its figure (or None).

    With ``figures``, a case gets a figure when it is at x8 (else the largest
    scale) or, for the ``pairs`` protocol, among the first
    :data:`MAX_PAIR_FIGURES`. The figures of one protocol share one error
    scale (:func:`~.figures.error_scale`), so they are drawn when the
    protocol's last case is done and yielded then, with no rows; their
    results are dropped once drawn. ``progress(done, total, case)`` counts
    the (method, case) runs. With ``curves`` (a dict), each method's
    confidence map is scored too (``run_benchmark(confidence=True)``: the
    rows' AUSE fields) and its sparsification curves, with the steepness
    baseline's, are put into ``curves`` (keyed as ``BenchResult.curves``).
    """
    from . import figures as scene_figures
    from .runner import run_benchmark

    scales = {case.scale for case in cases}
    figure_scale = 8 if 8 in scales else max(scales)
    total = len(cases) * len(methods)
    done_before = 0
    made = 0
    pending: list[tuple] = []   # (case, results, rmse) of the current protocol's figures

    def draw_pending() -> Iterator[tuple[list, CaseFigure]]:
        errors = [{m: scene_figures.error_map(d, c.depth_gt, border=c.border) for m, d in kept.items()}
                  for c, kept, _ in pending]
        error_max = scene_figures.error_scale(errors)
        for case, kept, rmse in pending:
            split = " (a tuning scene of the peers)" if case.split == "tune" else ""
            yield [], CaseFigure(f"fig_{case.protocol}_{case.scene}_x{case.scale}.png",
                                 f"{case.protocol} · {case.scene} · ×{case.scale}{split}",
                                 scene_figures.scene_figure(case, kept, rmse=rmse, error_max=error_max))
        pending.clear()

    for case in cases:
        if pending and pending[0][0].protocol != case.protocol:
            yield from draw_pending()
        label = f"{case.protocol} {case.scene} x{case.scale}"
        if case.protocol == PAIRS:
            want = figures and made < MAX_PAIR_FIGURES
        else:
            want = figures and case.scale == figure_scale
        offset = done_before
        result = run_benchmark([case], methods, params=protocol_params(case.protocol), keep=(lambda c: want),
                               confidence=curves is not None,
                               progress=None if progress is None else (
                                   lambda done, _total: progress(offset + done, total, label)))
        done_before += len(methods)
        if curves is not None:
            curves.update(result.curves)
        if want:
            made += 1
            pending.append((case, result.kept[case.key], {r.method: r.rmse for r in result.rows}))
        yield result.rows, None
    if pending:
        yield from draw_pending()


def protocol_params(protocol: str) -> dict[str, Any]:
    """``{method: params}`` a protocol tuned for itself (``Protocol.method_params``); the defaults for the rest.

    On a protocol whose inputs are reprojected (``Protocol.reprojected``), every registered method whose
    parameters have ``reprojected`` is told so (:func:`depthrefine.rig.chain.reprojected_params`).
    """
    from ..methods.registry import METHODS, get_method

    entry = PROTOCOLS.get(protocol)
    tuned = entry.method_params if entry is not None else {}
    params = {m: get_method(m).params_type(**fields) for m, fields in tuned.items()}
    if entry is not None and entry.reprojected:
        from ..rig.chain import reprojected_params

        for name in METHODS:
            told = reprojected_params(name, params.get(name))
            if told is not None:
                params[name] = told
    return params


def report_notes(rows: Sequence, methods: Sequence[str], skipped: Sequence[str] = ()) -> list[str]:
    """The notes under the report's tables: tuning, left-out scenes, simulated input, timing, skipped inputs."""
    from ..methods.peers import fast_bilateral_solver_status

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
    for p in (p for p in TUNING_SCENES if PROTOCOLS[p].reprojected and p in present):
        params = protocol_params(p)
        told = [m for m in methods if getattr(params.get(m), "reprojected", False)]
        if told:
            notes.append(f"The {p} protocol's inputs come through the rig chain's reprojection, so "
                         f"{', '.join(told)} {'is' if len(told) == 1 else 'are'} told so (reprojected = true), "
                         "as depthrefine run tells them.")
    if "gbp" in methods:
        notes.append("gbp's defaults were chosen on the same tuning scenes, except the local-range clip before the "
                     "guide trust and its hole margin (picked with the realtof Kinect capture in view) and the "
                     "point-sample smoothing (picked on generated point-sampled scenes; no benchmark input is "
                     "point-sampled); the lu scores were seen while the defaults were explored; see docs/tuning.md.")
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
    return notes


def report_files(rows: Sequence, methods: Sequence[str], figures: Sequence[tuple[str, str]],
                 skipped: Sequence[str] = (), *, curves: Mapping | None = None) -> dict[str, Any]:
    """The report folder's files besides the case figures: name -> text, or a matplotlib figure (the plot).

    ``figures`` are the case figures already written, ``(caption, file name)``.
    The files: ``rmse_vs_scale.png``, ``scores.csv``, ``summary.md``,
    ``index.html`` and ``run.json`` (the version, methods and parameters);
    with ``curves`` (:func:`run_suite`'s), ``sparsification.png``, the
    confidence maps' sparsification curves, and their section in the pages.
    """
    from .. import __version__
    from ..methods.params import params_to_dict
    from ..methods.registry import get_method
    from . import report

    params_used = {m: params_to_dict(get_method(m).default_params()) for m in methods}
    notes = report_notes(rows, methods, skipped)
    plot = "rmse_vs_scale.png"
    files: dict[str, Any] = {plot: report.rmse_scale_figure(rows)}
    confidence_plot = None
    if curves:
        from .confidence_report import sparsification_figure

        confidence_plot = "sparsification.png"
        files[confidence_plot] = sparsification_figure(curves, rows)
    return files | {
        "scores.csv": report.csv_text(rows),
        "summary.md": report.summary_markdown(rows, params_used=params_used, notes=notes, figures=figures, plot=plot,
                                              confidence_plot=confidence_plot),
        "index.html": report.html_page(rows, params_used=params_used, notes=notes, figures=figures, plot=plot,
                                       confidence_plot=confidence_plot),
        "run.json": json.dumps({"depthrefine": __version__, "methods": list(methods), "params": params_used},
                               indent=2) + "\n",
    }
