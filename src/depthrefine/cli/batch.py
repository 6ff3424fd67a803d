"""``depthrefine batch INPUT -o OUTDIR``: refine a folder, manifest or ROS bag of frames on Dask."""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
import time
from pathlib import Path
from typing import Any

from .. import __version__
from ..io import InputFileError, atomic_write
from ..io._names import DEFAULT_MAX_DT
from ._common import add_depth_options, add_output, add_overwrite, add_params_options, build_params, params_dict, \
    parse_count, progress_bar

#: Seconds between rewrites of batch.json during a run.
_RECORD_EVERY = 5.0


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "batch",
        help="refine many frames (a folder, a CSV manifest or a ROS bag) in parallel, locally or on a Dask cluster",
        description=(
            "Refine every depth + color pair of INPUT: a folder with depth/ and color/ subfolders whose files pair "
            "by stem, a CSV manifest with columns depth,color (paths relative to it), or a ROS 1 bag (.bag) or "
            "ROS 2 bag (folder with metadata.yaml, .db3 or .mcap) with --depth-topic and --color-topic. Writes "
            "OUTDIR/<stem>.<ext> in the depth's dtype (for bags the stem is the depth time stamp in ns) and "
            "OUTDIR/batch.json. Runs on a local Dask cluster (one process per core) or, with --scheduler, on a "
            "remote one. Run the same command again to resume: frames already written are skipped. Exit status "
            "0 if every frame was refined, 2 if a frame's input was bad, 1 if a frame failed otherwise."
        ),
    )
    p.add_argument("input", metavar="INPUT", help="folder with depth/ and color/, CSV manifest, or ROS bag")
    add_output(p, help="output folder (created; it may not lie inside INPUT)", metavar="OUTDIR")
    add_params_options(p)
    p.add_argument("--workers", type=parse_count, metavar="N",
                   help="worker processes of the local cluster (default: the number of cores)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run on the Dask cluster of this scheduler (tcp://host:port) instead of a local one")
    p.add_argument("--temporal", action="store_true",
                   help="process frames in order within chunks, each warm-starting from the previous one "
                        "(thesis: k-means from the previous means, so labels do not flicker)")
    p.add_argument("--chunk", type=parse_count, metavar="N", default=None,
                   help="frames per chunk with --temporal (default 32); each chunk's first frame starts cold")
    p.add_argument("--depth-topic", metavar="TOPIC", help="ROS bag: the depth topic (sensor_msgs/Image)")
    p.add_argument("--color-topic", metavar="TOPIC",
                   help="ROS bag: the color topic (sensor_msgs/Image or CompressedImage)")
    p.add_argument("--max-dt", type=parse_duration, metavar="T", default=DEFAULT_MAX_DT,
                   help="ROS bag: pair a depth frame with the nearest color frame within T (20ms, 0.02s or 0.02 "
                        "seconds; default 20ms)")
    add_overwrite(p)
    add_depth_options(p)
    p.set_defaults(func=run)


def parse_duration(text: str) -> float:
    """``"20ms"``, ``"0.02s"`` or ``"0.02"`` (seconds) -> seconds."""
    m = re.fullmatch(r"\s*(\d+(?:\.\d*)?|\.\d+)\s*(ms|s)?\s*", text)
    if not m:
        raise argparse.ArgumentTypeError(f"expected a duration such as 20ms or 0.02s; got {text!r}")
    return float(m.group(1)) / (1000.0 if m.group(2) == "ms" else 1.0)


