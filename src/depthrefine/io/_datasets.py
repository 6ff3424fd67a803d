"""Reading the benchmark data sets: the readers the protocols of :mod:`depthrefine.bench.protocols` name.

A data folder holds dataset folders laid out as in ``shared/data`` (each has
a README saying how it is scored)::

    DATA/middlebury2005_park/<scene>/{color.png, gt_disp.png, noisy_x4.png, ...}
    DATA/middlebury_lu30/{RGB/Middlebury_NN_output_color.png, Depth/Middlebury_NN_output_depth.png}
    DATA/lu6/{RGB/RGBD_0N_ouput_color.png, Depth/RGBD_0N_output_depth.png}
    DATA/real_tof/{iphone_lidar_bookshelf/{arkit_depth.png, image.jpg},
                   azure_kinect_mug/derived/{depth_640x576_mm.png, ir_640x576.png}}

A folder with only some of the scenes works too: whatever scenes are
present are read. A scene (or one scale of it) whose files are missing or
unusable is skipped with a note naming the file and the reason; only a
dataset folder with no usable scene at all is an error. ``DATA`` may also be
one dataset folder itself.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from ._files import InputFileError
from ._images import read_depth, read_rgb

__all__ = ["DatasetScene", "DATASET_READERS", "dataset_folder", "read_dataset", "read_scene_folders",
           "read_rgbd_pairs", "read_triplets", "TRIPLET_FOLDERS", "read_real_tof", "REAL_TOF_CAPTURES"]

_COLOR_RE = re.compile(r"^(?P<name>.+?)_(?:output|ouput)_color\.png$", re.IGNORECASE)


@dataclass(frozen=True, eq=False)
class DatasetScene:
    """One scene of a dataset as stored: guide, ground truth and any given low-resolution inputs.

    ``inputs`` maps a scale to the given input at that scale (the Park set's
    ``noisy_x<s>.png``); ``source`` is the scene's folder or color file.
    """

    name: str
    rgb_hr: np.ndarray
    depth_gt: np.ndarray
    inputs: dict[int, np.ndarray] = field(default_factory=dict)
    source: Path = Path(".")


def dataset_folder(data_dir: str | os.PathLike, name: str, *, protocol: str = "", layout: str = "") -> Path:
    """The dataset folder ``name`` inside ``data_dir`` (or ``data_dir`` itself, if that is it).

    Raises
    ------
    InputFileError
        ``data_dir`` or the dataset folder is missing (the message names the
        protocol that reads it and the layout it expects).
    """
    root = Path(data_dir)
    if not root.is_dir():
        raise InputFileError(f"data folder {root} does not exist or is not a folder; pass --data DIR.")
    if root.name == name:
        return root
    folder = root / name
    if not folder.is_dir():
        who = f", which the {protocol!r} protocol reads" if protocol else ""
        raise InputFileError(
            f"data folder {root} has no {name}/ folder{who}; lay it out as shared/data: {root}/{layout or name}."
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


def read_scene_folders(folder: str | os.PathLike, *, scales: tuple[int, ...] = (),
                       notes: list[str] | None = None) -> list[DatasetScene]:
    """Each scene folder holding ``color.png`` and ``gt_disp.png`` (and ``noisy_x<s>.png`` inputs).

    Scenes are sorted by name; ``depth_gt`` is as stored; ``inputs`` holds the
    ``noisy_x<s>.png`` of each of ``scales`` that exists. A scene folder
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
        inputs = {}
        for s in scales:
            noisy = sub / f"noisy_x{s}.png"
            if noisy.is_file():
                try:
                    inputs[s] = read_depth(noisy)
                except (InputFileError, ValueError, OSError) as exc:
                    _note(notes, f"skipped {sub.name} x{s}: {exc}")
        scenes.append(DatasetScene(sub.name, rgb, gt, inputs, sub))
    if not scenes:
        raise InputFileError(
            f"{folder} holds no usable scene folder; expected {folder.name}/<scene>/color.png and gt_disp.png "
            "(as shared/data/middlebury2005_park)."
        )
    return scenes


