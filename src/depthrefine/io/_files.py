"""Safe output: refuse to overwrite, write whole or not at all (atomic rename)."""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from pathlib import Path
from typing import Callable, Iterator

__all__ = ["check_output", "atomic_write", "atomic_directory", "InputFileError"]


class InputFileError(ValueError):
    """A file a user gave cannot be used; the message names it and says what to do."""


def check_output(path: str | os.PathLike, *, overwrite: bool = False, what: str = "output") -> Path:
    """Check, before any work, that ``path`` can be written.

    Raises ``InputFileError`` if it exists and ``overwrite`` is false, if it is
    a directory, or if its folder does not exist or cannot be written.
    """
    p = Path(path)
    if p.is_dir():
        raise InputFileError(f"{what} {p} is a folder; give a file name.")
    if p.exists() and not overwrite:
        raise InputFileError(f"{what} {p} exists; pass --overwrite to replace it.")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise InputFileError(f"{what} {p}: folder {parent} does not exist; create it first.")
    if not os.access(parent, os.W_OK):
        raise InputFileError(f"{what} {p}: folder {parent} is not writable.")
    return p


def atomic_write(path: str | os.PathLike, write: Callable[[Path], None]) -> Path:
    """Call ``write(tmp)`` on a temporary file beside ``path``, then rename it over ``path``.

    The file appears whole or not at all; on any error the temporary file is
    removed and the error re-raised. The temporary name keeps the suffix so
    writers that pick a format by extension work.
    """
    p = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{p.stem}.", suffix=p.suffix or ".part",
                               dir=p.parent if str(p.parent) else ".")
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        write(tmp_path)
        os.chmod(tmp_path, 0o666 & ~_umask())
        os.replace(tmp_path, p)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp_path.unlink()
        raise
    return p


@contextlib.contextmanager
def atomic_directory(path: str | os.PathLike, *, overwrite: bool = False) -> Iterator[Path]:
    """Yield a temporary folder that becomes ``path`` when the block ends without error.

    An existing non-empty ``path`` is an error unless ``overwrite``; then its
    files are replaced by the new ones only at the end (files of the same
    name are overwritten, others kept).
    """
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise InputFileError(f"{p} exists and is not a folder; give a folder name.")
    if p.is_dir() and any(p.iterdir()) and not overwrite:
        raise InputFileError(f"folder {p} exists and is not empty; pass --overwrite to write into it.")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise InputFileError(f"folder {p}: its parent {parent} does not exist; create it first.")
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
