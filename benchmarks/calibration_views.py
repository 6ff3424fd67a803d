"""How many board views each lens model needs: the fitted lens against the true one, by number of views.

Board corners are projected through a known lens (``cv2.projectPoints``) at
random poses (board tilted up to 45 degrees, filling 30-80 % of the image
width, anywhere in the image; corners outside the image are dropped, as in a
partial ChArUco view), Gaussian detection noise of 0.25 px is added, and
``depthrefine.rig.calibrate_from_views`` fits the model from V views. The
fitted lens is compared with the true one over a 33 x 25 grid of pixels
covering the whole image: each pixel's true ray is projected with the fitted
model, and the distance to the pixel is the disagreement. Printed per model
and V: the median and the 90th percentile over the trials of the largest
disagreement in the image, and of its median. These are the figures behind
``depthrefine.rig.RECOMMENDED_VIEWS`` (docs/rig.md).

All three models are fitted on one 640x480 image and one ChArUco board of
13x8 inner corners (partial views; ``--board checkerboard``: a 9x6
checkerboard, whole in every view), so that only the lens differs: ``plain``
(k1, k2, p1, p2; k3 fixed at 0) and ``k3`` (k3 fitted) a ToF camera's barrel
lens; ``rational`` (8 coefficients) the Azure Kinect color camera's upstream
30-view fit (``real_tof/azure_kinect_charuco/calibration/calib.yml``) scaled
from 4096x3072 to 640x480.

With ``--real DIR`` (``real_tof/azure_kinect_charuco/calibration``) the
same comparison runs on real views: every subset of V of the 8 Azure Kinect
ChArUco views is fitted with each model and compared with the upstream fit
from 30 views (``calib.yml``, rational), the reference.

Usage::

    python benchmarks/calibration_views.py [--trials 100] [--views 4,6,8,10,12,15,20,25,30,40] [--seed 0]
        [--board charuco|checkerboard]
    python benchmarks/calibration_views.py --real ../shared/data/real_tof/azure_kinect_charuco/calibration
"""

from __future__ import annotations

import argparse

import numpy as np

#: The Azure Kinect color camera's upstream 30-view fit (4096x3072, rational), scaled to 640x480.
_KINECT = 640 / 4096
#: The true lenses: (K, dist, (width, height), board inner corners (cols, rows), square metres, flags).
#: All on one 640x480 image with one ChArUco board (13x8 inner corners, partial views), so that
#: only the lens model differs.
LENSES = {
    "plain": (np.array([[525.0, 0, 322.0], [0, 524.0, 243.0], [0, 0, 1]]),
              np.array([-0.28, 0.09, 0.0012, -0.0008, 0.0]), (640, 480), (13, 8), 0.04,
              dict(estimate_k3=False, rational=False)),
    "k3": (np.array([[525.0, 0, 322.0], [0, 524.0, 243.0], [0, 0, 1]]),
           np.array([-0.28, 0.09, 0.0012, -0.0008, -0.02]), (640, 480), (13, 8), 0.04,
           dict(estimate_k3=True, rational=False)),
    "rational": (np.array([[1960.95 * _KINECT, 0, (2053.05 + 0.5) * _KINECT - 0.5],
                           [0, 1960.94 * _KINECT, (1556.20 + 0.5) * _KINECT - 0.5], [0, 0, 1]]),
                 np.array([-0.3199063, -2.3283483, 1.8335e-05, 4.8592e-05, 1.7688710, -0.4331594, -2.1051927,
                           1.6538154]), (640, 480), (13, 8), 0.04,
                 dict(estimate_k3=False, rational=True)),
}
NOISE_PX = 0.25


def _pose(rng: np.random.Generator, K: np.ndarray, size: tuple[int, int], board_w: float, board_h: float):
    """A random board pose: tilted up to 45 degrees, 30-80 % of the image wide, centred anywhere."""
    import cv2

    w, h = size
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    rvec = axis * np.deg2rad(rng.uniform(5, 45))
    width_px = rng.uniform(0.3, 0.8) * w
    z = K[0, 0] * board_w / width_px
    u, v = rng.uniform(0.1, 0.9) * w, rng.uniform(0.1, 0.9) * h
    centre = np.array([(u - K[0, 2]) / K[0, 0] * z, (v - K[1, 2]) / K[1, 1] * z, z])
    R, _ = cv2.Rodrigues(rvec)
    tvec = centre - R @ np.array([board_w / 2, board_h / 2, 0.0])
    return rvec, tvec


def _views(rng, K, dist, size, grid, square, count, partial):
    import cv2

    from depthrefine.rig import Board, BoardView

    # A ChArUco board of the same inner corners takes partial views; a checkerboard needs every corner.
    board = (Board.charuco((grid[0] + 1, grid[1] + 1), square, 0.75 * square) if partial
             else Board.checkerboard(grid, square))
    points = board.points.astype(np.float64)
    w, h = size
    views = []
    while len(views) < count:
        rvec, tvec = _pose(rng, K, size, (grid[0] - 1) * square, (grid[1] - 1) * square)
        image, _ = cv2.projectPoints(points, rvec, tvec, K, dist)
        image = image.reshape(-1, 2) + rng.normal(scale=NOISE_PX, size=(points.shape[0], 2))
        inside = (image[:, 0] >= 0) & (image[:, 0] <= w - 1) & (image[:, 1] >= 0) & (image[:, 1] <= h - 1)
        if inside.sum() < (0.6 if partial else 1.0) * points.shape[0]:  # a view shows most of the board
            continue
        ids = np.flatnonzero(inside).astype(np.int32)
        views.append(BoardView(ids, image[inside].astype(np.float32)))
    return board, views


