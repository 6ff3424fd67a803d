"""Calibration: synthetic checkerboards rendered with known intrinsics and distortion.

The boards are rendered by ray casting every (3x supersampled) pixel through
the known lens onto the board plane; ``cv2.projectPoints`` of the board's
corners is the oracle that the renderer and the detector agree with. The
helpers here are reused by ``test_cli_rig.py``.
"""

from __future__ import annotations

import functools

import cv2
import numpy as np
import pytest

from depthrefine.rig import (
    MIN_VIEWS,
    CameraModel,
    StereoRig,
    board_points,
    calibrate_camera,
    calibrate_from_corners,
    calibrate_stereo,
    find_board_corners,
    to_gray8,
)

BOARD = (8, 6)          # inner corners (cols, rows)
SQUARE = 0.03           # metres
SUPERSAMPLE = 3

#: The depth camera (the ToF intensity images), with strong barrel distortion.
DEPTH_K = np.array([[200.0, 0.0, 121.3], [0.0, 202.0, 88.6], [0.0, 0.0, 1.0]])
DEPTH_DIST = np.array([-0.28, 0.09, 0.0012, -0.0008, 0.0])
DEPTH_SIZE = (240, 180)
#: The color camera: higher resolution, mild distortion.
COLOR_K = np.array([[392.0, 0.0, 198.0], [0.0, 390.0, 151.5], [0.0, 0.0, 1.0]])
COLOR_DIST = np.array([0.05, -0.02, 0.0, 0.0, 0.0])
COLOR_SIZE = (400, 300)
#: Depth -> color: color camera 6 cm to the right, turned 1.5 degrees.
RIG_RVEC = np.array([0.004, -0.026, 0.003])
RIG_T = np.array([-0.06, 0.002, 0.001])


@functools.lru_cache(maxsize=None)
def _rays(K: tuple, dist: tuple, size: tuple[int, int], ss: int) -> np.ndarray:
    """(3, rows*ss, cols*ss) normalized rays of the supersampled pixels (depend only on the camera)."""
    w, h = size
    ys, xs = np.mgrid[0:h * ss, 0:w * ss].astype(np.float64)
    pix = np.stack([(xs + 0.5) / ss - 0.5, (ys + 0.5) / ss - 0.5], axis=-1).reshape(-1, 1, 2)
    crit = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 30, 1e-10)
    norm = cv2.undistortPoints(pix, np.array(K).reshape(3, 3), np.array(dist), criteria=crit).reshape(h * ss, w * ss, 2)
    return np.stack([norm[..., 0], norm[..., 1], np.ones((h * ss, w * ss))])


def render_board(K, dist, size, rvec, tvec, *, board=BOARD, square=SQUARE, ss=SUPERSAMPLE) -> np.ndarray:
    """An 8-bit image of a checkerboard at pose (rvec, tvec), seen through lens (K, dist).

    Each supersampled pixel's ray is intersected with the board plane (the
    inverse of the plane's homography ``[r1 r2 t]``), the square it hits gives
    its gray level, and INTER_AREA averages the supersamples. Only the box
    around the board's projection (``cv2.projectPoints``) is ray cast.
    """
    w, h = size
    cols, rows = board
    R, _ = cv2.Rodrigues(np.asarray(rvec, np.float64))
    outline = np.array([[-2, -2, 0], [cols + 1, -2, 0], [cols + 1, rows + 1, 0], [-2, rows + 1, 0]]) * square
    edge = np.linspace(0, 1, 9)[:, None]
    outline = np.concatenate([a + edge * (b - a) for a, b in zip(outline, np.roll(outline, -1, axis=0))])
    box, _ = cv2.projectPoints(outline, np.asarray(rvec, np.float64), np.ravel(tvec), K, dist)
    box = box.reshape(-1, 2) * ss
    c0, r0 = np.clip(np.floor(box.min(axis=0)).astype(int) - 2 * ss, 0, None)
    c1, r1 = np.minimum(np.ceil(box.max(axis=0)).astype(int) + 2 * ss, (w * ss, h * ss))
    img = np.full((h * ss, w * ss), 0.35, np.float32)
    if c1 > c0 and r1 > r0:
        rays = _rays(tuple(np.ravel(K)), tuple(np.ravel(dist)), (w, h), ss)[:, r0:r1, c0:c1]
        Hinv = np.linalg.inv(np.column_stack([R[:, 0], R[:, 1], np.ravel(tvec)]))
        uvw = np.tensordot(Hinv, rays, axes=1)
        iu = np.floor(uvw[0] / (uvw[2] * square))
        iv = np.floor(uvw[1] / (uvw[2] * square))
        squares = (iu >= -1) & (iu <= cols - 1) & (iv >= -1) & (iv <= rows - 1)
        margin = (iu >= -2) & (iu <= cols) & (iv >= -2) & (iv <= rows) & (uvw[2] > 0)
        patch = np.where(margin, np.float32(0.95), np.float32(0.35))
        patch[squares & ((iu + iv) % 2 == 0)] = 0.05
        img[r0:r1, c0:c1] = patch
    img = cv2.resize(img, (w, h), interpolation=cv2.INTER_AREA)
    return np.floor(img * 255 + 0.5).astype(np.uint8)


