"""The thesis method's command-line options (``--patches``, ``--patch-file``, ``--clusters``).

Its registry entry declares them (``Method.options``); the command line adds
them to every refining command under "thesis method options". Light: no
numpy, so that ``--help`` stays fast.
"""

from __future__ import annotations

from ..options import MethodOption, parse_count, parse_grid, show_grid

__all__ = ["OPTIONS"]


def _read_patch_layout(path: str):
    from ...io import read_patch_layout

    return read_patch_layout(path)


#: The options, in the order ``--help`` lists them.
OPTIONS = (
    MethodOption("--patches", "patches", type=parse_grid, metavar="COLSxROWS", show=show_grid,
                 exclusive="patch layout", conflicts=("patch_layout",),
                 help="automatic patch grid: COLS patches across, ROWS down, columns first as in --board "
                      "(thesis default 4x4)"),
    MethodOption("--patch-file", "patch_layout", metavar="F", to_param=_read_patch_layout,
                 exclusive="patch layout",
                 help="manual patch layout: JSON list of [x, y, width, height] in color pixels"),
    MethodOption("--clusters", "n_clusters", type=parse_count, metavar="K",
                 help="k-means clusters per patch (thesis: 4)"),
)
