"""gbp's command-line options (``--snap-edges``, ``--sampling``, ``--reprojected``; gbp-fast shares all three).

Its registry entry declares them (``Method.options``); the command line adds
them to every refining command under "gbp method options". Light: no numpy,
so that ``--help`` stays fast.
"""

from __future__ import annotations

import argparse

from ..options import MethodOption

__all__ = ["OPTIONS", "REPROJECTED", "SAMPLING", "SNAP_EDGES", "SAMPLING_MODELS", "check_sampling"]

#: The sampling models ``GbpParams.sampling`` names (``measure.SAMPLING_FOOTPRINT`` says what each stands for).
SAMPLING_MODELS = ("auto", "point", "mean")


def _sampling_error(value: object) -> str | None:
    """What is wrong with ``value`` as a sampling model, or None."""
    if isinstance(value, str) and value in SAMPLING_MODELS:
        return None
    return f"must be one of {', '.join(map(repr, SAMPLING_MODELS))}; got {value!r}"


def check_sampling(value: object) -> None:
    """Raise ValueError unless ``value`` is one of :data:`SAMPLING_MODELS`."""
    if (error := _sampling_error(value)) is not None:
        raise ValueError(f"sampling {error}.")


def parse_sampling(text: str) -> str:
    """``--sampling``'s value: one of :data:`SAMPLING_MODELS`."""
    if (error := _sampling_error(text)) is not None:
        raise argparse.ArgumentTypeError(error + ".")
    return text


#: ``--reprojected``, shared by gbp and gbp-fast.
REPROJECTED = MethodOption(
    "--reprojected", "reprojected", switch=True,
    help="(gbp and gbp-fast) the depth was reprojected onto the color camera from a depth camera beside it, "
         "e.g. aligned by the camera's SDK, as ARKit's iPhone LiDAR depth is (GbpParams.reprojected): smooth at "
         "least as much as lambda_lr = 2, as its samples sit a fraction of a pixel off, and move the map back by "
         "the shift its depth edges show against the color edges; run and batch with a rig set it themselves")

#: ``--sampling``, shared by gbp and gbp-fast.
SAMPLING = MethodOption(
    "--sampling", "sampling", type=parse_sampling, metavar="{auto,point,mean}",
    help="(gbp and gbp-fast) what each depth pixel is (GbpParams.sampling): mean = the mean over its footprint "
         "(ToF, area downsampling), point = the depth at its block's centre (depth[s//2::s, s//2::s] of a map; "
         "samples taken elsewhere, such as depth[::s, ::s], do worse than auto), auto (default) = measured from "
         "the input, which cannot tell when the map was smooth before it was sampled")

#: ``--snap-edges``, shared by gbp and gbp-fast.
SNAP_EDGES = MethodOption(
    "--snap-edges", "snap_edges", switch=True,
    help="(gbp and gbp-fast) move each large depth jump onto the color edge within two depth pixels "
         "(GbpParams.snap_edges): for cameras whose depth edges sit off the color edges, such as iPhone LiDAR "
         "(sofa outline 6.3 -> 1.4 px off); it can follow texture edges, so it is off by default")

#: gbp's options, in the order ``--help`` lists them.
OPTIONS = (SNAP_EDGES, SAMPLING, REPROJECTED)
