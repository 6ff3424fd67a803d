"""A batch job: the frames of a sequence into an output folder, with resume and a record (``batch.json``).

:class:`BatchJob` is what ``depthrefine batch`` runs; the command only parses
its options into :class:`BatchOptions`, opens the sequence, runs the job on a
Dask client and prints the :class:`BatchSummary`. Everything the job writes
goes through :mod:`depthrefine.io` (atomic writes: a file is whole or absent).

The record is true to the files: a frame is ``done`` exactly when all its
outputs exist, also after an error, an interrupt or a lost scheduler (the
job checks the files before it writes the record on the way out), and a
run of the same job later does only the frames that are not done.
"""

from __future__ import annotations

import dataclasses
import json
import os
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ..methods.registry import DEFAULT_METHOD, get_method
from ._frame import FramePlan
from ._schedule import DEFAULT_CHUNK, needed_keys, run_frames

__all__ = ["BatchOptions", "BatchJob", "BatchSummary"]

#: Seconds between rewrites of ``batch.json`` during a run.
RECORD_EVERY = 5.0
#: Frames whose depth sets the fixed range of the preview video's colors.
_RANGE_FRAMES = 8
#: Frame rate of the preview video when neither the options nor the recording give one.
DEFAULT_FPS = 30.0
#: Settings that must match for a run to resume in a folder (see :meth:`BatchJob.settings`).
_SETTING_KEYS = ("input", "method", "params", "temporal", "chunk", "max_dt", "saturated_invalid", "rig", "align",
                 "fill_holes", "output_scale", "output_dtype", "save_color", "ply", "ply_stride", "confidence",
                 "min_confidence")
_OUTPUT_DTYPES = ("uint8", "uint16", "float32")
#: The file types of OUTDIR/confidence/<stem>.<ext> (as ``batch --confidence FORMAT``).
CONFIDENCE_FORMATS = ("tif", "npy", "png")


