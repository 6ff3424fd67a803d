"""Point clouds as PLY files (binary little-endian; ASCII read too).

Written: one ``vertex`` element with ``float x, y, z`` (metres, the camera's
frame: X right, Y down, Z forward) and, with colors, ``uchar red, green,
blue``. MeshLab, CloudCompare and Open3D read it.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ._files import InputFileError, check_output, existing_input
from ._images import write_bytes

__all__ = ["write_ply", "encode_ply", "read_ply"]

_PLY_TYPES = {
    "char": "i1", "uchar": "u1", "short": "<i2", "ushort": "<u2", "int": "<i4", "uint": "<u4",
    "float": "<f4", "double": "<f8", "int8": "i1", "uint8": "u1", "int16": "<i2", "uint16": "<u2",
    "int32": "<i4", "uint32": "<u4", "float32": "<f4", "float64": "<f8",
}


def write_ply(
    path: str | os.PathLike,
    points: np.ndarray,
    colors: np.ndarray | None = None,
    *,
    overwrite: bool = False,
    comments: tuple[str, ...] = (),
) -> Path:
    """Write a (colored) point cloud as binary PLY, atomically.

    Parameters
    ----------
    path : str or path-like
        Output ``.ply`` file.
    points : (N, 3) ndarray
        Coordinates, metres (stored as float32).
    colors : (N, 3) uint8 ndarray, optional
        RGB per point.
    overwrite : bool
        Replace an existing file.
    comments : tuple of str
        ``comment`` lines for the header (one line each).

    Raises
    ------
    InputFileError
        Existing file without ``overwrite``, wrong suffix, bad shapes.
    """
    p = check_output(path, overwrite=overwrite, what="output", suffixes=(".ply",))
    return write_bytes(p, encode_ply(points, colors, comments=comments), overwrite=overwrite)


def encode_ply(points: np.ndarray, colors: np.ndarray | None = None, *, comments: tuple[str, ...] = ()) -> bytes:
    """The bytes of the binary PLY file :func:`write_ply` writes, in memory.

    Examples
    --------
    >>> encode_ply(np.zeros((1, 3)), comments=("one point",)).split(b"\\n")[:4]
    [b'ply', b'format binary_little_endian 1.0', b'comment one point', b'element vertex 1']
    """
    pts = np.asarray(points)
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise ValueError(f"points must have shape (N, 3); got {pts.shape}.")
    fields = [("x", "<f4"), ("y", "<f4"), ("z", "<f4")]
    if colors is not None:
        colors = np.asarray(colors)
        if colors.shape != pts.shape or colors.dtype != np.uint8:
            raise ValueError(f"colors must be uint8 of shape {pts.shape}; got {colors.dtype} {colors.shape}.")
        fields += [("red", "u1"), ("green", "u1"), ("blue", "u1")]
    vertices = np.empty(pts.shape[0], dtype=fields)
    for i, name in enumerate("xyz"):
        vertices[name] = pts[:, i]
    if colors is not None:
        for i, name in enumerate(("red", "green", "blue")):
            vertices[name] = colors[:, i]
    header = ["ply", "format binary_little_endian 1.0"]
    header += [f"comment {' '.join(str(c).split())}" for c in comments]
    header.append(f"element vertex {pts.shape[0]}")
    header += [f"property {'float' if t == '<f4' else 'uchar'} {n}" for n, t in fields]
    header.append("end_header")
    return ("\n".join(header) + "\n").encode("ascii") + vertices.tobytes()


def read_ply(path: str | os.PathLike) -> tuple[np.ndarray, np.ndarray | None]:
    """Read the vertices of a PLY file (binary little-endian or ASCII).

    Returns
    -------
    points : (N, 3) float32 ndarray
    colors : (N, 3) uint8 ndarray or None
        When the vertices have ``red``, ``green`` and ``blue``.
    """
    p = existing_input(path, "point cloud")
    raw = p.read_bytes()
    end = raw.find(b"end_header")
    if not raw.startswith(b"ply") or end < 0:
        raise InputFileError(f"point cloud file {p} is not a PLY file (no 'ply' ... 'end_header' header).")
    body_start = raw.index(b"\n", end) + 1
    lines = raw[:end].decode("ascii", errors="replace").splitlines()
    fmt, elements = None, []
    for line in lines[1:]:
        words = line.split()
        if not words or words[0] in ("comment", "obj_info"):
            continue
        if words[0] == "format":
            fmt = words[1]
        elif words[0] == "element":
            elements.append((words[1], int(words[2]), []))
        elif words[0] == "property":
            if words[1] == "list" or not elements or words[1] not in _PLY_TYPES:
                raise InputFileError(f"point cloud file {p}: unsupported property line {line!r}.")
            elements[-1][2].append((words[2], _PLY_TYPES[words[1]]))
    if fmt not in ("binary_little_endian", "ascii") or not elements or elements[0][0] != "vertex":
        raise InputFileError(
            f"point cloud file {p}: need a binary_little_endian or ascii PLY whose first element is vertex."
        )
    _, count, props = elements[0]
    dtype = np.dtype(props)
    if fmt == "ascii":
        table = np.loadtxt(raw[body_start:].decode("ascii").splitlines()[:count], ndmin=2)
        vertices = np.empty(count, dtype=dtype)
        for i, (name, _) in enumerate(props):
            vertices[name] = table[:, i]
    else:
        if len(raw) - body_start < count * dtype.itemsize:
            raise InputFileError(f"point cloud file {p} is truncated.")
        vertices = np.frombuffer(raw, dtype=dtype, count=count, offset=body_start)
    names = dtype.names or ()
    if not all(n in names for n in "xyz"):
        raise InputFileError(f"point cloud file {p}: the vertices lack x, y or z.")
    points = np.column_stack([vertices[n] for n in "xyz"]).astype(np.float32)
    colors = None
    if all(n in names for n in ("red", "green", "blue")):
        colors = np.column_stack([vertices[n] for n in ("red", "green", "blue")]).astype(np.uint8)
    return points, colors
