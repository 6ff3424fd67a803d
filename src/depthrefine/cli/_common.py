"""Options shared by several subcommands, defined once.

Building a parser imports no numpy, OpenCV or method: ``--help`` stays fast
(issue 13). What a command needs to run is imported by the function that
runs it.
"""

from __future__ import annotations

import argparse
import math
import sys
from typing import TYPE_CHECKING, Any, Callable, Mapping

from ..methods._names import DEFAULT_METHOD, RegisteredMethodNames, registered_method_options
from ..methods.options import parse_count, parse_grid
from ..methods.params import params_from_mapping, params_to_dict

if TYPE_CHECKING:
    import numpy as np

__all__ = [
    "add_output",
    "add_overwrite",
    "add_params_options",
    "add_depth_options",
    "add_shared_options",
    "add_units_option",
    "add_output_format_options",
    "add_deprecated_alias",
    "build_params",
    "depth_units_label",
    "output_depth",
    "parse_range",
    "parse_grid",
    "parse_count",
    "parse_pixel_count",
    "progress_bar",
]


def add_output(parser: argparse.ArgumentParser, *, help: str, metavar: str = "OUT") -> None:
    parser.add_argument("-o", "--output", required=True, metavar=metavar, help=help)


def add_overwrite(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--overwrite", action="store_true", help="replace existing output files")


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


def add_params_options(parser: argparse.ArgumentParser, *, method_flag: str = "--method",
                       method_help: str | None = None) -> None:
    """The refinement method (``method_flag``, dest ``method``), --params, and every method's own options.

    Each registered method's options (``Method.options``) go into an argument
    group of their own, "NAME method options"; :func:`build_params` refuses
    them with another method.
    """
    parser.add_argument(method_flag, dest="method", default=DEFAULT_METHOD, choices=RegisteredMethodNames(),
                        help=method_help or f"refinement (upsampling) method (default: {DEFAULT_METHOD}, guided back-projection; "
                             "thesis: the thesis method as specified)")
    parser.add_argument("--params", metavar="FILE",
                        help="method parameters as TOML (or JSON): key = value per parameter")
    parser.set_defaults(method_flag=method_flag)
    for name, options in registered_method_options().items():
        options = [o for o in options if o.flag not in parser._option_string_actions]  # not another method's too
        if not options:
            continue
        group = parser.add_argument_group(f"{name} method options",
                                          f"parameters of {method_flag} {name} (an error with another method)")
        exclusive: dict[str, Any] = {}
        for option in options:
            where = group
            if option.exclusive is not None:
                if option.exclusive not in exclusive:
                    exclusive[option.exclusive] = group.add_mutually_exclusive_group()
                where = exclusive[option.exclusive]
            if option.switch:
                where.add_argument(option.flag, dest=option.dest, action="store_const", const=True, help=option.help)
            else:
                where.add_argument(option.flag, dest=option.dest, type=option.type, metavar=option.metavar,
                                   help=option.help)


def add_units_option(parser: argparse.ArgumentParser, *, help: str | None = None) -> None:
    """``--units LABEL``: the depth's units as a label for pictures and tables; it changes no value."""
    parser.add_argument("--units", metavar="LABEL", help=help or (
        "the depth's units, written on the pictures' colorbars (e.g. mm, m, 'disparity levels'); a label "
        "only, no value changes (default: the file's type, e.g. 'uint16 values as stored')"))


def depth_units_label(units: str | None, dtype: Any) -> str:
    """``--units`` if given, else a label saying the values are as stored in a ``dtype`` file.

    Examples
    --------
    >>> import numpy as np
    >>> depth_units_label(None, np.uint16), depth_units_label("mm", np.uint16)
    ('uint16 values as stored', 'mm')
    """
    import numpy as np

    return units if units else f"{np.dtype(dtype).name} values as stored"


def parse_range(text: str) -> tuple[float, float]:
    """``"0.5,4"`` -> ``(0.5, 4.0)``: MIN,MAX with MIN < MAX."""
    try:
        lo, hi = (float(p) for p in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected MIN,MAX such as 0.5,4; got {text!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise argparse.ArgumentTypeError(f"expected finite numbers MIN < MAX; got {text!r}")
    return lo, hi


def _positive_number(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"expected a positive number such as 1000; got {text!r}")
    return value


#: Types an output depth file can be given with --output-dtype.
OUTPUT_DTYPES = ("uint8", "uint16", "float32")


def add_output_format_options(parser: argparse.ArgumentParser) -> None:
    """``--output-scale S`` and ``--output-dtype T``: how the result's values are stored."""
    parser.add_argument(
        "--output-scale", type=_positive_number, metavar="S",
        help="multiply the result by S before writing it, e.g. 1000 to store metres as millimetres "
             "(with --output-dtype uint16 for a 16-bit PNG); a value that would clip is an error")
    parser.add_argument(
        "--output-dtype", choices=OUTPUT_DTYPES,
        help="type of the output file's values (default: DEPTH's); PNG holds uint8 and uint16")


def output_depth(args: argparse.Namespace, depth: np.ndarray, input_dtype: Any) -> tuple[np.ndarray, np.dtype]:
    """The depth to write and its dtype, after ``--output-scale`` / ``--output-dtype``.

    Without either option: ``depth`` and the input's dtype, as always. With
    one of them the conversion is explicit, so a value that the output type
    cannot hold is an error (:func:`depthrefine.io.scale_to_dtype`) instead
    of a silent clip.
    """
    import numpy as np

    from ..io import output_values

    try:
        return output_values(depth, input_dtype, scale=args.output_scale, dtype=args.output_dtype)
    except ValueError as exc:
        scale = 1.0 if args.output_scale is None else args.output_scale
        dtype = np.dtype(args.output_dtype or input_dtype)
        raise ValueError(f"--output-scale {scale:g} --output-dtype {dtype}: {exc}") from None


class _DeprecatedAlias(argparse.Action):
    """An old spelling of an option: works like the new one after a one-line note on stderr."""

    def __init__(self, option_strings, dest, *, new: str, **kwargs):
        self.new = new
        super().__init__(option_strings, dest, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None):
        print(f"depthrefine: note: {option_string} is deprecated; use {self.new} (same meaning).", file=sys.stderr)
        setattr(namespace, self.dest, values)


def add_deprecated_alias(parser: argparse.ArgumentParser, old: str, *, new: str, dest: str, **kwargs: Any) -> None:
    """Accept ``old`` as a hidden spelling of ``new`` (same ``dest``), printing a deprecation note when used."""
    parser.add_argument(old, dest=dest, action=_DeprecatedAlias, new=new, help=argparse.SUPPRESS,
                        default=argparse.SUPPRESS, **kwargs)


def build_params(args: argparse.Namespace, *, method: str | None = None,
                 base: Mapping[str, Any] | None = None) -> Any:
    """The method's parameter dataclass: ``base`` (a settings file's), then --params FILE, then the options.

    ``method`` defaults to ``args.method``. Every command that refines builds
    its parameters here, so the checks (an option of another method, an
    option against the file's value it contradicts, parameters for a method
    that takes none) are the same everywhere.
    """
    from ..io import read_mapping
    from ..methods.registry import METHODS, get_method

    entry = get_method(args.method if method is None else method)
    own = {option.flag: option for option in entry.options}
    given: dict[str, tuple[Any, Any]] = {}  # flag -> (the chosen method's option, parsed value)
    owners: dict[str, list[str]] = {}       # each option given that the method lacks -> the methods that have it
    for owner in METHODS.values():
        for option in owner.options:
            value = getattr(args, option.dest, None)
            if value is None:
                continue
            if option.flag in own:
                given[option.flag] = (own[option.flag], value)
            else:
                owners.setdefault(option.flag, []).append(owner.name)
    if owners:
        names = next(iter(owners.values()))
        flags = [flag for flag, its in owners.items() if its == names]
        others = f" (or {', '.join(names[1:])})" if len(names) > 1 else ""
        raise ValueError(f"{' and '.join(flags)} set{'s' if len(flags) == 1 else ''} parameters of the "
                         f"{' and '.join(names)} method{'s' if len(names) > 1 else ''}; the method is {entry.name!r}: "
                         f"add {getattr(args, 'method_flag', '--method')} {names[0]}{others}.")
    overrides: dict[str, Any] = dict(base or {})
    if args.params:
        overrides.update(read_mapping(args.params, what="parameter"))
    for option, value in given.values():
        for key in option.conflicts:
            if overrides.get(key) is not None:
                raise ValueError(f"{option.flag} {option.show(value)} conflicts with {key} in parameter file "
                                 f"{args.params}; drop one of them.")
    for option, value in given.values():
        overrides[option.param] = option.param_value(value)
    if entry.params_type is None:
        if overrides:
            origin = "--params and the settings file" if base else "--params"
            raise ValueError(f"method {entry.name!r} takes no parameters; drop {', '.join(sorted(overrides))} "
                             f"(from {origin}).")
        return None
    source = f"parameter file {args.params}" if args.params else "parameters"
    return params_from_mapping(entry.params_type, overrides, source=source)


#: The JSON-ready dict of a parameter dataclass (``{}`` for ``None``), as the commands record it.
params_dict = params_to_dict


def progress_bar(desc: str, *, enabled: bool | None = None, unit: str = "patch") -> tuple[Callable[[int, int], None], Callable[[], None]]:
    """A ``progress(done, total)`` callback drawing a tqdm bar on stderr, and a closer."""
    from tqdm import tqdm

    state: dict[str, Any] = {}
    disable = (not sys.stderr.isatty()) if enabled is None else not enabled

    def update(done: int, total: int) -> None:
        bar = state.get("bar")
        if bar is None:
            bar = state["bar"] = tqdm(total=total, desc=desc, unit=unit, disable=disable, leave=False)
        bar.update(done - bar.n)

    def close() -> None:
        if "bar" in state:
            state["bar"].close()

    return update, close
