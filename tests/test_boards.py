"""Calibration boards: ChArUco boards rendered by `render_board`, seen by a known camera, detected and calibrated.

The views are the board picture warped by the homography of a known pose
(rendered 3x supersampled, then averaged down), so the corners' true
positions are ``cv2.projectPoints`` of the board's object points. No shared
data needed.
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from depthrefine.rig import (Board, BoardView, MIN_VIEW_CORNERS, calibrate_from_views, calibrate_stereo_from_views,
                             detect_board, render_board)
from depthrefine.rig.boards import check_dictionary, usable

BOARD = Board.charuco((5, 7), 0.03, 0.022, "DICT_5X5_250")
PIXELS = 120                    # per square in the board picture
K = np.array([[600.0, 0.0, 318.2], [0.0, 602.0, 241.5], [0.0, 0.0, 1.0]])
SIZE = (640, 480)
SS = 3
#: Board poses: tilts about x and y (radians) and a roll, the board centred at `DISTANCE` metres.
TILTS = [(0.35, 0.0, -0.4), (-0.35, 0.0, -0.3), (0.0, 0.35, -0.2), (0.0, -0.35, -0.1),
         (0.25, 0.25, 0.1), (-0.25, 0.25, 0.2), (0.25, -0.25, 0.3), (-0.25, -0.25, 0.4)]
DISTANCE = 0.42


def pose(i: int) -> tuple[np.ndarray, np.ndarray]:
    rvec = np.array(TILTS[i], dtype=np.float64)
    R, _ = cv2.Rodrigues(rvec)
    centre = R @ np.array([BOARD.size_m[0] / 2, BOARD.size_m[1] / 2, 0.0])
    return rvec, np.array([0.0, 0.0, DISTANCE]) - centre


def view(picture: np.ndarray, rvec: np.ndarray, tvec: np.ndarray, K: np.ndarray = K, size=SIZE) -> np.ndarray:
    """The board picture seen from pose (rvec, tvec) through a pinhole K (white around it)."""
    R, _ = cv2.Rodrigues(rvec)
    metres_per_px = BOARD.square_size / PIXELS
    to_board = np.array([[metres_per_px, 0, metres_per_px / 2], [0, metres_per_px, metres_per_px / 2], [0, 0, 1]])
    up = np.array([[SS, 0, (SS - 1) / 2], [0, SS, (SS - 1) / 2], [0, 0, 1]])
    H = up @ K @ np.column_stack([R[:, 0], R[:, 1], tvec]) @ to_board
    big = cv2.warpPerspective(picture, H, (size[0] * SS, size[1] * SS), flags=cv2.INTER_LINEAR, borderValue=255)
    return cv2.resize(big, size, interpolation=cv2.INTER_AREA)


@pytest.fixture(scope="module")
def views() -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    picture = render_board(BOARD, PIXELS)
    return [(view(picture, *pose(i)), *pose(i)) for i in range(len(TILTS))]


def test_board_geometry_and_picture():
    assert BOARD.inner_corners == (4, 6) and BOARD.points.shape == (24, 3)
    assert BOARD.spec == "charuco:5x7" and "22 mm markers" in BOARD.describe()
    picture = render_board(BOARD, PIXELS, margin=10)
    assert picture.shape == (7 * PIXELS + 20, 5 * PIXELS + 20) and set(np.unique(picture)) == {0, 255}
    # OpenCV's ChArUco layout: the top-left square is black, the next one holds marker 0
    assert picture[10 + PIXELS // 2, 10 + 5].max() == 0 and picture[10 + 5, 10 + PIXELS + 5] == 255
    # a flat, frontal picture of the board: every corner found exactly at the square grid
    found = detect_board(np.pad(render_board(BOARD, 40), 20, constant_values=255), BOARD)
    assert found.count == 24 and found.markers == 17
    expected = BOARD.points[found.ids, :2] / BOARD.square_size * 40 + 20 - 0.5
    assert np.abs(found.corners - expected).max() < 0.3
    checker = Board.checkerboard((4, 3), 0.02)
    img = render_board(checker, 30, margin=30)
    assert detect_board(img, checker).count == 12


def test_detected_corners_agree_with_the_projection(views):
    for image, rvec, tvec in views:
        found = detect_board(image, BOARD)
        assert usable(found, BOARD)
        truth, _ = cv2.projectPoints(BOARD.points[found.ids], rvec, tvec, K, None)
        assert np.abs(found.corners - truth.reshape(-1, 2)).max() < 0.35


def test_render_detect_calibrate_round_trip(views):
    found = [detect_board(image, BOARD) for image, _, _ in views]
    camera = calibrate_from_views(found, board=BOARD, image_size=SIZE)
    fx, fy = camera.focal
    assert abs(fx / K[0, 0] - 1) < 0.01 and abs(fy / K[1, 1] - 1) < 0.01
    assert abs(camera.K[0, 2] - K[0, 2]) < 3 and abs(camera.K[1, 2] - K[1, 2]) < 3
    assert camera.rms < 0.3 and camera.dist.size == 5
    rational = calibrate_from_views(found, board=BOARD, image_size=SIZE, rational=True)
    assert rational.dist.size == 8


def test_partial_views_count(views):
    """Half of the board hidden: the corners of the visible half are still identified and used."""
    found = []
    for image, _, _ in views:
        covered = image.copy()
        covered[:, : SIZE[0] // 2 - 40] = 255
        found.append(detect_board(covered, BOARD))
    counts = [v.count for v in found]
    assert all(MIN_VIEW_CORNERS <= c < 24 for c in counts), counts
    camera = calibrate_from_views(found, board=BOARD, image_size=SIZE)
    assert abs(camera.focal[0] / K[0, 0] - 1) < 0.03


def test_stereo_from_partial_charuco_views(views):
    """A second camera 5 cm to the right sees the same poses; pairs use the corners both found."""
    R_rig, _ = cv2.Rodrigues(np.array([0.0, -0.02, 0.0]))
    t_rig = np.array([-0.05, 0.0, 0.0])
    picture = render_board(BOARD, PIXELS)
    left, right = [], []
    for i in range(len(TILTS)):
        rvec, tvec = pose(i)
        R, _ = cv2.Rodrigues(rvec)
        rvec2, _ = cv2.Rodrigues(R_rig @ R)
        left.append(detect_board(view(picture, rvec, tvec), BOARD))
        right.append(detect_board(view(picture, rvec2.ravel(), R_rig @ tvec + t_rig), BOARD))
    rig = calibrate_stereo_from_views(left, right, board=BOARD, depth_size=SIZE, color_size=SIZE)
    assert np.abs(rig.t - t_rig).max() < 0.003 and rig.rotation_degrees < 2.0


def test_bad_boards_and_views():
    with pytest.raises(ValueError, match="unknown ArUco dictionary 'DICT_5X5_25'"):
        check_dictionary("DICT_5X5_25")
    assert check_dictionary("dict_4x4_50") == "DICT_4X4_50"
    with pytest.raises(ValueError, match="needs 63 markers but DICT_4X4_50 has 50"):
        Board.charuco((14, 9), 0.04, 0.03, "DICT_4X4_50")
    with pytest.raises(ValueError, match="smaller than square_size"):
        Board.charuco((5, 7), 0.03, 0.03)
    with pytest.raises(ValueError, match="needs marker_size"):
        Board("charuco", (5, 7), 0.03)
    with pytest.raises(ValueError, match="pixels_per_square"):
        render_board(BOARD, 5)
    empty = BoardView(np.zeros(0, np.int32), np.zeros((0, 2), np.float32))
    with pytest.raises(ValueError, match=r"at least 3 views.*got 3 view\(s\) with 0, 0, 0 corners"):
        calibrate_from_views([empty] * 3, board=BOARD, image_size=SIZE)


def test_a_board_spec_that_does_not_match_finds_no_corners(views):
    image = views[0][0]
    wrong_layout = detect_board(image, Board.charuco((7, 5), 0.03, 0.022, "DICT_5X5_250"))
    assert wrong_layout.markers > 0 and not usable(wrong_layout, Board.charuco((7, 5), 0.03, 0.022))
    wrong_dictionary = detect_board(image, Board.charuco((5, 7), 0.03, 0.022, "DICT_6X6_250"))
    assert wrong_dictionary.count == 0 and wrong_dictionary.markers == 0
