"""Undistortion and alignment on synthetic two-camera scenes with known geometry.

A scene is a fronto-parallel background plane and a nearer rectangle, both
given in the depth camera's frame. ``render_depth`` ray casts it for any
camera (with or without lens distortion), so the depth "rendered directly in
the color camera's view" is the ground truth the alignments must reproduce:
equal values away from depth edges, edges within 1 px, holes filled as the
spec says. The helpers are reused by ``test_cli_rig.py``.
"""

from __future__ import annotations

import warnings

import cv2
import numpy as np
import pytest
from scipy import ndimage

import depthrefine
from depthrefine.rig import (
    AlignmentWarning,
    AlignSettings,
    align_depth,
    align_pair,
    align_reproject,
    align_shift,
    background_depth,
    distort_depth,
    distort_image,
    reproject_camera,
    shift_from_rig,
    shift_misregistration,
    undistort_depth,
    undistort_image,
)
from depthrefine._geodesic import color_step_costs
from depthrefine.rig import CameraModel, StereoRig
from depthrefine.rig.chain import keep_unmeasured, unmeasured_along_color

#: Background plane (Z, metres) and the nearer rectangle (Z, x0, x1, y0, y1), depth camera frame.
Z_BACK = 2.0
FRONT = (1.0, -0.16, 0.08, -0.12, 0.10)

DEPTH_CAM = CameraModel(np.array([[75.0, 0, 47.8], [0, 75.5, 35.2], [0, 0, 1]]),
                        np.array([-0.22, 0.05, 0.001, -0.0005, 0.0]), (96, 72))
COLOR_CAM = CameraModel(np.array([[560.0, 0, 337.0], [0, 561.0, 250.0], [0, 0, 1]]),
                        np.array([0.04, -0.01, 0.0, 0.0, 0.0]), (672, 504))
RIG_R = cv2.Rodrigues(np.array([0.01, -0.03, 0.005]))[0]
RIG_T = np.array([-0.06, 0.003, 0.002])
RIG = StereoRig(DEPTH_CAM, COLOR_CAM, RIG_R, RIG_T)


def render_depth(camera: CameraModel, R=np.eye(3), t=np.zeros(3), *, distorted=True, front=FRONT,
                 z_back=Z_BACK) -> tuple[np.ndarray, np.ndarray]:
    """Z (metres, the camera's own frame) and a foreground mask of the scene for ``camera``.

    ``R, t`` take depth-camera (scene) coordinates to the camera's:
    ``X_cam = R X + t``. ``distorted`` renders the raw image (rays through
    the lens distortion); otherwise the ideal pinhole image.
    """
    rows, cols = camera.shape
    grid = np.mgrid[0:rows, 0:cols].astype(np.float64)
    pix = np.stack([grid[1], grid[0]], axis=-1).reshape(-1, 1, 2)
    dist = camera.dist if distorted else None
    crit = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 50, 1e-12)
    norm = cv2.undistortPoints(pix, camera.K, dist, criteria=crit).reshape(-1, 2)
    rays_cam = np.column_stack([norm, np.ones(len(norm))])
    centre = -R.T @ t
    rays = rays_cam @ R  # R.T @ ray for each row: directions in the scene frame
    lam_back = (z_back - centre[2]) / rays[:, 2]
    z_f, x0, x1, y0, y1 = front
    lam_front = (z_f - centre[2]) / rays[:, 2]
    hit = centre[:2] + lam_front[:, None] * rays[:, :2]
    on_front = (hit[:, 0] >= x0) & (hit[:, 0] <= x1) & (hit[:, 1] >= y0) & (hit[:, 1] <= y1) & (lam_front > 0)
    z = np.where(on_front, lam_front, lam_back)
    return z.reshape(rows, cols), on_front.reshape(rows, cols)


def edge_zone(mask: np.ndarray, width: int = 1) -> np.ndarray:
    """Pixels within ``width`` px (8-connected) of a change of ``mask``."""
    edges = np.zeros_like(mask, dtype=bool)
    edges[:, 1:] |= mask[:, 1:] != mask[:, :-1]
    edges[:, :-1] |= mask[:, 1:] != mask[:, :-1]
    edges[1:, :] |= mask[1:, :] != mask[:-1, :]
    edges[:-1, :] |= mask[1:, :] != mask[:-1, :]
    return ndimage.binary_dilation(edges, np.ones((3, 3), bool), iterations=max(width - 1, 0)) if width > 1 else edges


def border_zone(shape, width):
    zone = np.ones(shape, bool)
    zone[width:-width, width:-width] = False
    return zone


# ----------------------------------------------------------------------------
# Undistortion
# ----------------------------------------------------------------------------


def test_undistort_depth_matches_the_pinhole_render():
    raw, _ = render_depth(DEPTH_CAM, distorted=True)
    ideal, front = render_depth(DEPTH_CAM, distorted=False)
    out = undistort_depth((raw * 1000).round().astype(np.uint16), DEPTH_CAM)
    assert out.dtype == np.float32 and out.shape == raw.shape
    valid = np.isfinite(out)
    assert valid[border_zone(out.shape, 3) == 0].all()  # barrel lens: the raw image covers the pinhole view
    wrong = valid & (np.abs(out - ideal * 1000) > 0.5)
    assert not (wrong & ~edge_zone(front)).any()
    assert set(np.unique(out[valid])) <= {1000.0, 2000.0}  # nearest: no blended depth


