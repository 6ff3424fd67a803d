"""The scale step (thesis 3.2.2, spec step 2): integer factor, color resize, result back to color size."""

from __future__ import annotations

import numpy as np
import pytest

import depthrefine
from depthrefine.methods.scale import MAX_ASPECT_MISMATCH, plan_scale, resize_color, resize_depth_nearest


def test_integer_ratio_needs_no_resize():
    step = plan_scale((144, 176), (1008, 1232, 3))
    assert step.factor == 7 and step.ratio == 7.0
    assert step.work_shape == step.color_shape == (1008, 1232)
    assert not step.resizes_color and step.color_scale == 1.0
    assert step.describe() == "scale factor 7 (color 1232x1008)"


def test_thesis_geometry_ratio_7_4():
    # SR4000 176 x 144 and a color image 7.4 times larger: s = 7, color x 7/7.4 = 0.946.
    step = plan_scale((144, 176), (1066, 1302))
    assert step.factor == 7
    assert step.work_shape == (1008, 1232) and step.color_shape == (1066, 1302)
    assert step.resizes_color
    assert step.color_scale == pytest.approx(7 / 7.4, abs=2e-3)
    text = step.describe()
    assert "non-integer ratio 7.4" in text and "x7" in text and "1302x1066 -> 1232x1008" in text


def test_ratio_rounds_to_nearest_integer():
    assert plan_scale((10, 10), (36, 36)).factor == 4     # 3.6 -> 4
    assert plan_scale((10, 10), (34, 34)).factor == 3     # 3.4 -> 3
    assert plan_scale((10, 10), (15, 15)).factor == 2     # 1.5 -> 2 (half up)
    assert plan_scale((10, 10), (12, 12)).factor == 1
    assert plan_scale((4, 4), (4, 4)).factor == 1


def test_equal_integer_ratios_per_axis_only():
    # 2x across, 3x down is not one integer factor (and is refused as a different aspect).
    with pytest.raises(ValueError, match="aspect"):
        plan_scale((10, 10), (30, 20))


def test_aspect_mismatch_within_tolerance_is_accepted():
    # 1 % difference between the axes: one camera pair.
    step = plan_scale((100, 100), (400, 404))
    assert step.factor == 4 and step.resizes_color
    assert MAX_ASPECT_MISMATCH == 0.05


@pytest.mark.parametrize(
    "depth_shape, color_shape, match",
    [
        ((100, 100), (50, 50), "smaller than the depth map"),
        ((100, 100), (400, 480), "aspect ratios"),
    ],
)
def test_bad_shapes(depth_shape, color_shape, match):
    with pytest.raises(ValueError, match=match):
        plan_scale(depth_shape, color_shape)


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16, np.float32])
def test_resize_color_to_the_work_grid(rng, dtype):
    step = plan_scale((10, 12), (37, 44))
    rgb = (rng.random((37, 44, 3)) * (255 if dtype == np.uint8 else 1000 if dtype == np.uint16 else 1)).astype(dtype)
    out = resize_color(rgb, step)
    assert out.shape == step.work_shape + (3,) == (40, 48, 3)
    assert out.dtype == dtype
    # Bilinear: values stay in the input's range.
    assert out.min() >= rgb.min() and out.max() <= rgb.max()


def test_resize_color_is_identity_for_an_integer_ratio(rng):
    rgb = rng.integers(0, 256, (8, 8, 3)).astype(np.uint8)
    assert resize_color(rgb, plan_scale((2, 2), rgb.shape)) is rgb


def test_resize_depth_nearest_never_blends():
    depth = np.array([[1.0, 5.0, np.nan], [9.0, 2.0, 7.0]], np.float32)
    out = resize_depth_nearest(depth, (5, 7))
    assert out.shape == (5, 7)
    finite = out[np.isfinite(out)]
    assert set(finite.tolist()) <= {1.0, 5.0, 9.0, 2.0, 7.0}
    assert np.isnan(out).any()


def test_refine_with_a_non_integer_ratio_warns_and_returns_the_color_shape():
    depth = np.full((10, 12), 100, np.uint8)
    depth[:, 6:] = 30
    rgb = np.zeros((37, 44, 3), np.uint8)
    rgb[:, 22:] = 200
    with pytest.warns(depthrefine.ScaleWarning, match="non-integer ratio"):
        out = depthrefine.refine(depth, rgb, params=depthrefine.ThesisParams(patches=(1, 1)), method="thesis")
    assert out.shape == (37, 44) and out.dtype == np.float32
    assert set(np.unique(out).tolist()) == {30.0, 100.0}
    # The edge stays where the color edge is, within the resize (one work pixel = 44/48 color pixels).
    assert (out[:, :21] == 100).all() and (out[:, 23:] == 30).all()


def test_no_warning_for_an_integer_ratio(recwarn):
    depthrefine.refine(np.full((4, 4), 9, np.uint8), np.zeros((16, 16, 3), np.uint8), method="thesis")
    assert not [w for w in recwarn if issubclass(w.category, depthrefine.ScaleWarning)]
