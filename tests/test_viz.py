"""Pictures: colorized depth, cluster labels, and the figures behind every depth picture we write.

Figures are checked on the arrays and objects behind them (panel kinds,
color ranges, colorbars, titles), never by matching pixels.
"""

from __future__ import annotations

import io

import numpy as np
import pytest

from depthrefine import viz


def depth_images(fig):
    """``[(axes label, title, AxesImage)]`` of every depth-colored image in ``fig``."""
    out = []
    for ax in fig.axes:
        label = ax.get_label()
        if label.startswith("panel:") and label.split(":")[1] in ("depth", "samples", "blend"):
            out.append((label, ax.get_title(), ax.get_images()[-1]))
    return out


def colorbars(fig):
    """``{kind: colorbar}`` of ``fig`` (``"depth"``, ``"error"``)."""
    return {ax.get_label().split(":")[1]: ax._colorbar for ax in fig.axes if ax.get_label().startswith("colorbar:")}


def legend_texts(fig):
    return [t.get_text() for legend in fig.legends for t in legend.get_texts()]


def test_colorize_depth_shape_dtype_and_invalid_gray():
    depth = np.array([[1.0, 2.0, np.nan], [3.0, 4.0, 5.0]], np.float32)
    rgb = viz.colorize_depth(depth)
    assert rgb.shape == (2, 3, 3) and rgb.dtype == np.uint8
    assert rgb[0, 2].tolist() == list(viz.INVALID_COLOR)
    assert not (rgb[np.isfinite(depth)] == viz.INVALID_COLOR).all(axis=1).any()


def test_colorize_depth_is_viridis_lighter_for_larger_values():
    import matplotlib

    rgb = viz.colorize_depth(np.array([[1.0, 10.0]], np.float32)).astype(int)
    assert rgb[0, 1].sum() > rgb[0, 0].sum()   # viridis: dark violet low, light yellow high
    expected = np.round(np.array(matplotlib.colormaps["viridis"]([0.0, 1.0]))[:, :3] * 255)
    np.testing.assert_allclose(rgb[0], expected, atol=3)   # OpenCV's viridis LUT is matplotlib's


def test_colorize_depth_limits_give_one_scale_for_several_maps():
    a = np.array([[1.0, 2.0]], np.float32)
    b = np.array([[2.0, 3.0]], np.float32)
    limits = viz.depth_limits(a, b)
    assert limits == (1.0, 3.0)
    assert viz.colorize_depth(a, limits=limits)[0, 1].tolist() == viz.colorize_depth(b, limits=limits)[0, 0].tolist()
    assert viz.colorize_depth(a)[0, 1].tolist() != viz.colorize_depth(b)[0, 0].tolist()


def test_depth_limits_edge_cases():
    assert viz.depth_limits(np.full((2, 2), np.nan)) == (0.0, 1.0)
    assert viz.depth_limits(np.full((2, 2), 7.0)) == (7.0, 8.0)
    assert viz.depth_limits(np.array([[3, 0]], np.uint16).astype(np.float32)) == (0.0, 3.0)


def test_colorize_labels_distinct_colors():
    labels = np.array([[0, 1, 2, 3]])
    rgb = viz.colorize_labels(labels)
    assert rgb.shape == (1, 4, 3) and rgb.dtype == np.uint8
    assert len({tuple(c) for c in rgb[0]}) == 4
    patch_index = np.array([[0, 0, 1, 1]])
    same = viz.colorize_labels(np.array([[0, 1, 0, 1]]), patch_index)
    assert same[0, 0].tolist() != same[0, 2].tolist()


def test_to_rgb8():
    assert viz.to_rgb8(np.array([[[65535, 0, 32896]]], np.uint16)).tolist() == [[[255, 0, 128]]]
    assert viz.to_rgb8(np.array([[[1.0, 0.0, 0.5]]], np.float32)).tolist() == [[[255, 0, 128]]]


