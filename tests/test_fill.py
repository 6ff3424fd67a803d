"""Hole filling shared by the methods and the rig: nearest, enclosed holes, the smooth fill."""

from __future__ import annotations

import numpy as np

from depthrefine._fill import enclosed_holes, fill_smooth


def test_enclosed_holes_are_the_ones_one_surface_surrounds():
    depth = np.full((60, 80), 1000.0, np.float32)
    depth[:, 40:] = 2000.0                                   # a depth jump at column 40
    depth[10:14, 10:16] = np.nan                             # a dropout inside the near surface
    depth[30:34, 37:43] = np.nan                             # a shadow across the jump
    depth[:, :3] = np.nan                                    # the edge of the view
    depth[50:56, 60:66] = np.nan                             # a dropout inside the far surface
    enclosed = enclosed_holes(depth)
    assert enclosed[10:14, 10:16].all() and enclosed[50:56, 60:66].all()
    assert not enclosed[30:34, 37:43].any() and not enclosed[:, :3].any()
    assert enclosed.sum() == 4 * 6 + 6 * 6


def test_the_smooth_fill_spans_a_plane_exactly_and_leaves_unreached_holes():
    rows, cols = np.mgrid[0:40, 0:50].astype(np.float32)
    plane = 500 + 3 * rows - 2 * cols
    holed = plane.copy()
    holed[10:20, 15:30] = np.nan
    filled = fill_smooth(holed, np.isnan(holed))
    np.testing.assert_allclose(filled, plane, atol=1e-3)     # a plane is harmonic: the membrane is the plane
    nothing = np.full((5, 5), np.nan, np.float32)
    assert np.isnan(fill_smooth(nothing, np.isnan(nothing))).all()
