"""The leave-out hole-filling measure (``depthrefine.bench.holes``) on small maps with known answers."""

from __future__ import annotations

import numpy as np
import pytest

from depthrefine.bench.holes import fill_holes, hole_shapes, leave_out, place_holes, rescale_shapes


def _ramp(rows=40, cols=60) -> np.ndarray:
    """A slanted plane in mm (1000 + 3 mm per column + 1 mm per row)."""
    r, c = np.mgrid[0:rows, 0:cols]
    return (1000.0 + 3.0 * c + r).astype(np.float32)


def test_hole_shapes_keep_the_holes_inside_the_measured_area():
    depth = _ramp()
    depth[:, :5] = 0            # outside the field of view: touches the border, not a hole
    depth[10:13, 20:24] = 0     # a 3x4 hole
    depth[30, 40] = np.nan      # a 1-px hole
    depth[25:27, 50:51] = 0     # a 2-px hole
    shapes = hole_shapes(depth)
    assert [s.shape for s in shapes] == [(3, 4), (2, 1)]  # largest first; the 1-px one is below min_pixels
    assert [s.shape for s in hole_shapes(depth, min_pixels=1, max_pixels=5)] == [(2, 1), (1, 1)]


def test_placed_holes_lie_on_valid_surface_apart_and_deterministic():
    depth = _ramp()
    depth[15:25, 25:35] = 0  # a real hole the placement must avoid
    shapes = [np.ones((4, 4), bool), np.ones((3, 6), bool), np.eye(5, dtype=bool)]
    hidden = place_holes(depth, shapes, seed=3, margin=2)
    assert hidden.sum() == 16 + 18 + 5
    assert (depth[hidden] > 0).all()
    from scipy import ndimage as ndi

    near_hole = ndi.binary_dilation(depth == 0, iterations=2)
    assert not (hidden & near_hole).any()  # a ring of 2 valid pixels around each
    _, count = ndi.label(hidden, np.ones((3, 3)))
    assert count == 3  # the rings keep them apart
    assert np.array_equal(hidden, place_holes(depth, shapes, seed=3, margin=2))
    assert not np.array_equal(hidden, place_holes(depth, shapes, seed=4, margin=2))
    assert place_holes(depth, [np.ones((50, 70), bool)]).sum() == 0  # fits nowhere: skipped


def test_rescaled_shapes_keep_their_share_of_the_map():
    shapes = rescale_shapes([np.ones((20, 40), bool), np.ones((2, 2), bool)], 0.25)
    assert [s.shape for s in shapes] == [(5, 10)]


def test_inpainting_fills_a_plane_closer_than_nearest():
    depth = _ramp()
    hidden = np.zeros(depth.shape, bool)
    hidden[15:25, 20:32] = True
    scores = {s.filler: s for s in leave_out(depth, None, hidden, ["nearest", "inpaint"])}
    assert scores["nearest"].pixels == scores["inpaint"].pixels == 120 and scores["nearest"].coverage == 1.0
    # Telea blends the border's values (weighted by distance and direction): closer to the plane than the
    # nearest border pixel's (measured 4.3 and 5.3 mm), though it does not extrapolate the slope.
    assert scores["inpaint"].rmse < 0.9 * scores["nearest"].rmse
    assert scores["nearest"].rmse > 3.0  # up to 6 columns from the border: 3 mm each


def test_leave_out_with_a_refinement_method_and_bad_input():
    depth = _ramp(16, 24)
    rgb = np.full((64, 96, 3), 128, np.uint8)
    hidden = np.zeros(depth.shape, bool)
    hidden[6:9, 10:14] = True
    (score,) = leave_out(depth, rgb, hidden, ["bilinear"])
    assert score.pixels == 12 and score.rmse < 20
    with pytest.raises(ValueError, match="needs the color image"):
        leave_out(depth, None, hidden, ["bilinear"])
    depth[7, 11] = 0
    with pytest.raises(ValueError, match="invalid depth"):
        leave_out(depth, None, hidden, ["nearest"])
    with pytest.raises(ValueError, match="unknown filler"):
        fill_holes(depth, "telea")
