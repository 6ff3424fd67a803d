"""Parameter files (TOML or JSON) and manual patch layouts (JSON)."""

from __future__ import annotations

import json
import os
import tomllib
from typing import Any

from ._files import InputFileError, existing_input

__all__ = ["read_mapping", "read_patch_layout"]


def read_mapping(path: str | os.PathLike, *, what: str = "parameter") -> dict[str, Any]:
    """Read a TOML (``.toml``) or JSON file holding one table of settings."""
    p = existing_input(path, what)
    text = p.read_bytes()
    try:
        if p.suffix.lower() == ".json":
            data = json.loads(text.decode("utf-8"))
        else:
            data = tomllib.loads(text.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError, tomllib.TOMLDecodeError) as exc:
        kind = "JSON" if p.suffix.lower() == ".json" else "TOML"
        raise InputFileError(f"{what} file {p} is not valid {kind} ({exc}); fix its syntax.") from None
    if not isinstance(data, dict):
        raise InputFileError(f"{what} file {p} must hold a table of key = value pairs.")
    return data


def read_patch_layout(path: str | os.PathLike) -> tuple[tuple[int, int, int, int], ...]:
    """Read a manual patch layout: a JSON list of rectangles in color-image pixels.

    Each rectangle is ``[x, y, width, height]`` or
    ``{"x": .., "y": .., "width": .., "height": ..}`` (x = column, y = row of
    the top-left corner).
    """
    p = existing_input(path, "patch")
    try:
        data = json.loads(p.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputFileError(
            f"patch file {p} is not valid JSON ({exc}); give a list of rectangles [x, y, width, height]."
        ) from None
    if isinstance(data, dict) and "patches" in data:
        data = data["patches"]
    if not isinstance(data, list) or not data:
        raise InputFileError(f"patch file {p} must hold a non-empty JSON list of rectangles [x, y, width, height].")
    rects = []
    for i, item in enumerate(data):
        if isinstance(item, dict):
            try:
                item = [item["x"], item["y"], item["width"], item["height"]]
            except KeyError as exc:
                raise InputFileError(f"patch file {p}: rectangle {i} lacks key {exc}; give x, y, width, height.") from None
        if (not isinstance(item, list) or len(item) != 4
                or not all(isinstance(v, int) and not isinstance(v, bool) for v in item)):
            raise InputFileError(f"patch file {p}: rectangle {i} must be four integers [x, y, width, height]; got {item!r}.")
        x, y, w, h = item
        if x < 0 or y < 0 or w < 1 or h < 1:
            raise InputFileError(f"patch file {p}: rectangle {i} {item} needs x, y >= 0 and width, height >= 1.")
        rects.append((x, y, w, h))
    return tuple(rects)
