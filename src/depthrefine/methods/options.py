"""A method's own command-line options, declared with its registry entry.

A :class:`MethodOption` says how one option (``--clusters K``) sets one
parameter of the method's parameter dataclass (``n_clusters``). The registry
entry of a method lists its options (``Method.options``); every command that
refines adds them, in an argument group per method, and builds the method's
parameters from them, so the command line knows no method by name. Using a
method's option with another method is an error.

This module imports neither numpy nor any method: the command line builds
its parsers from it (fast ``--help``). The value parsers below raise
``argparse.ArgumentTypeError``, whose message argparse prints as it is.
"""

from __future__ import annotations

import argparse
import re
from dataclasses import dataclass
from typing import Any, Callable

__all__ = ["MethodOption", "parse_grid", "parse_count", "show_grid"]


@dataclass(frozen=True)
class MethodOption:
    """One command-line option that sets one parameter of a method.

    Attributes
    ----------
    flag : str
        The option as typed, ``"--clusters"``.
    param : str
        The field of the method's parameter dataclass it sets, ``"n_clusters"``.
    help : str
        One line for ``--help``.
    type : callable
        Parses the option's text (argparse ``type``); raises
        ``argparse.ArgumentTypeError`` with a message for bad text.
    metavar : str, optional
        The value's name in ``--help`` (``"K"``).
    to_param : callable, optional
        Turns the parsed value into the parameter's value, when the command
        runs (``--patch-file F``: read the file). Default: the parsed value.
    show : callable, optional
        The parsed value as the user would type it, for messages.
    exclusive : str, optional
        Options of one method with the same ``exclusive`` name cannot be given
        together (``--patches`` or ``--patch-file``).
    conflicts : tuple of str
        Parameters that, set in a ``--params`` or settings file, contradict
        this option (``--patches`` against the file's ``patch_layout``).
    switch : bool
        An option without a value that sets its boolean parameter to True
        (``--snap-edges``); ``type`` and ``metavar`` are then unused.

    Examples
    --------
    >>> clusters = MethodOption("--clusters", "n_clusters", "k-means clusters per patch", type=parse_count)
    >>> clusters.dest, clusters.type("3")
    ('clusters', 3)
    """

    flag: str
    param: str
    help: str
    type: Callable[[str], Any] = str
    metavar: str | None = None
    to_param: Callable[[Any], Any] | None = None
    show: Callable[[Any], str] = str
    exclusive: str | None = None
    conflicts: tuple[str, ...] = ()
    switch: bool = False

    def __post_init__(self) -> None:
        if not re.fullmatch(r"--[a-z][a-z0-9-]*", self.flag):
            raise ValueError(f"a method option is a long option such as --clusters; got {self.flag!r}.")

    @property
    def dest(self) -> str:
        """The attribute of the parsed arguments that holds the value (``--patch-file`` -> ``patch_file``)."""
        return self.flag[2:].replace("-", "_")

    def param_value(self, value: Any) -> Any:
        """The parameter's value for the parsed ``value``."""
        return value if self.to_param is None else self.to_param(value)


def parse_grid(text: str) -> tuple[int, int]:
    """``"6x4"`` -> ``(6, 4)``: columns first, then rows (as ``--board`` and ``--patches``).

    Examples
    --------
    >>> parse_grid("6x4"), show_grid((6, 4))
    ((6, 4), '6x4')
    """
    m = re.fullmatch(r"\s*(\d+)\s*[xX*]\s*(\d+)\s*", text)
    if not m or int(m.group(1)) < 1 or int(m.group(2)) < 1:
        raise argparse.ArgumentTypeError(f"expected COLSxROWS (columns first) such as 6x4; got {text!r}")
    return int(m.group(1)), int(m.group(2))


def show_grid(grid: tuple[int, int]) -> str:
    """``(6, 4)`` -> ``"6x4"``, as :func:`parse_grid` reads it."""
    return f"{grid[0]}x{grid[1]}"


def parse_count(text: str) -> int:
    """A whole number >= 1 (``--clusters``, ``--workers``).

    Examples
    --------
    >>> parse_count("4")
    4
    """
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be a whole number >= 1; got {text!r}")
    return value