@dataclass(frozen=True)
class BatchOptions:
    """How a batch runs and what it writes beside each refined depth map.

    Attributes
    ----------
    method, params
        The refinement method and its parameters (as :func:`depthrefine.refine`).
    temporal, chunk
        Warm start within chunks of ``chunk`` consecutive frames.
    rig : StereoRig, optional
        The frames are raw captures of this rig: each is undistorted and
        aligned before it is refined, as ``depthrefine run`` does. Default:
        the recording's own calibration (``Sequence.rig``) when the
        sequence says its frames are raw (``Sequence.raw``).
    rig_source : str, optional
        Where ``rig`` came from, for the record.
    align : AlignSettings, optional
        Alignment settings with a rig; units left unset are the recording's
        (``Sequence.depth_units``, e.g. a RealSense bag's "Depth Units").
    fill_holes : bool
        With a rig: keep the refinement's depth where nothing was measured.
    output_scale, output_dtype
        Store ``depth * output_scale`` as ``output_dtype`` (``uint8``,
        ``uint16``, ``float32``); a value that would clip fails its frame.
        Default: the depth as refined, in the input depth's dtype.
    save_color : bool
        Also write the color image each depth lies on (undistorted with a
        rig) as ``OUTDIR/color/<stem>.png``.
    ply, ply_stride
        Also write a colored point cloud ``OUTDIR/ply/<stem>.ply`` (needs a
        rig and the depth's units), every ``ply_stride``-th row and column.
    confidence : str, optional
        Also write each frame's confidence map (0..1, 1 = most trusted, 0 =
        no depth; :func:`depthrefine.refine_with_confidence`) as
        ``OUTDIR/confidence/<stem>.<confidence>``: ``"tif"`` or ``"npy"``
        (float32) or ``"png"`` (16-bit, confidence x 65535).
    min_confidence : float, optional
        Write 0 (no measurement) in the depth where the confidence is below
        it (0..1); the confidence map has 0 there too.
    video, fps
        Also write a preview video (color | input | refined) at ``fps``
        frames per second (default: the recording's rate, else 30).
    frames_per_task : int, optional
        Without ``temporal``: frames sent to a worker at once (default: as
        many as hold about a million color pixels, at most 8; see
        :func:`depthrefine.batch.run_frames`). More: less overhead per frame;
        fewer: finer progress, less work redone after a lost worker.
    max_dt : float, optional
        The pairing tolerance the sequence was opened with (for the record).
    saturated_invalid, overwrite
        As for ``depthrefine batch``.
    """

    method: str = DEFAULT_METHOD
    params: Any = None
    temporal: bool = False
    chunk: int = DEFAULT_CHUNK
    rig: Any = None
    rig_source: str | None = None
    align: Any = None
    fill_holes: bool = False
    output_scale: float | None = None
    output_dtype: str | None = None
    save_color: bool = False
    ply: bool = False
    ply_stride: int = 1
    confidence: str | None = None
    min_confidence: float | None = None
    video: str | os.PathLike | None = None
    fps: float | None = None
    frames_per_task: int | None = None
    max_dt: float | None = None
    saturated_invalid: bool = False
    overwrite: bool = False

    def __post_init__(self) -> None:
        get_method(self.method)
        if not (isinstance(self.chunk, int) and self.chunk >= 1):
            raise ValueError(f"chunk must be a whole number >= 1; got {self.chunk!r}.")
        if self.frames_per_task is not None and not (isinstance(self.frames_per_task, int)
                                                     and self.frames_per_task >= 1):
            raise ValueError(f"frames_per_task must be a whole number >= 1; got {self.frames_per_task!r}.")
        if not (isinstance(self.ply_stride, int) and self.ply_stride >= 1):
            raise ValueError(f"the point cloud stride must be a whole number >= 1; got {self.ply_stride!r}.")
        if self.output_dtype is not None and self.output_dtype not in _OUTPUT_DTYPES:
            raise ValueError(f"output_dtype must be one of {', '.join(_OUTPUT_DTYPES)}; got {self.output_dtype!r}.")
        if self.confidence is not None and self.confidence not in CONFIDENCE_FORMATS:
            raise ValueError(f"confidence must be one of {', '.join(CONFIDENCE_FORMATS)} (the file type of "
                             f"OUTDIR/confidence/<stem>.<ext>); got {self.confidence!r}.")
        if self.min_confidence is not None and not (isinstance(self.min_confidence, (int, float))
                                                    and 0.0 <= self.min_confidence <= 1.0):
            raise ValueError(f"min_confidence must be a number between 0 and 1; got {self.min_confidence!r}.")
        for name in ("output_scale", "fps"):
            value = getattr(self, name)
            if value is not None and not (isinstance(value, (int, float)) and np.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a positive number; got {value!r}.")


@dataclass
class BatchSummary:
    """The outcome of :meth:`BatchJob.run`.

    Attributes
    ----------
    frames : int
        Frames of the sequence (paired depth + color).
    refined : int
        Frames refined and written by this run.
    already_done : int
        Frames whose outputs an earlier run wrote (skipped).
    failed : list of (key, reason, bad_input)
        Frames that failed, in order.
    unpaired : list of dict
        Frames of one stream without a partner in the other
        (``Sequence.unpaired``): listed, not failures.
    seconds : float
        Wall time of the run.
    workers : int
        Dask workers at the start.
    outdir : Path
    video : Path or None
        The preview video, if one was written.
    notes : list of str
        The sequence's and the chain's notes, one line each.
    """

    frames: int
    refined: int
    already_done: int
    failed: list[tuple[str, str, bool]]
    unpaired: list[dict]
    seconds: float
    workers: int
    outdir: Path
    video: Path | None = None
    notes: list[str] = field(default_factory=list)

    @property
    def exit_status(self) -> int:
        """0: every paired frame refined; 2: a frame's input was bad; 1: a frame failed otherwise."""
        if any(not bad for _, _, bad in self.failed):
            return 1
        return 2 if self.failed else 0

    def line(self) -> str:
        """The one-line summary ``depthrefine batch`` prints."""
        computed = self.refined + len(self.failed)
        rate = f"{computed / self.seconds:.2f} frames/s" if self.seconds > 0 else "-"
        unpaired = f", {len(self.unpaired)} unpaired (see batch.json)" if self.unpaired else ""
        return (f"batch: {self.frames} frames: {self.refined} refined, {self.already_done} already done, "
                f"{len(self.failed)} failed{unpaired} in {self.seconds:.1f} s ({rate}, {self.workers} "
                f"worker{'s' if self.workers != 1 else ''}) -> {self.outdir}")


class BatchJob:
    """The frames of ``sequence`` refined into ``outdir`` as ``options`` say (see the module's notes).

    Construction checks everything that can be checked before a frame is
    computed and writes nothing: the output folder (new, empty, or holding
    an earlier run of the same job), the output formats, the rig against
    the first frame's sizes and the alignment settings (the first frame is
    aligned here). :meth:`run` does the work.

    Parameters
    ----------
    sequence : depthrefine.io.Sequence
        From :func:`depthrefine.io.open_sequence`.
    outdir : path-like
        The output folder (created by :meth:`run`; its parent must exist).
    options : BatchOptions, optional

    Attributes
    ----------
    plan : FramePlan
        What the workers do with each frame.
    outputs : dict
        Per frame key, the files it writes: ``{"depth": Path, "color": Path, "ply": Path}``
        (``color`` and ``ply`` when asked).
    done_before : set of str
        Keys whose outputs an earlier run wrote (skipped unless ``overwrite``).
    warnings : list of str
        What looks wrong but is not refused, one line each (the depth units
        putting the first frame's median depth outside 5 cm .. 50 m).

    Raises
    ------
    InputFileError, ValueError
        One line naming what is wrong and what to do.

    Examples
    --------
    ::

        from depthrefine.io import open_sequence
        from depthrefine.batch import BatchJob, BatchOptions, local_client

        job = BatchJob(open_sequence("recording.mkv"), "out", BatchOptions(method="gbp"))
        with local_client() as client:                  # a LocalCluster, or local_client(scheduler=ADDRESS)
            summary = job.run(client)
        print(summary.line())                           # batch: 300 frames: 300 refined, ...
    """

    def __init__(self, sequence: Any, outdir: str | os.PathLike, options: BatchOptions | None = None):
        from ..io import InputFileError

        self.sequence = sequence
        self.outdir = Path(outdir)
        self.options = options = options or BatchOptions()
        self.method = get_method(options.method)
        rig, rig_source, align = self._chain()
        if options.ply and rig is None:
            raise InputFileError("a point cloud per frame (--ply) needs the rig: give --rig RIG (a rig file from "
                                 "`depthrefine calibrate-stereo`) or a recording with its calibration.")
        if options.ply and align.depth_units is None and align.inverse_scale is None:
            raise InputFileError("a point cloud per frame (--ply) needs the depth's units: --depth-units M or "
                                 "--inverse-depth-scale C.")
        self.plan = FramePlan(self.method, options.params, rig=rig, align=align, fill_holes=options.fill_holes,
                              color=options.save_color, points=options.ply, stride=options.ply_stride,
                              preview=options.video is not None,
                              confidence=options.confidence is not None or options.min_confidence is not None,
                              min_confidence=options.min_confidence, output_scale=options.output_scale,
                              output_dtype=options.output_dtype)
        self._rig_source = rig_source
        self.video_path = None
        self.outputs = {f.key: self._frame_outputs(f) for f in sequence.frames}
        self._check_outdir()
        if options.video is not None:
            from ..io import VIDEO_SUFFIXES, check_output

            self.video_path = check_output(options.video, overwrite=options.overwrite, what="video",
                                           suffixes=VIDEO_SUFFIXES)
        self.done_before = {key for key, files in self.outputs.items()
                            if not options.overwrite and all(p.is_file() for p in files.values())}
        self.warnings: list[str] = []
        if rig is not None:
            self._check_first_frame()

    # ------------------------------------------------------------------ set-up

    def _chain(self) -> tuple[Any, str | None, Any]:
        """The rig, where it came from, and the alignment settings (rig None: registered frames, refined as they are)."""
        from ..io import InputFileError
        from ..rig.chain import AlignSettings

        options, seq = self.options, self.sequence
        rig, source = options.rig, options.rig_source
        if rig is None and seq.raw:
            rig, source = seq.require_rig(), seq.rig_source or "recording"
        if rig is None:
            if options.align is not None or options.fill_holes:
                raise InputFileError("alignment options (--align-method, --depth-units, --fill-holes ...) apply to "
                                     "raw frames of a rig: give --rig RIG.")
            return None, None, AlignSettings()
        align = options.align or AlignSettings()
        if align.depth_units is None and align.inverse_scale is None and seq.depth_units is not None:
            align = dataclasses.replace(align, depth_units=float(seq.depth_units))
        return rig, source, align

    def _frame_outputs(self, frame: Any) -> dict[str, Path]:
        suffix = frame.suffix
        dtype = self.options.output_dtype
        if dtype is not None and not _holds(suffix, dtype):
            suffix = ".tif" if dtype == "float32" else ".png"
        files = {"depth": self.outdir / f"{frame.key}{suffix}"}
        if self.options.save_color:
            files["color"] = self.outdir / "color" / f"{frame.key}.png"
        if self.options.ply:
            files["ply"] = self.outdir / "ply" / f"{frame.key}.ply"
        if self.options.confidence:
            files["confidence"] = self.outdir / "confidence" / f"{frame.key}.{self.options.confidence}"
        return files

    def settings(self) -> dict[str, Any]:
        """What the outputs depend on (the record's header; a resumed run must have the same)."""
        o = self.options
        out: dict[str, Any] = {
            "input": self.sequence.describe() | {"path": str(Path(self.sequence.source).resolve())},
            "method": self.method.name,
            "params": _params_dict(self.plan.told_params()),
            "temporal": bool(o.temporal),
            "chunk": o.chunk if o.temporal else None,
            "max_dt": o.max_dt if self.sequence.topics else None,
            "saturated_invalid": bool(o.saturated_invalid),
        }
        if self.plan.rig is not None:
            out["rig"] = {"source": self._rig_source, **self.plan.rig.to_dict()}
            out["align"] = {k: v for k, v in self.plan.align.to_dict().items() if v is not None}
            out["fill_holes"] = bool(o.fill_holes)
        for name in ("output_scale", "output_dtype", "save_color", "ply", "confidence"):
            if getattr(o, name):
                out[name] = getattr(o, name)
        if o.ply:
            out["ply_stride"] = o.ply_stride
        if o.min_confidence is not None:
            out["min_confidence"] = o.min_confidence
        return out

    def _check_outdir(self) -> None:
        """Refuse an output folder inside the input, holding inputs, or holding another batch."""
        from ..io import InputFileError

        outdir, seq = self.outdir, self.sequence
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
        if not out.parent.is_dir():
            raise InputFileError(f"output folder {outdir}: its parent {out.parent} does not exist; create it first.")
        if not os.access(outdir if outdir.is_dir() else out.parent, os.W_OK):
            raise InputFileError(f"output folder {outdir} is not writable; choose another folder.")
        if not outdir.is_dir() or self.options.overwrite:
            return
        record = outdir / "batch.json"
        if not record.is_file():
            if any(outdir.iterdir()):
                raise InputFileError(f"output folder {outdir} is not empty and holds no batch.json; choose an empty "
                                     "or new folder (or pass --overwrite to write into it).")
            return
        try:
            old = json.loads(record.read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise InputFileError(f"{record} cannot be read ({exc}); remove it or choose another folder.") from None
        settings = self.settings()
        changed = [k for k in _SETTING_KEYS if _comparable(old.get(k)) != _comparable(settings.get(k))]
        if changed:
            raise InputFileError(f"output folder {outdir} holds a batch run with other {', '.join(changed)}; to "
                                 "resume it give the same command (another depthrefine version may record other "
                                 "parameters for it), else choose another folder or pass --overwrite to redo every "
                                 "frame.")

    def _check_first_frame(self) -> None:
        """Align the first frame here: a rig of other sizes, or settings the chain refuses, fail before any work."""
        from ..io import InputFileError
        from ..rig.chain import align_pair
        from ..rig.pointcloud import implausible_units

        first = next((f for f in self.sequence.frames if f.problem is None), None)
        if first is None:
            return
        frame, data = next(iter(self.sequence.load([first], saturated_invalid=self.options.saturated_invalid)))
        if isinstance(data, BaseException):
            return  # an unreadable first frame fails on its own, as any other
        depth, rgb = data
        rig = self.plan.rig
        for what, image, camera in (("depth", depth, rig.depth_camera), ("color", rgb, rig.color_camera)):
            if tuple(image.shape[:2]) != camera.shape:
                w, h = camera.image_size
                raise InputFileError(
                    f"the rig{f' ({self._rig_source})' if self._rig_source else ''} has a {w}x{h} {what} camera "
                    f"but the {what} frames are {image.shape[1]}x{image.shape[0]} (frame {frame.key}); give the "
                    "rig of this recording at this resolution.")
        units = implausible_units(depth, depth_units=self.plan.align.depth_units,
                                  inverse_scale=self.plan.align.inverse_scale)
        if units:
            self.warnings.append(f"frame {frame.key}: {units}")
        try:
            align_pair(depth, rgb, rig, settings=self.plan.align)
        except (ValueError, TypeError) as exc:
            raise InputFileError(f"frame {frame.key}: {' '.join(str(exc).split())}") from None

    # ------------------------------------------------------------------ running

    def run(self, client: Any, *, progress: Callable[[int, int], None] | None = None) -> BatchSummary:
        """Refine the frames not done yet on ``client`` and write them; return the summary.

        ``progress(done, total)`` is called as frames finish. On any error
        (a lost scheduler: :class:`ClusterLost`; an interrupt:
        ``KeyboardInterrupt``) ``batch.json`` is rewritten true to the files
        on disk before the error propagates, and no partial file is left.
        """
        from ._writer import BatchWriter

        seq, options = self.sequence, self.options
        writer = self._writer = BatchWriter(self)
        start = time.perf_counter()
        with writer:
            writer.begin(workers=len(client.nthreads()), scheduler=_scheduler_name(client))
            to_run = [f.key for f in seq.frames if f.key not in self.done_before]
            write = set(to_run)
            want = (lambda key: True) if self.plan.preview else (lambda key: key in write)
            need = needed_keys([f.key for f in seq.frames], want, temporal=options.temporal, chunk=options.chunk)
            loaded = seq.load([f for f in seq.frames if f.key in need], saturated_invalid=options.saturated_invalid)
            if progress:
                progress(0, len(to_run))
            for result in run_frames(self._tasks(need, loaded), plan=self.plan, client=client,
                                     temporal=options.temporal, chunk=options.chunk, want=want,
                                     frames_per_task=options.frames_per_task, total=len(seq.frames)):
                writer.settle(result, write=result.key in write)
                if progress and result.key in write:
                    progress(writer.computed, len(to_run))
        return writer.summary(time.perf_counter() - start)

    def describe_progress(self) -> str:
        """Where the job stands, for a message after an interrupt: ``"12 of 48 frames written (...)"``."""
        writer = getattr(self, "_writer", None)
        rows = writer.rows.values() if writer is not None and writer.rows else None
        done = sum(r["status"] == "done" for r in rows) if rows is not None else len(self.done_before)
        where = f"; {self.outdir / 'batch.json'} lists them" if rows is not None else ""
        return f"{done} of {len(self.sequence.frames)} frames written, each whole{where}"

    def _tasks(self, need, loaded):
        """``(key, loader)`` of every frame; a loader gives ``(depth, rgb, suffixes)``: the worker encodes the files."""
        from ..io import InputFileError

        for frame in self.sequence.frames:
            if frame.key not in need:
                yield frame.key, InputFileError("not loaded")  # never used: the frame is not wanted
                continue
            got, data = next(loaded)
            if got.key != frame.key:  # the reader must keep the order it was given
                raise RuntimeError(f"frames out of order: {got.key} instead of {frame.key}")
            if isinstance(data, BaseException):
                yield frame.key, data
            else:
                suffixes = {kind: path.suffix.lower() for kind, path in self.outputs[frame.key].items()}
                yield frame.key, (lambda value=(*data, suffixes): value)


def _holds(suffix: str, dtype: str) -> bool:
    from ..io import InputFileError, check_depth_format

    try:
        check_depth_format(f"x{suffix}", np.dtype(dtype))
    except InputFileError:
        return False
    return True


def _params_dict(params: Any) -> dict[str, Any]:
    if params is None:
        return {}
    if hasattr(params, "to_dict"):
        return params.to_dict()
    return dataclasses.asdict(params)


def _comparable(value: Any) -> Any:
    """Settings as they read back from JSON (tuples become lists; the input's notes may change)."""
    value = json.loads(json.dumps(value))
    if isinstance(value, dict):
        value.pop("notes", None)
        value.pop("frames", None)
    return value


def _scheduler_name(client: Any) -> str:
    cluster = getattr(client, "cluster", None)
    if cluster is not None and type(cluster).__name__ == "LocalCluster":
        return "local"
    return getattr(client.scheduler, "address", None) or "local"

