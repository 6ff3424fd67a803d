"""Checking a data folder against :data:`~depthrefine.io._catalog.DATASETS`, and downloading a data set.

:func:`verify_data` compares a folder laid out as ``shared/data`` (or one
data set's own folder) with the expected files and SHA-256 of each data set
in it. :func:`fetch_dataset` downloads a data set whose licence allows it
from its original repository (``{base}/{repo}/{commit}/{path}``, the base
being ``https://raw.githubusercontent.com`` unless given, e.g. a mirror or
a test server), derives the files that are computed from downloaded ones
(the Azure Kinect recording's frames, with PyAV), checks every SHA-256 and
only then moves the finished folder into place: a failed fetch leaves
nothing behind.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import urllib.request
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from ._catalog import DATASETS, DOCUMENTATION_FILES, RAW_BASE_URL, Dataset, get_dataset
from ._files import InputFileError, atomic_directory, check_output_dir

__all__ = ["DataProblem", "file_sha256", "find_datasets", "verify_dataset", "verify_data", "fetch_dataset",
           "DATA_URL_ENV"]

#: The environment variable that replaces :data:`RAW_BASE_URL` (a mirror; the tests' loopback server).
DATA_URL_ENV = "DEPTHREFINE_DATA_URL"
_CHUNK = 1 << 20


@dataclass(frozen=True)
class DataProblem:
    """One file that does not match: ``kind`` is ``"missing"``, ``"extra"`` or ``"mismatch"``."""

    kind: str
    path: str
    detail: str = ""

    def __str__(self) -> str:
        return f"{self.kind:<8} {self.path}" + (f" ({self.detail})" if self.detail else "")


def file_sha256(path: str | os.PathLike) -> str:
    """SHA-256 of a file, hex (read in 1 MiB pieces)."""
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(_CHUNK), b""):
            digest.update(block)
    return digest.hexdigest()


def find_datasets(root: str | os.PathLike) -> list[tuple[Dataset, Path]]:
    """The data sets present in ``root``: a data root laid out as ``shared/data``, or one data set's folder."""
    root = Path(root)
    if not root.is_dir():
        raise InputFileError(f"data folder {root} does not exist or is not a folder.")
    if root.name in DATASETS and not any((root / d.folder).is_dir() for d in DATASETS.values()):
        return [(DATASETS[root.name], root)]
    return [(d, root / d.folder) for d in DATASETS.values() if (root / d.folder).is_dir()]


def verify_dataset(dataset: Dataset, folder: str | os.PathLike, *, prefix: str = "") -> list[DataProblem]:
    """Every missing, extra or changed file of ``folder`` against ``dataset``'s checksums, sorted by path.

    Paths in the problems are ``prefix`` + the path inside the data set.
    ``README.md`` and ``SHA256SUMS`` files are documentation and not checked.
    """
    folder = Path(folder)
    expected = dataset.checksums
    present = sorted(str(p.relative_to(folder)).replace(os.sep, "/") for p in folder.rglob("*")
                     if p.is_file() and p.name not in DOCUMENTATION_FILES)
    problems = [DataProblem("missing", prefix + path) for path in sorted(set(expected) - set(present))]
    problems += [DataProblem("extra", prefix + path, "not a file of the data set")
                 for path in present if path not in expected]
    for path in present:
        if path in expected:
            digest = file_sha256(folder / path)
            if digest != expected[path]:
                problems.append(DataProblem("mismatch", prefix + path,
                                            f"SHA-256 {digest[:12]}..., expected {expected[path][:12]}..."))
    return sorted(problems, key=lambda p: (p.path, p.kind))


def verify_data(root: str | os.PathLike, names: tuple[str, ...] = ()) -> tuple[list[Dataset], list[DataProblem]]:
    """Check the data sets in ``root`` (all those present, or ``names``, which must be present).

    Returns
    -------
    (datasets checked, problems)

    Raises
    ------
    InputFileError
        ``root`` holds no known data set, or one of ``names`` is not in it.
    """
    found = find_datasets(root)
    if names:
        wanted = [get_dataset(n) for n in names]
        by_name = {d.name: f for d, f in found}
        missing = [d for d in wanted if d.name not in by_name]
        if missing:
            raise InputFileError(f"{root} has no {', '.join(d.folder + '/' for d in missing)}; "
                                 "fetch it or check the folder.")
        found = [(d, by_name[d.name]) for d in wanted]
    if not found:
        folders = ", ".join(d.folder for d in DATASETS.values())
        raise InputFileError(f"{root} holds none of the data set folders ({folders}); give a folder laid out as "
                             "shared/data, or one data set's folder.")
    problems = []
    single = len(found) == 1 and Path(root).resolve() == found[0][1].resolve()
    for dataset, folder in found:
        problems += verify_dataset(dataset, folder, prefix="" if single else dataset.folder + "/")
    return [d for d, _ in found], problems