def test_spread_samples_grows_dots_and_keeps_values():
    sparse = np.full((16, 16), np.nan, np.float32)
    sparse[2::4, 2::4] = np.arange(16, dtype=np.float32).reshape(4, 4)
    assert np.array_equal(viz.spread_samples(sparse, radius=0), sparse, equal_nan=True)
    grown = viz.spread_samples(sparse)                  # spacing 4: radius 1, 3 x 3 dots
    assert np.isfinite(grown).sum() == 16 * 9
    assert grown[1, 1] == grown[3, 3] == sparse[2, 2] and grown[5, 5] == sparse[6, 6]


def test_figure_grid_shares_one_range_and_one_colorbar_in_units():
    a = np.linspace(1, 2, 600, dtype=np.float32).reshape(20, 30)
    b = a + 1
    b[0, 0] = np.nan
    fig = viz.figure_grid([[viz.Panel("a", a), viz.Panel("b", b)]], units="mm")
    images = depth_images(fig)
    assert [t for _, t, _ in images] == ["a", "b"]
    assert {im.get_clim() for *_, im in images} == {(1.0, 3.0)}
    assert {im.cmap.name for *_, im in images} == {viz.DEPTH_COLORMAP}
    np.testing.assert_array_equal(images[1][2].get_array().mask, ~np.isfinite(b))  # NaN drawn as 'bad'
    assert tuple(np.round(np.array(images[1][2].cmap.get_bad()[:3]) * 255)) == viz.INVALID_COLOR
    bars = colorbars(fig)
    assert set(bars) == {"depth"}
    assert bars["depth"].ax.get_ylabel() == "depth (mm)"
    assert bars["depth"].mappable.norm is images[0][2].norm is images[1][2].norm
    assert legend_texts(fig) == [viz.INVALID_LABEL]


def test_figure_grid_limits_details_errors_and_arrows():
    gt = np.zeros((40, 60), np.float32)
    gt[10:30, 20:40] = 5
    pred = gt + 1
    err = np.abs(pred - gt)
    zoom = (10, 20, 20, 40)
    rows = [[viz.Panel("pred", pred), viz.Panel("d", pred, detail=True),
             viz.Panel("err", err, "error"), viz.Panel("d", err, "error", detail=True)]]
    fig = viz.figure_grid(rows, units="levels", limits=(0.0, 5.0), error_max=0.5, zoom=zoom, title="t")
    images = depth_images(fig)
    assert [label for label, *_ in images] == ["panel:depth", "panel:depth:detail"]
    assert images[1][2].get_array().shape == (10, 20)           # the zoom window, not the whole map
    assert {im.get_clim() for *_, im in images} == {(0.0, 5.0)}
    bars = colorbars(fig)
    assert bars["error"].ax.get_xlabel() == "|error| (levels)" and bars["error"].mappable.get_clim() == (0.0, 0.5)
    assert bars["depth"].extend == "max" and bars["error"].extend == "max"   # 6 > 5, 1 > 0.5
    assert fig.get_suptitle() if hasattr(fig, "get_suptitle") else fig._suptitle.get_text() == "t"
    with pytest.raises(ValueError, match="zoom"):
        viz.figure_grid([[viz.Panel("d", pred, detail=True)]], units="m")
    with pytest.raises(ValueError, match="kind"):
        viz.Panel("x", pred, "heatmap")


def test_samples_and_blend_panels_draw_over_the_color_image():
    color = np.full((16, 16, 3), 200, np.uint8)
    sparse = np.full((16, 16), np.nan, np.float32)
    sparse[2::4, 2::4] = 3.0
    dense = np.full((16, 16), 4.0, np.float32)
    fig = viz.figure_grid([[viz.Panel("s", sparse, "samples", background=color),
                            viz.Panel("b", dense, "blend", background=color)]], units="m")
    (_, _, dots), (_, _, blend) = depth_images(fig)
    assert np.isfinite(dots.get_array().filled(np.nan)).sum() == 16 * 9
    assert dots.cmap.get_bad()[3] == 0.0 and blend.get_alpha() == 0.5   # the color image shows through
    assert dots.get_clim() == blend.get_clim() == (3.0, 4.0)
    with pytest.raises(ValueError, match="background"):
        viz.Panel("s", sparse, "samples")


