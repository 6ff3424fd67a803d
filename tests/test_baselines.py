"""Baselines: nearest, bilinear, bicubic enlargement, with holes filled, never averaged in."""

from __future__ import annotations

import numpy as np
import pytest

from depthrefine.methods.baselines import fill_invalid_nearest, upsample_bicubic, upsample_bilinear, upsample_nearest

BASELINES = [upsample_nearest, upsample_bilinear, upsample_bicubic]


def test_nearest_repeats_each_pixel_s_times():
    depth = np.array([[1, 2, 3], [4, 5, 6]], np.uint8)
    out = upsample_nearest(depth, np.zeros((4, 6, 3), np.uint8))
    np.testing.assert_array_equal(out, np.repeat(np.repeat(depth, 2, axis=0), 2, axis=1).astype(np.float32))


def test_bilinear_known_values_pixel_centres_aligned():
    # Pixel centres aligned (OpenCV): for x4, output column c samples input position (c + 0.5) / 4 - 0.5.
    depth = np.array([[1.0, 5.0]], np.float32)
    out = upsample_bilinear(depth, np.zeros((1, 8, 3), np.uint8))
    np.testing.assert_allclose(out[0], [1, 1, 1.5, 2.5, 3.5, 4.5, 5, 5], atol=1e-6)


def test_bicubic_is_clipped_to_the_valid_input_range():
    depth = np.array([[10, 10, 10, 200, 200, 200]] * 3, np.uint8)
    out = upsample_bicubic(depth, np.zeros((12, 24, 3), np.uint8))
    assert out.min() == 10 and out.max() == 200
    # Without clipping bicubic overshoots a step: the clip is what keeps it in range.
    assert ((out > 10) & (out < 200)).any()


def test_fill_invalid_nearest_known_values():
    depth = np.array([[1, np.nan, np.nan, 4], [np.nan, np.nan, np.nan, np.nan]], np.float32)
    out = fill_invalid_nearest(depth)
    np.testing.assert_array_equal(out, [[1, 1, 4, 4], [1, 1, 4, 4]])
    assert np.isnan(depth[0, 1]), "the input is not modified"


@pytest.mark.parametrize("func", BASELINES)
def test_holes_are_filled_from_valid_neighbours_never_averaged_in(func):
    depth = np.full((4, 4), 100, np.uint8)
    depth[:, 2:] = 120
    depth[1, 1] = 0                                 # no measurement
    out = func(depth, np.zeros((16, 16, 3), np.uint8))
    # A 0 averaged in would pull values below 100.
    assert out.min() >= 100 and out.max() <= 120
    filled = depth.astype(np.float32)
    filled[1, 1] = 100
    np.testing.assert_array_equal(out, func(filled, np.zeros((16, 16, 3), np.uint8)))


@pytest.mark.parametrize("func", BASELINES)
@pytest.mark.parametrize("color_shape", [(12, 16, 3), (13, 17, 3), (12, 16)])
def test_output_has_the_color_shape_and_is_float32(func, color_shape, rng):
    depth = rng.integers(1, 255, (3, 4)).astype(np.uint16)
    before = depth.copy()
    out = func(depth, np.zeros(color_shape, np.uint8))
    assert out.shape == color_shape[:2] and out.dtype == np.float32
    np.testing.assert_array_equal(depth, before)
    assert depth.min() <= out.min() and out.max() <= depth.max()


@pytest.mark.parametrize("func", BASELINES)
def test_constant_stays_constant(func):
    out = func(np.full((5, 7), 0.37, np.float32), np.zeros((20, 28, 3), np.uint8))
    assert (out == np.float32(0.37)).all()


@pytest.mark.parametrize("func", BASELINES)
def test_no_valid_pixel_is_an_error(func):
    with pytest.raises(ValueError, match="no valid pixel"):
        func(np.zeros((3, 3), np.uint8), np.zeros((6, 6, 3), np.uint8))
