"""Safe output: refuse to overwrite, write whole or not at all (atomic rename)."""

from __future__ import annotations

import contextlib
import filecmp
import os
import shutil
import tempfile
from pathlib import Path
from typing import Callable, Iterator

__all__ = ["check_output", "check_output_dir", "check_distinct_inputs", "atomic_write", "atomic_directory",
           "existing_input", "InputFileError"]


class InputFileError(ValueError):
    """A file a user gave cannot be used; the message names it and says what to do."""


def existing_input(path: str | os.PathLike, what: str) -> Path:
    """``path`` as a ``Path`` once it is a readable, non-empty file; else :class:`InputFileError` naming ``what``."""
    p = Path(path)
    if not p.exists():
        raise InputFileError(f"{what} file {p} does not exist; check the path.")
    if p.is_dir():
        raise InputFileError(f"{what} file {p} is a folder; give an image file.")
    if not os.access(p, os.R_OK):
        raise InputFileError(f"{what} file {p} is not readable; check its permissions.")
    if p.stat().st_size == 0:
        raise InputFileError(f"{what} file {p} is empty (0 bytes); save it again.")
    return p


def check_output(
    path: str | os.PathLike,
    *,
    overwrite: bool = False,
    what: str = "output",
    suffixes: tuple[str, ...] | None = None,
    inputs: tuple[str | os.PathLike, ...] = (),
) -> Path:
    """Check, before any work, that ``path`` can be written.

    Parameters
    ----------
    path : str or path-like
        The output file.
    overwrite : bool
        Whether an existing file may be replaced.
    what : str
        What the file is, for the message (``"output"``).
    suffixes : tuple of str, optional
        Extensions the writer understands (lower case, with the dot).
    inputs : tuple of path-like
        Files the command reads: the output may never be one of them.

    Raises
    ------
    InputFileError
        If it exists and ``overwrite`` is false, if it is a folder or one of
        ``inputs``, if its extension is not in ``suffixes``, or if its folder
        does not exist or cannot be written.
    """
    p = Path(path)
    if p.is_dir():
        raise InputFileError(f"{what} {p} is a folder; give a file name.")
    for source in inputs:
        if source is not None and _same_file(p, Path(source)):
            raise InputFileError(f"{what} {p} is also an input file; choose another output name.")
    if suffixes is not None and p.suffix.lower() not in suffixes:
        raise InputFileError(
            f"{what} {p}: unknown format {p.suffix or '(no extension)'!r}; use one of {', '.join(suffixes)}."
        )
    if p.exists() and not overwrite:
        raise InputFileError(f"{what} {p} exists; pass --overwrite to replace it.")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise InputFileError(f"{what} {p}: folder {parent} does not exist; create it first.")
    if not os.access(parent, os.W_OK):
        raise InputFileError(f"{what} {p}: folder {parent} is not writable; choose another folder.")
    return p


def check_output_dir(path: str | os.PathLike, *, overwrite: bool = False, what: str = "folder") -> Path:
    """Check, before any work, that :func:`atomic_directory` will accept ``path``.

    Raises
    ------
    InputFileError
        ``path`` is a file, a non-empty folder (without ``overwrite``), or its
        parent folder is missing or not writable.
    """
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise InputFileError(f"{what} {p} exists and is not a folder; give a folder name.")
    if p.is_dir() and any(p.iterdir()) and not overwrite:
        raise InputFileError(f"{what} {p} exists and is not empty; pass --overwrite to write into it.")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise InputFileError(f"{what} {p}: its parent {parent} does not exist; create it first.")
    if not os.access(parent, os.W_OK) or (p.is_dir() and not os.access(p, os.W_OK)):
        raise InputFileError(f"{what} {p}: not writable; choose another folder.")
    return p


def check_distinct_inputs(depth: str | os.PathLike, color: str | os.PathLike) -> None:
    """Refuse the same file (path, link or identical bytes) given as both the depth map and the color image.

    Raises
    ------
    InputFileError
        ``depth`` and ``color`` are one file, or two files with the same bytes.
    """
    a, b = Path(depth), Path(color)
    if _same_file(a, b) or (a.resolve() == b.resolve()):
        raise InputFileError(f"DEPTH and COLOR are the same file ({a}); give the depth map first, then the "
                             "color image.")
    try:
        same = a.is_file() and b.is_file() and filecmp.cmp(a, b, shallow=False)
    except OSError:
        return  # unreadable: the reader says so, naming the file
    if same:
        raise InputFileError(f"DEPTH {a} and COLOR {b} have identical bytes: one image was given twice; give the "
                             "depth map first, then the color image.")


def _same_file(a: Path, b: Path) -> bool:
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def atomic_write(path: str | os.PathLike, write: Callable[[Path], None], *, overwrite: bool = True) -> Path:
    """Call ``write(tmp)`` on a temporary file beside ``path``, then rename it over ``path``.

    The file appears whole or not at all; on any error the temporary file is
    removed and the error re-raised. The temporary name keeps the suffix so
    writers that pick a format by extension work. With ``overwrite=False`` the
    final step is a hard link, which fails if ``path`` appeared meanwhile
    (another program wrote it after :func:`check_output`).

    Raises
    ------
    InputFileError
        ``overwrite`` is false and ``path`` exists.
    """
    p = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{p.stem}.", suffix=p.suffix or ".part",
                               dir=p.parent if str(p.parent) else ".")
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        write(tmp_path)
        os.chmod(tmp_path, 0o666 & ~_umask())
        if overwrite:
            os.replace(tmp_path, p)
        else:
            try:
                os.link(tmp_path, p)
            except FileExistsError:
                raise InputFileError(f"output {p} exists; pass --overwrite to replace it.") from None
            except OSError:  # no hard links on this file system
                if p.exists():
                    raise InputFileError(f"output {p} exists; pass --overwrite to replace it.") from None
                os.replace(tmp_path, p)
    finally:
        with contextlib.suppress(OSError):
            tmp_path.unlink()
    return p


@contextlib.contextmanager
def atomic_directory(path: str | os.PathLike, *, overwrite: bool = False) -> Iterator[Path]:
    """Yield a temporary folder that becomes ``path`` when the block ends without error.

    An existing non-empty ``path`` is an error unless ``overwrite``; then its
    files are replaced by the new ones only at the end (files of the same
    name are overwritten, others kept).
    """
    p = check_output_dir(path, overwrite=overwrite)
    parent = p.parent if str(p.parent) else Path(".")
    tmp = Path(tempfile.mkdtemp(prefix=f".{p.name}.", dir=parent))
    try:
        yield tmp
        os.chmod(tmp, 0o777 & ~_umask())
        if not p.exists():
            os.replace(tmp, p)
        else:
            for item in sorted(tmp.iterdir()):
                os.replace(item, p / item.name)
            tmp.rmdir()
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