def test_undistort_keeps_invalid_invalid():
    raw = np.full((72, 96), 1500, np.uint16)
    raw[30:40, 40:50] = 0
    out = undistort_depth(raw, DEPTH_CAM)
    maps = cv2.initUndistortRectifyMap(DEPTH_CAM.K, DEPTH_CAM.dist, None, DEPTH_CAM.K, (96, 72), cv2.CV_32FC1)
    src_c, src_r = np.floor(maps[0] + 0.5), np.floor(maps[1] + 0.5)
    from_hole = (src_r >= 30) & (src_r < 40) & (src_c >= 40) & (src_c < 50)
    assert np.isnan(out[from_hole]).all() and from_hole.sum() > 50
    assert np.array_equal(np.isnan(out) & ~border_zone(out.shape, 2), from_hole & ~border_zone(out.shape, 2))


def test_undistort_then_distort_round_trip():
    raw, front = render_depth(DEPTH_CAM, distorted=True)
    back = distort_depth(undistort_depth(raw.astype(np.float32), DEPTH_CAM), DEPTH_CAM)
    # the raw image of a barrel lens sees more than the undistorted one: its rim comes back empty
    inner = ~border_zone(raw.shape, 6)
    assert np.isfinite(back[inner]).all()
    ok = np.isclose(back, raw, rtol=1e-6)
    assert (ok | edge_zone(front))[inner].all()
    assert (ok | np.isnan(back)).mean() > 0.99
    # images: a smooth ramp survives the bilinear round trip to within a gray level
    cols = np.linspace(0, 250, 96, dtype=np.float32)
    image = np.repeat(cols[None, :], 72, axis=0).astype(np.uint8)
    image_back = distort_image(undistort_image(image, DEPTH_CAM), DEPTH_CAM)
    assert image_back.dtype == np.uint8
    assert np.abs(image_back.astype(int) - image)[inner].max() <= 2


def test_undistort_rejects_a_size_that_is_not_the_cameras():
    with pytest.raises(ValueError, match=r"depth is 50x40 .* calibrated on 96x72"):
        undistort_depth(np.ones((40, 50), np.uint16), DEPTH_CAM)


# ----------------------------------------------------------------------------
# The thesis's shift
# ----------------------------------------------------------------------------


def test_shift_occlusion_hole_filled_from_the_background_side():
    """Color camera on the right: the near block moves left; its trail takes the depth to its right."""
    row = np.array([[40, 40, 40, 40, 200, 200, 200, 60, 60, 60, 60, 60]], np.float32)
    out = align_shift(row, slope=2 / 160, background=40)
    # 200 moves 2 left (cols 2-4); 60 moves 0.25 -> 0; cols 5, 6 are holes -> nearest valid to the right (60)
    assert out.tolist() == [[40, 40, 200, 200, 200, 60, 60, 60, 60, 60, 60, 60]]


def test_shift_color_on_the_left_mirrors():
    row = np.array([[60, 60, 60, 60, 60, 200, 200, 200, 40, 40, 40, 40]], np.float32)
    out = align_shift(row, slope=2 / 160, background=40, color_side="left")
    assert out.tolist() == [[60, 60, 60, 60, 60, 60, 60, 200, 200, 200, 40, 40]]


def test_shift_border_hole_extends_the_foreground():
    """Thesis Fig. 24c: nothing to the right of a hole at the border, so the foreground fills it."""
    row = np.array([[40, 40, 40, 40, 40, 40, 40, 40, 200, 200, 200, 200]], np.float32)
    out = align_shift(row, slope=2 / 160, background=40)
    assert out.tolist() == [[40, 40, 40, 40, 40, 40, 200, 200, 200, 200, 200, 200]]


def test_shift_nearer_pixel_wins():
    row = np.array([[40, 100, 200, 40, 40, 40]], np.float32)
    out = align_shift(row, slope=1 / 40, background=40, color_side="left")
    # 100 moves 1.5 -> 2 right onto col 3 and beats the 40 there; 200 moves 4, out of the image;
    # cols 1, 2 are holes, filled from the left (the color camera's side)
    assert out.tolist() == [[40, 40, 40, 100, 40, 40]]
    out = align_shift(np.array([[40, 120, 80, 40, 40]], np.float32), slope=1 / 40, color_side="left", background=40)
    # 120 (col 1 + 2) and 80 (col 2 + 1) both land on col 3: the nearer one (120) wins
    assert out.tolist() == [[40, 40, 40, 120, 40]]