def board_poses(n: int, seed: int = 7, *, distance=(0.42, 0.55)) -> list[tuple[np.ndarray, np.ndarray]]:
    """``n`` varied board poses (rvec, tvec) in the depth camera's frame, board centred near the axis."""
    rng = np.random.default_rng(seed)
    centre = np.array([(BOARD[0] - 1) / 2 * SQUARE, (BOARD[1] - 1) / 2 * SQUARE, 0.0])
    poses = []
    for _ in range(n):
        rvec = np.array([rng.uniform(-0.45, 0.45), rng.uniform(-0.45, 0.45), rng.uniform(-0.3, 0.3)])
        R, _ = cv2.Rodrigues(rvec)
        offset = np.array([rng.uniform(-0.05, 0.05), rng.uniform(-0.035, 0.035), rng.uniform(*distance)])
        poses.append((rvec, offset - R @ centre))
    return poses


def to_color_frame(rvec, tvec):
    """The board pose of the depth camera's frame, seen from the color camera."""
    R_rig, _ = cv2.Rodrigues(RIG_RVEC)
    R_b, _ = cv2.Rodrigues(rvec)
    r, _ = cv2.Rodrigues(R_rig @ R_b)
    return r.ravel(), R_rig @ tvec + RIG_T


@functools.lru_cache(maxsize=None)
def depth_views(n: int = 10) -> tuple[np.ndarray, ...]:
    return tuple(render_board(DEPTH_K, DEPTH_DIST, DEPTH_SIZE, r, t) for r, t in board_poses(n))


@functools.lru_cache(maxsize=None)
def color_views(n: int = 10) -> tuple[np.ndarray, ...]:
    return tuple(render_board(COLOR_K, COLOR_DIST, COLOR_SIZE, *to_color_frame(r, t)) for r, t in board_poses(n))


# ----------------------------------------------------------------------------


def test_board_points_order_matches_opencv():
    pts = board_points((3, 2), 0.5)
    assert pts.shape == (6, 3) and pts.dtype == np.float32
    assert pts[:, 2].tolist() == [0.0] * 6
    assert pts[3].tolist() == [0.0, 0.5, 0.0]  # second row starts after `cols` corners


def test_rendered_corners_agree_with_project_points():
    """Renderer + detector against the oracle: corners within 0.3 px of cv2.projectPoints."""
    obj = board_points(BOARD, SQUARE)
    for (rvec, tvec), image in zip(board_poses(4), depth_views()):
        corners = find_board_corners(image, BOARD)
        assert corners is not None
        expected, _ = cv2.projectPoints(obj, rvec, tvec, DEPTH_K, DEPTH_DIST)
        assert np.abs(corners - expected.reshape(-1, 2)).max() < 0.3


