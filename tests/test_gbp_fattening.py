"""gbp step 1b: a direct-ToF camera's fattened objects are thinned back; registered inputs are left alone."""

from __future__ import annotations

import numpy as np
import pytest

from depthrefine._validate import as_depth
from depthrefine.methods.gbp import GbpParams, fattening, upsample_gbp
from depthrefine.methods.gbp.fattening import FATTEN_MIN, edge_offset, thin_fattened
from depthrefine.methods.gbp.measure import measure_input

SCALE = 4


def _footprint_means(depth_hr: np.ndarray, s: int) -> np.ndarray:
    """Each depth pixel the mean of its s x s block of the truth (a registered ToF pixel)."""
    h, w = depth_hr.shape[0] // s, depth_hr.shape[1] // s
    return depth_hr[:h * s, :w * s].reshape(h, s, w, s).mean(axis=(1, 3)).astype(np.float32)


def _fattened(depth_hr: np.ndarray, s: int, grow: int, larger_wins: bool) -> np.ndarray:
    """A direct-ToF input: the winning side grown by ``grow`` color pixels, then block means."""
    import cv2

    disc = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * grow + 1,) * 2)
    grown = cv2.dilate(depth_hr, disc) if larger_wins else cv2.erode(depth_hr, disc)
    return _footprint_means(grown, s)


class _Scene:
    """Discs of their own colors and depths before a wall: outlines facing every direction."""

    def __init__(self):
        import cv2

        self.depth_hr_gt = np.full((384, 384), 40.0, np.float32)
        self.rgb_hr = np.zeros((384, 384, 3), np.uint8)
        self.rgb_hr[:] = (90, 110, 130)
        for (x, y), radius, depth, color in (((110, 110), 80, 200.0, (230, 60, 40)),
                                              ((270, 260), 90, 120.0, (40, 200, 90)),
                                              ((290, 80), 50, 160.0, (250, 230, 60))):
            cv2.circle(self.depth_hr_gt, (x, y), radius, depth, -1)
            cv2.circle(self.rgb_hr, (x, y), radius, color, -1)


@pytest.fixture(scope="module")
def scene():
    return _Scene()


def _offset(depth_lr, rgb):
    return edge_offset(measure_input(as_depth(depth_lr), rgb), rgb)


def _rmse(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)))


def test_registered_input_has_no_offset_and_is_left_alone(scene):
    depth_lr = _footprint_means(scene.depth_hr_gt, SCALE)
    assert abs(_offset(depth_lr, scene.rgb_hr)) < 0.25
    m = measure_input(as_depth(depth_lr), scene.rgb_hr)
    assert thin_fattened(m, scene.rgb_hr) is m


@pytest.mark.parametrize("larger_wins", [True, False], ids=["disparity (larger nearer)", "depth (smaller nearer)"])
def test_fattening_is_measured_with_its_sign_and_undone(scene, larger_wins, monkeypatch):
    truth = scene.depth_hr_gt if larger_wins else (300.0 - scene.depth_hr_gt).astype(np.float32)
    depth_lr = _fattened(truth, SCALE, grow=SCALE, larger_wins=larger_wins)   # one depth pixel of fattening
    offset = _offset(depth_lr, scene.rgb_hr)
    assert 0.6 < abs(offset) < 1.4 and (offset > 0) == larger_wins
    thinned = upsample_gbp(depth_lr, scene.rgb_hr)
    monkeypatch.setattr(fattening, "FATTEN_MIN", np.inf)           # the same call without step 1b
    kept = upsample_gbp(depth_lr, scene.rgb_hr)
    assert _rmse(thinned, truth) < 0.6 * _rmse(kept, truth)


def test_an_outline_facing_few_directions_tells_nothing(scene):
    """One straight depth edge: a fattening cannot be told from a shift, so no offset."""
    truth = np.full((384, 384), 50.0, np.float32)
    truth[:, 192:] = 200.0
    rgb = np.zeros((384, 384, 3), np.uint8)
    rgb[:, 184:] = 255                                                # the color edge 2 depth pixels to the left
    assert _offset(_footprint_means(truth, SCALE), rgb) == 0.0


