"""Options shared by several subcommands, defined once."""

from __future__ import annotations

import argparse
import dataclasses
import re
import sys
from typing import Any, Callable

from ..io import read_mapping, read_patch_layout
from ..methods import METHODS, get_method
from ..params import params_from_mapping

__all__ = ["add_output", "add_overwrite", "add_params_options", "build_params", "parse_grid", "progress_bar"]


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


def add_params_options(parser: argparse.ArgumentParser) -> None:
    """--method, --patches / --patch-file, --clusters, --params."""
    parser.add_argument("--method", default="thesis", choices=sorted(METHODS),
                        help="upsampling method (default: thesis)")
    grid = parser.add_mutually_exclusive_group()
    grid.add_argument("--patches", type=parse_grid, metavar="AxD",
                      help="automatic patch grid, across x down (thesis default 4x4)")
    grid.add_argument("--patch-file", metavar="F",
                      help="manual patch layout: JSON list of [x, y, width, height] in color pixels")
    parser.add_argument("--clusters", type=int, metavar="K", help="k-means clusters per patch (thesis: 4)")
    parser.add_argument("--params", metavar="FILE",
                        help="method parameters as TOML (or JSON): key = value per parameter")


def build_params(args: argparse.Namespace) -> Any:
    """The method's parameter dataclass from --params FILE and the option overrides."""
    entry = get_method(args.method)
    overrides: dict[str, Any] = {}
    if args.params:
        overrides.update(read_mapping(args.params, what="parameter"))
    if args.patches is not None:
        overrides["patches"] = args.patches
    if args.patch_file is not None:
        overrides["patch_layout"] = read_patch_layout(args.patch_file)
    if args.clusters is not None:
        if args.clusters < 1:
            raise ValueError(f"--clusters must be >= 1; got {args.clusters}.")
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
