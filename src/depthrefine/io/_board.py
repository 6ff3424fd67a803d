"""Printable calibration boards: PNG at a given resolution, PDF at true size on A4 or Letter."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..rig.boards import Board, render_board
from ._files import InputFileError, atomic_write, check_output
from ._names import PAPER_SIZES_MM

__all__ = ["PAPER_SIZES_MM", "PAGE_MARGIN_MM", "write_board_png", "write_board_pdf"]

#: White margin kept on every side of the page (printers cannot print to the edge), millimetres.
PAGE_MARGIN_MM = 6.0
#: Space under the board for the ruler bar and the check line, millimetres.
_FOOTER_MM = 11.0
_MM_PER_INCH = 25.4


def _quiet_zone(board: Board) -> float:
    """White border around the squares, in squares: a checkerboard needs one square to be found."""
    return 1.0 if board.kind == "checkerboard" else 0.5


def write_board_png(path: str | os.PathLike, board: Board, *, dpi: int, overwrite: bool = False) -> tuple[Path, float]:
    """Write the board as an 8-bit gray PNG at ``dpi`` (recorded in the file); return (path, square side in mm).

    One square is ``round(square_size / 25.4 mm * dpi)`` pixels, so the printed
    square is that many pixels / dpi inches (the returned size; it differs
    from the board's by the rounding).
    """
    from PIL import Image

    p = check_output(path, overwrite=overwrite, what="output", suffixes=(".png",))
    pixels = int(round(board.square_size * 1000 / _MM_PER_INCH * dpi))
    least = 10 if board.kind == "charuco" else 1
    if pixels < least:
        raise InputFileError(f"--dpi {dpi} gives {pixels} pixel(s) per square; a {board.kind} board needs at least "
                             f"{least}: raise --dpi.")
    image = render_board(board, pixels, margin=int(round(_quiet_zone(board) * pixels)))

    def _write(tmp: Path) -> None:
        Image.fromarray(image).save(tmp, format="PNG", dpi=(dpi, dpi))

    return atomic_write(p, _write, overwrite=overwrite), pixels / dpi * _MM_PER_INCH


def write_board_pdf(path: str | os.PathLike, board: Board, *, paper: str = "A4", overwrite: bool = False) -> Path:
    """Write the board at true size on one page of ``paper`` ("A4" or "Letter"), with a check line and a ruler bar.

    The page is portrait or landscape, whichever holds the board, and the
    paper around the squares is their white border; the margin says the
    square's side and carries a bar of known length to check the
    print with a ruler (print at 100 %, no "fit to page").

    Raises
    ------
    InputFileError
        The board (with its white border) does not fit on the page.
    """
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    if paper not in PAPER_SIZES_MM:
        raise ValueError(f"paper must be one of {list(PAPER_SIZES_MM)}; got {paper!r}.")
    p = check_output(path, overwrite=overwrite, what="output", suffixes=(".pdf",))
    square_mm = board.square_size * 1000
    # The white border the detector needs is the page itself around the squares.
    board_w = board.squares[0] * square_mm
    board_h = board.squares[1] * square_mm
    page = None
    for w, h in (PAPER_SIZES_MM[paper], PAPER_SIZES_MM[paper][::-1]):
        if board_w <= w - 2 * PAGE_MARGIN_MM and board_h <= h - 2 * PAGE_MARGIN_MM - _FOOTER_MM:
            page = (w, h)
            break
    if page is None:
        raise InputFileError(
            f"the {board.describe()} is {board_w:.0f} x {board_h:.0f} mm; it does not fit on "
            f"{paper} ({PAPER_SIZES_MM[paper][0]:g} x {PAPER_SIZES_MM[paper][1]:g} mm, {PAGE_MARGIN_MM:g} mm margins). "
            "Use a smaller --square (and --marker), fewer squares, or write a PNG (-o board.png --dpi N) and "
            "have it printed at that size."
        )
    w, h = page
    pixels = 120 if board.kind == "charuco" else 20  # shown with nearest sampling: the squares stay exact
    image = render_board(board, pixels)
    fig = Figure(figsize=(w / _MM_PER_INCH, h / _MM_PER_INCH))
    left = (w - board_w) / 2
    bottom = PAGE_MARGIN_MM + _FOOTER_MM + (h - 2 * PAGE_MARGIN_MM - _FOOTER_MM - board_h) / 2
    ax = fig.add_axes((left / w, bottom / h, board_w / w, board_h / h))
    ax.imshow(image, cmap="gray", vmin=0, vmax=255, interpolation="nearest", aspect="auto")
    ax.set_axis_off()
    bar_mm = 100.0 if w - 2 * PAGE_MARGIN_MM >= 120 else 50.0
    page_ax = fig.add_axes((0, 0, 1, 1), facecolor="none")
    page_ax.set_xlim(0, w)
    page_ax.set_ylim(0, h)
    page_ax.set_axis_off()
    y_bar = PAGE_MARGIN_MM
    page_ax.add_patch(Rectangle((PAGE_MARGIN_MM, y_bar), bar_mm, 1.0, color="black", linewidth=0))
    for tick in np.arange(0, bar_mm + 1e-9, 10.0):
        page_ax.add_patch(Rectangle((PAGE_MARGIN_MM + tick - 0.15, y_bar), 0.3, 3.0, color="black", linewidth=0))
    page_ax.text(PAGE_MARGIN_MM + bar_mm + 3, y_bar, f"{bar_mm:g} mm", fontsize=8, va="bottom")
    page_ax.text(PAGE_MARGIN_MM, y_bar + 4.5,
                 f"{board.describe()} ({board.spec}). One square = {square_mm:g} mm, the bar = {bar_mm:g} mm: "
                 "check both with a ruler. Print at 100 % (no 'fit to page'); keep the board flat.",
                 fontsize=7, va="bottom", wrap=True)

    def _write(tmp: Path) -> None:
        fig.savefig(tmp, format="pdf", metadata={"CreationDate": None, "Creator": "depthrefine board"})

    return atomic_write(p, _write, overwrite=overwrite)
