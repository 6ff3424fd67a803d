"""Options shared by several subcommands, defined once."""

from __future__ import annotations

import argparse
import dataclasses
import re
import sys
from typing import Any, Callable, Mapping

from ..io import read_mapping, read_patch_layout
from ..methods.registry import METHODS, get_method
from ..methods.thesis.params import params_from_mapping

__all__ = [
    "add_output",
    "add_overwrite",
    "add_params_options",
    "add_depth_options",
    "add_shared_options",
    "build_params",
    "parse_grid",
    "parse_count",
    "parse_pixel_count",
    "progress_bar",
]


def add_output(parser: argparse.ArgumentParser, *, help: str) -> None:
    parser.add_argument("-o", "--output", required=True, metavar="OUT", help=help)


def add_overwrite(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--overwrite", action="store_true", help="replace existing output files")


def parse_grid(text: str) -> tuple[int, int]:
    """``"4x4"`` -> ``(4, 4)`` (across x down)."""
    m = re.fullmatch(r"\s*(\d+)\s*[xX*]\s*(\d+)\s*", text)
    if not m or int(m.group(1)) < 1 or int(m.group(2)) < 1:
        raise argparse.ArgumentTypeError(f"expected ACROSSxDOWN such as 4x4; got {text!r}")
    return int(m.group(1)), int(m.group(2))


def parse_count(text: str) -> int:
    """A whole number >= 1 (``--clusters``)."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be a whole number >= 1; got {text!r}")
    return value


def parse_pixel_count(text: str) -> int:
    """``"20000000"``, ``"20_000_000"`` or ``"2e7"`` -> 20000000 (a positive integer)."""
    try:
        value = float(text.replace("_", "")) if any(c in text for c in ".eE") else int(text.replace("_", ""))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a pixel count such as 20000000 or 2e7; got {text!r}") from None
    if value != value or value < 1 or value != int(value) or value > 2**62:
        raise argparse.ArgumentTypeError(f"expected a positive whole pixel count; got {text!r}")
    return int(value)


def add_shared_options(parser: argparse.ArgumentParser) -> None:
    """``--max-pixels`` and ``--debug``, which every subcommand takes (added by :func:`..cli.build_parser`)."""
    if "--max-pixels" not in parser._option_string_actions:
        parser.add_argument(
            "--max-pixels", type=parse_pixel_count, metavar="N", default=None,
            help="refuse any image over N pixels (rows x cols) before reading it; without it, images whose "
                 "processing would need more memory than the machine has available are refused")
    if "--debug" not in parser._option_string_actions:
        parser.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                            help="show tracebacks of internal failures")


def add_depth_options(parser: argparse.ArgumentParser) -> None:
    """``--saturated-invalid``: for commands that read a depth file."""
    parser.add_argument(
        "--saturated-invalid", action="store_true",
        help="read the largest code of an integer depth file (255, 65535), which many ToF cameras write for "
             "saturated pixels, as no measurement (default: a valid depth)")


def add_params_options(parser: argparse.ArgumentParser) -> None:
    """--method, --patches / --patch-file, --clusters, --params."""
    parser.add_argument("--method", default="thesis", choices=sorted(METHODS),
                        help="upsampling method (default: thesis)")
    grid = parser.add_mutually_exclusive_group()
    grid.add_argument("--patches", type=parse_grid, metavar="AxD",
                      help="automatic patch grid, across x down (thesis default 4x4)")
    grid.add_argument("--patch-file", metavar="F",
                      help="manual patch layout: JSON list of [x, y, width, height] in color pixels")
    parser.add_argument("--clusters", type=parse_count, metavar="K", help="k-means clusters per patch (thesis: 4)")
    parser.add_argument("--params", metavar="FILE",
                        help="method parameters as TOML (or JSON): key = value per parameter")


def build_params(args: argparse.Namespace, *, method: str | None = None,
                 base: Mapping[str, Any] | None = None) -> Any:
    """The method's parameter dataclass: ``base`` (a settings file's), then --params FILE, then the options.

    ``method`` defaults to ``args.method``. Every command that refines builds
    its parameters here, so the checks (--patches against a file's
    ``patch_layout``, parameters for a method that takes none) are the same
    everywhere.
    """
    entry = get_method(args.method if method is None else method)
    overrides: dict[str, Any] = dict(base or {})
    if args.params:
        overrides.update(read_mapping(args.params, what="parameter"))
    if args.patches is not None:
        if overrides.get("patch_layout") is not None:
            raise ValueError(
                f"--patches {args.patches[0]}x{args.patches[1]} conflicts with patch_layout in parameter file "
                f"{args.params}; drop one of them."
            )
        overrides["patches"] = args.patches
    if args.patch_file is not None:
        overrides["patch_layout"] = read_patch_layout(args.patch_file)
    if args.clusters is not None:
        if args.clusters < 1:
            raise ValueError(f"--clusters must be >= 1: n_clusters must be >= 1; got {args.clusters}.")
        overrides["n_clusters"] = args.clusters
    if entry.params_type is None:
        if overrides:
            raise ValueError(
                f"method {entry.name!r} takes no parameters; drop "
                f"{', '.join(sorted(overrides))} (from --params/--patches/--clusters)."
            )
        return None
    source = f"parameter file {args.params}" if args.params else "parameters"
    return params_from_mapping(entry.params_type, overrides, source=source)


def params_dict(params: Any) -> dict[str, Any]:
    """JSON-ready dict of a parameter dataclass (``{}`` for ``None``)."""
    if params is None:
        return {}
    if hasattr(params, "to_dict"):
        return params.to_dict()
    return dataclasses.asdict(params)


def progress_bar(desc: str, *, enabled: bool | None = None) -> tuple[Callable[[int, int], None], Callable[[], None]]:
    """A ``progress(done, total)`` callback drawing a tqdm bar on stderr, and a closer."""
    from tqdm import tqdm

    state: dict[str, Any] = {}
    disable = (not sys.stderr.isatty()) if enabled is None else not enabled

    def update(done: int, total: int) -> None:
        bar = state.get("bar")
        if bar is None:
            bar = state["bar"] = tqdm(total=total, desc=desc, unit="patch", disable=disable, leave=False)
        bar.update(done - bar.n)

    def close() -> None:
        if "bar" in state:
            state["bar"].close()

    return update, close