def test_holes_stay_holes_and_the_output_is_deterministic(scene):
    depth_lr = _fattened(scene.depth_hr_gt, SCALE, grow=SCALE, larger_wins=True)
    depth_lr[5:9, 5:9] = np.nan
    m = measure_input(as_depth(depth_lr), scene.rgb_hr)
    thinned = thin_fattened(m, scene.rgb_hr)
    assert thinned is not m and abs(edge_offset(m, scene.rgb_hr)) >= FATTEN_MIN
    assert np.array_equal(np.isnan(thinned.depth), np.isnan(depth_lr))
    assert np.isfinite(thinned.filled).all()
    assert np.array_equal(upsample_gbp(depth_lr, scene.rgb_hr), upsample_gbp(depth_lr, scene.rgb_hr))


def test_the_search_gives_the_same_offsets_on_any_number_of_threads(scene):
    from depthrefine import _numba
    from depthrefine.methods.gbp.fattening import edge_offsets

    m = measure_input(as_depth(_fattened(scene.depth_hr_gt, SCALE, grow=SCALE, larger_wins=True)), scene.rgb_hr)
    shared = edge_offsets(m, scene.rgb_hr)
    runs = []
    for threads in (1, None, 1, None):   # fresh arrays each time: the gradients' bits must not follow their alignment
        previous = _numba.set_threads(threads) if threads else None
        try:
            runs.append(edge_offsets(m, scene.rgb_hr.copy()))
        finally:
            if previous is not None:
                _numba.set_threads(previous)
    assert shared[0].size > 100
    for again in runs:
        assert all(np.array_equal(a, b) for a, b in zip(shared, again))


def test_gbp_fast_thins_as_gbp_measures(scene, monkeypatch):
    """gbp-fast takes its cheap work-grid measure only when it clearly says "registered"; else gbp's."""
    from depthrefine.methods.gbp.fast import upsample_gbp_fast
    from depthrefine.methods.gbp.fattening import clearly_unfattened

    registered = measure_input(as_depth(_footprint_means(scene.depth_hr_gt, SCALE)), scene.rgb_hr)
    fattened_lr = _fattened(scene.depth_hr_gt, SCALE, grow=SCALE, larger_wins=True)
    fattened = measure_input(as_depth(fattened_lr), scene.rgb_hr)
    work = scene.rgb_hr[::2, ::2]
    assert clearly_unfattened(registered, work) and not clearly_unfattened(fattened, work)
    thinned = upsample_gbp_fast(fattened_lr, scene.rgb_hr)
    monkeypatch.setattr(fattening, "FATTEN_MIN", np.inf)           # the same call without step 1b
    kept = upsample_gbp_fast(fattened_lr, scene.rgb_hr)
    assert _rmse(thinned, scene.depth_hr_gt) < 0.6 * _rmse(kept, scene.depth_hr_gt)


def test_gbp_measures_in_full_only_where_the_cheap_check_does_not_clearly_say_registered(scene, monkeypatch):
    """Step 1b's check (:func:`fattening.thin_if_fattened`): a registered input skips the full measure, with the
    same output as the full measure gives; a fattened input and any reprojected input get the full measure."""
    registered_lr = _footprint_means(scene.depth_hr_gt, SCALE)
    fattened_lr = _fattened(scene.depth_hr_gt, SCALE, grow=SCALE, larger_wins=True)
    full = fattening.thin_fattened
    calls = []
    monkeypatch.setattr(fattening, "thin_fattened", lambda *a, **k: calls.append(a[0]) or full(*a, **k))
    checked = upsample_gbp(registered_lr, scene.rgb_hr)
    assert calls == []
    upsample_gbp(fattened_lr, scene.rgb_hr)
    upsample_gbp(registered_lr, scene.rgb_hr, params=GbpParams(reprojected=True))
    assert len(calls) == 2
    # without the check (a check that never skips): the same bits
    monkeypatch.setattr(fattening, "clearly_unfattened", lambda m, guide: False)
    assert np.array_equal(upsample_gbp(registered_lr, scene.rgb_hr), checked) and len(calls) == 3


def _half_fattened(radius_fattened: int, radius_registered: int) -> tuple[np.ndarray, np.ndarray]:
    """Four discs grown by 2 depth pixels (8 color pixels) beside four registered ones: x4 block means, the guide."""
    import cv2

    n = 512
    rgb = np.full((n, n, 3), (90, 110, 130), np.uint8)
    depth = np.full((n, n), 40.0, np.float32)
    for x, y in ((0.2, 0.25), (0.5, 0.22), (0.8, 0.25), (0.2, 0.75)):
        cv2.circle(rgb, (int(x * n), int(y * n)), radius_fattened, (230, 60, 40), -1)
        cv2.circle(depth, (int(x * n), int(y * n)), radius_fattened + 8, 200.0, -1)
    for x, y in ((0.5, 0.75), (0.8, 0.75), (0.35, 0.5), (0.65, 0.5)):
        cv2.circle(rgb, (int(x * n), int(y * n)), radius_registered, (40, 200, 90), -1)
        cv2.circle(depth, (int(x * n), int(y * n)), radius_registered, 150.0, -1)
    return _footprint_means(depth, 4), rgb