def test_calibration_recovers_intrinsics():
    camera = calibrate_camera(list(depth_views()), board=BOARD, square_size=SQUARE)
    fx, fy = camera.focal
    assert abs(fx / DEPTH_K[0, 0] - 1) < 0.01 and abs(fy / DEPTH_K[1, 1] - 1) < 0.01
    assert abs(camera.K[0, 2] - DEPTH_K[0, 2]) < 2 and abs(camera.K[1, 2] - DEPTH_K[1, 2]) < 2
    assert camera.image_size == DEPTH_SIZE
    assert camera.dist.shape == (5,) and camera.dist[4] == 0.0  # k3 fixed, as in the Matlab toolbox
    assert abs(camera.dist[0] - DEPTH_DIST[0]) < 0.03
    assert 0 < camera.rms < 0.3


def test_estimate_k3_fits_five_coefficients():
    camera = calibrate_camera(list(depth_views()), board=BOARD, square_size=SQUARE, estimate_k3=True)
    assert camera.dist[4] != 0.0
    assert abs(camera.focal[0] / DEPTH_K[0, 0] - 1) < 0.01


def test_board_not_found_is_none_and_too_few_views_is_an_error():
    blank = np.full((180, 240), 128, np.uint8)
    assert find_board_corners(blank, BOARD) is None
    images = [blank, depth_views()[0], blank, depth_views()[1]]
    with pytest.raises(ValueError, match=r"found in 2 of 4 images \(not in images \[0, 2\]\).*at least 3"):
        calibrate_camera(images, board=BOARD, square_size=SQUARE)
    with pytest.raises(ValueError, match="at least 3"):
        calibrate_from_corners([], board=BOARD, square_size=SQUARE, image_size=DEPTH_SIZE)
    assert MIN_VIEWS == 3


def test_wrong_board_size_is_not_found():
    assert find_board_corners(depth_views()[0], (7, 7)) is None


def test_bad_arguments():
    with pytest.raises(TypeError, match="board must be two integers"):
        board_points("8x6", SQUARE)
    with pytest.raises(ValueError, match="square_size must be > 0"):
        board_points(BOARD, 0.0)
    with pytest.raises(ValueError, match="different sizes"):
        calibrate_camera([np.zeros((10, 10), np.uint8), np.zeros((10, 12), np.uint8)], board=BOARD,
                         square_size=SQUARE)


def test_to_gray8_stretches_16_bit_amplitude():
    amp = np.linspace(0, 4000, 400).reshape(20, 20).astype(np.uint16)
    gray = to_gray8(amp)
    assert gray.dtype == np.uint8 and gray.min() == 0 and gray.max() == 255
    rgb = np.zeros((2, 2, 3), np.uint8)
    rgb[..., 1] = 100
    assert to_gray8(rgb).tolist() == [[59, 59], [59, 59]]  # OpenCV's 0.587 * G


def _rotation_error_degrees(R: np.ndarray) -> float:
    R_true, _ = cv2.Rodrigues(RIG_RVEC)
    return float(np.degrees(np.arccos(np.clip((np.trace(R @ R_true.T) - 1) / 2, -1, 1))))


def test_stereo_calibration_recovers_the_rig():
    """Intrinsics and the rig from the pairs alone (one color view misses the board)."""
    rig = calibrate_stereo(list(depth_views()), list(color_views()), board=BOARD, square_size=SQUARE)
    assert _rotation_error_degrees(rig.R) < 0.5
    assert np.abs(rig.t - RIG_T).max() < 0.003  # metres, with SQUARE in metres
    assert abs(rig.color_camera.focal[0] / COLOR_K[0, 0] - 1) < 0.01
    assert abs(rig.depth_camera.focal[1] / DEPTH_K[1, 1] - 1) < 0.01
    assert abs(rig.color_camera.K[0, 2] - COLOR_K[0, 2]) < 2
    assert rig.color_centre[0] > 0.055  # the color camera is on the right
    assert rig.rms < 0.3


