"""Point clouds: metric conversion, back-projection / projection round trips, PLY files."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from depthrefine.rig import CameraModel
from depthrefine.io import InputFileError, read_ply, write_ply
from depthrefine.rig.pointcloud import (
    backproject,
    depth_to_metres,
    depth_to_points,
    metres_to_depth,
    pixel_rays,
    project_points,
)

CAMERA = CameraModel(np.array([[300.0, 0, 159.2], [0, 302.0, 121.7], [0, 0, 1]]),
                     np.array([-0.2, 0.05, 0.001, -0.002, 0.0]), (320, 240))

PIXEL_COL = st.floats(10, 310)
PIXEL_ROW = st.floats(10, 230)
DEPTH_M = st.floats(0.3, 20.0)


@settings(max_examples=60, deadline=None)
@given(col=PIXEL_COL, row=PIXEL_ROW, z=DEPTH_M, distorted=st.booleans())
def test_project_of_backproject_is_the_pixel(col, row, z, distorted):
    """project(backproject(p, z)) == p, with and without the lens distortion."""
    point = backproject(np.array([col]), np.array([row]), np.array([z]), CAMERA, distorted=distorted)
    assert point[0, 2] == pytest.approx(z)
    pixel = project_points(point, CAMERA, distorted=distorted)
    assert np.allclose(pixel, [[col, row]], atol=1e-4)


@settings(max_examples=40, deadline=None)
@given(x=st.floats(-1, 1), y=st.floats(-0.8, 0.8), z=DEPTH_M)
def test_backproject_of_project_is_the_point(x, y, z):
    point = np.array([[x * z * 0.5, y * z * 0.5, z]])
    pixel = project_points(point, CAMERA, distorted=True)
    back = backproject(pixel[:, 0], pixel[:, 1], point[:, 2], CAMERA, distorted=True)
    assert np.allclose(back, point, atol=1e-5 * z)


def test_project_points_matches_opencv():
    points = np.array([[0.1, -0.05, 1.2], [-0.3, 0.2, 2.5]])
    expected, _ = cv2.projectPoints(points, np.zeros(3), np.zeros(3), CAMERA.K, CAMERA.dist)
    assert np.allclose(project_points(points, CAMERA, distorted=True), expected.reshape(-1, 2))


def test_pixel_rays_of_a_pinhole():
    cam = CameraModel(np.array([[10.0, 0, 1.0], [0, 20.0, 0.5], [0, 0, 1]]), np.zeros(5), (3, 2))
    rays = pixel_rays(cam)
    assert rays.shape == (2, 3, 2)
    assert np.allclose(rays[1, 2], [(2 - 1.0) / 10, (1 - 0.5) / 20])


def test_depth_to_metres_both_conversions():
    mm = np.array([[0, 500, 2000]], np.uint16)
    assert np.array_equal(depth_to_metres(mm, depth_units=0.001), [[np.nan, 0.5, 2.0]], equal_nan=True)
    intensity = np.array([[255, 102, 0]], np.uint8)  # 255 at 0.8 m, larger = nearer
    z = depth_to_metres(intensity, inverse_scale=204.0)
    assert np.allclose(z[0, :2], [0.8, 2.0]) and np.isnan(z[0, 2])
    assert np.allclose(metres_to_depth(z, inverse_scale=204.0)[0, :2], [255, 102])
    with pytest.raises(ValueError, match="8-bit depth intensity cannot be placed in 3-D"):
        depth_to_metres(intensity)
    with pytest.raises(ValueError, match="not both"):
        depth_to_metres(mm, depth_units=0.001, inverse_scale=1.0)
    with pytest.raises(ValueError, match="must be > 0"):
        depth_to_metres(mm, depth_units=-1.0)


def test_depth_to_points_known_values_colors_and_invalid():
    cam = CameraModel(np.array([[100.0, 0, 1.5], [0, 100.0, 1.0], [0, 0, 1]]), np.zeros(5), (4, 3))
    depth = np.full((3, 4), 2000, np.uint16)
    depth[0, 0] = 0
    rgb = np.zeros((3, 4, 3), np.uint8)
    rgb[2, 3] = (10, 20, 30)
    points, colors = depth_to_points(depth, cam, rgb=rgb, depth_units=0.001)
    assert points.shape == (11, 3) and points.dtype == np.float32 and colors.shape == (11, 3)
    assert np.allclose(points[-1], [(3 - 1.5) / 100 * 2, (2 - 1.0) / 100 * 2, 2.0])  # pixel (row 2, col 3)
    assert colors[-1].tolist() == [10, 20, 30]
    assert not np.isnan(points).any()
    thin, none = depth_to_points(depth, cam, depth_units=0.001, stride=2)
    assert thin.shape == (3, 3) and none is None  # (0,0) invalid; (0,2), (2,0), (2,2)
    rgb16 = (rgb.astype(np.uint16) * 257)
    assert depth_to_points(depth, cam, rgb=rgb16, depth_units=0.001)[1][-1].tolist() == [10, 20, 30]


def test_depth_to_points_checks_the_camera():
    with pytest.raises(ValueError, match=r"shape \(3, 3\) but the camera's images are \(240, 320\)"):
        depth_to_points(np.ones((3, 3), np.uint16), CAMERA, depth_units=0.001)


def test_ply_round_trip_and_overwrite(tmp_path):
    rng = np.random.default_rng(3)
    points = rng.normal(size=(50, 3)).astype(np.float32)
    colors = rng.integers(0, 256, size=(50, 3), dtype=np.uint8)
    path = write_ply(tmp_path / "cloud.ply", points, colors, comments=("test",))
    assert path.read_bytes().startswith(b"ply\nformat binary_little_endian 1.0\ncomment test\n")
    back, back_colors = read_ply(path)
    assert np.array_equal(back, points) and np.array_equal(back_colors, colors)
    with pytest.raises(InputFileError, match="exists; pass --overwrite"):
        write_ply(path, points)
    write_ply(path, points, overwrite=True)
    only, none = read_ply(path)
    assert np.array_equal(only, points) and none is None
    with pytest.raises(InputFileError, match="ply"):
        write_ply(tmp_path / "cloud.txt", points)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cloud.ply"]  # no temporary files left


def test_read_ascii_ply(tmp_path):
    text = ("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
            "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n"
            "0 0 1 255 0 0\n0.5 -0.5 2 0 255 0\n")
    (tmp_path / "a.ply").write_text(text)
    points, colors = read_ply(tmp_path / "a.ply")
    assert points.tolist() == [[0, 0, 1], [0.5, -0.5, 2]] and colors.tolist() == [[255, 0, 0], [0, 255, 0]]
    (tmp_path / "bad.ply").write_text("not a ply")
    with pytest.raises(InputFileError, match="not a PLY file"):
        read_ply(tmp_path / "bad.ply")
