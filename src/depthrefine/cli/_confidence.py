"""``--confidence`` and ``--min-confidence`` for ``refine``, ``run`` and ``batch`` (issue 23), defined once.

The commands call these helpers so that each of them gains the options in a
few lines: :func:`add_confidence_options` at parser time (no numpy),
:func:`check_confidence_output` before any work, :func:`refine_maybe_confident`
instead of ``refine``, and :func:`apply_min_confidence` before writing.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

if TYPE_CHECKING:
    import numpy as np

__all__ = ["CONFIDENCE_FORMATS", "add_confidence_options", "parse_confidence_level", "wants_confidence",
           "check_confidence_output", "refine_maybe_confident", "refine_pair_maybe_confident", "apply_min_confidence", "confidence_note",
           "read_shown_confidence"]

#: ``batch --confidence FORMAT``: the file types of OUTDIR/confidence/<stem>.<FORMAT>.
CONFIDENCE_FORMATS = ("tif", "npy", "png")

_FORMATS_HELP = ".tif or .npy (float32 in 0..1) or .png (16-bit, confidence x 65535)"


def parse_confidence_level(text: str) -> float:
    """``--min-confidence C``: a number in [0, 1]."""
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not (math.isfinite(value) and 0.0 <= value <= 1.0):
        raise argparse.ArgumentTypeError(f"expected a confidence between 0 and 1 such as 0.5; got {text!r}")
    return value


def add_confidence_options(parser: argparse.ArgumentParser, *, folder: bool = False) -> None:
    """``--confidence`` (a file, or with ``folder`` a format for OUTDIR/confidence/) and ``--min-confidence``."""
    if folder:
        parser.add_argument(
            "--confidence", metavar="FORMAT", choices=CONFIDENCE_FORMATS,
            help="also write each frame's confidence map (0..1, 1 = most trusted, 0 = no depth) as "
                 "OUTDIR/confidence/<stem>.<FORMAT>: tif or npy (float32) or png (16-bit, confidence x 65535)")
    else:
        parser.add_argument(
            "--confidence", metavar="FILE",
            help=f"also write the confidence map (0..1, 1 = most trusted, 0 = no depth) on the output's grid: "
                 f"{_FORMATS_HELP}")
    parser.add_argument(
        "--min-confidence", type=parse_confidence_level, metavar="C",
        help="write 0 (no measurement) in the depth where the confidence is below C (0..1; e.g. 0.5: an "
             "expected error of more than 2 levels of the depth range)")


def wants_confidence(args: argparse.Namespace) -> bool:
    """Whether the run needs a confidence map (``--confidence`` or ``--min-confidence``)."""
    return bool(getattr(args, "confidence", None)) or getattr(args, "min_confidence", None) is not None


def check_confidence_output(args: argparse.Namespace, *, inputs: tuple, taken: tuple = ()) -> Path | None:
    """The ``--confidence`` file, checked before any work (format, existing file, inputs, other outputs)."""
    from ..io import CONFIDENCE_SUFFIXES, check_confidence_format, check_output

    if not args.confidence:
        return None
    check_confidence_format(args.confidence, what="--confidence file")
    path = check_output(args.confidence, overwrite=args.overwrite, suffixes=CONFIDENCE_SUFFIXES, inputs=inputs,
                        what="--confidence file")
    for other in taken:
        if other is not None and Path(other).resolve() == path.resolve():
            raise ValueError(f"--confidence {args.confidence} is also another output file; give it its own name.")
    return path


def refine_maybe_confident(args: argparse.Namespace, depth_lr: np.ndarray, rgb_hr: np.ndarray, *, method: str,
                           params: Any, progress: Callable[[int, int], None] | None = None
                           ) -> tuple[np.ndarray, np.ndarray | None]:
    """``refine``'s depth, and its confidence map when the options ask for one (else None)."""
    from ..methods.confidence import refine_with_confidence
    from ..methods.registry import refine

    if wants_confidence(args):
        return refine_with_confidence(depth_lr, rgb_hr, method=method, params=params, progress=progress)
    return refine(depth_lr, rgb_hr, method=method, params=params, progress=progress), None


def refine_pair_maybe_confident(args: argparse.Namespace, depth_lr: np.ndarray, rgb_hr: np.ndarray, *, method: str,
                                params: Any, progress: Callable[[int, int], None] | None = None
                                ) -> tuple[np.ndarray, np.ndarray | None, str]:
    """``run``'s refinement of an aligned pair (:func:`depthrefine.rig.chain.refine_pair`), its confidence map on
    the same grid when the options ask for one (else None), and the scale step's note."""
    from ..methods.confidence import confidence_on_grid, refine_with_confidence
    from ..rig.chain import refine_pair

    if not wants_confidence(args):
        depth_hr, note = refine_pair(depth_lr, rgb_hr, method=method, params=params, progress=progress)
        return depth_hr, None, note
    kept: list = []

    def solve(depth, rgb):
        depth_out, confidence = refine_with_confidence(depth, rgb, method=method, params=params, progress=progress)
        kept.append(confidence)
        return depth_out

    depth_hr, note = refine_pair(depth_lr, rgb_hr, method=method, solve=solve)
    return depth_hr, confidence_on_grid(kept[0], depth_hr), note


def apply_min_confidence(depth_hr: np.ndarray, confidence: np.ndarray | None,
                         minimum: float | None) -> tuple[np.ndarray, np.ndarray | None]:
    """``--min-confidence``: :func:`depthrefine.methods.confidence.apply_min_confidence`."""
    from ..methods.confidence import apply_min_confidence as apply

    return apply(depth_hr, confidence, minimum)


def confidence_note(confidence: np.ndarray, minimum: float | None) -> str:
    """One line for stderr: the median confidence of the pixels with depth, and what ``--min-confidence`` removed.

    Call it before :func:`apply_min_confidence`.
    """
    import numpy as np

    measured = confidence > 0
    median = float(np.median(confidence[measured])) if measured.any() else 0.0
    note = f"median confidence {median:.2f}"
    if minimum is not None:
        note += (f"; {100.0 * float(np.mean(measured & (confidence < minimum))):.1f} % of pixels below "
                 f"--min-confidence {minimum:g} written as 0")
    return note


def read_shown_confidence(path: str, shape: tuple[int, int]) -> np.ndarray:
    """``show --confidence FILE``: the map, which must lie on the depth's grid."""
    from ..io import InputFileError, read_confidence

    confidence = read_confidence(path)
    if confidence.shape != tuple(shape):
        raise InputFileError(f"--confidence {path} is {confidence.shape[1]}x{confidence.shape[0]} but the depth is "
                             f"{shape[1]}x{shape[0]}; give the confidence map written with this depth.")
    return confidence