def run(args: argparse.Namespace) -> int:
    from ..batch import DEFAULT_CHUNK, local_client, needed_keys, run_frames
    from ..io import open_sequence, write_depth
    from ..methods.registry import get_method

    if args.chunk is not None and not args.temporal:
        raise ValueError("--chunk applies to --temporal only; add --temporal or drop --chunk.")
    if args.workers is not None and args.scheduler:
        raise ValueError("--workers sets the size of the local cluster; with --scheduler the cluster's own workers "
                         "run the frames: drop --workers.")
    chunk = args.chunk or DEFAULT_CHUNK
    params = build_params(args)  # a bad parameter fails before anything is read
    entry = get_method(args.method)
    seq = open_sequence(args.input, depth_topic=args.depth_topic, color_topic=args.color_topic,
                        max_dt=args.max_dt)
    outdir = Path(args.output)
    settings = {
        "input": seq.describe() | {"path": str(Path(args.input).resolve())},
        "method": entry.name,
        "params": params_dict(params),
        "temporal": bool(args.temporal),
        "chunk": chunk if args.temporal else None,
        "max_dt": args.max_dt if seq.topics else None,
        "saturated_invalid": bool(args.saturated_invalid),
    }
    _check_outdir(outdir, seq, settings, overwrite=args.overwrite)

    outputs = {f.key: outdir / f"{f.key}{f.suffix}" for f in seq.frames}
    done_before = {f.key for f in seq.frames if not args.overwrite and outputs[f.key].is_file()}
    want = lambda key: key not in done_before  # noqa: E731
    need = needed_keys([f.key for f in seq.frames], want, temporal=args.temporal, chunk=chunk)
    outdir.mkdir(exist_ok=True)
    _remove_leftovers(outdir, outputs.values())

    records: dict[str, dict[str, Any]] = {}
    previous = _read_record(outdir)
    for frame in seq.frames:
        row = {"key": frame.key, "depth": frame.depth, "color": frame.color, "output": outputs[frame.key].name}
        if frame.key in done_before:
            old = previous.get(frame.key, {})
            row.update(status="done", seconds=old.get("seconds") if old.get("status") == "done" else None)
        else:
            row.update(status="pending", seconds=None)
        records[frame.key] = row
    dtypes: dict[str, Any] = {}
    loaded = seq.load([f for f in seq.frames if f.key in need], saturated_invalid=args.saturated_invalid)

    def tasks():
        for frame in seq.frames:
            if frame.key not in need:
                yield frame.key, InputFileError("not loaded")  # never used: the frame is not wanted
                continue
            got_frame, data = next(loaded)
            if got_frame.key != frame.key:  # the reader must keep the order it was given
                raise RuntimeError(f"frames out of order: {got_frame.key} instead of {frame.key}")
            if isinstance(data, BaseException):
                yield frame.key, data
            else:
                dtypes[frame.key] = data[0].dtype
                yield frame.key, (lambda value=data: value)

    to_run = sum(1 for f in seq.frames if f.key not in done_before)
    header = {"depthrefine": __version__, **settings, "output": str(outdir)}
    _write_record(outdir, header, records, complete=False)  # a resumed run checks its settings against it
    update, close = progress_bar(f"batch ({entry.name})", unit="frame")
    failures: list[tuple[str, str, bool]] = []
    start = time.perf_counter()
    last_record = start
    computed = 0
    n_workers = 0
    try:
        with local_client(args.workers, args.scheduler) as client:
            n_workers = len(client.scheduler_info().get("workers", {}))
            header["workers"] = n_workers
            header["scheduler"] = args.scheduler or "local"
            update(0, to_run)
            for result in run_frames(tasks(), entry=entry, params=params, client=client,
                                     temporal=args.temporal, chunk=chunk, want=want):
                row = records[str(result.key)]
                if result.key in done_before:
                    continue
                row["seconds"] = round(result.seconds, 4)
                if result.error is None:
                    try:
                        write_depth(outputs[result.key], result.depth_hr, dtype=dtypes[result.key],
                                    overwrite=args.overwrite)
                        row["status"] = "done"
                    except (OSError, ValueError) as exc:
                        row.update(status="failed", error=f"cannot write {outputs[result.key]}: {exc}")
                        failures.append((result.key, row["error"], False))
                else:
                    row.update(status="failed", error=result.error)
                    failures.append((result.key, result.error, result.bad_input))
                computed += 1
                update(computed, to_run)
                if time.perf_counter() - last_record > _RECORD_EVERY:
                    _write_record(outdir, header, records, complete=False)
                    last_record = time.perf_counter()
    except KeyboardInterrupt:
        close()
        _write_record(outdir, header, records, complete=False)
        print(f"depthrefine batch: interrupted after {computed} of {to_run} frames; the frames written are "
              f"whole: run the same command again to resume.", file=sys.stderr)
        return 130
    finally:
        close()
    elapsed = time.perf_counter() - start
    _write_record(outdir, header, records, complete=True)
    for note in seq.notes:
        print(f"depthrefine: note: {note}", file=sys.stderr)
    ok = computed - len(failures)
    rate = f"{computed / elapsed:.2f} frames/s" if elapsed > 0 else "-"
    print(f"batch: {len(seq.frames)} frames: {ok} refined, {len(done_before)} already done, {len(failures)} failed "
          f"in {elapsed:.1f} s ({rate}, {n_workers} worker{'s' if n_workers != 1 else ''}) -> {outdir}", file=sys.stderr)
    for key, message, _ in failures:
        print(f"  failed {key}: {message}", file=sys.stderr)
    if any(not bad for _, _, bad in failures):
        return 1
    return 2 if failures else 0