def test_shift_keeps_invalid_pixels_invalid():
    depth = np.full((3, 10), 40, np.uint8)
    depth[:, 6:9] = 200
    depth[1, 3] = 0
    out = align_shift(depth, slope=1 / 80, background=40)
    assert np.isnan(out[1, 3]) and np.isfinite(np.delete(out[1], 3)).all()
    assert np.isfinite(out[[0, 2]]).all()
    assert np.array_equal(align_shift(depth, slope=0.0, background=40), np.where(depth == 0, np.nan, depth),
                          equal_nan=True)


def test_shift_background_default_is_the_mean_of_the_farther_half():
    depth = np.array([[10, 20, 30, 200, 210, 220]], np.uint8)
    assert background_depth(depth) == 20.0
    assert background_depth(np.array([[1000, 1100, 3000, 3100]], np.uint16), encoding="distance") == 3050.0
    # with the default intercept the background does not move
    step = np.array([[20, 20, 20, 20, 200, 200]], np.uint8)
    assert background_depth(step) == 20.0
    assert align_shift(step, slope=0.01).tolist() == [[20, 20, 200, 200, 200, 200]]


def test_shift_background_default_is_not_decided_by_one_outlier():
    """Ties at the median: the farther half by rank, not the values strictly beyond the median."""
    intensity = np.array([[5] + [40] * 7 + [200] * 4], np.uint8)  # 12 values, the farther 6: 5 and five 40s
    assert background_depth(intensity) == pytest.approx((5 + 5 * 40) / 6)
    distance = np.array([[7000] + [2000] * 7 + [1000] * 4], np.uint16)
    assert background_depth(distance, encoding="distance") == pytest.approx((7000 + 5 * 2000) / 6)
    assert background_depth(np.array([[42.0]])) == 42.0  # one value: itself
    assert background_depth(np.array([[np.nan, 30.0, 0.0, 10.0]]), encoding="distance") == 30.0  # invalid ignored


def test_shift_on_a_parallel_rig_matches_the_color_view():
    """Parallel cameras 8 cm apart, 8-bit depth intensity d = 204 / Z; the slope comes from the rig."""
    f, b, c = 80.0, 0.08, 204.0
    K_d = np.array([[f, 0, 47.5], [0, f, 35.5], [0, 0, 1]])
    K_c = K_d.copy()
    K_c[0, 2] += f * b / Z_BACK  # a cropped color image in which the background does not move
    depth_cam = CameraModel(K_d, np.zeros(5), (96, 72))
    rig = StereoRig(depth_cam, CameraModel(K_c, np.zeros(5), (96, 72)), np.eye(3), np.array([-b, 0, 0]))
    z_d, _ = render_depth(depth_cam, distorted=False)
    z_c, front_c = render_depth(rig.color_camera, np.eye(3), rig.t, distorted=False)
    model = shift_from_rig(rig, inverse_scale=c)
    assert model.color_side == "right" and model.encoding == "inverse"
    assert model.slope == pytest.approx(f * b / c)
    out = align_shift((c / z_d).astype(np.float32), slope=model.slope, background=c / Z_BACK)
    truth = c / z_c
    wrong = ~np.isclose(out, truth)
    assert not (wrong & ~edge_zone(front_c)).any()
    assert wrong.sum() < 0.05 * front_c.sum()
    # the same with metric depth (mm) and the "distance" encoding
    model_mm = shift_from_rig(rig, depth_units=0.001)
    out_mm = align_shift(z_d * 1000, slope=model_mm.slope, background=Z_BACK * 1000, encoding="distance")
    assert np.array_equal(np.isclose(out_mm, z_c * 1000), np.isclose(out, truth))
    # the check agrees: the background lands where it was; with the uncropped color image it would not
    assert shift_misregistration(rig, (72, 96), (72, 96), Z_BACK) == pytest.approx(0.0, abs=1e-9)
    uncropped = StereoRig(depth_cam, CameraModel(K_d, np.zeros(5), (96, 72)), np.eye(3), rig.t)
    assert shift_misregistration(uncropped, (72, 96), (72, 96), Z_BACK) == pytest.approx(f * b / Z_BACK)
    assert shift_misregistration(uncropped, (72, 96), (72, 96)) == pytest.approx(0.0, abs=1e-9)  # at infinity


def _shift_rig(b: float = 0.06, size: tuple[int, int] = (672, 504)) -> StereoRig:
    """DEPTH_CAM and a parallel color camera of ``size`` (width, height) whose image shows the depth camera's
    view at the background (the depth intrinsics stretched, the principal point moved by f * b / Z_BACK as a
    crop would)."""
    K_d = DEPTH_CAM.K
    sx, sy = size[0] / 96, size[1] / 72
    K_c = np.array([[sx * K_d[0, 0], 0, (K_d[0, 2] + 0.5) * sx - 0.5 + sx * K_d[0, 0] * b / Z_BACK],
                    [0, sy * K_d[1, 1], (K_d[1, 2] + 0.5) * sy - 0.5], [0, 0, 1]])
    return StereoRig(DEPTH_CAM, CameraModel(K_c, np.zeros(5), size), np.eye(3), np.array([-b, 0, 0]))


