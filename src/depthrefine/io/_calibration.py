"""Calibration files of other tools: Azure Kinect ``calibration.json``, OpenCV FileStorage YAML, ROS camera_info.

The formats are described in :mod:`depthrefine.rig.formats`, which converts
the parsed files; this module only reads them. YAML is parsed with OpenCV's
``cv2.FileStorage`` (it reads OpenCV's ``!!opencv-matrix`` nodes and plain
YAML maps and lists alike), so no YAML library is needed.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from ..rig.camera import CameraModel, StereoRig
from ..rig.formats import (CALIBRATION_FORMATS, calibration_format, camera_from_opencv, camera_from_ros,
                           rig_from_k4a)
from ._files import InputFileError, existing_input

__all__ = ["read_calibration"]

_KNOWN = "; ".join(CALIBRATION_FORMATS.values())


def read_calibration(
    path: str | os.PathLike, *, depth_mode: str | None = None, color_resolution: str | None = None
) -> tuple[StereoRig | CameraModel, str]:
    """Read another tool's calibration file.

    Parameters
    ----------
    path : path
        An Azure Kinect ``calibration.json``, an OpenCV FileStorage YAML or a
        ROS camera_info YAML.
    depth_mode, color_resolution : str, optional
        Azure Kinect only, both required: the capture mode whose intrinsics to
        give (e.g. ``"NFOV_UNBINNED"`` and ``"720P"``).

    Returns
    -------
    calibration : StereoRig or CameraModel
        The rig of an Azure Kinect file; one camera otherwise.
    kind : str
        ``"k4a"``, ``"opencv"`` or ``"ros"``.

    Raises
    ------
    InputFileError
        A file that is none of these, or not valid JSON/YAML, a missing mode,
        or a mode the file cannot give (the message says what to do).
    """
    p = existing_input(path, "calibration")
    data = _parse(p)
    kind = calibration_format(data)
    if kind is None:
        hint = ""
        if isinstance(data, dict) and ("depth_camera" in data or "K" in data):
            hint = " It looks like a depthrefine rig or camera file already: use it as it is."
        raise InputFileError(f"{p} is not a calibration file depthrefine can import; expected one of: {_KNOWN}.{hint}")
    try:
        if kind == "k4a":
            if depth_mode is None or color_resolution is None:
                raise InputFileError(
                    f"{p} is an Azure Kinect calibration, which holds every capture mode: give --depth-mode "
                    "(NFOV_UNBINNED, NFOV_2X2BINNED, WFOV_UNBINNED, WFOV_2X2BINNED, PASSIVE_IR) and "
                    "--color-resolution (720P, 1080P, 1440P, 1536P, 2160P, 3072P) of the capture."
                )
            return rig_from_k4a(data, depth_mode=depth_mode, color_resolution=color_resolution, source=str(p)), kind
        if depth_mode is not None or color_resolution is not None:
            raise InputFileError(f"{p} is an {CALIBRATION_FORMATS[kind]}; --depth-mode and --color-resolution "
                                 "are for Azure Kinect calibrations only.")
        convert = camera_from_opencv if kind == "opencv" else camera_from_ros
        return convert(data, source=str(p)), kind
    except (TypeError, ValueError) as exc:
        raise InputFileError(str(exc)) from None


def _parse(p: Path) -> Any:
    text = p.read_bytes()
    try:
        decoded = text.decode("utf-8")
    except UnicodeDecodeError:
        raise InputFileError(f"{p} is not a text file; expected one of: {_KNOWN}.") from None
    if decoded.lstrip().startswith("{"):
        try:
            return json.loads(decoded)
        except json.JSONDecodeError as exc:
            raise InputFileError(f"calibration file {p} is not valid JSON ({exc}); fix its syntax.") from None
    return _parse_yaml(decoded, p)


def _parse_yaml(text: str, p: Path) -> dict[str, Any]:
    import cv2

    # A dumped ROS message ends with a '---' document separator, which FileStorage refuses.
    lines = [line for line in text.splitlines() if line.strip() not in ("---", "...")]
    body = "\n".join(lines) + "\n"
    if not body.lstrip().startswith("%YAML"):
        body = "%YAML:1.0\n" + body
    try:
        fs = cv2.FileStorage(body, cv2.FILE_STORAGE_READ | cv2.FILE_STORAGE_MEMORY | cv2.FILE_STORAGE_FORMAT_YAML)
        root = fs.root()
        data = _node(root) if root.isMap() else None
        fs.release()
    except (cv2.error, SystemError) as exc:
        raise InputFileError(f"{p} is neither JSON nor YAML that OpenCV can read ({' '.join(str(exc).split())[:120]}); "
                             f"expected one of: {_KNOWN}.") from None
    if not isinstance(data, dict):
        raise InputFileError(f"{p} does not hold a YAML map; expected one of: {_KNOWN}.")
    return data


def _node(node: Any) -> Any:
    """A ``cv2.FileNode`` as Python: dicts, lists, floats, strings, and ndarrays for opencv-matrix nodes."""
    if node.isMap():
        if set(node.keys()) >= {"rows", "cols", "data"} and node.getNode("dt").isString():
            return np.asarray(node.mat(), dtype=np.float64)
        return {key: _node(node.getNode(key)) for key in node.keys()}
    if node.isSeq():
        return [_node(node.at(i)) for i in range(node.size())]
    if node.isString():
        return node.string()
    if node.isInt():
        return int(node.real())
    if node.isReal():
        return float(node.real())
    return None