def _download(url: str, target: Path, expected: str, *, timeout: float = 60.0) -> None:
    """``url`` into ``target``, checking its SHA-256 against ``expected`` (``ValueError`` on a mismatch)."""
    target.parent.mkdir(parents=True, exist_ok=True)
    digest = hashlib.sha256()
    request = urllib.request.Request(url, headers={"User-Agent": "depthrefine-data-fetch"})
    try:
        with urllib.request.urlopen(request, timeout=timeout) as response, open(target, "wb") as out:
            for block in iter(lambda: response.read(_CHUNK), b""):
                digest.update(block)
                out.write(block)
    except OSError as exc:  # URLError, HTTPError, timeouts
        why = f"HTTP {exc.code} {exc.reason}" if hasattr(exc, "code") else getattr(exc, "reason", exc)
        raise OSError(f"could not download {url}: {why}; nothing was written.") from None
    if digest.hexdigest() != expected:
        raise ValueError(f"{url} has SHA-256 {digest.hexdigest()[:12]}..., expected {expected[:12]}... (changed "
                         "upstream, or a wrong mirror); nothing was written.")


def _derive_k4a(folder: Path) -> None:
    """``derived/`` of the Azure Kinect mug: the first COLOR, DEPTH and IR packets of ``recording.mkv``.

    As the data set's README says: the color packet unchanged (MJPG), the
    depth and IR packets read as big-endian uint16 (576 x 640) and written
    as 16-bit PNG by Pillow.
    """
    import io

    import numpy as np
    from PIL import Image

    try:
        import av
    except ImportError:
        raise ValueError("deriving the Azure Kinect frames from recording.mkv needs PyAV, a dependency of "
                         "depthrefine: pip install av.") from None
    packets: dict[str, bytes] = {}
    with av.open(str(folder / "recording.mkv")) as container:
        titles = {s.index: s.metadata.get("title", "") for s in container.streams}
        for packet in container.demux():
            title = titles.get(packet.stream.index, "")
            if packet.size and title in ("COLOR", "DEPTH", "IR") and title not in packets:
                packets[title] = bytes(packet)
    if set(packets) != {"COLOR", "DEPTH", "IR"}:
        raise ValueError(f"{folder / 'recording.mkv'} lacks a {', '.join({'COLOR', 'DEPTH', 'IR'} - set(packets))} "
                         "frame.")
    (folder / "derived").mkdir(exist_ok=True)
    (folder / "derived" / "color_1280x720.jpg").write_bytes(packets["COLOR"])
    for title, name in (("DEPTH", "depth_640x576_mm.png"), ("IR", "ir_640x576.png")):
        frame = np.frombuffer(packets[title], ">u2").reshape(576, 640).astype(np.uint16)
        buffer = io.BytesIO()
        Image.fromarray(frame).save(buffer, format="PNG")
        (folder / "derived" / name).write_bytes(buffer.getvalue())


#: How the derived files of a data set are made from its downloaded ones.
_DERIVERS: dict[str, Callable[[Path], None]] = {"azure_kinect_mug": _derive_k4a}


def fetch_dataset(name: str, to: str | os.PathLike, *, base_url: str | None = None, overwrite: bool = False,
                  progress: Callable[[str], None] | None = None) -> Path:
    """Download data set ``name`` into ``to/<its folder>``, checking every file's SHA-256; return the folder.

    Parameters
    ----------
    name : str
        A key of :data:`DATASETS` whose licence allows a download.
    to : path-like
        The data root (created if missing); the data set lands in
        ``to / dataset.folder`` (e.g. ``to/real_tof/azure_kinect_mug``).
    base_url : str, optional
        Replaces :data:`RAW_BASE_URL` (default: ``$DEPTHREFINE_DATA_URL``, else it).
    overwrite : bool
        Replace the files of an existing non-empty folder.
    progress : callable, optional
        Called with each URL before it is downloaded.

    Raises
    ------
    ValueError
        The data set may not be fetched (the message says why and where to
        get it), or a downloaded file does not match its checksum.
    OSError
        A download failed.
    """
    dataset = get_dataset(name)
    if dataset.fetch_refused:
        each = (f" (`depthrefine data list {dataset.name} --sources` gives each file's source)"
                if dataset.sourced else "")
        raise ValueError(f"{dataset.name} is not downloaded: {dataset.fetch_refused}. Get it from "
                         f"{dataset.original} under its terms, lay it out as {dataset.folder}/{each} and check it "
                         "with `depthrefine data verify DIR`.")
    base = (base_url or os.environ.get(DATA_URL_ENV) or RAW_BASE_URL).rstrip("/")
    root = Path(to)
    target = root / dataset.folder
    if target.exists():
        check_output_dir(target, overwrite=overwrite, what="data set folder")
    if root.exists() and not root.is_dir():
        raise InputFileError(f"--to {root} is a file; give a folder (the data root).")
    expected = dataset.checksums
    parts = Path(dataset.folder).parts
    chain = [root] + [root.joinpath(*parts[:i]) for i in range(1, len(parts))]
    made = [folder for folder in chain if not folder.exists()]  # created here: removed again on failure
    target.parent.mkdir(parents=True, exist_ok=True)
    try:
        with atomic_directory(target, overwrite=overwrite) as tmp:
            for local, url in dataset.file_urls(base).items():
                if progress is not None:
                    progress(url)
                _download(url, tmp / local, expected[local])
            if dataset.derived:
                _DERIVERS[dataset.name](tmp)
            problems = verify_dataset(dataset, tmp)
            if problems:
                raise ValueError(f"{dataset.name}: {len(problems)} file(s) do not match after the download: "
                                 + "; ".join(str(p) for p in problems[:5]) + "; nothing was written.")
    except BaseException:
        for folder in reversed(made):  # the parents this call created, if still empty
            if folder.is_dir() and not any(folder.iterdir()):
                shutil.rmtree(folder, ignore_errors=True)
        raise
    return target
