"""``depthrefine board``: a printable checkerboard or ChArUco board (PNG at a resolution, PDF at true size)."""

from __future__ import annotations

import argparse
import sys

from ..io._names import PAPER_SIZES_MM
from . import CliError
from ._common import add_overwrite
from .calibrate import add_board_options, board_from_args


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "board",
        help="make a printable calibration board (checkerboard or ChArUco) as PDF or PNG",
        description=(
            "Draw the board `calibrate` and `calibrate-stereo` look for, with the same --board, --square, "
            "--marker and --dictionary. A .pdf holds it at true size on one A4 or Letter page, with the square's "
            "side and a ruler bar in the margin to check the print; a .png holds it at --dpi (recorded in the "
            "file), one square being round(square / 25.4 mm * dpi) pixels. A checkerboard gets one square of "
            "white border, which OpenCV needs to find it; a ChArUco board half a square."
        ),
    )
    add_board_options(p, fit=False)
    p.add_argument("-o", "--output", required=True, metavar="OUT", help="board.pdf or board.png")
    p.add_argument("--dpi", type=int, default=300, metavar="N", help="PNG: dots per inch (default 300)")
    p.add_argument("--paper", choices=tuple(PAPER_SIZES_MM), default="A4", help="PDF: paper size (default A4)")
    add_overwrite(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..io import write_board_pdf, write_board_png

    board = board_from_args(args)
    suffix = args.output.lower().rsplit(".", 1)[-1] if "." in args.output else ""
    if suffix == "pdf":
        out = write_board_pdf(args.output, board, paper=args.paper, overwrite=args.overwrite)
        print(f"wrote {out}: {board.describe()} at true size on {args.paper}; print at 100 % and check the square "
              "with a ruler", file=sys.stderr)
    elif suffix == "png":
        if not 50 <= args.dpi <= 2400:
            raise CliError(f"--dpi must be between 50 and 2400; got {args.dpi}.")
        out, square_mm = write_board_png(args.output, board, dpi=args.dpi, overwrite=args.overwrite)
        print(f"wrote {out}: {board.describe()}; at {args.dpi} dpi one square prints {square_mm:.2f} mm",
              file=sys.stderr)
    else:
        raise CliError(f"output {args.output}: write the board as .pdf (true size) or .png (at --dpi).")
    return 0
