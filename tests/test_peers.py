"""The OpenCV-contrib peers (depthrefine.methods.peers) and their registration."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

import depthrefine
from depthrefine.methods import peers
from depthrefine.methods.baselines import upsample_bilinear
from depthrefine.evaluate import score
from depthrefine.bench.synthetic import make_two_planes

PEERS = {
    "jbf": (peers.upsample_jbf, peers.JointBilateralParams),
    "guided": (peers.upsample_guided, peers.GuidedParams),
    "fgs": (peers.upsample_fgs, peers.FastGlobalSmootherParams),
    "wmf": (peers.upsample_wmf, peers.WeightedMedianParams),
}


@pytest.mark.parametrize("name", sorted(PEERS))
def test_registered_with_their_params_type(name):
    func, params_type = PEERS[name]
    entry = depthrefine.get_method(name)
    assert entry.func is func and entry.params_type is params_type and entry.guided and entry.summary


@pytest.mark.parametrize("name", sorted(PEERS))
def test_shape_dtype_and_constant_fixed_point(name, rng):
    func, _ = PEERS[name]
    rgb = rng.integers(0, 256, (32, 48, 3)).astype(np.uint8)
    out = func(np.full((8, 12), 93, np.uint8), rgb)
    assert out.shape == (32, 48) and out.dtype == np.float32
    np.testing.assert_allclose(out, 93.0, atol=1e-3)


@pytest.mark.parametrize("name", sorted(PEERS))
def test_invalid_pixels_are_never_averaged_in(name):
    func, _ = PEERS[name]
    depth = np.full((8, 8), 100.0, np.float32)
    depth[2:4, 2:4] = np.nan
    depth[5, 5] = 0.0
    depth[6, 1] = -3.0
    depth0 = depth.copy()
    out = func(depth, np.full((32, 32, 3), 128, np.uint8))
    assert np.isfinite(out).all()
    np.testing.assert_allclose(out, 100.0, atol=1e-3)  # holes filled from valid pixels only
    np.testing.assert_array_equal(depth, depth0)


@pytest.mark.parametrize("name", ["jbf", "wmf", "fgs"])
def test_color_edge_sharpens_the_depth_edge(name):
    # Two planes with aligned color and depth edges: a color-guided filter must beat
    # plain bilinear enlargement near the edge.
    scene = make_two_planes((64, 64), 8, edge_col=29)
    func, _ = PEERS[name]
    gt = scene.depth_hr_gt
    bilinear = score(upsample_bilinear(scene.depth_lr, scene.rgb_hr), gt).edge_rmse
    peer = score(func(scene.depth_lr, scene.rgb_hr), gt).edge_rmse
    assert peer < 0.8 * bilinear


def test_lengths_scale_with_the_factor():
    # The guided filter radius is radius_lr * s color pixels: doubling both the
    # factor and the image (same content) gives the same result, enlarged.
    scene4 = make_two_planes((32, 64), 4, edge_col=29)
    scene8 = make_two_planes((64, 128), 8, edge_col=58)
    params = peers.GuidedParams(radius_lr=1.0, eps=1e-2)
    a = peers.upsample_guided(scene4.depth_lr, scene4.rgb_hr, params=params)
    b = peers.upsample_guided(scene8.depth_lr, scene8.rgb_hr, params=params)
    assert a.shape == (32, 64) and b.shape == (64, 128)
    assert np.abs(cv2.resize(b, (64, 32), interpolation=cv2.INTER_AREA) - a).mean() < 2.0


def test_params_are_used_and_validated():
    scene = make_two_planes((32, 64), 4, edge_col=29)
    weak = peers.upsample_fgs(scene.depth_lr, scene.rgb_hr,
                              params=peers.FastGlobalSmootherParams(lambda_lr=0.01, sigma_color=2.0))
    strong = peers.upsample_fgs(scene.depth_lr, scene.rgb_hr,
                                params=peers.FastGlobalSmootherParams(lambda_lr=1000.0, sigma_color=200.0))
    assert not np.allclose(weak, strong)
    with pytest.raises(ValueError, match="sigma_color must be > 0"):
        peers.JointBilateralParams(sigma_color=0)
    with pytest.raises(TypeError, match="radius_lr"):
        peers.GuidedParams(radius_lr="2")
    with pytest.raises(ValueError, match="num_iter"):
        peers.FastGlobalSmootherParams(num_iter=0)
    with pytest.raises(ValueError, match="max_diameter"):
        peers.JointBilateralParams(max_diameter=1)
    with pytest.raises(TypeError, match="GuidedParams"):
        peers.upsample_guided(scene.depth_lr, scene.rgb_hr, params=peers.WeightedMedianParams())
    with pytest.raises(TypeError, match="takes params of type"):
        depthrefine.refine(scene.depth_lr, scene.rgb_hr, method="wmf", params=peers.GuidedParams())


def test_deterministic_and_float_guides_accepted(rng):
    depth = rng.integers(20, 200, (8, 8)).astype(np.uint8)
    rgb = rng.integers(0, 256, (32, 32, 3)).astype(np.uint8)
    for name, (func, _) in PEERS.items():
        a, b = func(depth, rgb), func(depth, rgb)
        np.testing.assert_array_equal(a, b, err_msg=name)
        c = func(depth, rgb.astype(np.float32) / 255.0)
        assert c.shape == (32, 32) and np.isfinite(c).all(), name


def test_fast_bilateral_solver_availability_matches_opencv():
    available = peers.fast_bilateral_solver_available()
    try:
        cv2.ximgproc.fastBilateralSolverFilter(np.zeros((8, 8, 3), np.uint8), np.ones((8, 8), np.float32),
                                               np.ones((8, 8), np.float32))
        works = True
    except cv2.error as exc:
        assert "EIGEN" in str(exc).upper()
        works = False
    assert available is works


def test_fast_bilateral_solver_is_registered_exactly_when_it_works():
    from depthrefine import METHODS
    from depthrefine.methods import peers
    status = peers.fast_bilateral_solver_status()
    assert peers.fast_bilateral_solver_available() == (status == "")
    assert ("fbs" in METHODS) == (status == "")
    depth_lr = np.full((4, 4), 7.0, np.float32)
    rgb = np.zeros((16, 16, 3), np.uint8)
    if status:
        assert "fastBilateralSolverFilter" in status and ("EIGEN" in status or "has no" in status)
        with pytest.raises(ValueError, match="'fbs' is unavailable"):
            peers.upsample_fbs(depth_lr, rgb)
    else:
        out = peers.upsample_fbs(depth_lr, rgb)
        assert out.shape == (16, 16) and np.allclose(out, 7.0, atol=1e-3)
    with pytest.raises(ValueError, match="lam"):
        peers.FastBilateralSolverParams(lam=0.0)
