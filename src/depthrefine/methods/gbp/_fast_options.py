"""gbp-fast's command-line options: gbp's ``--sampling`` and ``--reprojected`` (``_options``).

Its registry entry declares them (``Method.options``). Light: no numpy.
"""

from __future__ import annotations

from ._options import REPROJECTED, SAMPLING

__all__ = ["OPTIONS"]

#: The options, in the order ``--help`` lists them.
OPTIONS = (SAMPLING, REPROJECTED)