@pytest.mark.parametrize("radii", [(41, 52), (45, 61)])
def test_the_check_does_not_skip_where_half_the_objects_are_fattened(radii, monkeypatch):
    """Half the outline fattened, half registered: each sector's median is a toss-up between the two, and the full
    measure thins (offset 0.73 / 0.54). The medians on the check grid said "clearly registered" (a review found these
    scenes); the quantiles around them do not, so gbp and gbp-fast give the full measure's result."""
    from depthrefine.methods.gbp.fast import upsample_gbp_fast
    from depthrefine.methods.gbp.solve import resize, work_shape

    import cv2

    depth_lr, rgb = _half_fattened(*radii)
    m = measure_input(as_depth(depth_lr), rgb)
    assert abs(edge_offset(m, rgb)) >= FATTEN_MIN                          # the full measure thins
    reduced = resize(rgb, work_shape(depth_lr.shape, rgb.shape[:2], fattening.CHECK_SCALE), cv2.INTER_AREA)
    assert all(abs(a) <= FATTEN_MIN / 2 for a in fattening.offset_axes(m, reduced))   # the medians alone would skip
    assert not fattening.clearly_unfattened(m, reduced)
    checked = upsample_gbp(depth_lr, rgb), upsample_gbp_fast(depth_lr, rgb)
    monkeypatch.setattr(fattening, "clearly_unfattened", lambda m, guide: False)   # always the full measure
    assert np.array_equal(checked[0], upsample_gbp(depth_lr, rgb))
    assert np.array_equal(checked[1], upsample_gbp_fast(depth_lr, rgb))


def _moved(depth_hr: np.ndarray, dy: int, dx: int) -> np.ndarray:
    """The truth moved by (dy, dx) color pixels, as a miscalibrated depth camera sees it."""
    import cv2

    move = np.float32([[1, 0, dx], [0, 1, dy]])
    return cv2.warpAffine(depth_hr, move, depth_hr.shape[::-1], flags=cv2.INTER_NEAREST,
                          borderMode=cv2.BORDER_REPLICATE)


def _shifted(depth_hr: np.ndarray, s: int, dy: int, dx: int) -> np.ndarray:
    """A reprojected input whose calibration is off: the truth moved by (dy, dx) color pixels, then block means."""
    return _footprint_means(_moved(depth_hr, dy, dx), s)


@pytest.mark.parametrize("dy, dx", [(2, 0), (-1, 2), (0, -3)])
def test_a_shift_is_measured_along_both_axes(scene, dy, dx):
    """Edges facing every direction, the whole map off by (dy, dx) color pixels: ``edge_shift`` reads it in depth
    pixels within 0.15, and no fattening (the shift cancels there)."""
    from depthrefine.methods.gbp.fattening import edge_shift

    depth_lr = _shifted(scene.depth_hr_gt, SCALE, dy, dx)
    m = measure_input(as_depth(depth_lr), scene.rgb_hr)
    measured = edge_shift(m, scene.rgb_hr)
    assert np.allclose(measured, (dy / SCALE, dx / SCALE), atol=0.15), measured
    assert abs(edge_offset(m, scene.rgb_hr)) < FATTEN_MIN


