"""gbp's command-line options (``--snap-edges``, ``--reprojected``; gbp-fast shares the second: ``_fast_options``).

Its registry entry declares them (``Method.options``); the command line adds
them to every refining command under "gbp method options". Light: no numpy,
so that ``--help`` stays fast.
"""

from __future__ import annotations

from ..options import MethodOption

__all__ = ["OPTIONS", "REPROJECTED"]

#: ``--reprojected``, shared by gbp and gbp-fast.
REPROJECTED = MethodOption(
    "--reprojected", "reprojected", switch=True,
    help="(gbp and gbp-fast) the depth was reprojected onto the color camera from a depth camera beside it, "
         "e.g. aligned by the camera's SDK (GbpParams.reprojected): smooth at least as much as lambda_lr = 2, "
         "as its samples sit a fraction of a pixel off; run and batch with a rig set it themselves")

#: gbp's options, in the order ``--help`` lists them.
OPTIONS = (
    MethodOption("--snap-edges", "snap_edges", switch=True,
                 help="move each large depth jump onto the color edge within two depth pixels (GbpParams.snap_edges): "
                      "for cameras whose depth edges sit off the color edges, such as iPhone LiDAR (sofa outline 6.3 "
                      "-> 1.4 px off); it can follow texture edges, so it is off by default"),
    REPROJECTED,
)
