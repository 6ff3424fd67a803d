"""Parameter dataclasses to and from plain mappings (TOML, JSON), for every method.

A method's parameters are one frozen dataclass (:class:`depthrefine.ThesisParams`,
:class:`depthrefine.GbpParams`, the peers' ``...Params``); a ``--params`` file,
a chain settings file's ``[refine.params]`` or a run record holds them as a
mapping of field name to value. :func:`params_from_mapping` builds the
dataclass from such a mapping and :func:`params_to_dict` writes it back.

A key that was once a parameter and is now fixed is declared on the
dataclass as ``removed_parameters: ClassVar[Mapping[str, str]]`` (old key ->
what it is fixed at); a mapping naming it gets an error that says so instead
of "unknown parameter".

This module imports neither numpy nor any method (the command line and
:mod:`depthrefine.io` read it).
"""

from __future__ import annotations

import dataclasses
from typing import Any, Mapping

__all__ = ["params_from_mapping", "params_to_dict"]


def params_from_mapping(cls: type, mapping: Mapping[str, Any], *, source: str = "parameters") -> Any:
    """Instantiate the parameter dataclass ``cls`` from ``mapping``.

    Parameters
    ----------
    cls : dataclass type
        The parameters' class; its fields are the known keys.
    mapping : mapping
        Key = value pairs (sequences may be lists: the dataclass normalises them).
    source : str
        Where the mapping came from (``"parameter file p.toml"``), the start of every message.

    Returns
    -------
    An instance of ``cls``.

    Raises
    ------
    TypeError
        ``mapping`` is not a mapping, or a value has the wrong type.
    ValueError
        A key that is not a field (the message lists the known ones), a key that
        ``cls.removed_parameters`` names (the message says what it is fixed at), or
        a value the dataclass refuses.

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> @dataclass(frozen=True)
    ... class Knobs:
    ...     radius: int = 2
    >>> Knobs.removed_parameters = {"clip": "always on"}  # in a class body: removed_parameters: ClassVar[...] = {...}
    >>> params_from_mapping(Knobs, {"radius": 3})
    Knobs(radius=3)
    >>> params_from_mapping(Knobs, {"clip": True}, source="parameter file p.toml")
    Traceback (most recent call last):
    ...
    ValueError: parameter file p.toml: 'clip' is no longer a parameter of Knobs (it is fixed: always on); remove it.
    """
    if not isinstance(mapping, Mapping):
        raise TypeError(f"{source} must be a table of key = value pairs; got {type(mapping).__name__}.")
    known = [f.name for f in dataclasses.fields(cls)]
    removed = getattr(cls, "removed_parameters", None) or {}
    gone = [key for key in mapping if key in removed and key not in known]
    if gone:
        key = gone[0]
        also = f" (and {', '.join(map(repr, gone[1:]))}, also removed)" if len(gone) > 1 else ""
        raise ValueError(f"{source}: {key!r} is no longer a parameter of {cls.__name__} "
                         f"(it is fixed: {removed[key]}); remove it{also}.")
    unknown = sorted(set(mapping) - set(known))
    if unknown:
        raise ValueError(
            f"{source}: unknown parameter(s) {', '.join(map(repr, unknown))} for {cls.__name__}; "
            f"known: {', '.join(known)}."
        )
    try:
        return cls(**dict(mapping))
    except (TypeError, ValueError) as exc:
        raise type(exc)(f"{source}: {exc}") from None


def params_to_dict(params: Any) -> dict[str, Any]:
    """A parameter dataclass as a plain JSON/TOML-ready dict (tuples become lists; ``None`` gives ``{}``).

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> @dataclass(frozen=True)
    ... class Grid:
    ...     cells: tuple = (4, 4)
    ...     size: float | None = None
    >>> params_to_dict(Grid()), params_to_dict(None)
    ({'cells': [4, 4], 'size': None}, {})
    """
    if params is None:
        return {}
    return {f.name: _plain(getattr(params, f.name)) for f in dataclasses.fields(params)}


def _plain(value: Any) -> Any:
    if isinstance(value, tuple):
        return [_plain(v) for v in value]
    return value
