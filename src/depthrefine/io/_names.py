"""Names and defaults of :mod:`depthrefine.io` that the command line shows, importable without numpy.

``depthrefine demo --help``, ``board --help`` and ``batch --help`` show these
without importing the readers (fast start-up, issue 13); the modules that
use them import them from here.
"""

from __future__ import annotations

__all__ = ["SCENES", "SAMPLE_SCALES", "PAPER_SIZES_MM", "DEFAULT_MAX_DT"]

#: The shipped scenes (``depthrefine demo --scene``).
SCENES = ("art", "mug", "bookshelf")

#: Scale factors of the shipped low-resolution inputs.
SAMPLE_SCALES = (4, 8, 16)

#: Paper sizes (width, height) in millimetres, portrait.
PAPER_SIZES_MM = {"A4": (210.0, 297.0), "Letter": (215.9, 279.4)}

#: Default pairing tolerance for bags, seconds.
DEFAULT_MAX_DT = 0.020
