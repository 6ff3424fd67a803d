"""What a :class:`~depthrefine.batch.BatchJob` writes: each frame's files, ``batch.json`` and the preview video.

Every file goes through :mod:`depthrefine.io`'s atomic writers. A frame's
files are written all or none; the record is rewritten every few seconds,
and on the way out (also after an error or an interrupt) from the files on
disk, so that it never says ``done`` for a frame whose files are missing,
nor ``pending`` for one whose files are all there.
"""

from __future__ import annotations

import contextlib
import json
import time
from pathlib import Path
from typing import Any

from .. import __version__
from ._job import DEFAULT_FPS, RECORD_EVERY, _RANGE_FRAMES, BatchSummary

__all__ = ["BatchWriter"]


class BatchWriter:
    """The output side of one :meth:`BatchJob.run`; a context manager that leaves the record true to the files."""

    def __init__(self, job: Any):
        self.job = job
        self.options = job.options
        self.outdir: Path = job.outdir
        self.rows: dict[str, dict[str, Any]] = {}
        self.header: dict[str, Any] = {}
        self.failed: list[tuple[str, str, bool]] = []
        self.refined = 0
        self.computed = 0
        self.chain_notes: tuple[str, ...] = ()
        self.unpaired = list(job.sequence.unpaired)
        self._wrote: set[str] = set()
        self._last_record = 0.0
        self._video: Any = None
        self._video_path: Path | None = None
        self._preview_buffer: list[Any] = []
        self._limits: tuple[float, float] | None = None

    # ------------------------------------------------------------------ start and end

    def begin(self, *, workers: int, scheduler: str) -> None:
        """Create the folders, remove what a killed run left half-written, write the first record."""
        job, seq = self.job, self.job.sequence
        self.outdir.mkdir(exist_ok=True)
        for kind in ("color", "ply", "confidence"):
            if any(kind in files for files in job.outputs.values()):
                (self.outdir / kind).mkdir(exist_ok=True)
        _remove_leftovers([p for files in job.outputs.values() for p in files.values()]
                          + [self.outdir / "batch.json"] + ([job.video_path] if job.video_path else []))
        previous = _read_record(self.outdir)
        for frame in seq.frames:
            files = job.outputs[frame.key]
            row: dict[str, Any] = {"key": frame.key, "depth": frame.depth, "color": frame.color}
            if frame.stamp_ns is not None:
                row["stamp_ns"] = int(frame.stamp_ns)
            row["output"] = files["depth"].name
            for kind in ("color", "ply", "confidence"):
                if kind in files:
                    row[f"{kind}_output"] = f"{kind}/{files[kind].name}"
            if frame.key in job.done_before:
                old = previous.get(frame.key, {})
                row.update(status="done", seconds=old.get("seconds") if old.get("status") == "done" else None)
            else:
                row.update(status="pending", seconds=None)
            self.rows[frame.key] = row
        self.header = {"depthrefine": __version__, **job.settings(), "output": str(self.outdir),
                       "workers": workers, "scheduler": scheduler}
        if job.video_path is not None:
            from ..io import VideoWriter

            fps = self.options.fps or seq.frame_rate or DEFAULT_FPS
            self._video = VideoWriter(job.video_path, fps=float(fps), overwrite=self.options.overwrite)
        self.write_record(complete=False)

    def __enter__(self) -> BatchWriter:
        return self

    def __exit__(self, kind, value, traceback) -> None:
        if kind is None:
            self._flush_preview()
            if self._video is not None:
                self._video_path = self._video.close()
            self.write_record(complete=True)
            return
        if self._video is not None:
            self._video.abort()
        if self.header:  # began: the record is rewritten from the files on disk
            self.write_record(complete=False)

    def summary(self, seconds: float) -> BatchSummary:
        """The run's :class:`BatchSummary`."""
        seq = self.job.sequence
        notes = list(seq.notes) + (["chain: " + "; ".join(self.chain_notes)] if self.chain_notes else [])
        return BatchSummary(frames=len(seq.frames), refined=self.refined, already_done=len(self.job.done_before),
                            failed=list(self.failed), unpaired=self.unpaired, seconds=seconds,
                            workers=int(self.header.get("workers", 0)), outdir=self.outdir,
                            video=self._video_path, notes=notes)

    # ------------------------------------------------------------------ frames

    def settle(self, result: Any, *, write: bool) -> None:
        """Record and write one frame's result (``write`` false: an earlier run wrote it; only its preview)."""
        if write:
            row = self.rows[str(result.key)]
            row["seconds"] = round(result.seconds, 4)
            error, bad = result.error, result.bad_input
            if error is None:
                try:
                    self._write_frame(result.key, result.output)
                except OSError as exc:
                    error, bad = f"cannot write the outputs of {result.key}: {' '.join(str(exc).split())}", False
            if error is None:
                row["status"] = "done"
                row.pop("error", None)
                self.refined += 1
            else:
                row.update(status="failed", error=error)
                self.failed.append((str(result.key), error, bad))
            self.computed += 1
        if result.output is not None:
            if not self.chain_notes and result.output.notes:
                self.chain_notes = tuple(result.output.notes)
            if self._video is not None:
                self._add_preview(result.output)
        if time.perf_counter() - self._last_record > RECORD_EVERY:
            self.write_record(complete=False)

    def _write_frame(self, key: str, output: Any) -> None:
        """All of a frame's files (encoded by the worker: ``output.files``), or none (those written are removed
        if a later one fails)."""
        from ..io import write_bytes

        files = self.job.outputs[key]
        written: list[Path] = []
        try:
            for kind in ("color", "ply", "confidence", "depth"):
                if kind in files:
                    written.append(write_bytes(files[kind], output.files[kind], overwrite=True))
            self._wrote.add(key)
        except BaseException:
            for path in written:
                with contextlib.suppress(OSError):
                    path.unlink()
            raise

    # ------------------------------------------------------------------ preview video

    def _add_preview(self, output: Any) -> None:
        """Frames wait until the first few set the video's depth range, then go out in order."""
        self._preview_buffer.append(output)
        if self._limits is not None or len(self._preview_buffer) >= _RANGE_FRAMES:
            self._flush_preview()

    def _flush_preview(self) -> None:
        from ._preview import preview_frame, preview_limits, units_label

        if not self._preview_buffer or self._video is None:
            return
        if self._limits is None:
            self._limits = preview_limits([o.depth_lr for o in self._preview_buffer])
        plan = self.job.plan
        units = plan.align.depth_units if plan.rig is not None else self.job.sequence.depth_units
        for output in self._preview_buffer:
            frame = preview_frame(output.rgb_hr, output.depth_lr, output.depth_hr, limits=self._limits,
                                  units=units_label(units), method=plan.method.name)
            size = self._video.size
            if size is not None and (frame.shape[1], frame.shape[0]) != size:  # a frame of another size
                import cv2

                frame = cv2.resize(frame, size, interpolation=cv2.INTER_AREA)
            self._video.write(frame)
        self._preview_buffer.clear()

    # ------------------------------------------------------------------ the record

    def write_record(self, *, complete: bool) -> None:
        """Rewrite ``batch.json`` (atomically), each frame's status checked against its files on disk."""
        from ..io import atomic_write

        outputs = self.job.outputs
        for key, row in self.rows.items():
            on_disk = all(p.is_file() for p in outputs[key].values())
            if on_disk and row["status"] == "pending" and (key in self._wrote or not self.options.overwrite):
                row["status"] = "done"  # written just before an interrupt reached the row
            elif not on_disk and row["status"] == "done":
                row["status"] = "pending"
        rows = list(self.rows.values())
        counts: dict[str, int] = {}
        for row in rows:
            counts[row["status"]] = counts.get(row["status"], 0) + 1
        body = dict(self.header, complete=complete, counts=counts, unpaired=self.unpaired, frames=rows)
        text = json.dumps(body, indent=1) + "\n"
        atomic_write(self.outdir / "batch.json", lambda tmp: tmp.write_text(text, encoding="utf-8"))
        self._last_record = time.perf_counter()


def _remove_leftovers(outputs: list[Path]) -> None:
    """Remove the temporary files a killed run left beside ``outputs`` (``.<stem>.XXXX<ext>``, see ``atomic_write``)."""
    by_folder: dict[Path, set[tuple[str, str]]] = {}
    for p in outputs:
        by_folder.setdefault(p.parent, set()).add((f".{p.stem}.", p.suffix))
    for folder, names in by_folder.items():
        if not folder.is_dir():
            continue
        for item in folder.iterdir():
            if item.name.startswith(".") and item.is_file():
                if any(item.name.startswith(prefix) and item.name.endswith(suffix) for prefix, suffix in names):
                    item.unlink()


def _read_record(outdir: Path) -> dict[str, dict]:
    try:
        old = json.loads((outdir / "batch.json").read_text(encoding="utf-8"))
        return {row["key"]: row for row in old.get("frames", [])}
    except (OSError, ValueError, KeyError, TypeError):
        return {}