def test_shift_misregistration_measures_the_rig():
    # the test rig: turned 1.8 degrees, other focal lengths and principal point: several depth pixels off
    assert shift_misregistration(RIG, (72, 96), (504, 672), Z_BACK) > 2.0
    assert shift_misregistration(_shift_rig(), (72, 96), (504, 672), Z_BACK) < 0.01
    # a rotation of theta moves the background by f * theta depth pixels at the centre, (1 + x**2) times
    # that at the edges (x = 0.64 at the corners here)
    theta = np.radians(1.0)
    turned = StereoRig(DEPTH_CAM, DEPTH_CAM, cv2.Rodrigues(np.array([0.0, theta, 0.0]))[0], np.zeros(3))
    assert 1.4 * 75.0 * theta < shift_misregistration(turned, (72, 96), (72, 96)) < 1.5 * 75.0 * theta
    behind = StereoRig(DEPTH_CAM, DEPTH_CAM, cv2.Rodrigues(np.array([0.0, np.pi, 0.0]))[0], np.zeros(3))
    assert shift_misregistration(behind, (72, 96), (72, 96)) == np.inf
    with pytest.raises(ValueError, match="z_background must be > 0"):
        shift_misregistration(RIG, (72, 96), (504, 672), -1.0)


def test_chain_shift_on_a_rig_that_fits_matches_the_color_view():
    """The whole shift chain (undistort, d_bg, k from the rig) on a parallel rig whose color image shows the
    depth camera's view: edges within 1 depth pixel of the depth rendered on the color grid / 7."""
    rig = _shift_rig()
    out, notes = align_depth(_raw_depth_mm(), rig, settings=AlignSettings(method="shift", depth_units=0.001))
    assert "shifted" in notes[-1] and "d_bg = 2000" in notes[-1]
    truth, front = render_depth(rig.color_camera.resized((72, 96)), np.eye(3), rig.t, distorted=False)
    valid = np.isfinite(out)
    assert valid[~border_zone(out.shape, 3)].all()
    wrong = valid & (np.abs(out / 1000 - truth) > 0.01 * truth)
    assert not (wrong & ~edge_zone(front, 1)).any()
    assert wrong.sum() < 0.1 * front.sum()


def test_chain_shift_refuses_a_rig_whose_color_view_differs():
    """Before the check, the test rig's shift silently put the rectangle ~3.5 depth pixels off (1a)."""
    settings = AlignSettings(method="shift", depth_units=0.001)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # 1.8 degrees: shift_from_rig does not warn, the check refuses
        with pytest.raises(ValueError, match=r"misplace the depth by \d+\.\d depth pixels.*reproject.*crop"):
            align_depth(_raw_depth_mm(), RIG, settings=settings)
        with pytest.raises(ValueError, match="checked at the background, 2 m"):
            align_pair(_raw_depth_mm(), np.zeros((504, 672, 3), np.uint8), RIG, settings=settings)
    # without units (a slope given) the check looks at infinity, where the background plane of _shift_rig moves
    with pytest.raises(ValueError, match="infinity"):
        align_depth(_raw_depth_mm(), _shift_rig(), settings=AlignSettings(method="shift", slope=2.25))


def test_shift_from_a_rotated_rig_warns():
    turned = StereoRig(DEPTH_CAM, COLOR_CAM, cv2.Rodrigues(np.array([0.0, 0.06, 0.0]))[0], RIG_T)
    with pytest.warns(AlignmentWarning, match="not a parallel"):
        shift_from_rig(turned, depth_units=0.001)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        shift_from_rig(RIG, depth_units=0.001)  # 1.8 degrees: parallel enough
    with pytest.raises(ValueError, match="units are unknown"):
        shift_from_rig(RIG)


def test_shift_bad_arguments():
    depth = np.full((4, 4), 50, np.uint8)
    with pytest.raises(ValueError, match="color_side must be one of"):
        align_shift(depth, slope=1.0, color_side="up")
    with pytest.raises(ValueError, match="slope must be >= 0"):
        align_shift(depth, slope=-1.0)
    with pytest.raises(ValueError, match="no valid pixel"):
        align_shift(np.zeros((4, 4), np.uint8), slope=1.0)


# ----------------------------------------------------------------------------
# The calibrated reprojection
# ----------------------------------------------------------------------------


def _raw_depth_mm() -> np.ndarray:
    z, _ = render_depth(DEPTH_CAM, distorted=True)
    return np.floor(z * 1000 + 0.5).astype(np.uint16)


def test_reproject_grid_is_the_color_grid_divided_by_s():
    s, grid = reproject_camera(RIG)
    assert s == 7 and grid.image_size == (96, 72) and not grid.has_distortion
    assert grid.K[0, 0] == pytest.approx(80.0) and grid.K[0, 2] == pytest.approx((337.0 + 0.5) / 7 - 0.5)


