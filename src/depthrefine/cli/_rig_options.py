"""Options of the commands that work with a rig (align, run, export-ply), defined once."""

from __future__ import annotations

import argparse
import dataclasses
import sys
from typing import TYPE_CHECKING, Any

from ..rig._names import ALIGN_METHODS, COLOR_SIDES, ENCODINGS
from . import CliError

if TYPE_CHECKING:
    import numpy as np

    from ..io import ChainSettings

__all__ = ["add_units_options", "add_align_options", "align_overrides", "chain_settings", "warn_implausible_units"]


def add_units_options(p: argparse.ArgumentParser) -> None:
    """--depth-units / --inverse-depth-scale: how depth values become metres."""
    units = p.add_mutually_exclusive_group()
    units.add_argument("--depth-units", type=float, metavar="M",
                       help="metres per depth unit, for depth that grows with distance (0.001 for uint16 mm)")
    units.add_argument("--inverse-depth-scale", type=float, metavar="C",
                       help="for 8-bit depth intensity / disparity (larger = nearer): metres = C / value "
                            "(255 at z_min metres: C = 255 * z_min)")


def _factor(text: str) -> float:
    """``--factor``: a number >= 1, kept an integer when it is one (``"2"`` -> 2, ``"1.21"`` -> 1.21)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number >= 1 such as 2 or 1.21; got {text!r}") from None
    if not value >= 1 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"expected a number >= 1 such as 2 or 1.21; got {text!r}")
    return int(value) if value.is_integer() else value


def add_align_options(p: argparse.ArgumentParser, *, method_action: type[argparse.Action] | None = None,
                      method_flag: str = "--method") -> None:
    """The alignment options shared by ``align``, ``run`` and ``batch`` (None = take the settings file's value).

    ``method_flag`` (dest ``align_method``) is the alignment method: ``--method``
    in ``align`` and ``run``, ``--align-method`` in ``batch`` (whose
    ``--method`` is the refinement's); ``method_action`` replaces its plain
    store (it then checks the choices).
    """
    how: dict[str, Any] = ({"action": method_action, "metavar": "{" + ",".join(ALIGN_METHODS) + "}"}
                           if method_action is not None else {"choices": ALIGN_METHODS})
    p.add_argument(method_flag, dest="align_method", default=None, **how,
                   help="alignment method: reproject (calibrated, any rig; default) or shift (the thesis's "
                        "horizontal shift: a parallel rig whose color image shows the depth camera's view; "
                        "refused when the background would land more than 1 depth pixel off)")
    add_units_options(p)
    p.add_argument("--factor", type=_factor, metavar="S",
                   help="reproject: the output is the color grid / S, S >= 1 (default: the focal-length ratio, "
                        "rounded when at least 2: a grid at the depth camera's resolution)")
    p.add_argument("--radial", action="store_true", default=None,
                   help="reproject: the depth is the distance along each ray, not Z")
    p.add_argument("--slope", type=float, metavar="K",
                   help="shift: k, the shift in depth pixels is k * (d - d_bg) for --encoding inverse (k in "
                        "depth pixels per depth unit) and k * (1/D - 1/D_bg) for distance (k in depth pixels "
                        "times depth units); default: from the rig and the depth units")
    p.add_argument("--background", type=float, metavar="D",
                   help="shift: background depth d_bg, which does not move (default: mean of the farther half)")
    p.add_argument("--color-side", choices=COLOR_SIDES, default=None,
                   help="shift: side of the color camera seen from behind (default: from the rig)")
    p.add_argument("--encoding", choices=ENCODINGS, default=None,
                   help="shift: inverse (depth intensity, larger = nearer) or distance (mm, m); default: "
                        "distance with --depth-units, else inverse")
    p.add_argument("--no-undistort", action="store_true",
                   help="the depth map and color image are already undistorted: neither is resampled and "
                        "the depth is aligned to the undistorted color camera")


def align_overrides(args: argparse.Namespace) -> dict[str, Any]:
    """The ``AlignSettings`` fields the alignment options set (the options left out are not in it)."""
    overrides: dict[str, Any] = {}
    for option, key in (("align_method", "method"), ("factor", "factor"), ("radial", "radial"),
                        ("slope", "slope"), ("background", "background"), ("color_side", "color_side"),
                        ("encoding", "encoding")):
        value = getattr(args, option)
        if value is not None:
            overrides[key] = value
    if args.depth_units is not None:
        overrides.update(depth_units=args.depth_units, inverse_scale=None)
    if args.inverse_depth_scale is not None:
        overrides.update(inverse_scale=args.inverse_depth_scale, depth_units=None)
    if args.no_undistort:
        overrides.update(undistort_depth=False, undistort_color=False)
    return overrides


def chain_settings(args: argparse.Namespace) -> ChainSettings:
    """The chain settings of ``--rig`` (and ``--settings``), with the command-line options on top."""
    from ..io import read_chain_settings

    base = read_chain_settings(args.rig)
    settings_file = getattr(args, "settings", None)
    if settings_file:
        extra = read_chain_settings(settings_file)
        base = dataclasses.replace(extra, rig=base.rig or extra.rig,
                                   rig_source=base.rig_source if base.rig is not None else extra.rig_source)
    if base.rig is None:
        raise CliError(f"{args.rig} holds no rig; give a rig file from `depthrefine calibrate-stereo`.")
    overrides = align_overrides(args)
    try:
        align = dataclasses.replace(base.align, **overrides)
    except (TypeError, ValueError) as exc:
        raise CliError(f"alignment settings: {exc}") from None
    return dataclasses.replace(base, align=align)


def warn_implausible_units(command: str, depth: np.ndarray, *, depth_units: float | None,
                           inverse_scale: float | None) -> None:
    """A warning line on stderr when the units put the median depth outside 5 cm .. 50 m (PLAUSIBLE_DEPTH_M)."""
    from ..rig.pointcloud import implausible_units

    problem = implausible_units(depth, depth_units=depth_units, inverse_scale=inverse_scale)
    if problem:
        print(f"depthrefine {command}: warning: {problem}.", file=sys.stderr)
