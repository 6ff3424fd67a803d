"""Reading the benchmark data sets into cases of :mod:`depthrefine.bench`.

A data folder holds dataset folders laid out as in ``shared/data`` (each has
a README saying how it is scored)::

    DATA/middlebury2005_park/<scene>/{color.png, gt_disp.png, noisy_x4.png, ...}
    DATA/middlebury_lu30/{RGB/Middlebury_NN_output_color.png, Depth/Middlebury_NN_output_depth.png}
    DATA/lu6/{RGB/RGBD_0N_ouput_color.png, Depth/RGBD_0N_output_depth.png}

A folder with only some of the scenes works too: whatever scenes are
present are read. ``DATA`` may also be one dataset folder itself.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np

from ..bench import PROTOCOLS, BenchCase, lu_case, park_case, tof_case
from ._files import InputFileError
from ._images import read_depth, read_rgb

__all__ = ["DATASET_FOLDERS", "dataset_folder", "read_park_scenes", "read_rgbd_pairs", "load_cases"]

#: The dataset folder each protocol reads.
DATASET_FOLDERS = {
    "park": "middlebury2005_park",
    "middlebury30": "middlebury_lu30",
    "lu": "lu6",
    "tof": "middlebury2005_park",
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
            "lay it out as shared/data (see its README)."
        )
    return folder


def read_park_scenes(folder: str | os.PathLike) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """``(scene, rgb_hr, depth_gt)`` of each scene folder holding ``color.png`` and ``gt_disp.png``.

    Scenes are sorted by name; ``depth_gt`` is uint8 as stored.
    """
    folder = Path(folder)
    scenes = []
    for sub in sorted(p for p in folder.iterdir() if p.is_dir()):
        if (sub / "color.png").is_file() and (sub / "gt_disp.png").is_file():
            rgb = read_rgb(sub / "color.png")
            gt = read_depth(sub / "gt_disp.png")
            if rgb.shape[:2] != gt.shape:
                raise InputFileError(
                    f"{sub}: color.png {rgb.shape[1]}x{rgb.shape[0]} and gt_disp.png {gt.shape[1]}x{gt.shape[0]} "
                    "must be on the same grid."
                )
            scenes.append((sub.name, rgb, gt))
    if not scenes:
        raise InputFileError(f"{folder} holds no scene folder with color.png and gt_disp.png.")
    return scenes


def read_rgbd_pairs(folder: str | os.PathLike) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """``(name, rgb_hr, depth_gt)`` of each ``RGB/<name>_output_color.png`` with its ``Depth/<name>_output_depth.png``.

    The Lu set's color files are spelt ``_ouput_color``; both spellings are
    read. Pairs are sorted by name; ``depth_gt`` is uint8 as stored.
    """
    folder = Path(folder)
    rgb_dir, depth_dir = folder / "RGB", folder / "Depth"
    if not rgb_dir.is_dir() or not depth_dir.is_dir():
        raise InputFileError(f"{folder} must hold RGB/ and Depth/ folders (as shared/data/{folder.name}).")
    pairs = []
    for color in sorted(rgb_dir.iterdir()):
        m = _COLOR_RE.match(color.name)
        if not m:
            continue
        name = m.group("name")
        depth = depth_dir / f"{name}_output_depth.png"
        if not depth.is_file():
            raise InputFileError(f"{color} has no ground truth {depth}; add it or remove the color file.")
        rgb = read_rgb(color)
        gt = read_depth(depth)
        if rgb.shape[:2] != gt.shape:
            raise InputFileError(
                f"{color} ({rgb.shape[1]}x{rgb.shape[0]}) and {depth} ({gt.shape[1]}x{gt.shape[0]}) "
                "must have the same size."
            )
        pairs.append((name, rgb, gt))
    if not pairs:
        raise InputFileError(f"{rgb_dir} holds no *_output_color.png file.")
    return pairs


def load_cases(data_dir: str | os.PathLike, protocol: str, scales: tuple[int, ...]) -> list[BenchCase]:
    """Every case of ``protocol`` at ``scales`` found under ``data_dir``, scene by scene.

    Parameters
    ----------
    data_dir : path-like
        A folder laid out as ``shared/data`` (or one dataset folder).
    protocol : {"park", "middlebury30", "lu", "tof"}
    scales : tuple of int

    Returns
    -------
    list of BenchCase
        Ordered by scene, then scale.

    Raises
    ------
    InputFileError
        Missing folders or files (e.g. a Park scene without ``noisy_x16.png``).
    """
    folder = dataset_folder(data_dir, protocol)
    cases: list[BenchCase] = []
    if protocol in ("park", "tof"):
        for scene, rgb, gt in read_park_scenes(folder):
            for s in scales:
                if protocol == "tof":
                    cases.append(tof_case(scene, s, rgb, gt))
                    continue
                noisy = folder / scene / f"noisy_x{s}.png"
                if not noisy.is_file():
                    raise InputFileError(
                        f"{noisy} is missing: the park protocol at x{s} needs the given noisy input; "
                        "drop that scale (--scales) or add the file."
                    )
                cases.append(park_case(scene, s, read_depth(noisy), rgb, gt))
    else:
        for name, rgb, gt in read_rgbd_pairs(folder):
            for s in scales:
                cases.append(lu_case(protocol, name, s, rgb, gt))
    return cases
