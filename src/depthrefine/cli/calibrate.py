"""``depthrefine calibrate`` and ``depthrefine calibrate-stereo``: calibration from checkerboard or ChArUco images."""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from ..rig._names import DEFAULT_MAX_RMS, LENS_MODELS, MIN_VIEWS, RECOMMENDED_VIEWS
from . import CliError
from ._common import add_overwrite

if TYPE_CHECKING:  # what a command needs is imported where it runs: --help stays fast
    import numpy as np

    from ..rig.boards import Board, BoardView
    from ..rig.calibrate import CalibrationFit

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
            "[width, height] and the RMS reprojection error (pixels) as JSON, and print each view's error. "
            f"Images where the board is not found are reported and skipped; at least {MIN_VIEWS} must remain. "
            "A fit over --max-rms is refused (nothing written); fewer views than the lens model needs for a "
            "stable fit is a warning ("
            + ", ".join(f"{model}: {n}" for model, n in RECOMMENDED_VIEWS.items())
            + " views, covering the whole image; see docs/rig.md)."
        ),
    )
    p.add_argument("images", nargs="+", metavar="IMAGES", help="checkerboard images of one camera")
    add_board_options(p)
    p.add_argument("-o", "--output", required=True, metavar="OUT", help="camera file to write (.json)")
    p.add_argument("--report", metavar="DIR",
                   help="also write DIR/coverage.png (the corners of all views over the image, empty cells shaded, "
                        "and each corner's reprojection residual) and DIR/views.csv (each view's error)")
    add_overwrite(p)
    p.set_defaults(func=run_calibrate)

    s = sub.add_parser(
        "calibrate-stereo",
        help="calibrate a depth + color rig from pairs of checkerboard or ChArUco images",
        description=(
            "Pairs of images of the same board pose, one from the depth camera (intensity) and one from the "
            "color camera, in the same order. Writes both cameras' intrinsics and the rotation R and "
            "translation t (metres) from the depth camera to the color camera as JSON "
            "(X_color = R X_depth + t). Pairs where either image lacks the board are reported and skipped. "
            "A fit (of a camera from the pairs, or of the pair) over --max-rms is refused, nothing written; "
            "each pair's error is printed."
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
                            f"lenses such as the Azure Kinect's (needs about {RECOMMENDED_VIEWS['rational']} views)")
        p.add_argument("--max-rms", type=_max_rms, default=DEFAULT_MAX_RMS, metavar="PX",
                       help=f"refuse a fit whose RMS reprojection error is over PX pixels (default "
                            f"{DEFAULT_MAX_RMS:g}; good fits reach 0.1-0.5 px); nothing is written")


def _max_rms(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not value > 0:  # NaN fails too; inf turns the check off
        raise argparse.ArgumentTypeError(f"expected a positive number of pixels such as 1.0; got {text!r}")
    return value


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

    from ..io import atomic_directory, check_output, check_output_dir, write_camera
    from ..rig.boards import usable
    from ..rig.calibrate import fit_camera

    out = check_output(args.output, overwrite=args.overwrite, suffixes=(".json",), inputs=tuple(args.images))
    if args.report:
        check_output_dir(args.report, overwrite=args.overwrite, what="--report folder")
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
    used = [p for p, v in zip(args.images, found) if usable(v, board)]
    fit = fit_camera(views, board=board, image_size=size, estimate_k3=args.k3, rational=args.rational)
    check_fit(fit, used, args.max_rms, what="calibration", images=len(args.images))
    for path in skipped:  # after the checks, so that an error stays one line
        print(f"depthrefine calibrate: board {board.spec} not found in {path}; skipped", file=sys.stderr)
    warn_few_views(fit.model, len(views), "views")
    print_view_errors(used, fit.view_rms, [v.count for v in views])
    camera = fit.camera
    extra = {
        "board": list(board.inner_corners) if board.kind == "checkerboard" else board.to_dict(),
        "square_size_m": board.square_size,
        "lens_model": fit.model,
        "images_used": used,
        "images_skipped": skipped,
        "view_rms": [round(float(e), 4) for e in fit.view_rms],
    }
    if board.kind == "charuco":
        extra["corners_used"] = [v.count for v in views]
    if args.report:
        with atomic_directory(args.report, overwrite=args.overwrite) as tmp:
            _write_report(tmp, fit, used, title=f"calibrate: {len(views)} views, {fit.model} lens model")
            write_camera(out, camera, overwrite=args.overwrite, extra=extra)
    else:
        write_camera(out, camera, overwrite=args.overwrite, extra=extra)
    fx, fy = camera.focal
    print(f"wrote {out}: fx {fx:.2f}, fy {fy:.2f}, cx {camera.K[0, 2]:.2f}, cy {camera.K[1, 2]:.2f} px, "
          f"dist {np.round(camera.dist, 4).tolist()}, RMS {camera.rms:.3f} px from {len(views)} of "
          f"{len(args.images)} images", file=sys.stderr)
    if args.report:
        print(f"wrote {args.report}/coverage.png and views.csv", file=sys.stderr)
    return 0


def check_fit(fit: CalibrationFit, names: list[str], max_rms: float, *, what: str, images: int | None = None) -> None:
    """Refuse (``CliError``, one line) a fit whose RMS error is over ``max_rms``, naming the worst views.

    ``images``: how many images were given, when some had no board (said, as a wrong --board finds few).
    """
    rms = fit.camera.rms
    if rms is None or rms <= max_rms:
        return
    views = len(fit.views)
    found = (f"the board found in {views} of {images} images" if images is not None and images > views
             else f"{views} views")
    raise CliError(
        f"{what} refused: RMS reprojection error {rms:.2f} px is over --max-rms {max_rms:g} px "
        f"({found}, {fit.model} lens model; worst views: {_worst(names, fit.view_rms)}). "
        "Check --board (a ChArUco board is charuco:COLSxROWS) and --square, leave out the worst views or "
        "take new ones; nothing was written."
    )


def _worst(names: list[str], errors, count: int = 3) -> str:
    """``"a.png 6.10 px, b.png 4.02 px"``: the ``count`` largest errors."""
    import numpy as np

    order = np.argsort(-np.asarray(errors), kind="stable")[:count]
    return ", ".join(f"{names[i]} {errors[i]:.2f} px" for i in order)


def warn_few_views(model: str, count: int, what: str) -> None:
    """A warning line when ``count`` views are fewer than ``model`` needs for a stable fit."""
    need = RECOMMENDED_VIEWS[model]
    if count < need:
        print(f"depthrefine calibrate: warning: only {count} {what} for the {model} lens model "
              f"({LENS_MODELS[model]}); a stable fit needs about {need} covering the whole image: the "
              "distortion is poorly determined (see docs/rig.md)", file=sys.stderr)


def print_view_errors(names: list[str], errors, corners: list[int]) -> None:
    """One line per view: its RMS reprojection error and corner count (stderr)."""
    width = max(len(n) for n in names)
    for name, error, count in zip(names, errors, corners):
        print(f"  {name:<{width}}  {error:6.3f} px  ({count} corners)", file=sys.stderr)


def _write_report(folder, fit: CalibrationFit, names: list[str], *, title: str) -> None:
    """coverage.png and views.csv of ``calibrate --report``."""
    from pathlib import Path

    from ..io import write_figure
    from ..rig.coverage import coverage_figure

    write_figure(Path(folder) / "coverage.png", coverage_figure(fit, names=[Path(n).name for n in names],
                                                                title=title))
    lines = ["image,rms_px,corners"] + [f"{n},{e:.4f},{v.count}" for n, e, v in zip(names, fit.view_rms, fit.views)]
    (Path(folder) / "views.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")


def run_calibrate_stereo(args: argparse.Namespace) -> int:
    import numpy as np

    from ..io import check_output, read_camera, write_rig
    from ..rig.boards import usable
    from ..rig.calibrate import fit_stereo

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
    fit = fit_stereo(
        depth_views, color_views, board=board, depth_size=depth_size, color_size=color_size,
        depth_camera=depth_camera, color_camera=color_camera, estimate_k3=args.k3, rational=args.rational,
    )
    for camera_fit, paths, views, what in ((fit.depth_fit, args.depth_images, depth_views, "depth camera"),
                                           (fit.color_fit, args.color_images, color_views, "color camera")):
        if camera_fit is not None:
            check_fit(camera_fit, [p for p, v in zip(paths, views) if usable(v, board)], args.max_rms,
                      what=f"the {what}'s calibration")
    rig = fit.rig
    pair_names = [f"{Path(args.depth_images[i]).name} + {Path(args.color_images[i]).name}" for i in fit.pairs]
    pair_error = fit.pair_rms.max(axis=1)
    if rig.rms > args.max_rms:
        raise CliError(
            f"stereo calibration refused: RMS reprojection error {rig.rms:.2f} px is over --max-rms "
            f"{args.max_rms:g} px ({len(fit.pairs)} pairs; worst pairs: {_worst(pair_names, pair_error)}). Check "
            "that the pairs show the same board pose in the same order, and --board and --square; nothing was "
            "written."
        )
    for note in notes:  # after the checks, so that an error stays one line
        print(note, file=sys.stderr)
    for camera_fit, what in ((fit.depth_fit, "depth"), (fit.color_fit, "color")):
        if camera_fit is not None:
            warn_few_views(camera_fit.model, len(camera_fit.views), f"{what} camera views")
    for name, (d_err, c_err) in zip(pair_names, fit.pair_rms):
        print(f"  {name}  depth {d_err:6.3f} px, color {c_err:6.3f} px", file=sys.stderr)
    extra = {"board": list(board.inner_corners) if board.kind == "checkerboard" else board.to_dict(),
             "square_size_m": board.square_size,
             "pairs_used": [[args.depth_images[i], args.color_images[i]] for i in fit.pairs],
             "pair_rms": [[round(float(e), 4) for e in row] for row in fit.pair_rms]}
    write_rig(out, rig, overwrite=args.overwrite, extra=extra)
    centre = rig.color_centre
    print(f"wrote {out}: color camera at {np.round(centre, 4).tolist()} m from the depth camera, rotated "
          f"{rig.rotation_degrees:.2f} deg, stereo RMS {rig.rms:.3f} px from {len(fit.pairs)} pairs", file=sys.stderr)
    return 0