def test_stereo_with_known_intrinsics_is_exact():
    depth_cam = CameraModel(DEPTH_K, DEPTH_DIST, DEPTH_SIZE)
    color_cam = CameraModel(COLOR_K, COLOR_DIST, COLOR_SIZE)
    rig = calibrate_stereo(list(depth_views()), list(color_views()), board=BOARD, square_size=SQUARE,
                           depth_camera=depth_cam, color_camera=color_cam)
    assert _rotation_error_degrees(rig.R) < 0.05
    assert np.abs(rig.t - RIG_T).max() < 0.0005
    assert rig.depth_camera is depth_cam and rig.color_camera is color_cam


def test_stereo_needs_pairs_in_both_cameras():
    blank = np.full((300, 400), 128, np.uint8)
    colors = [blank] * 8 + list(color_views()[8:])
    with pytest.raises(ValueError, match="both images of 2 pairs"):
        calibrate_stereo(list(depth_views()), colors, board=BOARD, square_size=SQUARE)
    with pytest.raises(ValueError, match="in pairs"):
        calibrate_stereo(list(depth_views()[:3]), list(color_views()[:4]), board=BOARD, square_size=SQUARE)


def test_camera_model_round_trip_and_checks():
    cam = CameraModel(DEPTH_K, DEPTH_DIST, DEPTH_SIZE, 0.1)
    back = CameraModel.from_dict(cam.to_dict())
    assert np.array_equal(back.K, cam.K) and np.array_equal(back.dist, cam.dist)
    assert back.image_size == DEPTH_SIZE and back.rms == 0.1 and back.shape == (180, 240)
    assert not cam.K.flags.writeable
    with pytest.raises(ValueError, match="lacks key"):
        CameraModel.from_dict({"K": DEPTH_K.tolist()})
    with pytest.raises(ValueError, match="fx, fy > 0"):
        CameraModel(np.diag([0.0, 1.0, 1.0]), np.zeros(5), (4, 4))
    with pytest.raises(ValueError, match="4, 5, 8, 12 or 14"):
        CameraModel(DEPTH_K, np.zeros(3), DEPTH_SIZE)
    with pytest.raises(ValueError, match="image_size"):
        CameraModel(DEPTH_K, np.zeros(5), (240,))
    skewed = DEPTH_K.copy()
    skewed[0, 1] = 0.5  # OpenCV's projectPoints / undistortPoints would ignore it
    with pytest.raises(ValueError, match=r"skew K\[0\]\[1\] = 0.5.*set it to 0"):
        CameraModel(skewed, np.zeros(5), DEPTH_SIZE)


def test_resized_camera_projects_to_resized_pixels():
    """A point's pixel in the resized grid is the resize of its pixel (pixel areas aligned)."""
    cam = CameraModel(COLOR_K, np.zeros(5), COLOR_SIZE)
    small = cam.resized((75, 100))  # 1/4
    point = np.array([[0.03, -0.02, 0.7]])
    big, _ = cv2.projectPoints(point, np.zeros(3), np.zeros(3), cam.K, None)
    little, _ = cv2.projectPoints(point, np.zeros(3), np.zeros(3), small.K, None)
    assert np.allclose((big.ravel() + 0.5) / 4 - 0.5, little.ravel())


def test_rig_round_trip_and_checks():
    cam = CameraModel(DEPTH_K, DEPTH_DIST, DEPTH_SIZE)
    R, _ = cv2.Rodrigues(RIG_RVEC)
    rig = StereoRig(cam, cam, R, RIG_T, 0.2)
    back = StereoRig.from_dict(rig.to_dict())
    assert np.allclose(back.R, R) and np.allclose(back.t, RIG_T) and back.rms == 0.2
    assert abs(rig.rotation_degrees - np.degrees(np.linalg.norm(RIG_RVEC))) < 1e-6
    with pytest.raises(ValueError, match="rotation matrix"):
        StereoRig(cam, cam, np.diag([1.0, 1.0, -1.0]), RIG_T)
    with pytest.raises(ValueError, match="lacks key"):
        StereoRig.from_dict({"R": R.tolist()})
