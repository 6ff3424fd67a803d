"""``depthrefine calibrate`` and ``depthrefine calibrate-stereo``: calibration from checkerboard or ChArUco images."""

from __future__ import annotations

import argparse
import re
import sys
from typing import TYPE_CHECKING

from ..rig._names import MIN_VIEWS
from . import CliError
from ._common import add_overwrite

if TYPE_CHECKING:  # what a command needs is imported where it runs: --help stays fast
    import numpy as np

    from ..rig.boards import Board, BoardView

_UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001}


def parse_board(text: str) -> tuple[str, tuple[int, int]]:
    """``"9x6"`` -> ``("checkerboard", (9, 6))`` inner corners; ``"charuco:14x9"`` -> ``("charuco", (14, 9))`` squares."""
    m = re.fullmatch(r"\s*(?:(charuco|checkerboard)\s*:\s*)?(\d+)\s*[xX*]\s*(\d+)\s*", text, flags=re.IGNORECASE)
    kind = (m.group(1) or "checkerboard").lower() if m else ""
    least = 3 if kind == "charuco" else 2
    if not m or int(m.group(2)) < least or int(m.group(3)) < least:
        raise argparse.ArgumentTypeError(
            "expected COLSxROWS: the inner corners of a checkerboard such as 9x6 (each >= 2), or the squares of "
            f"a ChArUco board as charuco:14x9 (each >= 3); got {text!r}")
    return kind, (int(m.group(2)), int(m.group(3)))


def parse_square(text: str) -> tuple[float, bool]:
    """``"0.025"``, ``"25mm"``, ``"2.5cm"``, ``"0.025m"`` -> (metres, unit given)."""
    m = re.fullmatch(r"\s*([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*(m|cm|mm)?\s*", text)
    if not m or float(m.group(1)) <= 0:
        raise argparse.ArgumentTypeError(
            f"expected the square's side as a positive length such as 25mm, 2.5cm or 0.025 (metres); got {text!r}")
    return float(m.group(1)) * _UNITS[m.group(2) or "m"], m.group(2) is not None


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "calibrate",
        help="calibrate a camera (the ToF camera's intensity images) from checkerboard or ChArUco images",
        description=(
            "Find a checkerboard or ChArUco board in each image (the ToF camera's intensity/amplitude images, "
            "thesis 3.2.1; a ChArUco view may show part of the board), "
            "fit OpenCV's pinhole + distortion model and write K, dist (OpenCV order), image_size "
            "[width, height] and the RMS reprojection error (pixels) as JSON. Images where the board is not "
            f"found are reported and skipped; at least {MIN_VIEWS} must remain (10-20 covering the image "
            "are best)."
        ),
    )
    p.add_argument("images", nargs="+", metavar="IMAGES", help="checkerboard images of one camera")
    add_board_options(p)
    p.add_argument("-o", "--output", required=True, metavar="OUT", help="camera file to write (.json)")
    add_overwrite(p)
    p.set_defaults(func=run_calibrate)

    s = sub.add_parser(
        "calibrate-stereo",
        help="calibrate a depth + color rig from pairs of checkerboard or ChArUco images",
        description=(
            "Pairs of images of the same board pose, one from the depth camera (intensity) and one from the "
            "color camera, in the same order. Writes both cameras' intrinsics and the rotation R and "
            "translation t (metres) from the depth camera to the color camera as JSON "
            "(X_color = R X_depth + t). Pairs where either image lacks the board are reported and skipped."
        ),
    )
    s.add_argument("--depth-images", nargs="+", required=True, metavar="IMG",
                   help="the depth camera's intensity images")
    s.add_argument("--color-images", nargs="+", required=True, metavar="IMG",
                   help="the color camera's images, paired with --depth-images in order")
    add_board_options(s)
    s.add_argument("--depth-camera", metavar="FILE",
                   help="known depth-camera intrinsics (from `calibrate`); default: fit them from the pairs")
    s.add_argument("--color-camera", metavar="FILE",
                   help="known color-camera intrinsics; default: fit them from the pairs")
    s.add_argument("-o", "--output", required=True, metavar="OUT", help="rig file to write (.json)")
    add_overwrite(s)
    s.set_defaults(func=run_calibrate_stereo)