def test_reproject_matches_the_depth_rendered_in_the_color_view():
    out = align_reproject(_raw_depth_mm(), RIG, depth_units=0.001, color_distorted=True)
    _, grid = reproject_camera(RIG, distorted=True)
    truth, front = render_depth(grid, RIG_R, RIG_T, distorted=True)
    assert out.shape == truth.shape == (72, 96) and out.dtype == np.float32
    valid = np.isfinite(out)
    near_edge = edge_zone(front, 1)
    good = valid & (np.abs(out / 1000 - truth) < 0.01 * truth)
    assert (good | near_edge)[valid].all()              # values right, edges within 1 px
    disoccluded = edge_zone(front, 3) | border_zone(out.shape, 2)  # disparity step 2.4 px
    assert not (~valid & ~disoccluded).any()             # holes only where the depth camera could not see
    assert valid.mean() > 0.97


def test_reproject_agrees_with_cv2_register_depth():
    """Oracle: cv2.registerDepth (OpenCV 5, top level) on an undistorted uint16 mm map.

    registerDepth writes each depth pixel to one output pixel, so where the
    color grid is finer than the depth grid (here x1.07) it leaves gaps, and
    through a gap in the near rectangle the background shows. Ours fills each
    pixel's footprint: it covers every pixel registerDepth covers, with the
    same depth away from the rectangle's edges.
    """
    depth_cam = DEPTH_CAM.without_distortion()
    rig = StereoRig(depth_cam, COLOR_CAM.without_distortion(), RIG_R, RIG_T)
    z, _ = render_depth(depth_cam, distorted=False)
    depth = np.floor(z * 1000 + 0.5).astype(np.uint16)
    ours = align_reproject(depth, rig, depth_units=0.001, depth_distorted=False)
    _, grid = reproject_camera(rig)
    Rt = np.eye(4)
    Rt[:3, :3], Rt[:3, 3] = RIG_R, RIG_T
    theirs = cv2.registerDepth(depth_cam.K, grid.K, np.zeros(5), Rt, depth, grid.image_size).astype(np.float32)
    _, front = render_depth(grid, RIG_R, RIG_T, distorted=False)
    both = (theirs > 0) & np.isfinite(ours)
    assert np.array_equal(both, theirs > 0)                         # ours covers theirs
    assert np.isfinite(ours).mean() > (theirs > 0).mean() + 0.05    # and closes their gaps
    diff = np.abs(ours - theirs)
    assert (diff[both & ~edge_zone(front, 2)] <= 2.0).all()         # mm: rounding, and the tilt within a pixel
    assert (diff[both] <= 2.0).mean() > 0.995


def test_reproject_identity_rig_is_the_identity():
    cam = DEPTH_CAM.without_distortion()
    depth = _raw_depth_mm()
    out = align_reproject(depth, StereoRig(cam, cam, np.eye(3), np.zeros(3)), depth_units=0.001,
                          depth_distorted=False)
    assert np.array_equal(out, depth.astype(np.float32))


def test_reproject_keeps_invalid_invalid():
    depth = _raw_depth_mm()
    depth[20:30, 10:20] = 0  # a hole in the background, left of the near rectangle
    out = align_reproject(depth, RIG, depth_units=0.001)
    full = align_reproject(_raw_depth_mm(), RIG, depth_units=0.001)
    lost = np.isfinite(full) & np.isnan(out)
    assert lost.sum() >= 0.8 * 100  # about the 10 x 10 block, not closed by the pinhole rule
    # elsewhere the same surface (at the block's rim a neighbour's footprint replaces the lost sample)
    assert np.allclose(out[~lost], full[~lost], atol=2.0, equal_nan=True)


def test_reproject_invalid_outline_hides_the_background_behind_it():
    """A depth camera leaves the pixels empty that straddle an outline (the Azure Kinect 2-3 of them between a mug
    and the wall). Reprojected, the wall beside the outline moves behind the near object by the parallax; where
    the empty pixels leave no near sample, it must not show through as background depth inside the outline."""
    near = (0.5, -0.08, 0.04, -0.06, 0.05)   # at 0.5 m: 4.8 px of parallax against the wall (21 pixels showed it)
    z, front_raw = render_depth(DEPTH_CAM, distorted=True, front=near)
    depth = np.floor(z * 1000 + 0.5).astype(np.uint16)
    depth[edge_zone(front_raw, 2)] = 0   # the outline's pixels, on both sides
    out = align_reproject(depth, RIG, depth_units=0.001)
    _, grid = reproject_camera(RIG)
    truth, front = render_depth(grid, RIG_R, RIG_T, distorted=False, front=near)
    inside = front & ~edge_zone(front, 1)
    with np.errstate(invalid="ignore"):
        background_inside = inside & (out > 1500)
    assert not background_inside.any(), np.argwhere(background_inside)
    # the rectangle's own depth stays where it was measured, and the background away from it is whole
    assert np.isfinite(out[inside]).mean() > 0.6
    assert np.isfinite(out[~edge_zone(front, 10) & ~front]).all()   # beyond the parallax and the empty outline


