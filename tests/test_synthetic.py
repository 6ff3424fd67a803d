"""The scene generator: it must meet the thesis's assumptions, or the tests built on it mean nothing."""

from __future__ import annotations

import numpy as np
import pytest

from depthrefine.bench.synthetic import DEPTH_CONSTANT, PALETTE, make_scene, make_two_planes


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16, np.float32])
def test_shapes_dtypes_and_units(dtype):
    scene = make_scene((96, 64), 8, n_objects=2, seed=4, dtype=dtype)
    assert scene.rgb_hr.shape == (96, 64, 3) and scene.rgb_hr.dtype == np.uint8
    assert scene.depth_hr_gt.shape == (96, 64) and scene.depth_hr_gt.dtype == np.float32
    assert scene.labels_hr.shape == (96, 64)
    assert scene.depth_lr.shape == (12, 8) and scene.depth_lr.dtype == dtype
    assert scene.scale == 8
    assert scene.units == {np.uint8: "levels", np.uint16: "mm", np.float32: "m"}[dtype]


def test_same_seed_same_scene_other_seed_other_scene():
    a = make_scene((64, 64), 4, seed=7, color_noise_std=3, shading=0.2, hole_fraction=0.1)
    b = make_scene((64, 64), 4, seed=7, color_noise_std=3, shading=0.2, hole_fraction=0.1)
    c = make_scene((64, 64), 4, seed=8, color_noise_std=3, shading=0.2, hole_fraction=0.1)
    for name in ("rgb_hr", "depth_hr_gt", "depth_lr", "labels_hr"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert not np.array_equal(a.depth_lr, c.depth_lr)


def test_surfaces_are_flat_colored_and_fronto_parallel():
    scene = make_scene((128, 128), 4, n_objects=3, seed=1)
    labels = scene.labels_hr
    assert sorted(np.unique(labels).tolist()) == [0, 1, 2, 3]
    colors = []
    for surface, depth in enumerate(scene.depths):
        mask = labels == surface
        # One depth and one color per surface (flat, fronto-parallel).
        assert np.all(scene.depth_hr_gt[mask] == np.float32(depth))
        pixels = np.unique(scene.rgb_hr[mask], axis=0)
        assert len(pixels) == 1
        colors.append(tuple(pixels[0]))
    assert len(set(colors)) == 4, "every surface has its own color"
    assert all(any((c == p).all() for p in PALETTE) for c in np.array(colors))


def test_depths_are_distinct_far_beyond_the_tolerance():
    for seed in range(10):
        scene = make_scene((128, 128), 4, n_objects=4, seed=seed, noise_std=0)
        levels = np.sort(np.array(scene.depths))
        assert np.diff(levels).min() >= 20, seed
        assert scene.depths[0] == levels[0], "the wall is the farthest surface (smallest intensity)"


def test_objects_are_large_and_apart():
    """Each object spans >= 2s pixels and >= s pixels separate objects and the border."""
    s = 8
    scene = make_scene((192, 192), s, n_objects=3, seed=2)
    labels = scene.labels_hr
    assert (labels[:s] == 0).all() and (labels[-s:] == 0).all()
    assert (labels[:, :s] == 0).all() and (labels[:, -s:] == 0).all()
    for obj in (1, 2, 3):
        rows, cols = np.nonzero(labels == obj)
        assert rows.max() - rows.min() + 1 >= 2 * s and cols.max() - cols.min() + 1 >= 2 * s
        # Every object holds depth samples.
        assert (labels[s // 2::s, s // 2::s] == obj).sum() >= 2
    # No two objects closer than s pixels (along rows or columns).
    for shift in range(1, s):
        a, b = labels[:, :-shift], labels[:, shift:]
        assert not ((a > 0) & (b > 0) & (a != b)).any()
        a, b = labels[:-shift], labels[shift:]
        assert not ((a > 0) & (b > 0) & (a != b)).any()


def test_low_resolution_depth_is_sampled_at_pixel_centres():
    s = 4
    scene = make_scene((64, 96), s, n_objects=3, seed=5, noise_std=0)
    expected = scene.depth_hr_gt[s // 2::s, s // 2::s]
    np.testing.assert_array_equal(scene.depth_lr.astype(np.float32), expected)


@pytest.mark.parametrize("dtype, noise", [(np.uint8, 2.0), (np.float32, 0.01), (np.uint16, 10.0)])
def test_noise_is_gaussian_with_the_requested_std(dtype, noise):
    s = 2
    scene = make_scene((256, 256), s, n_objects=0, seed=6, noise_std=noise, dtype=dtype)
    residual = scene.depth_lr.astype(np.float64) - scene.depth_hr_gt[s // 2::s, s // 2::s]
    # 16384 samples: the std is within a few percent; rounding to integers adds 1/12.
    expected = np.sqrt(noise**2 + (1 / 12 if dtype != np.float32 else 0))
    assert abs(residual.std() - expected) < 0.05 * expected
    assert abs(residual.mean()) < 0.05 * expected


def test_default_noise_per_dtype_is_nonzero():
    for dtype in (np.uint8, np.uint16, np.float32):
        scene = make_scene((64, 64), 4, seed=0, dtype=dtype)
        assert not np.array_equal(scene.depth_lr.astype(np.float32), scene.depth_hr_gt[2::4, 2::4])


def test_units_follow_the_intensity_to_distance_relation():
    a = make_scene((64, 64), 4, seed=9, noise_std=0, dtype=np.uint8)
    m = make_scene((64, 64), 4, seed=9, noise_std=0, dtype=np.float32)
    mm = make_scene((64, 64), 4, seed=9, noise_std=0, dtype=np.uint16)
    np.testing.assert_array_equal(a.labels_hr, m.labels_hr)
    np.testing.assert_allclose(np.array(m.depths), DEPTH_CONSTANT / np.array(a.depths), rtol=1e-6)
    np.testing.assert_allclose(np.array(mm.depths), np.round(1000 * np.array(m.depths)), atol=0.5)
    # Larger intensity = nearer = smaller distance.
    assert np.argmax(a.depths) == np.argmin(m.depths)


@pytest.mark.parametrize("dtype, invalid", [(np.uint8, 0), (np.uint16, 0), (np.float32, np.nan)])
def test_holes(dtype, invalid):
    scene = make_scene((128, 128), 4, seed=1, hole_fraction=0.2, dtype=dtype)
    lr = scene.depth_lr.astype(np.float64)
    holes = np.isnan(lr) if np.isnan(invalid) else lr == 0
    assert 0.12 < holes.mean() < 0.28
    assert (lr[~holes] > 0).all()


def test_no_holes_by_default_and_valid_values_stay_valid():
    # Huge noise would push samples below zero: they are clipped to a valid value instead.
    scene = make_scene((64, 64), 4, seed=2, noise_std=500.0, dtype=np.uint8)
    assert (scene.depth_lr > 0).all()
    scene = make_scene((64, 64), 4, seed=2, noise_std=5.0, dtype=np.float32)
    assert np.isfinite(scene.depth_lr).all() and (scene.depth_lr > 0).all()


def test_shading_and_color_noise_change_the_colors_but_not_the_geometry():
    flat = make_scene((64, 64), 4, seed=3)
    shaded = make_scene((64, 64), 4, seed=3, shading=0.2, color_noise_std=5.0)
    np.testing.assert_array_equal(flat.labels_hr, shaded.labels_hr)
    np.testing.assert_array_equal(flat.depth_hr_gt, shaded.depth_hr_gt)
    diff = shaded.rgb_hr.astype(int) - flat.rgb_hr.astype(int)
    assert 0 < np.abs(diff).mean() < 40


def test_edge_band():
    scene = make_two_planes((8, 16), 4, edge_col=7)
    band = scene.edge_band(1)
    assert band[:, [6, 7]].all() and band.sum() == 16
    assert scene.edge_band(3)[:, 4:10].all() and scene.edge_band(3).sum() == 48
    with pytest.raises(ValueError, match="width"):
        scene.edge_band(0)


def test_two_planes_default_edge_is_between_samples():
    for s in (4, 8, 16):
        scene = make_two_planes((2 * s, 8 * s), s)
        edge = int(np.argmax(scene.labels_hr[0]))
        samples = np.arange(s // 2, 8 * s, s)
        # No sample column on either side of the edge (columns edge-1 | edge).
        assert edge not in samples and edge - 1 not in samples, s
        assert (scene.depth_hr_gt[:, :edge] == 200).all() and (scene.depth_hr_gt[:, edge:] == 60).all()


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(shape_hr=(65, 64), scale=4), "multiples of scale"),
        (dict(shape_hr=(64, 64), scale=0), "scale"),
        (dict(shape_hr=(64, 64), scale=4, n_objects=8), "n_objects"),
        (dict(shape_hr=(64, 64), scale=4, hole_fraction=1.0), "hole_fraction"),
        (dict(shape_hr=(64, 64), scale=4, shading=-0.1), "shading"),
        (dict(shape_hr=(64, 64), scale=4, noise_std=-1), "noise_std"),
        (dict(shape_hr=(64, 64), scale=4, dtype=np.int64), "dtype"),
        (dict(shape_hr=(32, 32), scale=8, n_objects=3), "could not place"),
    ],
)
def test_bad_arguments(kwargs, match):
    with pytest.raises(ValueError, match=match):
        make_scene(**kwargs)