def test_large_maps_are_drawn_at_display_size_without_mixing_in_holes():
    depth = np.full((400, 800), 2.0, np.float32)
    depth[:, :400] = np.nan
    fig = viz.figure_grid([[viz.Panel("d", depth)]], units="m", panel_width=1.0, dpi=100)
    shown = depth_images(fig)[0][2].get_array()
    assert shown.shape == (100, 200)                    # reduced 4x to 2 x 100 px per inch
    assert shown.mask[:, :100].all() and not shown.mask[:, 100:].any()
    assert np.allclose(shown[:, 100:], 2.0)


def test_comparison_figure_titles_details_and_rendering():
    rgb = np.zeros((20, 30, 3), np.uint8)
    d = np.linspace(1, 2, 600, dtype=np.float32).reshape(20, 30)
    panels = [("input\nRMSE 2.00", d), ("bilinear\nRMSE 1.00", d), ("thesis\nRMSE 0.50", d)]
    fig = viz.comparison_figure(rgb, panels, units="levels", zoom=(0, 10, 0, 10), title="t", ncols=2)
    titles = [ax.get_title() for ax in fig.axes if ax.get_label().startswith("panel:")]
    assert titles == ["color", "input\nRMSE 2.00", "detail: color", "detail: input",
                      "bilinear\nRMSE 1.00", "thesis\nRMSE 0.50", "detail: bilinear", "detail: thesis"]
    assert len(depth_images(fig)) == 6 and "depth" in colorbars(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    assert buf.getvalue()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(ValueError, match="ncols"):
        viz.comparison_figure(rgb, panels, units="m", ncols=0)


def test_depth_figure_with_and_without_color():
    depth = np.array([[1.0, np.nan], [3.0, 4.0]], np.float32)
    fig = viz.depth_figure(depth, np.zeros((4, 4, 3), np.uint8), units="mm", title="x.png")
    kinds = [ax.get_label() for ax in fig.axes if ax.get_label().startswith("panel:")]
    assert kinds == ["panel:color", "panel:depth"]
    (_, title, im), = depth_images(fig)
    assert "75.0% measured" in title and im.get_clim() == (1.0, 4.0)
    assert colorbars(fig)["depth"].ax.get_ylabel() == "depth (mm)" and legend_texts(fig) == [viz.INVALID_LABEL]
    fig = viz.depth_figure(depth, units="m", limits=(0.0, 10.0))
    assert [ax.get_label() for ax in fig.axes if ax.get_label().startswith("panel:")] == ["panel:depth"]
    assert depth_images(fig)[0][2].get_clim() == (0.0, 10.0)


def test_pick_detail_finds_the_edges():
    d = np.zeros((40, 40), np.float32)
    d[5:12, 22:30] = 5
    r0, r1, c0, c1 = viz.pick_detail(d, size=(10, 10))
    assert (r1 - r0, c1 - c0) == (10, 10)
    assert r0 <= 5 and r1 >= 13 and c0 <= 22 and c1 >= 31
    assert viz.pick_detail(d) == viz.pick_detail(d.copy())


@pytest.mark.parametrize("func", [viz.colorize_depth, viz.colorize_labels, viz.spread_samples])
def test_image_functions_do_not_modify_their_input(func):
    arr = np.array([[0, 1], [2, 3]], np.int16 if func is viz.colorize_labels else np.float32)
    before = arr.copy()
    func(arr)
    np.testing.assert_array_equal(arr, before)