def test_a_reprojected_inputs_shift_is_undone_and_a_registered_one_is_not_moved(scene, monkeypatch):
    from depthrefine.methods.gbp import GbpParams
    from depthrefine.methods.gbp.fast import GbpFastParams, upsample_gbp_fast

    truth = scene.depth_hr_gt
    depth_lr = _shifted(truth, SCALE, 3, -3)                          # 0.75 depth pixels along each axis
    m = measure_input(as_depth(depth_lr), scene.rgb_hr)
    assert thin_fattened(m, scene.rgb_hr) is m                        # not said to be reprojected: left alone
    moved = thin_fattened(m, scene.rgb_hr, shift=True)
    assert moved is not m and np.array_equal(np.isnan(moved.depth), np.isnan(depth_lr))
    told = {"gbp": upsample_gbp(depth_lr, scene.rgb_hr, params=GbpParams(reprojected=True)),
            "gbp-fast": upsample_gbp_fast(depth_lr, scene.rgb_hr, params=GbpFastParams(reprojected=True))}
    monkeypatch.setattr(fattening, "SHIFT_MIN", np.inf)               # the same calls without the move
    kept = {"gbp": upsample_gbp(depth_lr, scene.rgb_hr, params=GbpParams(reprojected=True)),
            "gbp-fast": upsample_gbp_fast(depth_lr, scene.rgb_hr, params=GbpFastParams(reprojected=True))}
    for method in told:
        assert _rmse(told[method], truth) < 0.6 * _rmse(kept[method], truth), method
    # a registered input (no shift) told it is reprojected measures below SHIFT_MIN and is not moved
    monkeypatch.setattr(fattening, "SHIFT_MIN", 0.25)
    registered = measure_input(as_depth(_footprint_means(truth, SCALE)), scene.rgb_hr)
    assert thin_fattened(registered, scene.rgb_hr, shift=True) is registered


def test_a_shift_at_a_non_integer_ratio_moves_the_map_by_the_shift_only(scene, monkeypatch):
    """At a colour/depth ratio that is not an integer (a Kinect frame's 1.21 on its grid), the move works on a grid an
    integer multiple of the input's: the discs moved by (-2, 3) colour pixels, seen at ratio 2.42 and told they are
    reprojected, come back close to the truth (a nearest/area round trip through the colour grid moved jumps by up
    to 0.8 depth pixels)."""
    import cv2

    from depthrefine.methods.gbp import GbpParams

    depth_lr = cv2.resize(_moved(scene.depth_hr_gt, -2, 3), (159, 159), interpolation=cv2.INTER_AREA)
    m = measure_input(as_depth(depth_lr), scene.rgb_hr)
    assert thin_fattened(m, scene.rgb_hr, shift=True) is not m
    told = upsample_gbp(depth_lr, scene.rgb_hr, params=GbpParams(reprojected=True))
    monkeypatch.setattr(fattening, "SHIFT_MIN", np.inf)
    kept = upsample_gbp(depth_lr, scene.rgb_hr, params=GbpParams(reprojected=True))
    assert _rmse(told, scene.depth_hr_gt) < 0.6 * _rmse(kept, scene.depth_hr_gt)


@pytest.mark.parametrize("color_shape", [(48, 72), (48, 73), (55, 81)])
def test_the_move_is_exact_at_any_ratio(monkeypatch, color_shape):
    """A measured shift of half a depth pixel along x moves a step by exactly that: the column beside it becomes the
    mean of the two sides, every other pixel keeps its value, whatever the colour/depth ratio (2, 2.4, 2.7)."""
    depth_lr = np.where(np.arange(30)[None, :] < 15, 10.0, 110.0).repeat(20, axis=0).astype(np.float32)
    rgb = np.zeros((*color_shape, 3), np.uint8)
    m = measure_input(as_depth(depth_lr), rgb)
    monkeypatch.setattr(fattening, "edge_shift", lambda *args: (0.0, 0.5))
    monkeypatch.setattr(fattening, "edge_offset", lambda *args: 0.0)
    moved = thin_fattened(m, rgb, shift=True).filled
    expected = depth_lr.copy()
    expected[:, 14] = 60.0
    np.testing.assert_allclose(moved, expected, atol=1e-4)


def test_holes_move_with_the_map(monkeypatch):
    """Moved back by one depth pixel along x, a hole moves one pixel too; its filled values stay finite."""
    depth_lr = np.tile(np.linspace(10.0, 100.0, 30, dtype=np.float32), (20, 1))
    depth_lr[:, 10:13] = np.nan
    rgb = np.zeros((60, 90, 3), np.uint8)
    m = measure_input(as_depth(depth_lr), rgb)
    monkeypatch.setattr(fattening, "edge_shift", lambda *args: (0.0, 1.0))
    monkeypatch.setattr(fattening, "edge_offset", lambda *args: 0.0)
    moved = thin_fattened(m, rgb, shift=True)
    holes = np.zeros(depth_lr.shape, bool)
    holes[:, 9:12] = True
    np.testing.assert_array_equal(~moved.valid, holes)
    np.testing.assert_array_equal(np.isnan(moved.depth), holes)
    assert np.isfinite(moved.filled).all()