def test_reproject_hides_far_samples_the_parallax_moved_between_near_ones():
    """_seen_between: a wall sample between two of a mug's, from far away in the depth image, is hidden; one the
    depth camera saw through a gap (its neighbours in the depth image) stays, and so does a run of 3 or more."""
    from depthrefine.rig.reproject import _seen_between

    def row(far: list[int], from_column: int) -> np.ndarray:
        z = np.full((3, 9), 0.27)
        origin = np.stack([np.full((3, 9), 50.0), np.tile(np.arange(100.0, 109.0), (3, 1))])
        z[:, far] = 0.8
        origin[1][:, far] = from_column + np.arange(len(far))
        return _seen_between(z, origin)[1]

    assert row([4], 60).tolist() == [False] * 4 + [True] + [False] * 4           # moved in by the parallax
    assert not row([4], 104).any()                                                # a gap the camera saw
    assert row([4, 5], 60)[4:6].all() and not row([3, 4, 5], 60).any()            # runs of 2 only
    assert not _seen_between(np.full((3, 3), np.nan), np.full((2, 3, 3), np.nan)).any()


def test_reproject_radial_depth():
    z, _ = render_depth(DEPTH_CAM, distorted=True)
    rows, cols = np.mgrid[0:72, 0:96]
    norm = cv2.undistortPoints(np.stack([cols, rows], -1).reshape(-1, 1, 2).astype(np.float64), DEPTH_CAM.K,
                               DEPTH_CAM.dist).reshape(72, 96, 2)
    ranges = z * np.sqrt(1 + (norm ** 2).sum(axis=2))
    out_z = align_reproject(z.astype(np.float32), RIG, depth_units=1.0)
    out_r = align_reproject(ranges.astype(np.float32), RIG, depth_units=1.0, radial=True)
    # float32 inputs round differently, so a few pixels take a neighbouring sample of the same surface
    assert np.isclose(out_z, out_r, rtol=1e-3, equal_nan=True).mean() > 0.995


def test_reproject_8bit_intensity_needs_a_conversion():
    intensity = np.full((72, 96), 120, np.uint8)
    with pytest.raises(ValueError, match="inverse_scale"):
        align_reproject(intensity, RIG)
    out = align_reproject(intensity, RIG, inverse_scale=240.0)  # 2 m everywhere
    assert np.nanmax(np.abs(out - 120)) < 4  # the 1.8 degree turn tilts the plane by a few levels
    assert np.isfinite(out).mean() > 0.97


# ----------------------------------------------------------------------------
# The chain
# ----------------------------------------------------------------------------


def test_align_pair_reproject_and_shift():
    depth = _raw_depth_mm()
    rgb = np.zeros((504, 672, 3), np.uint8)
    pair = align_pair(depth, rgb, RIG, settings=AlignSettings(depth_units=0.001))
    assert pair.depth_lr.shape == (72, 96) and pair.rgb_hr.shape == (504, 672, 3)
    assert not pair.camera.has_distortion and pair.method == "reproject"
    assert any("undistorted" in n for n in pair.notes)
    depth_lr, notes = align_depth(depth, _shift_rig(), settings=AlignSettings(method="shift", depth_units=0.001))
    assert depth_lr.shape == (72, 96) and "shifted" in notes[-1]
    with pytest.raises(ValueError, match="needs the depth's units"):
        align_depth(depth, RIG)
    with pytest.raises(ValueError, match="needs its slope"):
        align_depth(depth, RIG, settings=AlignSettings(method="shift"))
    with pytest.raises(ValueError, match="color image is 10x10"):
        align_pair(depth, np.zeros((10, 10, 3), np.uint8), RIG, settings=AlignSettings(depth_units=0.001))
    with pytest.raises(ValueError, match="method must be one of"):
        AlignSettings(method="warp")


def test_chain_without_undistortion_takes_both_images_as_undistorted():
    """undistort_depth / undistort_color false: the images are already undistorted (2a), so the depth is
    rendered for the undistorted color camera, not for a raw one."""
    color = CameraModel(COLOR_CAM.K, np.array([-0.3, 0.1, 0, 0, 0]), COLOR_CAM.image_size)
    rig = StereoRig(DEPTH_CAM, color, RIG_R, RIG_T)
    z, _ = render_depth(DEPTH_CAM, distorted=False)
    depth = np.floor(z * 1000 + 0.5).astype(np.uint16)
    settings = AlignSettings(depth_units=0.001, undistort_depth=False, undistort_color=False)
    rgb = np.arange(504 * 672 * 3, dtype=np.uint32).reshape(504, 672, 3).astype(np.uint8)
    pair = align_pair(depth, rgb, rig, settings=settings)
    expected = align_reproject(depth, rig, depth_units=0.001, depth_distorted=False, color_distorted=False)
    assert np.array_equal(pair.depth_lr, expected, equal_nan=True)
    assert not np.array_equal(expected, align_reproject(depth, rig, depth_units=0.001, depth_distorted=False,
                                                        color_distorted=True), equal_nan=True)
    assert np.array_equal(pair.rgb_hr, rgb) and not pair.camera.has_distortion  # not resampled
    assert "color image taken as already undistorted" in pair.notes
    _, grid = reproject_camera(rig)
    truth, front = render_depth(grid, RIG_R, RIG_T, distorted=False)
    valid = np.isfinite(pair.depth_lr)
    good = valid & (np.abs(pair.depth_lr / 1000 - truth) < 0.01 * truth)
    assert (good | edge_zone(front, 1))[valid].all() and valid.mean() > 0.95


