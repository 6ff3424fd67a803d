"""Pictures: colorized depth, cluster labels, overlays, the comparison figure."""

from __future__ import annotations

import io

import numpy as np
import pytest

from depthrefine import viz


def test_colorize_depth_shape_dtype_and_invalid_black():
    depth = np.array([[1.0, 2.0, np.nan], [3.0, 4.0, 5.0]], np.float32)
    rgb = viz.colorize_depth(depth)
    assert rgb.shape == (2, 3, 3) and rgb.dtype == np.uint8
    assert rgb[0, 2].tolist() == [0, 0, 0]
    assert (rgb[np.isfinite(depth)].sum(axis=1) > 0).all()


def test_colorize_depth_larger_is_warmer():
    rgb = viz.colorize_depth(np.array([[1.0, 10.0]], np.float32))
    low, high = rgb[0, 0].astype(int), rgb[0, 1].astype(int)
    assert low[2] > low[0] and high[0] > high[2]     # turbo: blue end low, red end high


def test_colorize_depth_limits_give_one_scale_for_several_maps():
    a = np.array([[1.0, 2.0]], np.float32)
    b = np.array([[2.0, 3.0]], np.float32)
    limits = viz.depth_limits(a, b)
    assert limits == (1.0, 3.0)
    # The same value gets the same color in both pictures.
    assert viz.colorize_depth(a, limits=limits)[0, 1].tolist() == viz.colorize_depth(b, limits=limits)[0, 0].tolist()
    # Without common limits it would not.
    assert viz.colorize_depth(a)[0, 1].tolist() != viz.colorize_depth(b)[0, 0].tolist()


def test_depth_limits_edge_cases():
    assert viz.depth_limits(np.full((2, 2), np.nan)) == (0.0, 1.0)
    assert viz.depth_limits(np.full((2, 2), 7.0)) == (7.0, 8.0)


def test_colorize_labels_distinct_colors():
    labels = np.array([[0, 1, 2, 3]])
    rgb = viz.colorize_labels(labels)
    assert rgb.shape == (1, 4, 3) and rgb.dtype == np.uint8
    assert len({tuple(c) for c in rgb[0]}) == 4
    # The same label in neighbouring patches gets different colors.
    patch_index = np.array([[0, 0, 1, 1]])
    same = viz.colorize_labels(np.array([[0, 1, 0, 1]]), patch_index)
    assert same[0, 0].tolist() != same[0, 2].tolist()


def test_blend_weights():
    depth_rgb = np.full((2, 2, 3), 200, np.uint8)
    color = np.full((2, 2, 3), 100, np.uint8)
    assert (viz.blend(depth_rgb, color, alpha=0.5) == 150).all()
    assert (viz.blend(depth_rgb, color, alpha=0.0) == 100).all()
    assert (viz.blend(depth_rgb, color, alpha=1.0) == 200).all()
    # A 16-bit color image is brought to 8 bits first.
    assert (viz.blend(depth_rgb, (color.astype(np.uint16) * 257), alpha=0.5) == 150).all()


def test_to_rgb8():
    assert viz.to_rgb8(np.array([[[65535, 0, 32896]]], np.uint16)).tolist() == [[[255, 0, 128]]]
    assert viz.to_rgb8(np.array([[[1.0, 0.0, 0.5]]], np.float32)).tolist() == [[[255, 0, 128]]]


def test_overlay_sparse_draws_dots_on_a_dimmed_image():
    color = np.full((16, 16, 3), 200, np.uint8)
    sparse = np.full((16, 16), np.nan, np.float32)
    sparse[2::4, 2::4] = np.arange(16, dtype=np.float32).reshape(4, 4)
    out = viz.overlay_sparse(sparse, color, radius=0)
    assert out.shape == (16, 16, 3) and out.dtype == np.uint8
    dots = np.isfinite(sparse)
    assert (out[~dots] == 120).all()                  # 200 * 0.6
    np.testing.assert_array_equal(out[dots], viz.colorize_depth(sparse)[dots])
    # The default radius grows the dots with the sample spacing (4 // 4 = 1 pixel).
    grown = viz.overlay_sparse(sparse, color)
    assert (grown != 120).any(axis=2).sum() == 16 * 9


def test_comparison_figure_layout_and_rendering():
    rgb = np.zeros((20, 30, 3), np.uint8)
    d = np.linspace(1, 2, 600, dtype=np.float32).reshape(20, 30)
    fig = viz.comparison_figure(rgb, [("nearest", d), ("refined\nRMSE 1.0", d)], zoom=(0, 10, 0, 10), title="t")
    assert len(fig.axes) == 6
    assert [ax.get_title() for ax in fig.axes[:3]] == ["color", "nearest", "refined\nRMSE 1.0"]
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    assert buf.getvalue()[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(viz.comparison_figure(rgb, [("a", d)]).axes) == 2


def test_pick_detail_finds_the_edges():
    d = np.zeros((40, 40), np.float32)
    d[5:12, 22:30] = 5
    r0, r1, c0, c1 = viz.pick_detail(d, size=(10, 10))
    assert (r1 - r0, c1 - c0) == (10, 10)
    # The edge pixels (jumps into and out of the block) are rows 5..12, cols 22..30: all inside.
    assert r0 <= 5 and r1 >= 13 and c0 <= 22 and c1 >= 31
    assert viz.pick_detail(d) == viz.pick_detail(d.copy())


@pytest.mark.parametrize("func", [viz.colorize_depth, viz.colorize_labels])
def test_image_functions_do_not_modify_their_input(func):
    arr = np.array([[0, 1], [2, 3]], np.float32 if func is viz.colorize_depth else np.int16)
    before = arr.copy()
    func(arr)
    np.testing.assert_array_equal(arr, before)
