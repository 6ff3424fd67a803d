"""Writing a video (a batch's preview) with PyAV, the Python binding of FFmpeg's libraries.

PyAV (``av``) is imported when the first frame is written. The file appears
whole or not at all: frames go to a temporary file beside it, renamed when
the writer is closed without an error.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

from ._files import InputFileError, check_output

__all__ = ["VIDEO_SUFFIXES", "VideoWriter"]

#: Video containers the writer knows, and the codec of each (the first one FFmpeg has).
_CODECS = {".mp4": ("libx264", "h264", "mpeg4"), ".mkv": ("libx264", "h264", "mpeg4"),
           ".mov": ("libx264", "h264", "mpeg4"), ".avi": ("mpeg4",), ".webm": ("libvpx-vp9",)}
VIDEO_SUFFIXES = tuple(_CODECS)


class VideoWriter:
    """RGB uint8 frames of one size into a video file at ``fps`` frames per second.

    Use as a context manager (or call :meth:`close` / :meth:`abort`)::

        with VideoWriter("preview.mp4", fps=30) as video:
            for frame in frames:
                video.write(frame)

    Raises
    ------
    InputFileError
        (at construction) An existing file without ``overwrite``, an unknown
        container (:data:`VIDEO_SUFFIXES`), a missing folder.
    """

    def __init__(self, path: str | os.PathLike, *, fps: float, overwrite: bool = False, what: str = "video"):
        self.path = check_output(path, overwrite=overwrite, what=what, suffixes=VIDEO_SUFFIXES)
        if not (isinstance(fps, (int, float)) and np.isfinite(fps) and fps > 0):
            raise ValueError(f"the frame rate must be a positive number; got {fps!r}.")
        self.fps = float(fps)
        self.overwrite = overwrite
        self.frames = 0
        self._tmp: Path | None = None
        self._container: Any = None
        self._stream: Any = None

    @property
    def size(self) -> tuple[int, int] | None:
        """(width, height) of the frames, once the first was written."""
        return None if self._stream is None else (self._stream.width, self._stream.height)

    def write(self, rgb: np.ndarray) -> None:
        """Append one frame: (rows, cols, 3) uint8 RGB, even sizes, the size of the first frame."""
        rgb = np.ascontiguousarray(rgb)
        if rgb.dtype != np.uint8 or rgb.ndim != 3 or rgb.shape[2] != 3 or rgb.shape[0] % 2 or rgb.shape[1] % 2:
            raise ValueError(f"a video frame is (rows, cols, 3) uint8 with even sizes; got {rgb.dtype} {rgb.shape}.")
        if self._stream is None:
            self._open(rgb.shape[1], rgb.shape[0])
        elif (self._stream.height, self._stream.width) != rgb.shape[:2]:
            raise ValueError(f"video frame {self.frames} is {rgb.shape[1]}x{rgb.shape[0]}; the video is "
                             f"{self._stream.width}x{self._stream.height}.")
        import av

        frame = av.VideoFrame.from_ndarray(rgb, format="rgb24")
        for packet in self._stream.encode(frame):
            self._container.mux(packet)
        self.frames += 1

    def close(self) -> Path | None:
        """Finish the file and give it its name (``None`` if no frame was written: then no file)."""
        if self._container is None:
            return None
        try:
            for packet in self._stream.encode():
                self._container.mux(packet)
            self._container.close()
            self._container = None
            if self.overwrite:
                os.replace(self._tmp, self.path)
            elif self.path.exists():
                raise InputFileError(f"video {self.path} exists; pass --overwrite to replace it.")
            else:
                os.replace(self._tmp, self.path)
        finally:
            self.abort()
        return self.path

    def abort(self) -> None:
        """Drop the frames written so far (no file)."""
        if self._container is not None:
            with contextlib.suppress(Exception):
                self._container.close()
            self._container = None
        if self._tmp is not None:
            with contextlib.suppress(OSError):
                self._tmp.unlink()
            self._tmp = None

    def __enter__(self) -> VideoWriter:
        return self

    def __exit__(self, kind, value, traceback) -> None:
        if kind is None:
            self.close()
        else:
            self.abort()

    def _open(self, width: int, height: int) -> None:
        try:
            import av
        except ImportError:  # pragma: no cover - a dependency
            raise InputFileError("writing a video needs PyAV: pip install av") from None
        suffix = self.path.suffix.lower()
        codec = next((c for c in _CODECS[suffix] if c in av.codecs_available), None)
        if codec is None:
            raise InputFileError(f"video {self.path}: this FFmpeg build has no encoder for {suffix} "
                                 f"({', '.join(_CODECS[suffix])}); choose .mp4 or .avi.")
        fd, tmp = tempfile.mkstemp(prefix=f".{self.path.stem}.", suffix=suffix, dir=self.path.parent)
        os.close(fd)
        self._tmp = Path(tmp)
        self._container = av.open(str(self._tmp), mode="w")
        rate = Fraction(self.fps).limit_denominator(1001)
        stream = self._container.add_stream(codec, rate=rate)
        stream.width, stream.height = width, height
        stream.pix_fmt = "yuv420p"
        if codec == "libx264":
            stream.options = {"crf": "20", "preset": "veryfast"}
        stream.thread_count = 1  # the preview must not take cores from the workers
        self._stream = stream
