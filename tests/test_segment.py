"""Color clustering (thesis 4.3): median, L*a*b*, L* unification, deterministic k-means."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from depthrefine.methods.thesis.segment import (
    AB_STEP, cluster_colors, initial_means, kmeans, lightness_classes, median_rgb, rgb_to_lab, unify_lightness,
)


# ---------------------------------------------------------------------------
# 4.3.1 median
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("dtype, top", [(np.uint8, 255), (np.uint16, 65535), (np.float32, 1.0)])
@pytest.mark.parametrize("size", [3, 5, 7])
def test_median_matches_a_per_channel_reference(rng, dtype, top, size):
    img = rng.integers(0, 256, (13, 17, 3)).astype(np.float64) / 255 * top
    img = img.astype(dtype)
    out = median_rgb(img, size)
    assert out.dtype == dtype and out.shape == img.shape
    for ch in range(3):
        expected = ndimage.median_filter(img[:, :, ch], size=size, mode="nearest")
        np.testing.assert_array_equal(out[:, :, ch], expected)


def test_median_removes_salt_and_pepper_and_keeps_edges():
    img = np.zeros((21, 21, 3), np.uint8)
    img[:, 10:] = (200, 100, 50)
    img[5, 3] = 255          # salt on the dark side
    img[15, 16] = 0          # pepper on the bright side
    out = median_rgb(img, 7)
    expected = np.zeros_like(img)
    expected[:, 10:] = (200, 100, 50)
    np.testing.assert_array_equal(out, expected)


def test_median_filters_channels_separately():
    # Per-channel medians can make a color that is in no input pixel: the thesis filters R, G, B separately.
    img = np.zeros((3, 3, 3), np.uint8)
    img[0, :, 0] = 100
    img[1:, :, 1] = 100
    out = median_rgb(img, 3)
    assert out[1, 1].tolist() == [0, 100, 0]
    # Red, green, blue side by side: the per-channel median is black, a color none of them has.
    img2 = np.array([[[100, 0, 0], [0, 100, 0], [0, 0, 100]]], np.uint8)
    assert median_rgb(img2, 3)[0, 1].tolist() == [0, 0, 0]


def test_median_size_one_is_a_copy_and_even_sizes_fail():
    img = np.arange(27, dtype=np.uint8).reshape(3, 3, 3)
    out = median_rgb(img, 1)
    np.testing.assert_array_equal(out, img)
    assert out is not img
    with pytest.raises(ValueError, match="odd"):
        median_rgb(img, 4)


def test_median_does_not_modify_its_input(rng):
    img = rng.integers(0, 256, (9, 9, 3)).astype(np.uint16)
    before = img.copy()
    median_rgb(img, 7)
    np.testing.assert_array_equal(img, before)


# ---------------------------------------------------------------------------
# 4.3.2 L*a*b*
# ---------------------------------------------------------------------------


def test_lab_known_values():
    # CIE L*a*b* (D65) of sRGB primaries, from the standard formulas.
    rgb = np.array([[[255, 255, 255], [0, 0, 0], [255, 0, 0], [0, 255, 0], [0, 0, 255], [128, 128, 128]]],
                   np.uint8)
    lab = rgb_to_lab(rgb)[0]
    assert lab.dtype == np.float32
    expected = np.array([
        [100.0, 0.0, 0.0],
        [0.0, 0.0, 0.0],
        [53.24, 80.09, 67.20],
        [87.73, -86.18, 83.18],
        [32.30, 79.19, -107.86],
        [53.59, 0.0, 0.0],
    ])
    np.testing.assert_allclose(lab, expected, atol=0.6)


def test_lab_is_the_same_for_every_input_dtype(rng):
    rgb8 = rng.integers(0, 256, (5, 7, 3)).astype(np.uint8)
    rgb16 = rgb8.astype(np.uint16) * 257
    rgbf = rgb8.astype(np.float32) / 255
    np.testing.assert_allclose(rgb_to_lab(rgb16), rgb_to_lab(rgb8), atol=1e-3)
    np.testing.assert_allclose(rgb_to_lab(rgbf), rgb_to_lab(rgb8), atol=1e-4)


# ---------------------------------------------------------------------------
# 4.3.2 L* unification (Fig. 32)
# ---------------------------------------------------------------------------


def test_unify_lightness_known_values():
    lab = np.array([[[5, 1, 2], [15, 3, 4], [30, 5, 6], [60, 7, 8], [85, 9, 10], [95, 11, 12]]], np.float32)
    out = unify_lightness(lab)
    # Black (<= 20): mean of 5, 15 = 10; color: mean of 30, 60 = 45; white (>= 80): mean of 85, 95 = 90.
    assert out[0, :, 0].tolist() == [10.0, 10.0, 45.0, 45.0, 90.0, 90.0]
    np.testing.assert_array_equal(out[..., 1:], lab[..., 1:])
    assert out.dtype == np.float32


def test_unify_lightness_bounds_are_inclusive_and_scale_with_max_lightness():
    lab = np.array([[[20, 0, 0], [80, 0, 0], [50, 0, 0]]], np.float32)
    # 20 is black, 80 white (<= and >=): each alone in its class.
    assert unify_lightness(lab)[0, :, 0].tolist() == [20.0, 80.0, 50.0]
    # With max L* 50, the bounds are 10 and 40: 50 and 80 are white, 20 is color.
    out = unify_lightness(lab, max_lightness=50.0)[0, :, 0].tolist()
    assert out == [20.0, 65.0, 65.0]
    # Custom bounds: black <= 60 -> 20 and 50 are black.
    out = unify_lightness(lab, black_bound=0.6, white_bound=0.9)[0, :, 0].tolist()
    assert out == [35.0, 80.0, 35.0]


def test_unify_lightness_without_black_or_white_pixels_and_input_kept():
    lab = np.array([[[30, 0, 0], [50, 0, 0]]], np.float32)
    before = lab.copy()
    assert unify_lightness(lab)[0, :, 0].tolist() == [40.0, 40.0]
    np.testing.assert_array_equal(lab, before)


# ---------------------------------------------------------------------------
# 4.3.3 k-means
# ---------------------------------------------------------------------------


def test_initial_means_are_spread_on_the_bounding_box_diagonal():
    x = np.array([[0.0, 10.0, -4.0], [8.0, 30.0, 4.0], [2.0, 12.0, 0.0]])
    means = initial_means(x, 4)
    expected = np.array([[1, 12.5, -3], [3, 17.5, -1], [5, 22.5, 1], [7, 27.5, 3]], float)
    np.testing.assert_allclose(means, expected)


def test_kmeans_known_answer_three_blobs():
    x = np.array([[0, 0], [1, 0], [0, 1], [10, 10], [11, 10], [20, 0], [21, 1]], float)
    labels, means = kmeans(x, 3, 10)
    # Initial means on the box diagonal at 1/6, 3/6, 5/6: (3.5, 1.7), (10.5, 5), (17.5, 8.3);
    # labels are numbered in the order of the surviving means.
    assert labels.tolist() == [0, 0, 0, 1, 1, 2, 2]
    np.testing.assert_allclose(means, [[1 / 3, 1 / 3], [10.5, 10.0], [20.5, 0.5]])


def test_kmeans_labels_in_range_and_dtype(rng):
    x = rng.normal(size=(500, 3)).astype(np.float32)
    labels, means = kmeans(x, 4, 10)
    assert labels.dtype == np.int32 and labels.shape == (500,)
    assert labels.min() == 0 and labels.max() == len(means) - 1 <= 3
    # Every label is used (renumbered 0 .. k'-1) and each point is at its nearest mean.
    assert set(np.unique(labels)) == set(range(len(means)))
    d = ((x[:, None, :] - means[None, :, :]) ** 2).sum(axis=2)
    np.testing.assert_array_equal(np.argmin(d, axis=1), labels)


def test_kmeans_is_deterministic(rng):
    x = rng.normal(size=(300, 3)).astype(np.float32)
    a = kmeans(x, 4, 10)
    b = kmeans(x.copy(), 4, 10)
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])


def test_kmeans_drops_empty_clusters():
    # Two distinct colors and k = 4: the inner means end empty and are dropped.
    x = np.array([[0, 0, 0]] * 5 + [[100, 50, -50]] * 3, np.float32)
    labels, means = kmeans(x, 4, 10)
    assert labels.tolist() == [0] * 5 + [1] * 3
    np.testing.assert_allclose(means, [[0, 0, 0], [100, 50, -50]])



@pytest.mark.parametrize("weights", [np.zeros(6), -np.ones(6), np.array([1, 1, 1, 1, 1, np.nan]), np.ones(5)])
def test_kmeans_refuses_weights_that_are_not_one_positive_count_per_point(weights):
    """A zero or negative total weight left no cluster, and the kernels then indexed empty arrays (garbage labels)."""
    with pytest.raises(ValueError, match="weights must be 6 finite values > 0"):
        kmeans(np.arange(18, dtype=np.float32).reshape(6, 3), 3, 10, weights=weights)

def test_kmeans_one_color_gives_one_cluster():
    x = np.full((10, 3), 7.0, np.float32)
    labels, means = kmeans(x, 4, 10)
    assert (labels == 0).all() and means.shape == (1, 3)


def test_kmeans_zero_iterations_assigns_to_the_initial_means():
    x = np.array([[0.0], [1.0], [2.0], [9.0], [10.0]])
    labels, means = kmeans(x, 2, 0)
    # Initial means 2.5 and 7.5.
    assert labels.tolist() == [0, 0, 0, 1, 1]
    np.testing.assert_allclose(means, [[2.5], [7.5]])
    labels, means = kmeans(x, 2, 5)
    np.testing.assert_allclose(means, [[1.0], [9.5]])


def test_kmeans_ties_go_to_the_lower_index():
    # 5 is equidistant from the initial means 2.5 and 7.5.
    labels, _ = kmeans(np.array([[0.0], [5.0], [10.0]]), 2, 0)
    assert labels.tolist() == [0, 0, 1]


def test_kmeans_warm_start_keeps_the_previous_label_numbers():
    pts = np.array([[0.0, 0.0], [0.0, 1.0], [10.0, 10.0], [10.0, 11.0]])
    labels, means = kmeans(pts, 2)
    assert labels.tolist() == [0, 0, 1, 1]
    warm_labels, warm_means = kmeans(pts, 2, init_means=means[::-1])  # the previous frame had them the other way
    assert warm_labels.tolist() == [1, 1, 0, 0]
    assert np.array_equal(warm_means, means[::-1])


def test_kmeans_warm_start_gives_way_when_the_number_of_colors_changed():
    pts = np.array([[0.0, 0.0], [0.0, 1.0], [10.0, 10.0], [10.0, 11.0], [30.0, -20.0]])
    cold = kmeans(pts, 3)
    assert len(cold[1]) == 3
    warm = kmeans(pts, 3, init_means=np.array([[10.0, 10.5], [0.0, 0.5]]))  # a color appeared
    assert all(np.array_equal(a, b) for a, b in zip(warm, cold))


@pytest.mark.parametrize("init", [np.zeros((3, 2)), np.zeros((2, 3)), np.zeros((0, 2)), np.array([[np.nan, 0.0]])])
def test_kmeans_bad_init_means(init):
    with pytest.raises(ValueError, match="init_means"):
        kmeans(np.array([[0.0, 0.0], [1.0, 1.0]]), 2, init_means=init)


@pytest.mark.parametrize(
    "x, k, iterations, error",
    [
        (np.zeros((0, 3)), 4, 10, ValueError),
        (np.zeros(5), 4, 10, ValueError),
        (np.zeros((5, 3)), 0, 10, ValueError),
        (np.zeros((5, 3)), 4, -1, ValueError),
        (np.zeros((5, 3)), 4, 1.5, ValueError),
        (np.zeros((5, 3)), 2.0, 10, TypeError),
    ],
)
def test_kmeans_bad_arguments(x, k, iterations, error):
    with pytest.raises(error):
        kmeans(x, k, iterations)


# ---------------------------------------------------------------------------
# The pipeline's clustering: k-means over the histogram of binned L*a*b* features
# ---------------------------------------------------------------------------


def test_lightness_classes_bounds():
    lightness = np.array([0.0, 19.9, 20.0, 20.01, 79.99, 80.0, 100.0])
    assert lightness_classes(lightness).tolist() == [0, 0, 0, 1, 1, 2, 2]
    assert lightness_classes(lightness, black_bound=0.5, white_bound=0.9).tolist() == [0, 0, 0, 0, 1, 1, 2]


@pytest.mark.parametrize("unify, weight", [(True, 1.0), (False, 1.0), (True, 0.3), (False, 2.0)])
def test_cluster_colors_equals_kmeans_over_every_pixel(rng, unify, weight):
    """The histogram shortcut gives the clusters of k-means over every pixel of the binned features."""
    palette = np.array([[200, 40, 40], [40, 160, 60], [50, 80, 210], [230, 210, 50], [20, 20, 20]], float)
    blocks = rng.integers(0, 5, (6, 6))
    rgb = palette[np.repeat(np.repeat(blocks, 5, axis=0), 5, axis=1)] + rng.normal(0, 12, (30, 30, 3))
    lab = rgb_to_lab(np.clip(rgb, 0, 255).astype(np.uint8))
    labels, features = cluster_colors(lab, n_clusters=4, iterations=10, unify=unify,
                                      lightness_weight=weight, return_features=True)
    # The features per pixel: L* (unified to its class mean when asked), a*, b*.
    if unify:
        assert len(np.unique(features[..., 0])) <= 3
        np.testing.assert_allclose(features, unify_lightness(lab), atol=1e-4)
    else:
        np.testing.assert_array_equal(features, lab)
    # k-means over every pixel of the binned features (a*, b* and a non-unified L* at AB_STEP).
    binned = features.reshape(-1, 3).astype(np.float64)
    cols = (1, 2) if unify else (0, 1, 2)
    for c in cols:
        binned[:, c] = np.floor(binned[:, c] / AB_STEP + 0.5) * AB_STEP
    binned[:, 0] *= weight
    expected, _ = kmeans(binned.astype(np.float32), 4, 10)
    np.testing.assert_array_equal(labels.reshape(-1), expected)
    assert labels.dtype == np.int16


def test_cluster_colors_small_and_large_patches_agree(rng):
    """The histogram path (large patch) and the sorting path (small patch) give one answer."""
    rgb = rng.integers(0, 256, (8, 8, 3)).astype(np.uint8)
    lab = rgb_to_lab(rgb)
    small = cluster_colors(lab, n_clusters=3)
    big = cluster_colors(np.tile(lab, (60, 60, 1)), n_clusters=3)
    np.testing.assert_array_equal(big[:8, :8], small)
    np.testing.assert_array_equal(big, np.tile(small, (60, 60)))


def test_cluster_colors_separates_black_gray_and_white():
    # After L* unification the three lie on the L* axis, the bounding-box diagonal: three clusters.
    rgb = np.zeros((8, 8, 3), np.uint8)
    rgb[:, 4:] = 255
    rgb[4:, :4] = 128
    labels = cluster_colors(rgb_to_lab(rgb), n_clusters=4)
    assert labels[0, 0] != labels[0, 7] and labels[0, 0] != labels[7, 0] and labels[0, 7] != labels[7, 0]
    assert len(np.unique(labels)) == 3
    for block in (labels[:4, :4], labels[:, 4:], labels[4:, :4]):
        assert len(np.unique(block)) == 1


def test_kmeans_diagonal_start_keeps_points_symmetric_about_the_diagonal_together():
    """A limit of the spec's deterministic start (decision 5.4), pinned here so it is known.

    Points placed symmetrically about the bounding-box diagonal are equally far from every
    initial mean, go to the first one on the tie, and never separate. In a patch, black,
    green and blue flat areas end in two clusters for this reason (black with green).
    """
    x = np.array([[0.0, 1.0]] * 3 + [[1.0, 0.0]] * 3)
    labels, means = kmeans(x, 2, 10)
    assert labels.tolist() == [0] * 6
    np.testing.assert_allclose(means, [[0.5, 0.5]])
