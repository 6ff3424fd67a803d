"""Reading the benchmark data sets into cases of :mod:`depthrefine.bench`.

A data folder holds dataset folders laid out as in ``shared/data`` (each has
a README saying how it is scored)::

    DATA/middlebury2005_park/<scene>/{color.png, gt_disp.png, noisy_x4.png, ...}
    DATA/middlebury_lu30/{RGB/Middlebury_NN_output_color.png, Depth/Middlebury_NN_output_depth.png}
    DATA/lu6/{RGB/RGBD_0N_ouput_color.png, Depth/RGBD_0N_output_depth.png}

A folder with only some of the scenes works too: whatever scenes are
present are read. A scene (or one scale of it) whose files are missing or
unusable is skipped with a note naming the file and the reason; only a
dataset folder with no usable scene at all is an error. ``DATA`` may also be
one dataset folder itself.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np

from ..bench.runner import PROTOCOLS, BenchCase, lu_case, park_case, tof_case
from ._files import InputFileError
from ._images import read_depth, read_rgb

__all__ = ["DATASET_FOLDERS", "DATASET_LAYOUTS", "dataset_folder", "read_park_scenes", "read_rgbd_pairs", "load_cases"]

#: The dataset folder each protocol reads.
DATASET_FOLDERS = {
    "park": "middlebury2005_park",
    "middlebury30": "middlebury_lu30",
    "lu": "lu6",
    "tof": "middlebury2005_park",
}

#: The expected file layout of each protocol's dataset folder (for error messages).
DATASET_LAYOUTS = {
    "park": "middlebury2005_park/<scene>/color.png, gt_disp.png (8-bit) and noisy_x<s>.png",
    "tof": "middlebury2005_park/<scene>/color.png and gt_disp.png (8-bit)",
    "middlebury30": "middlebury_lu30/RGB/<name>_output_color.png and middlebury_lu30/Depth/<name>_output_depth.png",
    "lu": "lu6/RGB/<name>_ouput_color.png (or _output_color.png) and lu6/Depth/<name>_output_depth.png",
}

_COLOR_RE = re.compile(r"^(?P<name>.+?)_(?:output|ouput)_color\.png$", re.IGNORECASE)


def dataset_folder(data_dir: str | os.PathLike, protocol: str) -> Path:
    """The folder of ``protocol``'s dataset inside ``data_dir`` (or ``data_dir`` itself).

    Raises
    ------
    ValueError
        Unknown protocol.
    InputFileError
        ``data_dir`` or the dataset folder is missing.
    """
    if protocol not in DATASET_FOLDERS:
        raise ValueError(f"unknown protocol {protocol!r}; choose one of {list(PROTOCOLS)}.")
    root = Path(data_dir)
    if not root.is_dir():
        raise InputFileError(f"data folder {root} does not exist or is not a folder; pass --data DIR.")
    name = DATASET_FOLDERS[protocol]
    if root.name == name:
        return root
    folder = root / name
    if not folder.is_dir():
        raise InputFileError(
            f"data folder {root} has no {name}/ folder, which the {protocol!r} protocol reads; "
            f"lay it out as shared/data: {root}/{DATASET_LAYOUTS[protocol]}."
        )
    return folder


def _note(notes: list[str] | None, text: str) -> None:
    if notes is not None:
        notes.append(text)


def _read_pair(color: Path, depth: Path) -> tuple[np.ndarray, np.ndarray]:
    rgb = read_rgb(color)
    gt = read_depth(depth)
    if gt.ndim != 2:
        raise InputFileError(f"{depth} must be a one-channel depth map; it has shape {gt.shape}.")
    if rgb.shape[:2] != gt.shape:
        raise InputFileError(
            f"{color.name} ({rgb.shape[1]}x{rgb.shape[0]}) and {depth.name} ({gt.shape[1]}x{gt.shape[0]}) "
            "must be on the same grid."
        )
    return rgb, gt


def read_park_scenes(folder: str | os.PathLike, *, notes: list[str] | None = None
                     ) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """``(scene, rgb_hr, depth_gt)`` of each scene folder holding ``color.png`` and ``gt_disp.png``.

    Scenes are sorted by name; ``depth_gt`` is as stored. A scene folder
    whose files are missing or unreadable is skipped, with a note appended
    to ``notes``.

    Raises
    ------
    InputFileError
        No usable scene at all.
    """
    folder = Path(folder)
    scenes = []
    for sub in sorted(p for p in folder.iterdir() if p.is_dir()):
        missing = [n for n in ("color.png", "gt_disp.png") if not (sub / n).is_file()]
        if missing:
            _note(notes, f"skipped scene {sub.name}: {sub} has no {' and no '.join(missing)}.")
            continue
        try:
            rgb, gt = _read_pair(sub / "color.png", sub / "gt_disp.png")
        except (InputFileError, ValueError, OSError) as exc:
            _note(notes, f"skipped scene {sub.name}: {exc}")
            continue
        scenes.append((sub.name, rgb, gt))
    if not scenes:
        raise InputFileError(
            f"{folder} holds no usable scene folder; expected {folder.name}/<scene>/color.png and gt_disp.png "
            "(as shared/data/middlebury2005_park)."
        )
    return scenes


def read_rgbd_pairs(folder: str | os.PathLike, *, notes: list[str] | None = None
                    ) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """``(name, rgb_hr, depth_gt)`` of each ``RGB/<name>_output_color.png`` with its ``Depth/<name>_output_depth.png``.

    The Lu set's color files are spelt ``_ouput_color``; both spellings are
    read. Pairs are sorted by name; ``depth_gt`` is as stored. A pair with a
    missing or unreadable file is skipped, with a note appended to ``notes``.

    Raises
    ------
    InputFileError
        No ``RGB/`` or ``Depth/`` folder, or no usable pair at all.
    """
    folder = Path(folder)
    rgb_dir, depth_dir = folder / "RGB", folder / "Depth"
    expected = (f"expected {folder.name}/RGB/<name>_output_color.png (or _ouput_color.png) and "
                f"{folder.name}/Depth/<name>_output_depth.png, as shared/data/middlebury_lu30 and lu6")
    if not rgb_dir.is_dir() or not depth_dir.is_dir():
        raise InputFileError(f"{folder} must hold RGB/ and Depth/ folders; {expected}.")
    pairs = []
    for color in sorted(rgb_dir.iterdir()):
        m = _COLOR_RE.match(color.name)
        if not m:
            continue
        name = m.group("name")
        depth = depth_dir / f"{name}_output_depth.png"
        if not depth.is_file():
            _note(notes, f"skipped {name}: {color} has no ground truth {depth}.")
            continue
        try:
            rgb, gt = _read_pair(color, depth)
        except (InputFileError, ValueError, OSError) as exc:
            _note(notes, f"skipped {name}: {exc}")
            continue
        pairs.append((name, rgb, gt))
    if not pairs:
        raise InputFileError(f"{folder} holds no usable color/depth pair; {expected}.")
    return pairs


def load_cases(data_dir: str | os.PathLike, protocol: str, scales: tuple[int, ...], *,
               notes: list[str] | None = None) -> list[BenchCase]:
    """Every case of ``protocol`` at ``scales`` found under ``data_dir``, scene by scene.

    Parameters
    ----------
    data_dir : path-like
        A folder laid out as ``shared/data`` (or one dataset folder).
    protocol : {"park", "middlebury30", "lu", "tof"}
    scales : tuple of int
    notes : list of str, optional
        Each scene or scale skipped (a missing or unusable file) appends
        one line here, naming the protocol, the scene, the scale and why.

    Returns
    -------
    list of BenchCase
        Ordered by scene, then scale.

    Raises
    ------
    InputFileError
        The dataset folder is missing, or no case at all is usable (the
        message names the expected layout and the first reason).
    """
    folder = dataset_folder(data_dir, protocol)
    mine: list[str] = []
    cases: list[BenchCase] = []
    if protocol in ("park", "tof"):
        scenes = read_park_scenes(folder, notes=mine)
    else:
        scenes = read_rgbd_pairs(folder, notes=mine)
    mine[:] = [f"{protocol}: {n}" for n in mine]
    for scene, rgb, gt in scenes:
        for s in scales:
            try:
                if protocol == "tof":
                    case = tof_case(scene, s, rgb, gt)
                elif protocol == "park":
                    noisy = folder / scene / f"noisy_x{s}.png"
                    if not noisy.is_file():
                        mine.append(f"park: skipped {scene} x{s}: {noisy} is missing (the park protocol needs "
                                    "the given noisy input).")
                        continue
                    case = park_case(scene, s, read_depth(noisy), rgb, gt)
                else:
                    case = lu_case(protocol, scene, s, rgb, gt)
            except (InputFileError, ValueError, OSError) as exc:
                mine.append(f"{protocol}: skipped {scene} x{s}: {exc}")
                continue
            cases.append(case)
    if not cases:
        first = f" First problem: {mine[0]}" if mine else ""
        raise InputFileError(
            f"{folder}: no usable case for the {protocol!r} protocol at x{','.join(map(str, scales))}; "
            f"expected {DATASET_LAYOUTS[protocol]}.{first}"
        )
    if notes is not None:
        notes.extend(mine)
    return cases
