"""Camera, rig and chain-settings files.

Camera file (JSON, written by ``depthrefine calibrate``)::

    {"K": [[fx, 0, cx], [0, fy, cy], [0, 0, 1]],
     "dist": [k1, k2, p1, p2, k3],          # OpenCV order
     "image_size": [width, height],
     "rms": 0.12,                           # RMS reprojection error, pixels
     ...}                                   # other keys are kept for the user, ignored here

Rig file (JSON, written by ``depthrefine calibrate-stereo``)::

    {"depth_camera": {camera}, "color_camera": {camera},
     "R": [[...], [...], [...]],            # depth frame -> color frame
     "t": [tx, ty, tz],                     # metres: X_color = R X_depth + t
     "rms": 0.3}

Chain settings file (TOML or JSON), the one file to keep next to the
captures: the rig (a path relative to the file, or the rig inline), the
alignment (:class:`depthrefine.rig.AlignSettings`) and the refinement::

    rig = "rig.json"
    [align]
    method = "reproject"
    depth_units = 0.001
    [refine]
    method = "thesis"
    [refine.params]
    patches = [4, 4]
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

from ..rig.chain import AlignSettings
from ..rig.camera import CameraModel, StereoRig
from ..methods.params import params_from_mapping
from ._files import InputFileError, atomic_write, check_output
from ._params import read_mapping

__all__ = [
    "read_camera",
    "write_camera",
    "read_rig",
    "write_rig",
    "ChainSettings",
    "read_chain_settings",
    "read_depth_units",
    "write_chain_settings",
]

_CHAIN_KEYS = ("rig", "align", "refine")
_REFINE_KEYS = ("method", "params", "fill_holes")


@dataclass(frozen=True, eq=False)
class ChainSettings:
    """The contents of a chain settings file.

    Attributes
    ----------
    rig : StereoRig or None
        The rig, if the file names or holds one.
    align : AlignSettings
        The ``[align]`` table (defaults where absent).
    method : str or None
        The refinement method of ``[refine]`` (None: the command's default).
    params : dict
        ``[refine.params]``: the method's parameters, checked when the method is known.
    rig_source : str or None
        Where the rig came from (a file path, or ``"inline"``).
    fill_holes : bool
        ``[refine] fill_holes``: keep the refinement's depth where nothing was
        measured (``run --fill-holes``); default false.
    """

    rig: StereoRig | None = None
    align: AlignSettings = field(default_factory=AlignSettings)
    method: str | None = None
    params: dict[str, Any] = field(default_factory=dict)
    rig_source: str | None = None
    fill_holes: bool = False

    def to_dict(self, *, inline_rig: bool = True) -> dict[str, Any]:
        """JSON-ready dict in the file layout (unset align options left out)."""
        out: dict[str, Any] = {}
        if self.rig is not None:
            out["rig"] = self.rig.to_dict() if inline_rig or self.rig_source in (None, "inline") else self.rig_source
        out["align"] = {k: v for k, v in self.align.to_dict().items() if v is not None}
        refine: dict[str, Any] = {}
        if self.method is not None:
            refine["method"] = self.method
        if self.params:
            refine["params"] = dict(self.params)
        if self.fill_holes:
            refine["fill_holes"] = True
        if refine:
            out["refine"] = refine
        return out


def _read_json_table(path: str | os.PathLike, what: str) -> dict[str, Any]:
    return read_mapping(path, what=what)


def read_camera(path: str | os.PathLike, *, which: str = "depth") -> CameraModel:
    """Read a camera file; from a rig or chain file, take its ``which`` camera ("depth" or "color")."""
    p = Path(path)
    data = _read_json_table(p, "camera")
    if "K" in data or "dist" in data or "image_size" in data:  # a camera file (perhaps lacking a key)
        try:
            return CameraModel.from_dict(data, source=f"camera file {p}")
        except (TypeError, ValueError) as exc:
            raise InputFileError(str(exc)) from None
    if which not in ("depth", "color"):
        raise ValueError(f"which must be 'depth' or 'color'; got {which!r}.")
    rig = read_rig(p)
    return rig.depth_camera if which == "depth" else rig.color_camera


def write_camera(
    path: str | os.PathLike, camera: CameraModel, *, overwrite: bool = False, extra: Mapping[str, Any] | None = None
) -> Path:
    """Write a camera file (JSON), atomically; ``extra`` keys are added after the model's."""
    return _write_json(path, {**camera.to_dict(), **dict(extra or {})}, overwrite=overwrite)


def read_rig(path: str | os.PathLike) -> StereoRig:
    """Read a rig file, or the rig of a chain settings file (inline or by path)."""
    p = Path(path)
    data = _read_json_table(p, "rig")
    if "depth_camera" in data:
        return _rig_from(data, p)
    if any(k in data for k in _CHAIN_KEYS):
        settings = read_chain_settings(p)
        if settings.rig is None:
            raise InputFileError(f"settings file {p} names no rig; add rig = \"rig.json\" or a [rig] table.")
        return settings.rig
    raise InputFileError(
        f"{p} is neither a rig file (keys depth_camera, color_camera, R, t, written by "
        "`depthrefine calibrate-stereo`) nor a chain settings file (tables rig, align, refine)."
    )


def write_rig(
    path: str | os.PathLike, rig: StereoRig, *, overwrite: bool = False, extra: Mapping[str, Any] | None = None
) -> Path:
    """Write a rig file (JSON), atomically."""
    return _write_json(path, {**rig.to_dict(), **dict(extra or {})}, overwrite=overwrite)


def read_chain_settings(path: str | os.PathLike) -> ChainSettings:
    """Read a chain settings file (TOML or JSON; layout in the module docstring).

    A plain rig file is accepted too (its settings are then the defaults).

    Raises
    ------
    InputFileError
        Unknown tables or keys (the message lists the known ones), a rig
        file that cannot be read, or invalid values.
    """
    p = Path(path)
    data = read_mapping(p, what="settings")
    if "depth_camera" in data:
        return ChainSettings(rig=_rig_from(data, p), rig_source=str(p))
    unknown = sorted(set(data) - set(_CHAIN_KEYS))
    if unknown:
        raise InputFileError(
            f"settings file {p}: unknown key(s) {', '.join(map(repr, unknown))}; known: {', '.join(_CHAIN_KEYS)}."
        )
    rig, rig_source = None, None
    if "rig" in data:
        value = data["rig"]
        if isinstance(value, str):
            rig_path = Path(value) if Path(value).is_absolute() else p.parent / value
            rig, rig_source = read_rig(rig_path), str(rig_path)
        elif isinstance(value, Mapping) and set(value) == {"file"} and isinstance(value["file"], str):
            rig_path = Path(value["file"]) if Path(value["file"]).is_absolute() else p.parent / value["file"]
            rig, rig_source = read_rig(rig_path), str(rig_path)
        elif isinstance(value, Mapping):
            rig, rig_source = _rig_from(value, p), "inline"
        else:
            raise InputFileError(f"settings file {p}: rig must be a file name or a table; got {value!r}.")
    align_table = data.get("align", {})
    if not isinstance(align_table, Mapping):
        raise InputFileError(f"settings file {p}: [align] must be a table.")
    try:
        align = params_from_mapping(AlignSettings, align_table, source=f"settings file {p} [align]")
    except (TypeError, ValueError) as exc:
        raise InputFileError(str(exc)) from None
    refine = data.get("refine", {})
    if not isinstance(refine, Mapping):
        raise InputFileError(f"settings file {p}: [refine] must be a table.")
    unknown = sorted(set(refine) - set(_REFINE_KEYS))
    if unknown:
        raise InputFileError(
            f"settings file {p} [refine]: unknown key(s) {', '.join(map(repr, unknown))}; "
            f"known: {', '.join(_REFINE_KEYS)}."
        )
    method = refine.get("method")
    if method is not None and not isinstance(method, str):
        raise InputFileError(f"settings file {p} [refine]: method must be a name; got {method!r}.")
    params = refine.get("params", {})
    if not isinstance(params, Mapping):
        raise InputFileError(f"settings file {p}: [refine.params] must be a table.")
    fill_holes = refine.get("fill_holes", False)
    if not isinstance(fill_holes, bool):
        raise InputFileError(f"settings file {p} [refine]: fill_holes must be true or false; got {fill_holes!r}.")
    return ChainSettings(rig=rig, align=align, method=method, params=dict(params), rig_source=rig_source,
                         fill_holes=fill_holes)



def read_depth_units(path: str | os.PathLike) -> tuple[float | None, float | None]:
    """``(depth_units, inverse_scale)`` recorded in a chain settings file's ``[align]``; ``(None, None)`` for a
    rig or camera file, which record no units."""
    data = read_mapping(path, what="rig")
    if not any(key in data for key in _CHAIN_KEYS):
        return None, None
    align = read_chain_settings(path).align
    return align.depth_units, align.inverse_scale

def write_chain_settings(path: str | os.PathLike, settings: ChainSettings, *, overwrite: bool = False) -> Path:
    """Write a chain settings file as JSON (the rig inline), atomically."""
    return _write_json(path, settings.to_dict(inline_rig=True), overwrite=overwrite)


def _rig_from(data: Mapping[str, Any], p: Path) -> StereoRig:
    try:
        return StereoRig.from_dict(data, source=f"rig in {p}")
    except (TypeError, ValueError) as exc:
        raise InputFileError(str(exc)) from None


def _write_json(path: str | os.PathLike, data: Mapping[str, Any], *, overwrite: bool) -> Path:
    p = check_output(path, overwrite=overwrite, what="output", suffixes=(".json",))
    text = json.dumps(data, indent=2, allow_nan=False) + "\n"

    def _write(tmp: Path) -> None:
        tmp.write_text(text, encoding="utf-8")

    return atomic_write(p, _write)