def add_board_options(p: argparse.ArgumentParser, *, fit: bool = True) -> None:
    """--board, --square, --marker, --dictionary (and the lens model options when ``fit``)."""
    p.add_argument("--board", required=True, type=parse_board, metavar="COLSxROWS",
                   help="a checkerboard's inner corners across x down, as OpenCV counts them (a board of 10x7 "
                        "squares is 9x6), or charuco:COLSxROWS, a ChArUco board's squares across x down as "
                        "cv2.aruco.CharucoBoard counts them (e.g. charuco:14x9)")
    p.add_argument("--square", required=True, type=parse_square, metavar="SIZE",
                   help="side of one square: 25mm, 2.5cm or 0.025 (a bare number is metres)")
    p.add_argument("--marker", type=parse_square, metavar="SIZE",
                   help="ChArUco: side of one marker, e.g. 30mm (required for charuco boards)")
    p.add_argument("--dictionary", default=None, metavar="NAME",
                   help="ChArUco: OpenCV predefined ArUco dictionary, e.g. DICT_5X5_250 (the default), "
                        "DICT_4X4_50, DICT_6X6_250, DICT_APRILTAG_36H11")
    if fit:
        p.add_argument("--k3", action="store_true",
                       help="also fit the radial term k3 (default fixed at 0, as the Matlab toolbox the thesis "
                            "used does; k3 over-fits with few views)")
        p.add_argument("--rational", action="store_true",
                       help="fit OpenCV's rational lens model (k1..k6, p1, p2: 8 coefficients), for wide-angle "
                            "lenses such as the Azure Kinect's")


def board_from_args(args: argparse.Namespace, *, need_unit: bool = False) -> Board:
    """The :class:`Board` of --board, --square, --marker and --dictionary."""
    from ..rig.boards import Board

    kind, grid = args.board
    square = _square(args, need_unit=need_unit)
    if kind == "checkerboard":
        for flag, value in (("--marker", args.marker), ("--dictionary", args.dictionary)):
            if value is not None:
                raise CliError(f"{flag} is for ChArUco boards; write --board charuco:COLSxROWS for one.")
        return Board.checkerboard(grid, square)
    if args.marker is None:
        raise CliError("a ChArUco board needs --marker, the side of one marker (e.g. --marker 30mm).")
    try:
        return Board.charuco(grid, square, args.marker[0], args.dictionary or "DICT_5X5_250")
    except ValueError as exc:
        raise CliError(f"--board/--marker/--dictionary: {exc}") from None


def _read_intensity(path: str) -> np.ndarray:
    """A calibration image: color/gray 8/16-bit via read_rgb, else a one-channel float map."""
    from ..io import InputFileError, read_depth, read_rgb

    try:
        return read_rgb(path)
    except InputFileError as first:
        try:
            return read_depth(path)
        except InputFileError:
            raise first from None


def _detect(paths: list[str], board: Board, what: str) -> tuple[list[BoardView], tuple[int, int]]:
    """The board's corners in each image and the common (width, height)."""
    from ..rig.boards import detect_board

    views, sizes = [], {}
    for path in paths:
        image = _read_intensity(path)
        sizes.setdefault(image.shape[:2], path)
        if len(sizes) > 1:
            (r0, c0), (r1, c1) = list(sizes)[:2]
            raise CliError(f"{what} {path} is {c1}x{r1} but {sizes[(r0, c0)]} is {c0}x{r0}; "
                           "all images of one camera must have one size.")
        views.append(detect_board(image, board))
    rows, cols = next(iter(sizes))
    return views, (cols, rows)


def _found(views: list[BoardView], board: Board) -> tuple[str, str]:
    """What was found (``"; ..."``) and what to check, for an error message."""
    from ..rig.boards import MIN_VIEW_CORNERS

    if board.kind == "checkerboard":
        return (f"; OpenCV finds all {board.points.shape[0]} inner corners of the {board.spec} checkerboard or none",
                "Check --board (inner corners, COLSxROWS)")
    counts = ", ".join(str(v.count) for v in views[:20]) + (", ..." if len(views) > 20 else "")
    markers = sum(v.markers for v in views)
    if markers == 0:
        hint = f"No {board.dictionary} marker was decoded: check --dictionary, and --board"
    else:
        hint = (f"{markers} markers were decoded but few corners interpolated: check --board (squares, "
                "charuco:COLSxROWS), --marker and --square")
    return f"; ChArUco corners found per image: {counts} (a view needs {MIN_VIEW_CORNERS})", hint


def _not_found(paths: list[str]) -> str:
    """``"; not found in a.png, b.png"`` (the first 10 names), or ``""``."""
    if not paths:
        return ""
    more = f" and {len(paths) - 10} more" if len(paths) > 10 else ""
    return "; board not found in " + ", ".join(paths[:10]) + more


def _square(args: argparse.Namespace, *, need_unit: bool) -> float:
    metres, unit_given = args.square
    if need_unit and not unit_given and metres >= 1.0:
        raise CliError(
            f"--square {metres:g} would be a {metres:g} m square; the rig's translation is in the square's "
            "unit, so give it, e.g. --square 25mm."
        )
    return metres


