"""The ``depthrefine`` command (also ``python -m depthrefine``).

One subcommand per module in this package; each module has
``add_parser(subparsers)`` that registers its parser and sets ``func``, a
function of the parsed arguments returning an exit status. Commands are thin:
parse, read with :mod:`depthrefine.io`, call the library, write.

Building a parser imports no numpy, OpenCV, SciPy or matplotlib, so that
``--help`` starts fast (issue 13): ``add_parser`` reads names and defaults
from the light modules ``methods/_names.py``, ``rig/_names.py`` and
``io/_names.py`` (and ``bench.protocols``, ``viz``, which load numpy on first
use), and the command's function imports what it runs.
``tests/test_startup.py`` checks every command's ``--help``.

Exit status: 0 success; 2 bad input (one line on stderr naming the file or
argument and what to do, no traceback, no output left behind); 1 internal
failure (traceback only with ``--debug``); 130 interrupted.

Every subcommand also takes ``--max-pixels N`` (refuse images over N pixels,
before decoding them; the default limit comes from the machine's available
memory, see ``docs/robustness.md``) and ``--debug``.
"""

from __future__ import annotations

import argparse
import atexit
import gc
import importlib
import sys
import traceback
import warnings
from typing import Sequence

from .. import __version__
from .._lazy import missing_dependency, missing_dependency_message

__all__ = ["main", "build_parser", "CliError"]

#: Subcommand modules, in the order ``--help`` lists them.
COMMAND_MODULES = [
    "refine",
    "show",
    "demo",
    "calibrate",
    "rig",
    "board",
    "align",
    "undistort",
    "run",
    "export_ply",
    "bench",
    "data",
    "batch",
]


class CliError(Exception):
    """Bad input found by a command: printed as one line, exit status 2."""


class _Version(argparse.Action):
    """``--version``: the package's version and which compiled kernels gbp and the thesis method run (C or numba, and why), made when asked."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, help=None):
        super().__init__(option_strings, dest=dest, default=default, nargs=0,
                         help=help or "show the version and which compiled kernels run (C or numba), and exit")

    def __call__(self, parser, namespace, values, option_string=None):
        from .._native import describe   # ctypes only: no numpy, no numba

        parser._print_message(f"depthrefine {__version__} ({describe()})\n", sys.stdout)   # as argparse's own
        parser.exit()


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, exit 2 (argparse's own status)
        self.exit(2, f"{self.prog}: error: {message} (see --help)\n")


def build_parser(argv: Sequence[str] | None = None) -> argparse.ArgumentParser:
    """The parser of every command; with ``argv``, only of the command it names.

    Each command module imports what its command needs, so ``depthrefine
    refine --help`` imports only the refine command's module and
    ``depthrefine --version`` none (fast start-up). ``argv`` without a known
    command (``--help``, a typo) gets every command, for the listing.
    """
    parser = _Parser(
        prog="depthrefine",
        description="Refine a low-resolution ToF depth map with a registered high-resolution color image.",
    )
    parser.add_argument("--version", action=_Version)
    parser.add_argument("--debug", action="store_true", help="show tracebacks of internal failures")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for name in _modules_for(argv):
        importlib.import_module(f"{__name__}.{name}").add_parser(sub)
    if sub.choices:
        from ._common import add_shared_options

        for command_parser in dict.fromkeys(sub.choices.values()):
            add_shared_options(command_parser)
    return parser


def _modules_for(argv: Sequence[str] | None) -> list[str]:
    """The command modules a parse of ``argv`` needs (all when unsure)."""
    if argv is None:
        return COMMAND_MODULES
    words = [a for a in argv if not a.startswith("-")]
    if not words:
        return [] if "--version" in argv else COMMAND_MODULES
    module = words[0].replace("-", "_")
    return [module] if module in COMMAND_MODULES else COMMAND_MODULES


def main(argv: list[str] | None = None) -> int:
    """Run the command line; return the exit status."""
    own_process = argv is None   # the process's own command line: it exits after this
    if own_process:
        # numba leaves hundreds of thousands of objects; the collection at the interpreter's exit walked them
        # all (half a second). Frozen, they are left to the process's end.
        atexit.register(gc.freeze)
    argv = sys.argv[1:] if argv is None else argv
    parser = build_parser(argv)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, or a usage error (already printed, status 2)
        return exc.code if isinstance(exc.code, int) else 2
    args.debug = bool(getattr(args, "debug", False))
    args.own_process = own_process   # a command may then set the process up for itself alone (refine: numba)
    from .._validate import pixel_limit

    try:
        with warnings.catch_warnings(), pixel_limit(getattr(args, "max_pixels", None)):
            warnings.simplefilter("default")
            warnings.showwarning = _show_warning
            return int(args.func(args) or 0)
    except KeyboardInterrupt:
        print("depthrefine: interrupted; no output was written.", file=sys.stderr)
        return 130
    except (CliError, ValueError, TypeError) as exc:
        if args.debug:
            traceback.print_exc()
        print(f"depthrefine {args.command}: error: {_one_line(exc)}", file=sys.stderr)
        return 2
    except MemoryError:
        print(f"depthrefine {args.command}: error: out of memory; try a smaller image or "
              "--max-pixels.", file=sys.stderr)
        return 2
    except OSError as exc:
        if args.debug:
            traceback.print_exc()
        print(f"depthrefine {args.command}: error: {_one_line(exc)}", file=sys.stderr)
        return 2
    except Exception as exc:  # noqa: BLE001 - the last resort: internal failure
        if args.debug:
            traceback.print_exc()
        package = missing_dependency(exc)
        if package:  # an optional import inside a command (numba for the thesis method): the user can fix it
            print(f"depthrefine {args.command}: error: {missing_dependency_message(package, exc)}", file=sys.stderr)
            return 2
        print(f"depthrefine {args.command}: internal error: {type(exc).__name__}: {_one_line(exc)} "
              "(run with --debug for the traceback and report it)", file=sys.stderr)
        return 1


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split()) or type(exc).__name__


def _show_warning(message, category, filename, lineno, file=None, line=None):
    print(f"depthrefine: note: {message}", file=sys.stderr)
