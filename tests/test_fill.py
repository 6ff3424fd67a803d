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


def test_a_sliver_of_a_hole_that_the_rays_miss_is_enclosed_with_it():
    rows = np.mgrid[0:60, 0:400][0].astype(np.float32)      # the rays reach 40 pixels
    depth = 100 + 0.08 * rows                                # a surface sloping gently
    depth[12:48, 10:51] = np.nan                             # a hole 41 pixels wide
    depth[30, 30] = 105.0                                    # a measured speck inside it
    depth[20:23, 395:] = np.nan                              # a notch open to the image's border
    enclosed = enclosed_holes(depth)
    # the hole's first and last columns each have one ray 41 pixels long, beyond the reach: alone, the four rays
    # leave them out (two lines through the hole); the pixels around them span under 5 %: they join the hole
    assert enclosed[12:48, 10].all() and enclosed[12:48, 50].all()
    assert enclosed[12:48, 10:51].sum() == 36 * 41 - 1
    assert not enclosed[20:23, 395:].any()


def test_a_sliver_needs_one_surface_around_it_and_an_enclosed_pixel_beside_it():
    depth = np.full((40, 500), 1000.0, np.float32)           # the rays reach 50 pixels
    depth[:, 150:] = 1500.0                                  # a depth jump at column 150
    depth[10:30, 100:140] = np.nan                           # a hole in the near surface ...
    depth[19:21, 140:152] = np.nan                           # ... with a channel across the jump
    enclosed = enclosed_holes(depth)
    assert enclosed[10:19, 100:140].all() and enclosed[21:30, 100:140].all()
    # rows 19-20 see the far surface through the channel: one group with it, touching enclosed pixels, but
    # the channel's pixels at the jump see both surfaces within 3 pixels: no sliver
    assert not enclosed[19:21, 100:152].any()
    crack = np.full((100, 100), 500.0, np.float32)
    crack[20:80, 50] = np.nan                                # a crack between measured pixels, no enclosed hole
    assert enclosed_holes(crack)[20:80, 50].sum() == 0       # nothing enclosed: the rays reach 10 pixels
    crack[5, 5] = np.nan                                     # a dropout far away changes nothing about it
    assert enclosed_holes(crack)[20:80, 50].sum() == 0


def test_a_line_the_rays_find_through_a_hole_of_no_one_surface_is_not_enclosed():
    depth = np.full((60, 400), 320.0, np.float32)            # the rays reach 40 pixels
    depth[:, :100] = 300.0                                   # a mug's body, left of its handle's loop
    depth[:, 130:] = 330.0                                   # the handle, right of it
    depth[12:48, 100:130] = np.nan                           # the loop: the wall behind it, unmeasured
    depth[30, 104] = 328.0                                   # a speck of the handle's depth inside the loop
    depth[20:24, 200:206] = np.nan                           # a dropout on the handle
    enclosed = enclosed_holes(depth)
    # the loop's four rays span 10 %, but on row 30 the speck stands in for the body: 320-330, one surface;
    # that line through the loop (unmeasured pixels above and below it) is not enclosed, the dropout still is
    assert not enclosed[12:48, 100:130].any()
    assert enclosed[20:24, 200:206].all() and enclosed.sum() == 4 * 6
    thick = depth.copy()
    thick[26:35, 104] = 328.0                                # nine specks: a band nine rows thick
    assert enclosed_holes(thick)[27:34, 110].all()           # wider than a line: its middle stays enclosed


def test_the_smooth_fill_spans_a_plane_exactly_and_leaves_unreached_holes():
    rows, cols = np.mgrid[0:40, 0:50].astype(np.float32)
    plane = 500 + 3 * rows - 2 * cols
    holed = plane.copy()
    holed[10:20, 15:30] = np.nan
    filled = fill_smooth(holed, np.isnan(holed))
    np.testing.assert_allclose(filled, plane, atol=1e-3)     # a plane is harmonic: the membrane is the plane
    nothing = np.full((5, 5), np.nan, np.float32)
    assert np.isnan(fill_smooth(nothing, np.isnan(nothing))).all()


def test_the_range_and_median_of_four_are_numpys_bit_for_bit(rng):
    """enclosed_holes' min, max and median of the four rays' depths without np.median's sort: the same bits, ties,
    equal pairs and a sum that overflows included, in float32 and float64."""
    from depthrefine._fill import _range_and_median

    for dtype in (np.float32, np.float64):
        values = (rng.random((4, 50, 60)) * 1000).astype(dtype)
        values[:, :5] = 7.0                                   # all four tied
        values[1, 10:20] = values[2, 10:20]                   # two tied
        values[0, 30:40] = values[2, 30:40] = values[3, 30:40] = np.finfo(dtype).max / 1.5   # sum overflows
        with np.errstate(over="ignore"):
            low, high, middle = _range_and_median(values.copy())     # it works in the memory of its argument
            want_middle = np.median(values, axis=0)
        for got, want in ((low, values.min(axis=0)), (high, values.max(axis=0)), (middle, want_middle)):
            assert got.dtype == dtype and np.array_equal(got.view(np.uint8), want.view(np.uint8))