# ----------------------------------------------------------------------------
# A ratio below 1.5 (the Azure Kinect's 1.21): a grid at the depth resolution, upsampled by the method
# ----------------------------------------------------------------------------


def _rig_ratio_1_2() -> StereoRig:
    """The depth camera of RIG beside a color camera with 1.2 times its focal length and size."""
    color = CameraModel(np.array([[90.0, 0, 57.5], [0, 90.6, 42.5], [0, 0, 1]]), np.zeros(5), (115, 86))
    return StereoRig(DEPTH_CAM.without_distortion(), color, RIG_R, RIG_T)


def test_a_ratio_below_1_5_renders_at_the_depth_resolution_and_the_method_upsamples_x2():
    from depthrefine.rig.chain import AlignSettings, align_pair, refine_pair, upsampling_grid

    rig = _rig_ratio_1_2()
    s, grid = reproject_camera(rig)
    assert s == pytest.approx(1.2) and grid.image_size == (96, 72)  # not rounded to 1 (115x86)
    assert reproject_camera(rig, factor=2)[1].image_size == (58, 43)
    z, front = render_depth(rig.depth_camera, distorted=False)
    depth = np.floor(z * 1000 + 0.5).astype(np.uint16)
    color_z, color_front = render_depth(rig.color_camera, RIG_R, RIG_T, distorted=False)
    rgb = np.where(color_front[..., None], 60, 200).astype(np.uint8).repeat(3, axis=2)
    pair = align_pair(depth, rgb, rig, settings=AlignSettings(depth_units=0.001, undistort_depth=False))
    assert pair.depth_lr.shape == (72, 96) and "s = 1.2" in pair.notes[-1]
    assert upsampling_grid(pair.depth_lr.shape, rgb.shape) == (2, (144, 192))
    refined, note = refine_pair(pair.depth_lr, pair.rgb_hr, method="bilinear")
    assert refined.shape == (86, 115) and "upsampled x2 onto a 192x144 grid" in note
    good = np.isfinite(refined) & (np.abs(refined / 1000 - color_z) < 0.01 * color_z)
    assert good[~edge_zone(color_front, 3)].mean() > 0.97
    with pytest.raises(ValueError, match="factor must be a number >= 1"):
        reproject_camera(rig, factor=0.5)
    with pytest.raises(ValueError, match="factor must be a number >= 1"):
        AlignSettings(factor=0.9)
    assert AlignSettings(factor=1.21).factor == 1.21


def test_the_chain_tells_gbp_its_input_is_reprojected():
    """refine_pair (run, batch with a rig, the mug demo) gives gbp and gbp-fast ``reprojected=True``, keeping the
    other parameters it was given; methods without that parameter get theirs unchanged."""
    from depthrefine.methods.gbp import GbpParams
    from depthrefine.methods.gbp.fast import GbpFastParams
    from depthrefine.rig.chain import refine_pair, reprojected_params

    assert reprojected_params("gbp") == GbpParams(reprojected=True)
    assert reprojected_params("gbp", GbpParams(lambda_lr=5.0)) == GbpParams(lambda_lr=5.0, reprojected=True)
    assert reprojected_params("gbp-fast") == GbpFastParams(reprojected=True)
    assert reprojected_params("bicubic") is None
    from test_gbp import misplaced_samples

    _, rgb, depth_lr = misplaced_samples()
    refined, _ = refine_pair(depth_lr, rgb, method="gbp")
    np.testing.assert_array_equal(refined, depthrefine.refine(depth_lr, rgb, params=GbpParams(reprojected=True)))
    assert not np.array_equal(refined, depthrefine.refine(depth_lr, rgb))


# ----------------------------------------------------------------------------
# The unmeasured pixels after a refinement (run)
# ----------------------------------------------------------------------------


def _strip_scene(scale: int = 4):
    """A near square (500) before a wall (2000) on a 24x24 depth grid with the two pixels between them empty (the
    strip a depth camera leaves at an outline), a 2x2 dropout inside the wall, the refinement's dense result
    (1000 where nothing was measured) and the color image at ``scale``: the square's color edge lies in the
    middle of the strip."""
    depth_lr = np.full((24, 24), 2000.0, np.float32)
    depth_lr[6:18, 6:18] = np.nan
    depth_lr[8:16, 8:16] = 500.0
    depth_lr[19:21, 2:4] = np.nan
    size = 24 * scale
    rgb = np.full((size, size, 3), (40, 90, 200), np.uint8)
    rgb[7 * scale:17 * scale, 7 * scale:17 * scale] = (210, 40, 30)
    dense = cv2.resize(np.nan_to_num(depth_lr, nan=1000.0), (size, size), interpolation=cv2.INTER_NEAREST)
    return depth_lr, rgb, dense