def read_rgbd_pairs(folder: str | os.PathLike, *, scales: tuple[int, ...] = (),
                    notes: list[str] | None = None) -> list[DatasetScene]:
    """Each ``RGB/<name>_output_color.png`` with its ``Depth/<name>_output_depth.png`` (``scales`` unused).

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
        pairs.append(DatasetScene(name, rgb, gt, {}, color))
    if not pairs:
        raise InputFileError(f"{folder} holds no usable color/depth pair; {expected}.")
    return pairs


#: The sub-folders of a folder of triplets (``bench --pairs DIR``): color, low-resolution input, ground truth.
TRIPLET_FOLDERS = ("color", "input", "gt")
_COLOR_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff")


def _by_stem(folder: Path, suffixes: tuple[str, ...], notes: list[str] | None) -> dict[str, Path]:
    """``{stem: file}`` of the files in ``folder`` with one of ``suffixes`` (a stem given twice is noted, skipped)."""
    files: dict[str, list[Path]] = {}
    for f in sorted(folder.iterdir()):
        if f.is_file() and f.suffix.lower() in suffixes and not f.name.startswith("."):
            files.setdefault(f.stem, []).append(f)
    for stem, found in files.items():
        if len(found) > 1:
            _note(notes, f"skipped {stem}: {folder} holds {', '.join(p.name for p in found)}; keep one file per stem.")
    return {stem: found[0] for stem, found in files.items() if len(found) == 1}


def _as_invalid(depth: np.ndarray, invalid: float) -> np.ndarray:
    """``depth`` with the value ``invalid`` replaced by 0 (the library's "no measurement" in a stored map)."""
    if invalid == 0:
        return depth
    return np.where(depth == invalid, depth.dtype.type(0), depth)


def read_triplets(folder: str | os.PathLike, *, scales: tuple[int, ...] = (), invalid: float = 0.0,
                  notes: list[str] | None = None) -> list[DatasetScene]:
    """The triplets of ``folder/color/``, ``folder/input/`` and ``folder/gt/`` that share a file stem.

    ``input/<stem>.*`` is the low-resolution depth, ``gt/<stem>.*`` the ground
    truth on the grid of ``color/<stem>.*`` (depth: PNG 8/16-bit, TIFF,
    ``.npy``; color: PNG, JPEG, BMP, TIFF). Pixels equal to ``invalid`` (and
    0, NaN) mean "no measurement" in both depth maps. Each scene's ``inputs``
    holds its input under its scale factor, the rounded ratio of the grids
    (``scales`` is not used: the files say it). Triplets are sorted by stem;
    a stem missing from a folder, or an unreadable triplet, is skipped with
    a note.

    Raises
    ------
    InputFileError
        A sub-folder is missing, or no usable triplet at all.
    """
    from ._images import DEPTH_SUFFIXES

    folder = Path(folder)
    layout = f"{folder}/color/<stem>.png, {folder}/input/<stem>.png and {folder}/gt/<stem>.png"
    missing = [name for name in TRIPLET_FOLDERS if not (folder / name).is_dir()]
    if missing:
        raise InputFileError(f"{folder} has no {', '.join(m + '/' for m in missing)} folder; "
                             f"--pairs expects {layout} (files paired by stem).")
    color = _by_stem(folder / "color", _COLOR_SUFFIXES, notes)
    inputs = _by_stem(folder / "input", DEPTH_SUFFIXES, notes)
    truth = _by_stem(folder / "gt", DEPTH_SUFFIXES, notes)
    scenes = []
    for stem in sorted(set(color) | set(inputs) | set(truth)):
        absent = [name for name, files in zip(TRIPLET_FOLDERS, (color, inputs, truth)) if stem not in files]
        if absent:
            _note(notes, f"skipped {stem}: no file of that stem in {', '.join(a + '/' for a in absent)}.")
            continue
        try:
            rgb, gt = _read_pair(color[stem], truth[stem])
            gt = _as_invalid(gt, invalid)
            depth_lr = _as_invalid(read_depth(inputs[stem]), invalid)
        except (InputFileError, ValueError, OSError) as exc:
            _note(notes, f"skipped {stem}: {exc}")
            continue
        scale = max(1, round(gt.shape[0] / depth_lr.shape[0]))
        scenes.append(DatasetScene(stem, rgb, gt, {scale: depth_lr}, color[stem]))
    if not scenes:
        raise InputFileError(f"{folder} holds no usable triplet; expected {layout} (files paired by stem).")
    return scenes


#: The real ToF captures of ``real_tof/``: scene name -> (depth file, guide file), relative to the folder.
#: ``iphone``: Apple LiDAR depth (mm) and the RGB frame it is registered to; ``kinect``: Azure Kinect
#: depth (mm, 0 = invalid) and the active IR image of the same sensor (16-bit, same grid).
REAL_TOF_CAPTURES = {
    "iphone": ("iphone_lidar_bookshelf/arkit_depth.png", "iphone_lidar_bookshelf/image.jpg"),
    "kinect": ("azure_kinect_mug/derived/depth_640x576_mm.png", "azure_kinect_mug/derived/ir_640x576.png"),
}


def read_real_tof(folder: str | os.PathLike, *, scales: tuple[int, ...] = (),
                  notes: list[str] | None = None) -> list[DatasetScene]:
    """The real ToF captures of :data:`REAL_TOF_CAPTURES` in ``folder`` (``scales`` unused).

    ``depth_gt`` is the real depth as stored (uint16 mm); ``rgb_hr`` is the
    guide as stored, RGB (the iPhone's 1920x1440 frame, on a different grid
    than the depth) or the Kinect's 16-bit IR repeated to three channels. A
    capture with a missing or unreadable file is skipped, with a note.

    Raises
    ------
    InputFileError
        No usable capture at all.
    """
    folder = Path(folder)
    scenes = []
    for name, (depth_name, guide_name) in REAL_TOF_CAPTURES.items():
        depth_path, guide_path = folder / depth_name, folder / guide_name
        missing = [str(p) for p in (depth_path, guide_path) if not p.is_file()]
        if missing:
            _note(notes, f"skipped {name}: {' and '.join(missing)} missing.")
            continue
        try:
            gt = read_depth(depth_path)
            guide = read_rgb(guide_path)
        except (InputFileError, ValueError, OSError) as exc:
            _note(notes, f"skipped {name}: {exc}")
            continue
        scenes.append(DatasetScene(name, guide, gt, {}, depth_path.parent))
    if not scenes:
        layout = ", ".join(f"{folder.name}/{d} with {folder.name}/{g}" for d, g in REAL_TOF_CAPTURES.values())
        raise InputFileError(f"{folder} holds no usable real ToF capture; expected {layout}.")
    return scenes


#: The readers a protocol can name (``Protocol.reader``).
DATASET_READERS: dict[str, Callable[..., list[DatasetScene]]] = {
    "scene_folders": read_scene_folders,
    "rgbd_pairs": read_rgbd_pairs,
    "triplets": read_triplets,
    "real_tof": read_real_tof,
}


def read_dataset(data_dir: str | os.PathLike, name: str, reader: str, *, protocol: str = "", layout: str = "",
                 scales: tuple[int, ...] = (), notes: list[str] | None = None,
                 options: dict | None = None) -> tuple[Path, list[DatasetScene]]:
    """The dataset folder ``name`` under ``data_dir`` and its scenes, read by ``DATASET_READERS[reader]``.

    ``options`` are passed on to the reader (e.g. ``invalid`` for ``triplets``).
    """
    folder = dataset_folder(data_dir, name, protocol=protocol, layout=layout)
    try:
        read = DATASET_READERS[reader]
    except KeyError:
        raise ValueError(f"unknown dataset reader {reader!r}; choose one of {sorted(DATASET_READERS)}.") from None
    return folder, read(folder, scales=scales, notes=notes, **(options or {}))
