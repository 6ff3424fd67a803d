"""Metrics of depthrefine.evaluate: known values, masks, edges and properties."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from depthrefine.evaluate import (
    Scores, bad_pixel_share, depth_edges, edge_band, mae, rmse, score, valid_mask,
)

DEPTH = arrays(np.float64, st.tuples(st.integers(2, 12), st.integers(2, 12)),
               elements=st.floats(1, 255, allow_nan=False))


def test_known_values_by_hand():
    gt = np.array([[10.0, 20.0], [30.0, 40.0]])
    pred = np.array([[11.0, 20.0], [26.0, 40.0]])  # errors 1, 0, -4, 0
    assert rmse(pred, gt) == pytest.approx(math.sqrt((1 + 16) / 4))
    assert mae(pred, gt) == pytest.approx(5 / 4)
    assert bad_pixel_share(pred, gt, threshold=1) == pytest.approx(0.25)  # 1 is not > 1
    assert bad_pixel_share(pred, gt, threshold=0.5) == pytest.approx(0.5)
    s = score(pred, gt)
    assert isinstance(s, Scores)
    assert (s.rmse, s.mae, s.bad_1, s.bad_3, s.coverage, s.n_pixels) == pytest.approx(
        (math.sqrt(17 / 4), 1.25, 0.25, 0.25, 1.0, 4))
    assert set(s.to_dict()) == {"rmse", "mae", "edge_rmse", "bad_1", "bad_3", "coverage", "n_pixels", "n_edge"}


def test_invalid_ground_truth_and_mask_are_ignored():
    gt = np.array([[0.0, np.nan, 50.0, 50.0]])
    pred = np.array([[999.0, 999.0, 52.0, 50.0]])
    assert rmse(pred, gt) == pytest.approx(math.sqrt(2))
    valid = np.array([[True, True, False, True]])
    assert rmse(pred, gt, valid=valid) == 0.0
    assert score(pred, gt).n_pixels == 2


def test_nan_prediction_is_not_scored_but_lowers_coverage():
    gt = np.full((2, 2), 100.0)
    pred = np.array([[100.0, np.nan], [103.0, 100.0]])
    s = score(pred, gt)
    assert s.coverage == pytest.approx(0.75)
    assert s.n_pixels == 3 and s.rmse == pytest.approx(math.sqrt(9 / 3))


def test_border_crop():
    gt = np.full((10, 10), 50.0)
    pred = gt.copy()
    pred[0, :] = 60.0  # only in the border
    assert score(pred, gt, border=1).rmse == 0.0
    assert score(pred, gt).rmse > 0
    assert valid_mask(gt, border=2).sum() == 36


def test_level_scales_bad_pixel_thresholds():
    gt = np.full((1, 4), 1.0)
    pred = gt + np.array([[0.0, 0.002, 0.004, 0.02]])  # in metres, 1 level = 5 mm
    s = score(pred, gt, level=0.005)
    assert s.bad_1 == pytest.approx(0.25) and s.bad_3 == pytest.approx(0.25)
    s = score(pred, gt, level=0.001)
    assert s.bad_1 == pytest.approx(0.75) and s.bad_3 == pytest.approx(0.5)


def test_depth_edges_mark_both_sides_of_a_jump_only():
    gt = np.array([[10, 10, 10, 12, 60, 60]] * 3, np.float64)
    edges = depth_edges(gt, threshold=4)
    assert edges[:, 3].all() and edges[:, 4].all()
    assert not edges[:, [0, 1, 2, 5]].any()  # the 2-level step is a slope, not an edge


def test_depth_edges_ignore_invalid_neighbours():
    gt = np.array([[0, 100, 100]], np.float64)
    assert not depth_edges(gt, threshold=4).any()


def test_edge_band_width_and_edge_rmse():
    gt = np.tile(np.r_[np.full(10, 20.0), np.full(10, 80.0)], (20, 1))
    band = edge_band(gt, threshold=4, radius=3)
    assert band[:, 6:14].all() and not band[:, :6].any() and not band[:, 14:].any()
    pred = gt.copy()
    pred[:, 9] = 50.0  # one mixed column at the edge
    s = score(pred, gt, edge_radius=3)
    assert s.n_edge == 20 * 8
    assert s.edge_rmse == pytest.approx(math.sqrt(30.0**2 / 8))
    assert s.rmse == pytest.approx(math.sqrt(30.0**2 / 20))


def test_no_edges_gives_nan_edge_rmse():
    gt = np.full((5, 5), 40.0)
    s = score(gt + 1, gt)
    assert math.isnan(s.edge_rmse) and s.n_edge == 0


def test_nothing_to_score_gives_nan():
    s = score(np.full((2, 2), np.nan), np.full((2, 2), 10.0))
    assert math.isnan(s.rmse) and s.coverage == 0.0 and s.n_pixels == 0
    assert math.isnan(rmse(np.ones((2, 2)), np.zeros((2, 2))))


def test_bad_inputs_raise_clear_errors():
    with pytest.raises(ValueError, match="same|shape"):
        rmse(np.ones((2, 3)), np.ones((3, 2)))
    with pytest.raises(ValueError, match="2-D"):
        rmse(np.ones((2, 2, 3)), np.ones((2, 2, 3)))
    with pytest.raises(TypeError, match="numpy array"):
        rmse([[1.0]], np.ones((1, 1)))
    with pytest.raises(ValueError, match="valid must be a boolean"):
        rmse(np.ones((2, 2)), np.ones((2, 2)), valid=np.ones((2, 2)))
    with pytest.raises(ValueError, match="level"):
        score(np.ones((2, 2)), np.ones((2, 2)), level=0)


def test_inputs_are_not_modified():
    gt = np.array([[0.0, 5.0], [np.nan, 7.0]])
    pred = np.array([[1.0, np.nan], [3.0, 4.0]])
    gt0, pred0 = gt.copy(), pred.copy()
    score(pred, gt, border=0)
    np.testing.assert_array_equal(gt, gt0)
    np.testing.assert_array_equal(pred, pred0)


@settings(max_examples=40, deadline=None)
@given(DEPTH, st.data())
def test_properties(gt, data):
    pred = data.draw(arrays(np.float64, gt.shape, elements=st.floats(1, 255, allow_nan=False)))
    assert rmse(gt, gt) == 0.0
    assert rmse(pred, gt) == pytest.approx(rmse(gt, pred))
    assert mae(pred, gt) <= rmse(pred, gt) + 1e-9
    s = score(pred, gt)
    assert 0.0 <= s.bad_3 <= s.bad_1 <= 1.0
    assert s.coverage == 1.0