def disagreement(K_true, dist_true, K_fit, dist_fit, size) -> np.ndarray:
    """Pixel distance between each grid pixel and its true ray projected through the fitted lens."""
    import cv2

    w, h = size
    xs, ys = np.meshgrid(np.linspace(0, w - 1, 33), np.linspace(0, h - 1, 25))
    pixels = np.stack([xs.ravel(), ys.ravel()], axis=1).reshape(-1, 1, 2)
    crit = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 50, 1e-12)
    rays = cv2.undistortPoints(pixels, K_true, dist_true, criteria=crit).reshape(-1, 2)
    rays3 = np.column_stack([rays, np.ones(len(rays))])
    back, _ = cv2.projectPoints(rays3, np.zeros(3), np.zeros(3), K_fit, dist_fit)
    return np.linalg.norm(back.reshape(-1, 2) - pixels.reshape(-1, 2), axis=1)


def real_views(folder: str) -> None:
    """Subsets of the real ChArUco views, each model against the 30-view reference."""
    import itertools
    from pathlib import Path

    from depthrefine.io import read_calibration, read_rgb
    from depthrefine.rig import Board, calibrate_from_views, detect_board

    board = Board.charuco((14, 9), 0.04, 0.03, "DICT_5X5_250")
    reference, _ = read_calibration(Path(folder) / "calib.yml")
    paths = sorted(Path(folder).glob("color-*.jpg"))
    views = [detect_board(read_rgb(p), board) for p in paths]
    size = reference.image_size
    print(f"{len(views)} real views ({', '.join(str(v.count) for v in views)} corners) against the upstream "
          f"30-view rational fit: largest / median disagreement (px), median [largest] over the subsets")
    print(f"{'views':>5}  {'subsets':>7}  " + "  ".join(f"{m + ' largest':>20}  {m + ' median':>18}"
                                                     for m in ("plain", "rational")))
    for count in range(4, len(views) + 1):
        subsets = list(itertools.combinations(range(len(views)), count))
        cells = []
        for flags in (dict(rational=False), dict(rational=True)):
            worst, typical = [], []
            for subset in subsets:
                camera = calibrate_from_views([views[i] for i in subset], board=board, image_size=size, **flags)
                d = disagreement(reference.K, reference.dist, camera.K, camera.dist, size)
                worst.append(d.max())
                typical.append(np.median(d))
            cells.append(f"{np.median(worst):9.2f} [{np.max(worst):7.2f}]  {np.median(typical):8.2f} "
                         f"[{np.max(typical):7.2f}]")
        print(f"{count:>5}  {len(subsets):>7}  " + "  ".join(cells))


def main() -> None:
    from depthrefine.rig import calibrate_from_views

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=100)
    parser.add_argument("--views", default="4,6,8,10,12,15,20,25,30,40")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--models", default=",".join(LENSES))
    parser.add_argument("--board", choices=("charuco", "checkerboard"), default="charuco",
                        help="charuco: 13x8 inner corners, partial views (default); checkerboard: 9x6 inner "
                             "corners, every corner in every view")
    parser.add_argument("--real", metavar="DIR", help="the Azure Kinect ChArUco views and calib.yml instead")
    args = parser.parse_args()
    if args.real:
        real_views(args.real)
        return
    counts = [int(v) for v in args.views.split(",")]
    print(f"largest / median disagreement of the fitted lens with the true one over the image (px), "
          f"{args.trials} trials, noise {NOISE_PX} px: median [90th percentile]")
    for model in args.models.split(","):
        K, dist, size, grid, square, flags = LENSES[model]
        if args.board == "checkerboard":
            grid, square = (9, 6), 0.025
        print(f"\n{model}: {size[0]}x{size[1]}, {args.board} {grid[0]}x{grid[1]} inner corners")
        print(f"{'views':>5}  {'largest':>16}  {'median':>16}  {'fit RMS':>7}")
        for count in counts:
            rng = np.random.default_rng([args.seed, count, len(model)])
            worst, typical, rms = [], [], []
            for _ in range(args.trials):
                board, views = _views(rng, K, dist, size, grid, square, count, partial=args.board == "charuco")
                camera = calibrate_from_views(views, board=board, image_size=size, **flags)
                d = disagreement(K, dist, camera.K, camera.dist, size)
                worst.append(d.max())
                typical.append(np.median(d))
                rms.append(camera.rms)
            print(f"{count:>5}  {np.median(worst):7.2f} [{np.percentile(worst, 90):6.2f}]  "
                  f"{np.median(typical):7.2f} [{np.percentile(typical, 90):6.2f}]  {np.median(rms):7.3f}")


if __name__ == "__main__":
    main()