def _check_outdir(outdir: Path, seq, settings: dict, *, overwrite: bool) -> None:
    """Refuse an output folder inside the input, holding inputs, or holding another batch."""
    out = outdir.resolve()
    for folder in seq.folders:
        folder = Path(folder).resolve()
        if out == folder or folder in out.parents:
            raise InputFileError(f"output folder {outdir} is inside the input {folder}; choose a folder outside it.")
    for frame in seq.frames:
        for ref in (frame.depth_ref, frame.color_ref):
            if isinstance(ref, Path) and out in ref.resolve().parents:
                raise InputFileError(f"output folder {outdir} holds input file {ref}; choose another folder.")
    if outdir.exists() and not outdir.is_dir():
        raise InputFileError(f"output {outdir} exists and is not a folder; give a folder name.")
    parent = out.parent
    if not parent.is_dir():
        raise InputFileError(f"output folder {outdir}: its parent {parent} does not exist; create it first.")
    if not os.access(outdir if outdir.is_dir() else parent, os.W_OK):
        raise InputFileError(f"output folder {outdir} is not writable; choose another folder.")
    if not outdir.is_dir() or overwrite:
        return
    record = outdir / "batch.json"
    if not record.is_file():
        if any(outdir.iterdir()):
            raise InputFileError(f"output folder {outdir} is not empty and holds no batch.json; choose an empty or "
                                 "new folder (or pass --overwrite to write into it).")
        return
    try:
        old = json.loads(record.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise InputFileError(f"{record} cannot be read ({exc}); remove it or choose another folder.") from None
    changed = [k for k, v in settings.items() if _comparable(old.get(k)) != _comparable(v)]
    if changed:
        raise InputFileError(f"output folder {outdir} holds a batch run with other {', '.join(changed)}; to resume "
                             "it give the same command, else choose another folder or pass --overwrite to redo "
                             "every frame.")


def _comparable(value: Any) -> Any:
    """Settings as they read back from JSON (tuples become lists; the input's notes may change)."""
    value = json.loads(json.dumps(value))
    if isinstance(value, dict):
        value.pop("notes", None)
        value.pop("frames", None)
    return value


def _remove_leftovers(outdir: Path, outputs) -> None:
    """Remove the temporary files a killed run left (``.<stem>.XXXX<ext>``, see ``atomic_write``)."""
    names = {(f".{p.stem}.", p.suffix) for p in outputs} | {(".batch.", ".json")}
    for item in outdir.iterdir():
        if item.name.startswith(".") and item.is_file():
            if any(item.name.startswith(prefix) and item.name.endswith(suffix) for prefix, suffix in names):
                item.unlink()


def _read_record(outdir: Path) -> dict[str, dict]:
    try:
        old = json.loads((outdir / "batch.json").read_text(encoding="utf-8"))
        return {row["key"]: row for row in old.get("frames", [])}
    except (OSError, ValueError, KeyError, TypeError):
        return {}


def _write_record(outdir: Path, header: dict, records: dict, *, complete: bool) -> None:
    rows = list(records.values())
    counts: dict[str, int] = {}
    for row in rows:
        counts[row["status"]] = counts.get(row["status"], 0) + 1
    body = dict(header, complete=complete, counts=counts, frames=rows)
    text = json.dumps(body, indent=1) + "\n"
    atomic_write(outdir / "batch.json", lambda tmp: tmp.write_text(text, encoding="utf-8"))
