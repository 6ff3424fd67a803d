"""Calibration boards: what a board is, finding its corners in an image, and its printable picture.

Two kinds of board, as OpenCV knows them:

``checkerboard``
    Black and white squares; OpenCV finds all inner corners or none, so the
    whole board must be in view. Described by its *inner* corners
    ``(cols, rows)`` (a board of 10 x 7 squares is ``9x6``).
``charuco``
    A checkerboard whose white squares hold ArUco markers
    (``cv2.aruco.CharucoBoard``), described by its *squares* ``(cols, rows)``
    as OpenCV counts them, the square and marker sides and the marker
    dictionary. Every inner corner is identified by the markers around it, so
    a view that shows part of the board still counts.

A detection is a :class:`BoardView`: the ids of the corners found (indices
into :attr:`Board.points`) and their pixel positions. Object points are in
metres in the board's plane (Z = 0), X across and Y down from the first
inner corner (checkerboard) or from the board's top-left corner (ChArUco,
OpenCV's convention).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from .._lazy import cv2
from .._validate import is_int

__all__ = [
    "BOARD_KINDS",
    "DICTIONARIES",
    "MIN_VIEW_CORNERS",
    "Board",
    "BoardView",
    "board_points",
    "to_gray8",
    "find_board_corners",
    "detect_board",
    "render_board",
    "check_dictionary",
    "usable",
]

#: The kinds of calibration board.
BOARD_KINDS = ("checkerboard", "charuco")

#: OpenCV's predefined ArUco dictionaries, by name (``cv2.aruco.DICT_*``).
DICTIONARIES = tuple(sorted({name.upper(): name for name in sorted(dir(cv2.aruco), reverse=True)
                             if name.startswith("DICT_")}.values()))

#: Fewest corners a ChArUco view needs to count (a homography needs 4 that are
#: not collinear; 6 leaves a margin against one bad corner).
MIN_VIEW_CORNERS = 6

_SUBPIX_CRITERIA = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 50, 1e-4)


def board_points(board: tuple[int, int], square_size: float) -> np.ndarray:
    """The inner corners of a checkerboard in its own plane (Z = 0), in OpenCV's order.

    Parameters
    ----------
    board : (int, int)
        Inner corners ``(cols, rows)``.
    square_size : float
        Side of a square, metres.

    Returns
    -------
    (cols * rows, 3) float32 ndarray
        Row by row, ``cols`` corners each: ``(col * size, row * size, 0)``.

    Examples
    --------
    >>> board_points((3, 2), 0.5)[:4].tolist()
    [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.5, 0.0]]
    """
    cols, rows = _check_board(board)
    size = _check_square(square_size)
    grid = np.mgrid[0:rows, 0:cols].astype(np.float32)
    pts = np.zeros((rows * cols, 3), np.float32)
    pts[:, 0] = grid[1].ravel() * size
    pts[:, 1] = grid[0].ravel() * size
    return pts


def to_gray8(image: np.ndarray) -> np.ndarray:
    """An 8-bit gray version of an intensity or color image, for corner detection.

    8-bit images are only converted to gray. 16-bit and float images (ToF
    amplitude) are stretched so that the 0.5th-99.5th percentiles of their
    finite values span 0..255.

    Examples
    --------
    >>> to_gray8(np.array([[0, 1000], [2000, 4000]], np.uint16)).tolist()
    [[0, 64], [128, 255]]
    """
    if not isinstance(image, np.ndarray):
        raise TypeError(f"image must be a numpy array; got {type(image).__name__}.")
    if image.ndim == 3 and image.shape[2] in (3, 4):
        if image.dtype == np.uint8 or image.dtype == np.uint16 or image.dtype == np.float32:
            image = cv2.cvtColor(np.ascontiguousarray(image[:, :, :3]), cv2.COLOR_RGB2GRAY)
        else:
            image = image[:, :, :3].astype(np.float64) @ np.array([0.299, 0.587, 0.114])
    elif image.ndim == 3 and image.shape[2] == 1:
        image = image[:, :, 0]
    if image.ndim != 2:
        raise ValueError(f"image must be (rows, cols) or (rows, cols, 3); got shape {image.shape}.")
    if image.dtype == np.uint8:
        return np.ascontiguousarray(image)
    values = image.astype(np.float64)
    finite = np.isfinite(values)
    if not finite.any():
        raise ValueError("image has no finite pixel.")
    lo, hi = np.percentile(values[finite], [0.5, 99.5])
    if hi <= lo:
        hi = lo + 1.0
    out = np.clip((np.where(finite, values, lo) - lo) * (255.0 / (hi - lo)), 0, 255)
    return np.floor(out + 0.5).astype(np.uint8)


def find_board_corners(image: np.ndarray, board: tuple[int, int]) -> np.ndarray | None:
    """Find a checkerboard's inner corners to sub-pixel accuracy.

    Parameters
    ----------
    image : (rows, cols) or (rows, cols, 3) ndarray
        Intensity (any dtype) or RGB image.
    board : (int, int)
        Inner corners ``(cols, rows)``.

    Returns
    -------
    (cols * rows, 2) float32 ndarray or None
        Corner positions ``(x, y)`` = (column, row) in pixels, in
        :func:`board_points` order, the first corner being the one nearest
        the image's top-left; ``None`` if the board is not found.
    """
    cols, rows = _check_board(board)
    gray = to_gray8(image)
    flags = cv2.CALIB_CB_ADAPTIVE_THRESH | cv2.CALIB_CB_NORMALIZE_IMAGE
    found, corners = cv2.findChessboardCorners(gray, (cols, rows), flags=flags)
    if found:
        corners = corners.reshape(-1, 2).astype(np.float32)
        step = _corner_spacing(corners, cols, rows)
        half = int(np.clip(np.floor(step * 0.4), 2, 11))
        refined = cv2.cornerSubPix(gray, corners.reshape(-1, 1, 2).copy(), (half, half), (-1, -1),
                                   _SUBPIX_CRITERIA)
        corners = refined.reshape(-1, 2)
    else:
        found, corners = cv2.findChessboardCornersSB(gray, (cols, rows), flags=cv2.CALIB_CB_ACCURACY)
        if not found:
            return None
        corners = corners.reshape(-1, 2).astype(np.float32)
    # OpenCV's order is defined up to a half turn of the board: put the first
    # corner top-left so that two cameras of an upright rig agree.
    if corners[0].sum() > corners[-1].sum():
        corners = corners[::-1].copy()
    return np.ascontiguousarray(corners, dtype=np.float32)


@dataclass(frozen=True)
class Board:
    """A calibration board: its kind, layout and sizes.

    Build one with :meth:`checkerboard` or :meth:`charuco`.

    Attributes
    ----------
    kind : {"checkerboard", "charuco"}
    squares : (int, int)
        Squares across and down (a checkerboard of 9 x 6 inner corners has 10 x 7).
    square_size : float
        Side of a square, metres.
    marker_size : float or None
        ChArUco: side of a marker, metres (smaller than ``square_size``).
    dictionary : str or None
        ChArUco: the OpenCV predefined dictionary, e.g. ``"DICT_5X5_250"``.

    Examples
    --------
    >>> board = Board.charuco((14, 9), 0.04, 0.03, "DICT_5X5_250")
    >>> board.inner_corners, board.points.shape, board.size_m
    ((13, 8), (104, 3), (0.56, 0.36))
    >>> Board.checkerboard((9, 6), 0.025).describe()
    'checkerboard 9x6 (inner corners), 25 mm squares'
    """

    kind: str
    squares: tuple[int, int]
    square_size: float
    marker_size: float | None = None
    dictionary: str | None = None

    def __post_init__(self) -> None:
        if self.kind not in BOARD_KINDS:
            raise ValueError(f"board kind must be one of {list(BOARD_KINDS)}; got {self.kind!r}.")
        cols, rows = _check_board(self.squares, what="squares", least=3 if self.kind == "checkerboard" else 2)
        object.__setattr__(self, "squares", (cols, rows))
        object.__setattr__(self, "square_size", _check_square(self.square_size))
        if self.kind == "checkerboard":
            if self.marker_size is not None or self.dictionary is not None:
                raise ValueError("a checkerboard has no markers; marker_size and dictionary are for ChArUco boards.")
            return
        if self.marker_size is None:
            raise ValueError("a ChArUco board needs marker_size (the side of a marker, metres).")
        marker = _check_square(self.marker_size, "marker_size")
        if marker >= self.square_size:
            raise ValueError(
                f"marker_size ({marker * 1000:g} mm) must be smaller than square_size "
                f"({self.square_size * 1000:g} mm): the marker sits inside a white square."
            )
        object.__setattr__(self, "marker_size", marker)
        object.__setattr__(self, "dictionary", check_dictionary(self.dictionary))
        n_markers = (cols * rows) // 2
        available = _opencv_dictionary(self.dictionary).bytesList.shape[0]
        if n_markers > available:
            raise ValueError(
                f"a {cols}x{rows} ChArUco board needs {n_markers} markers but {self.dictionary} has {available}; "
                "choose a larger dictionary (e.g. DICT_5X5_250) or a smaller board."
            )

    @classmethod
    def checkerboard(cls, inner_corners: tuple[int, int], square_size: float) -> "Board":
        """A checkerboard with ``inner_corners = (cols, rows)`` as OpenCV counts them."""
        cols, rows = _check_board(inner_corners)
        return cls("checkerboard", (cols + 1, rows + 1), square_size)

    @classmethod
    def charuco(cls, squares: tuple[int, int], square_size: float, marker_size: float,
                dictionary: str = "DICT_5X5_250") -> "Board":
        """A ChArUco board with ``squares = (cols, rows)`` as ``cv2.aruco.CharucoBoard`` counts them."""
        return cls("charuco", tuple(squares), square_size, marker_size, dictionary)

    @property
    def inner_corners(self) -> tuple[int, int]:
        """``(cols, rows)`` of inner corners."""
        return self.squares[0] - 1, self.squares[1] - 1

    @property
    def size_m(self) -> tuple[float, float]:
        """``(width, height)`` of the squares' area, metres."""
        return (round(self.squares[0] * self.square_size, 9), round(self.squares[1] * self.square_size, 9))

    @property
    def points(self) -> np.ndarray:
        """``(N, 3)`` float32 object points of the inner corners, metres; row ``i`` is corner id ``i``."""
        if self.kind == "checkerboard":
            return board_points(self.inner_corners, self.square_size)
        return np.asarray(self._opencv().getChessboardCorners(), np.float32).reshape(-1, 3)

    @property
    def spec(self) -> str:
        """The command-line spelling: ``"9x6"`` or ``"charuco:14x9"``."""
        if self.kind == "checkerboard":
            return "{}x{}".format(*self.inner_corners)
        return "charuco:{}x{}".format(*self.squares)

    def describe(self) -> str:
        """One line for the user."""
        mm = f"{self.square_size * 1000:g} mm squares"
        if self.kind == "checkerboard":
            return f"checkerboard {self.spec} (inner corners), {mm}"
        return (f"ChArUco board {self.squares[0]}x{self.squares[1]} squares, {mm}, "
                f"{self.marker_size * 1000:g} mm markers, {self.dictionary}")

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready description (recorded in camera and rig files)."""
        out: dict[str, Any] = {"kind": self.kind, "spec": self.spec, "squares": list(self.squares),
                               "square_size_m": self.square_size}
        if self.kind == "charuco":
            out.update(marker_size_m=self.marker_size, dictionary=self.dictionary)
        return out

    def _opencv(self) -> Any:
        return _opencv_charuco(self.squares, self.square_size, self.marker_size, self.dictionary)


@dataclass(frozen=True, eq=False)
class BoardView:
    """The corners of a board found in one image.

    Attributes
    ----------
    ids : (N,) int32 ndarray
        Corner ids: rows of :attr:`Board.points`, ascending.
    corners : (N, 2) float32 ndarray
        Their positions ``(x, y)`` = (column, row), pixels.
    markers : int
        ChArUco: markers decoded (0 for a checkerboard).
    """

    ids: np.ndarray
    corners: np.ndarray
    markers: int = 0

    @property
    def count(self) -> int:
        """Number of corners found."""
        return int(self.ids.size)


def check_dictionary(name: Any) -> str:
    """The name of an OpenCV predefined ArUco dictionary, checked (``ValueError`` lists the names)."""
    if not isinstance(name, str) or name.upper() not in {d.upper() for d in DICTIONARIES}:
        raise ValueError(
            f"unknown ArUco dictionary {name!r}; use one of OpenCV's predefined dictionaries: "
            f"{', '.join(DICTIONARIES)}."
        )
    return next(d for d in DICTIONARIES if d.upper() == name.upper())


def usable(view: BoardView | None, board: Board) -> bool:
    """True if ``view`` can enter a calibration (all corners of a checkerboard; 6 non-collinear ChArUco corners)."""
    if view is None:
        return False
    if board.kind == "checkerboard":
        return view.count == board.points.shape[0]
    if view.count < MIN_VIEW_CORNERS:
        return False
    return not bool(board._opencv().checkCharucoCornersCollinear(view.ids.reshape(-1, 1)))


def detect_board(image: np.ndarray, board: Board) -> BoardView:
    """Find a board's corners in an image.

    Parameters
    ----------
    image : (rows, cols) or (rows, cols, 3) ndarray
        Intensity (any dtype) or RGB image.
    board : Board

    Returns
    -------
    BoardView
        Possibly empty (``count == 0``). A checkerboard gives all its corners
        or none (:func:`find_board_corners`); a ChArUco board the corners
        identified by the markers around them, refined to sub-pixel accuracy
        by OpenCV's ``CharucoDetector``. See :func:`usable` for whether a
        view can be used.
    """
    if not isinstance(board, Board):
        raise TypeError(f"board must be a Board; got {type(board).__name__}.")
    if board.kind == "checkerboard":
        corners = find_board_corners(image, board.inner_corners)
        if corners is None:
            return BoardView(np.zeros(0, np.int32), np.zeros((0, 2), np.float32))
        return BoardView(np.arange(corners.shape[0], dtype=np.int32), corners)
    gray = to_gray8(image)
    detector = cv2.aruco.CharucoDetector(board._opencv())
    corners, ids, _, marker_ids = detector.detectBoard(gray)
    markers = 0 if marker_ids is None else int(len(marker_ids))
    if ids is None or len(ids) == 0:
        return BoardView(np.zeros(0, np.int32), np.zeros((0, 2), np.float32), markers)
    ids = np.asarray(ids, np.int32).ravel()
    corners = np.asarray(corners, np.float32).reshape(-1, 2)
    order = np.argsort(ids, kind="stable")
    return BoardView(ids[order], np.ascontiguousarray(corners[order]), markers)


def render_board(board: Board, pixels_per_square: int, *, margin: int = 0) -> np.ndarray:
    """The board as an 8-bit gray picture (white 255, black 0), for printing.

    Parameters
    ----------
    board : Board
    pixels_per_square : int
        Side of a square in pixels (>= 10 for a ChArUco board, whose markers
        need a few pixels per bit).
    margin : int
        White border around the squares, pixels (a checkerboard needs one
        square of white around it to be found reliably).

    Returns
    -------
    (rows * p + 2 * margin, cols * p + 2 * margin) uint8 ndarray

    Examples
    --------
    >>> img = render_board(Board.checkerboard((3, 2), 0.01), 4)
    >>> img.shape, int(img[0, 0]), int(img[0, 4])
    ((12, 16), 0, 255)
    """
    if not isinstance(board, Board):
        raise TypeError(f"board must be a Board; got {type(board).__name__}.")
    p = int(pixels_per_square)
    least = 10 if board.kind == "charuco" else 1
    if isinstance(pixels_per_square, bool) or not is_int(pixels_per_square) or p < least:
        raise ValueError(f"pixels_per_square must be an integer >= {least}; got {pixels_per_square!r}.")
    if not is_int(margin) or margin < 0:
        raise ValueError(f"margin must be an integer >= 0; got {margin!r}.")
    cols, rows = board.squares
    if board.kind == "checkerboard":
        r, c = np.indices((rows * p, cols * p))
        squares = np.where(((r // p) + (c // p)) % 2 == 0, 0, 255).astype(np.uint8)
    else:
        squares = board._opencv().generateImage((cols * p, rows * p), marginSize=0, borderBits=1)
    return np.pad(squares, int(margin), constant_values=255)



def _check_board(board: Any, *, what: str = "inner corners", least: int = 2) -> tuple[int, int]:
    if (isinstance(board, (str, bytes)) or not hasattr(board, "__len__") or len(board) != 2
            or not all(is_int(v) for v in board)):
        raise TypeError(f"board must be two integers (cols, rows) of {what}; got {board!r}.")
    cols, rows = int(board[0]), int(board[1])
    if cols < least or rows < least:
        raise ValueError(f"board must have at least {least}x{least} {what}; got {cols}x{rows}.")
    return cols, rows


def _check_square(square_size: Any, name: str = "square_size") -> float:
    if isinstance(square_size, bool) or not isinstance(square_size, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a number (metres); got {square_size!r}.")
    if not (math.isfinite(square_size) and square_size > 0):
        raise ValueError(f"{name} must be > 0 metres; got {square_size}.")
    return float(square_size)


@lru_cache(maxsize=None)
def _opencv_dictionary(name: str) -> Any:
    return cv2.aruco.getPredefinedDictionary(getattr(cv2.aruco, name))


@lru_cache(maxsize=16)
def _opencv_charuco(squares: tuple[int, int], square: float, marker: float, dictionary: str) -> Any:
    return cv2.aruco.CharucoBoard(squares, square, marker, _opencv_dictionary(dictionary))


def _corner_spacing(corners: np.ndarray, cols: int, rows: int) -> float:
    """Smallest distance between neighbouring corners, pixels."""
    grid = corners.reshape(rows, cols, 2)
    across = np.linalg.norm(np.diff(grid, axis=1), axis=2)
    down = np.linalg.norm(np.diff(grid, axis=0), axis=2)
    return float(min(across.min(), down.min()))