def run_calibrate(args: argparse.Namespace) -> int:
    import numpy as np

    from ..io import check_output, write_camera
    from ..rig.boards import usable
    from ..rig.calibrate import calibrate_from_views

    out = check_output(args.output, overwrite=args.overwrite, suffixes=(".json",), inputs=tuple(args.images))
    board = board_from_args(args)
    found, size = _detect(args.images, board, "image")
    skipped = [path for path, v in zip(args.images, found) if not usable(v, board)]
    views = [v for v in found if usable(v, board)]
    if len(views) < MIN_VIEWS:
        detail, hint = _found(found, board)
        raise CliError(
            f"the board was found in {len(views)} of {len(args.images)} images; calibration needs at least "
            f"{MIN_VIEWS}{detail}{_not_found(skipped)}. {hint}, and take more views."
        )
    for path in skipped:  # after the check, so that an error stays one line
        print(f"depthrefine calibrate: board {board.spec} not found in {path}; skipped", file=sys.stderr)
    camera = calibrate_from_views(views, board=board, image_size=size, estimate_k3=args.k3, rational=args.rational)
    extra = {
        "board": list(board.inner_corners) if board.kind == "checkerboard" else board.to_dict(),
        "square_size_m": board.square_size,
        "images_used": [p for p, v in zip(args.images, found) if usable(v, board)],
        "images_skipped": skipped,
    }
    if board.kind == "charuco":
        extra["corners_used"] = [v.count for v in views]
    write_camera(out, camera, overwrite=args.overwrite, extra=extra)
    fx, fy = camera.focal
    print(f"wrote {out}: fx {fx:.2f}, fy {fy:.2f}, cx {camera.K[0, 2]:.2f}, cy {camera.K[1, 2]:.2f} px, "
          f"dist {np.round(camera.dist, 4).tolist()}, RMS {camera.rms:.3f} px from {len(views)} of "
          f"{len(args.images)} images", file=sys.stderr)
    return 0


def run_calibrate_stereo(args: argparse.Namespace) -> int:
    import numpy as np

    from ..io import check_output, read_camera, write_rig
    from ..rig.boards import usable
    from ..rig.calibrate import calibrate_stereo_from_views

    inputs = tuple(args.depth_images) + tuple(args.color_images)
    out = check_output(args.output, overwrite=args.overwrite, suffixes=(".json",), inputs=inputs)
    if len(args.depth_images) != len(args.color_images):
        raise CliError(
            f"got {len(args.depth_images)} depth images and {len(args.color_images)} color images; give them "
            "in pairs (the same board pose, in the same order)."
        )
    board = board_from_args(args, need_unit=True)
    depth_camera = read_camera(args.depth_camera, which="depth") if args.depth_camera else None
    color_camera = read_camera(args.color_camera, which="color") if args.color_camera else None
    depth_views, depth_size = _detect(args.depth_images, board, "depth image")
    color_views, color_size = _detect(args.color_images, board, "color image")
    for cam, size, what in ((depth_camera, depth_size, "--depth-camera"), (color_camera, color_size, "--color-camera")):
        if cam is not None and cam.image_size != size:
            raise CliError(f"{what} was calibrated on {cam.image_size[0]}x{cam.image_size[1]} images but the "
                           f"images are {size[0]}x{size[1]}.")
    used, notes, missing = [], [], []
    for dpath, cpath, d, c in zip(args.depth_images, args.color_images, depth_views, color_views):
        if not (usable(d, board) and usable(c, board)):
            missing += [p for p, x in ((dpath, d), (cpath, c)) if not usable(x, board)]
            where = " and ".join(p for p, x in ((dpath, d), (cpath, c)) if not usable(x, board))
            notes.append(f"depthrefine calibrate-stereo: board not found in {where}; pair skipped")
        else:
            used.append([dpath, cpath])
    if len(used) < MIN_VIEWS:
        detail, hint = _found(depth_views + color_views, board)
        raise CliError(
            f"the board was found in both images of {len(used)} of {len(args.depth_images)} pairs; a stereo "
            f"calibration needs at least {MIN_VIEWS}{detail}{_not_found(missing)}. {hint}, and take more pairs."
        )
    for note in notes:  # after the check, so that an error stays one line
        print(note, file=sys.stderr)
    rig = calibrate_stereo_from_views(
        depth_views, color_views, board=board, depth_size=depth_size, color_size=color_size,
        depth_camera=depth_camera, color_camera=color_camera, estimate_k3=args.k3, rational=args.rational,
    )
    extra = {"board": list(board.inner_corners) if board.kind == "checkerboard" else board.to_dict(),
             "square_size_m": board.square_size, "pairs_used": used}
    write_rig(out, rig, overwrite=args.overwrite, extra=extra)
    centre = rig.color_centre
    print(f"wrote {out}: color camera at {np.round(centre, 4).tolist()} m from the depth camera, rotated "
          f"{rig.rotation_degrees:.2f} deg, stereo RMS {rig.rms:.3f} px from {len(used)} pairs", file=sys.stderr)
    return 0
