"""``depthrefine batch INPUT -o OUTDIR``: refine a folder, manifest, recording or bag of frames on Dask.

The command parses its options into :class:`depthrefine.batch.BatchOptions`,
opens the sequence, and runs a :class:`depthrefine.batch.BatchJob` (which
does the resume, the record keeping and the task submission) on a local or
remote Dask cluster; then it reports.
"""

from __future__ import annotations

import argparse
import contextlib
import re
import sys
from typing import Callable, Iterator

from ..io._names import DEFAULT_MAX_DT
from ..methods._names import DEFAULT_METHOD
from ._common import (add_depth_options, add_output, add_output_format_options, add_overwrite, add_params_options,
                      parse_count, progress_bar)
from ._confidence import add_confidence_options
from ._rig_options import add_align_options


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "batch",
        help="refine many frames (a folder, a CSV manifest, a recording or a ROS bag) in parallel, locally or on a "
             "Dask cluster",
        description=(
            "Refine every depth + color pair of INPUT: a folder with depth/ and color/ subfolders whose files pair "
            "by stem, a CSV manifest with columns depth,color (paths relative to it), or a recording or ROS bag. "
            "Registered frames are refined as they are; raw frames of a rig (--rig, or the recording's own "
            "calibration) are undistorted and aligned first, as `depthrefine run` does. Writes OUTDIR/<stem>.<ext> "
            "in the depth's dtype (for bags the stem is the depth time stamp in ns), with --confidence FORMAT "
            "OUTDIR/confidence/<stem>.<FORMAT>, and OUTDIR/batch.json. Runs on "
            "a local Dask cluster (one process per core) or, with --scheduler, on a remote one; a lost worker's "
            "frames are recomputed on the others. Run the same command again to resume: frames already written "
            "are skipped. Exit status 0 if every paired frame was refined, 2 if a frame's input was bad, 1 if a "
            "frame failed otherwise or the scheduler was lost, 130 if interrupted."
        ),
    )
    p.add_argument("input", metavar="INPUT", help="folder with depth/ and color/, CSV manifest, recording or ROS bag")
    add_output(p, help="output folder (created; it may not lie inside INPUT)", metavar="OUTDIR")
    add_params_options(p, method_help=f"refinement (upsampling) method (default: the --rig settings file's [refine] "
                                      f"method, else {DEFAULT_METHOD})")
    p.set_defaults(method=None)
    p.add_argument("--workers", type=parse_count, metavar="N",
                   help="worker processes of the local cluster (default: the number of cores)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run on the Dask cluster of this scheduler (tcp://host:port) instead of a local one")
    p.add_argument("--temporal", action="store_true",
                   help="process frames in order within chunks, each warm-starting from the previous one "
                        "(thesis: k-means from the previous means, so labels do not flicker)")
    p.add_argument("--chunk", type=parse_count, metavar="N", default=None,
                   help="frames per chunk with --temporal (default 32); each chunk's first frame starts cold")
    p.add_argument("--frames-per-task", type=parse_count, metavar="N",
                   help="without --temporal: frames sent to a worker at once (default: as many as hold about a "
                        "million color pixels, at most 8); fewer: finer progress, less work redone after a lost "
                        "worker")
    p.add_argument("--depth-topic", metavar="TOPIC", help="ROS bag: the depth topic (sensor_msgs/Image)")
    p.add_argument("--color-topic", metavar="TOPIC",
                   help="ROS bag: the color topic (sensor_msgs/Image or CompressedImage)")
    p.add_argument("--max-dt", type=parse_duration, metavar="T", default=DEFAULT_MAX_DT,
                   help="recordings and bags: pair a depth frame with the nearest color frame within T (20ms, "
                        "0.02s or 0.02 seconds; default 20ms); frames without a partner are listed as unpaired")
    chain = p.add_argument_group("raw frames of a rig (as `depthrefine run`)")
    chain.add_argument("--rig", metavar="FILE",
                       help="rig file (calibrate-stereo) or chain settings file (TOML/JSON): the frames are raw "
                            "captures of this rig (default: the recording's own calibration, when it has one and "
                            "its frames are not registered)")
    add_align_options(chain, method_flag="--align-method")
    chain.add_argument("--fill-holes", action="store_true",
                       help="keep the refinement's depth everywhere; default: pixels no depth measurement reached "
                            "stay invalid (0), as run")
    outputs = p.add_argument_group("outputs beside each refined depth map")
    add_output_format_options(outputs)
    outputs.add_argument("--save-color", action="store_true",
                         help="also write the color image each depth lies on (undistorted with a rig) as "
                              "OUTDIR/color/<stem>.png")
    outputs.add_argument("--ply", action="store_true",
                         help="also write a colored point cloud OUTDIR/ply/<stem>.ply (needs a rig and the depth's "
                              "units)")
    outputs.add_argument("--stride", type=parse_count, default=1, metavar="N",
                         help="--ply: keep every N-th row and column (default 1)")
    add_confidence_options(outputs, folder=True)
    outputs.add_argument("--video", metavar="FILE",
                         help="also write a preview video (.mp4, .mkv, .mov, .avi, .webm): color | input | refined "
                              "side by side, in order, with one colorbar")
    outputs.add_argument("--fps", type=_positive_float, metavar="F",
                         help="--video: frames per second (default: the recording's frame rate, else 30)")
    add_overwrite(p)
    add_depth_options(p)
    p.set_defaults(func=run)