def test_keep_unmeasured_border_follows_the_color():
    depth_lr, rgb, dense = _strip_scene()
    plain = keep_unmeasured(dense, depth_lr)
    guided = keep_unmeasured(dense, depth_lr, rgb_hr=rgb)
    square = (rgb == (210, 40, 30)).all(axis=2)
    assert np.isnan(plain[24:32, 24:72]).all()                     # the grid keeps the strip empty
    assert np.isin(guided[square], (500, 2000)).all() and (guided[square] == 500).sum() >= square.sum() - 4
    assert (guided[~square & np.isfinite(guided)] == 2000).all()   # the square up to its color edge (but for its
    # 4 corner pixels), the wall up to it: each pixel holds the depth of a measured surface, nothing invented
    assert np.isfinite(guided[20:76, 20:76]).all()                 # the strip is given to the two surfaces
    assert np.isnan(guided[76:84, 8:16]).all() and np.isnan(plain[76:84, 8:16]).all()   # the dropout stays
    # --fill-holes: the dropout takes the refinement's depth, the rest is the same
    filled = keep_unmeasured(dense, depth_lr, rgb_hr=rgb, fill_enclosed=True)
    assert (filled[76:84, 8:16] == 1000).all() and np.array_equal(filled[20:76, 20:76], guided[20:76, 20:76])


def test_keep_unmeasured_border_moves_only_onto_a_color_edge_within_the_band():
    depth_lr = np.full((24, 24), 2000.0, np.float32)
    depth_lr[:, 12:] = np.nan                                      # a wide region no depth reached
    rgb = np.full((96, 96, 3), 128, np.uint8)
    dense = np.full((96, 96), 2000.0, np.float32)
    grid_holes = np.isnan(keep_unmeasured(dense, depth_lr))
    assert grid_holes[:, 48:].all() and not grid_holes[:, :48].any()
    assert np.array_equal(np.isnan(keep_unmeasured(dense, depth_lr, rgb_hr=rgb)), grid_holes)   # flat color
    rgb[:, 52:] = 250                                              # a color edge one depth pixel inside the hole
    moved = np.isnan(keep_unmeasured(dense, depth_lr, rgb_hr=rgb))
    assert not moved[:, :52].any() and moved[:, 52:].all()
    rgb[:, 52:] = 128
    rgb[:, 64:] = 250                                              # four depth pixels inside: beyond the band
    assert np.array_equal(np.isnan(keep_unmeasured(dense, depth_lr, rgb_hr=rgb)), grid_holes)


def test_unmeasured_along_color_keeps_a_thin_measured_part():
    unmeasured = np.ones((1, 40), bool)
    unmeasured[0, 19:21] = False                                   # two measured pixels between wide holes
    costs = color_step_costs(np.zeros((1, 40, 3), np.uint8), blur=0, step_levels=2)
    moved = unmeasured_along_color(unmeasured, costs, 6)
    assert not moved[0, 19:21].all()                              # its middle stays measured


@pytest.mark.parametrize("blur", [0.0, 1.0])
@pytest.mark.parametrize("channels", [1, 3])
def test_color_step_costs_are_the_channel_sums_in_order(blur, channels):
    """The step costs (summed plane by plane for speed) have the bits of the plain expression ``sqrt(sum over the
    channels of squared differences, in channel order) + step_levels``: the geodesic's outputs do not move."""
    rng = np.random.default_rng(7)
    color = rng.integers(0, 256, (37, 53, channels)).astype(np.uint8)
    c = color.astype(np.float32)
    if blur:
        c = cv2.GaussianBlur(c, (0, 0), blur).reshape(c.shape)
    step = np.float32(2.0)
    dx, dy = c[:, 1:] - c[:, :-1], c[1:] - c[:-1]
    plain_x = np.sqrt(np.sum(np.square(dx), axis=2)) + step
    plain_y = np.sqrt(np.sum(np.square(dy), axis=2)) + step
    cost_x, cost_y = color_step_costs(color, blur=blur, step_levels=2.0)
    assert cost_x.dtype == cost_y.dtype == np.float32
    np.testing.assert_array_equal(cost_x, np.pad(plain_x, ((0, 0), (0, 1))))
    np.testing.assert_array_equal(cost_y, np.pad(plain_y, ((0, 1), (0, 0))))


def test_keep_unmeasured_checks_the_color_image_on_every_frame():
    measured = np.full((4, 4), 100.0, np.float32)           # nothing unmeasured: the border has nothing to do
    with pytest.raises(ValueError, match="rgb_hr has shape"):
        keep_unmeasured(np.full((8, 8), 100.0, np.float32), measured, rgb_hr=np.zeros((6, 6, 3), np.uint8))
    with pytest.raises(ValueError, match="rgb_hr"):
        keep_unmeasured(np.full((8, 8), 100.0, np.float32), measured, rgb_hr=np.full((8, 8, 3), 2.0))
    with pytest.raises(ValueError, match="costs must be"):
        unmeasured_along_color(np.zeros((8, 8), bool), (np.zeros((5, 5), np.float32),) * 2, 2)
