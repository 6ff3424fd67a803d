"""gbp measures each input once (issue 19): no measurement of the input is computed twice in one call."""

import cProfile
import pstats

import numpy as np
import pytest

from depthrefine.methods.gbp import GbpParams, edges, measure, solve, upsample_gbp, upsample_gbp_with_confidence

cv2 = pytest.importorskip("cv2")


def _calls(run) -> dict[str, int]:
    """How often each function of gbp's measure, solve and edges modules ran in ``run()``, by name."""
    profile = cProfile.Profile()
    profile.enable()
    try:
        run()
    finally:
        profile.disable()
    counts: dict[str, int] = {}
    files = {measure.__file__, solve.__file__, edges.__file__}
    for (file, _line, name), (_, calls, *_rest) in pstats.Stats(profile).stats.items():
        if file in files:
            counts[name] = counts.get(name, 0) + calls
    return counts


@pytest.fixture(scope="module")
def scene():
    """Block means (x8, the coarse-to-fine path) of three boxes on a slope, with holes; the color shows the boxes."""
    rng = np.random.default_rng(5)
    H, W = 256, 320
    rows, cols = np.mgrid[0:H, 0:W]
    depth = (1000.0 + rows + 0.5 * cols).astype(np.float32)
    rgb = np.full((H, W, 3), 90, np.uint8)
    for top, left, near, color in ((40, 40, 600.0, (200, 40, 40)), (120, 180, 700.0, (40, 200, 40)),
                                   (170, 60, 800.0, (40, 40, 200))):
        depth[top:top + 60, left:left + 90] = near
        rgb[top:top + 60, left:left + 90] = color
    depth_lr = depth.reshape(H // 8, 8, W // 8, 8).mean(axis=(1, 3)).astype(np.float32)
    depth_lr += rng.normal(0, 2.0, depth_lr.shape).astype(np.float32)
    depth_lr[5:8, 20:24] = np.nan
    depth_lr[::9, ::7] = np.nan
    rgb = np.clip(rgb + rng.normal(0, 2.0, rgb.shape), 0, 255).astype(np.uint8)
    return depth_lr, rgb


@pytest.mark.parametrize("params", [GbpParams(), GbpParams(snap_edges=True)])
def test_each_measure_runs_once_per_measured_input(scene, params):
    """Two inputs are measured: the input, and its reduction one octave down for the guide's check (step 5)."""
    depth_lr, rgb = scene
    upsample_gbp(depth_lr, rgb, params=params)   # compiled kernels and caches warm
    calls = _calls(lambda: upsample_gbp(depth_lr, rgb, params=params))
    for name in ("measure_input", "fill_holes", "estimate_noise", "estimate_guide_noise", "near_jump", "_span"):
        assert calls.get(name) == 2, (name, calls.get(name))
    # the 3x3 range is made where it is read, steps 2 and 4, not held through the solves (peak memory)
    assert calls.get("neighbourhood") == 4
    assert calls.get("_footprint_share") == 1   # the check's input is a block mean by construction
    # per measured input its local bounds, and the residual's bounds with a margin around the holes
    assert calls.get("local_bounds") == 4
    # the band around the large jumps: step 1b measures it, step 6 (snap_edges) reads it
    assert calls.get("jump_band") == 1


def test_the_confidence_map_measures_no_more(scene):
    depth_lr, rgb = scene
    upsample_gbp_with_confidence(depth_lr, rgb)
    calls = _calls(lambda: upsample_gbp_with_confidence(depth_lr, rgb))
    assert calls.get("measure_input") == 2 and calls.get("fill_holes") == 2 and calls.get("neighbourhood") == 4


def test_the_cached_measures_are_the_functions_results(scene):
    depth_lr, rgb = scene
    m = measure.measure_input(depth_lr, rgb)
    kernel = np.ones((3, 3), np.uint8)
    low, high = m.neighbourhood()
    assert np.array_equal(low, cv2.erode(m.filled, kernel)) and np.array_equal(high, cv2.dilate(m.filled, kernel))
    assert m.large_jumps is m.large_jumps
    assert np.array_equal(m.large_jumps, edges.jump_band(m)) and m.large_jumps.any()
    shape = rgb.shape[:2]
    assert np.array_equal(solve.clamped_bicubic(m.filled, shape, m.jump, neighbourhood=m.neighbourhood()),
                          solve.clamped_bicubic(m.filled, shape, m.jump))
