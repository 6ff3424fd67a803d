"""gbp-fast's command-line options: gbp's ``--snap-edges``, ``--sampling`` and ``--reprojected`` (``_options``).

Its registry entry declares them (``Method.options``). Light: no numpy.
"""

from __future__ import annotations

from ._options import REPROJECTED, SAMPLING, SNAP_EDGES

__all__ = ["OPTIONS"]

#: The options, in the order ``--help`` lists them.
OPTIONS = (SNAP_EDGES, SAMPLING, REPROJECTED)