def parse_duration(text: str) -> float:
    """``"20ms"``, ``"0.02s"`` or ``"0.02"`` (seconds) -> seconds."""
    m = re.fullmatch(r"\s*(\d+(?:\.\d*)?|\.\d+)\s*(ms|s)?\s*", text)
    if not m:
        raise argparse.ArgumentTypeError(f"expected a duration such as 20ms or 0.02s; got {text!r}")
    return float(m.group(1)) / (1000.0 if m.group(2) == "ms" else 1.0)


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not (value > 0 and value < float("inf")):
        raise argparse.ArgumentTypeError(f"expected a positive number such as 30; got {text!r}")
    return value


@contextlib.contextmanager
def _interrupt_latch() -> Iterator[Callable[[], None]]:
    """Ctrl-C remembered for the block; the callable given raises ``KeyboardInterrupt`` once one came.

    Python delivers Ctrl-C as a ``KeyboardInterrupt`` wherever the main thread
    is, and one raised in a finalizer (a Dask future released by the garbage
    collector, say) is printed and dropped: the batch would run on to the end.
    The batch calls the check after every frame, so a Ctrl-C stops it within
    a frame wherever it landed, and a dropped one is not printed (the
    interrupt's own one-line message follows). Outside the main thread,
    nothing is latched.
    """
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield lambda: None
        return
    came = threading.Event()

    def latch(signum, frame):
        came.set()
        raise KeyboardInterrupt

    def check() -> None:
        if came.is_set():
            raise KeyboardInterrupt

    def unraisable(info) -> None:
        if not (came.is_set() and isinstance(info.exc_value, KeyboardInterrupt)):
            hook(info)

    previous, hook = signal.signal(signal.SIGINT, latch), sys.unraisablehook
    sys.unraisablehook = unraisable
    try:
        yield check
    finally:
        signal.signal(signal.SIGINT, previous)
        sys.unraisablehook = hook


def run(args: argparse.Namespace) -> int:
    from ..batch import BatchJob, ClusterLost, local_client
    from ..io import open_sequence

    if args.chunk is not None and not args.temporal:
        raise ValueError("--chunk applies to --temporal only; add --temporal or drop --chunk.")
    if args.frames_per_task is not None and args.temporal:
        raise ValueError("--frames-per-task applies without --temporal (with it, a task is a chunk: --chunk).")
    if args.workers is not None and args.scheduler:
        raise ValueError("--workers sets the size of the local cluster; with --scheduler the cluster's own workers "
                         "run the frames: drop --workers.")
    options = _options(args)  # a bad parameter or rig file fails before anything is read
    seq = open_sequence(args.input, depth_topic=args.depth_topic, color_topic=args.color_topic, max_dt=args.max_dt)
    job = BatchJob(seq, args.output, options)
    for warning in job.warnings:
        print(f"depthrefine batch: warning: {warning}.", file=sys.stderr)
    update, close = progress_bar(f"batch ({job.method.name})", unit="frame")
    try:
        with _interrupt_latch() as check, local_client(args.workers, args.scheduler) as client:

            def progress(done: int, total: int) -> None:
                check()   # a Ctrl-C dropped on the way stops the batch at its next frame
                update(done, total)

            summary = job.run(client, progress=progress)
    except KeyboardInterrupt:
        close()
        print(f"depthrefine batch: interrupted; {job.describe_progress()}: run the same command again to resume.",
              file=sys.stderr)
        return 130
    except ClusterLost as exc:
        close()
        print(f"depthrefine batch: error: {exc}; {job.describe_progress()}: run the same command again (with a "
              "running scheduler) to resume.", file=sys.stderr)
        return 1
    finally:
        close()
    print(summary.line(), file=sys.stderr)
    for note in summary.notes:
        print(f"depthrefine: note: {note}", file=sys.stderr)
    if summary.video is not None:
        print(f"depthrefine: wrote {summary.video}", file=sys.stderr)
    for key, message, _ in summary.failed:
        print(f"  failed {key}: {message}", file=sys.stderr)
    return summary.exit_status


def _options(args: argparse.Namespace):
    """The :class:`BatchOptions` of the command line (and of the --rig settings file)."""
    import dataclasses

    from ..batch import DEFAULT_CHUNK, BatchOptions
    from ..rig.chain import AlignSettings
    from ._common import build_params
    from ._rig_options import align_overrides, chain_settings

    rig = rig_source = align = None
    fill_holes = args.fill_holes
    method, params = args.method or DEFAULT_METHOD, None
    if args.rig:
        chain = chain_settings(args)
        rig, rig_source, align = chain.rig, chain.rig_source, chain.align
        fill_holes = fill_holes or chain.fill_holes
        method = args.method or chain.method or DEFAULT_METHOD
        base = chain.params if chain.params and method == (chain.method or DEFAULT_METHOD) else None
        params = build_params(args, method=method, base=base)
    else:
        overrides = align_overrides(args)
        align = dataclasses.replace(AlignSettings(), **overrides) if overrides else None
        params = build_params(args, method=method)
    return BatchOptions(method=method, params=params, temporal=args.temporal, chunk=args.chunk or DEFAULT_CHUNK,
                        rig=rig, rig_source=rig_source, align=align, fill_holes=fill_holes,
                        output_scale=args.output_scale, output_dtype=args.output_dtype, save_color=args.save_color,
                        ply=args.ply, ply_stride=args.stride, confidence=args.confidence,
                        min_confidence=args.min_confidence, video=args.video, fps=args.fps,
                        frames_per_task=args.frames_per_task, max_dt=args.max_dt,
                        saturated_invalid=args.saturated_invalid, overwrite=args.overwrite)
