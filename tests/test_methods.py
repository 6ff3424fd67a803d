"""The method registry and :func:`depthrefine.refine`'s dispatch."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import depthrefine
from depthrefine import DEFAULT_METHOD, METHODS, GbpParams, ThesisParams, get_method, refine, register_method
from depthrefine.methods.gbp import upsample_gbp
from depthrefine.methods.thesis.refine import refine_thesis


@pytest.fixture
def registry():
    """The registry, restored to its state before the test."""
    saved = dict(METHODS)
    yield METHODS
    METHODS.clear()
    METHODS.update(saved)


@dataclasses.dataclass(frozen=True)
class OffsetParams:
    offset: float = 1.0


def offset_nearest(depth_lr, rgb_hr, *, params=None, progress=None):
    params = params or OffsetParams()
    out = depthrefine.refine(depth_lr, rgb_hr, method="nearest") + np.float32(params.offset)
    if progress is not None:
        progress(1, 1)
    return out


def test_the_thesis_and_baselines_are_registered():
    assert {"thesis", "nearest", "bilinear", "bicubic"} <= set(METHODS)
    thesis = get_method("thesis")
    assert thesis.func is refine_thesis and thesis.params_type is ThesisParams and thesis.guided
    assert thesis.default_params() == ThesisParams()
    for name in ("nearest", "bilinear", "bicubic"):
        entry = get_method(name)
        assert entry.params_type is None and entry.default_params() is None and not entry.guided
    assert all(entry.name == name and entry.summary for name, entry in METHODS.items())


def test_unknown_method_lists_the_known_ones():
    with pytest.raises(ValueError, match=r"unknown method 'thesys'; choose one of \[.*'bilinear'.*'thesis'.*\]"):
        refine(np.ones((2, 2), np.uint8), np.zeros((4, 4, 3), np.uint8), method="thesys")
    with pytest.raises(ValueError, match="unknown method"):
        get_method(["thesis"])  # type: ignore[arg-type]


def test_params_must_be_the_methods_own_type():
    depth, rgb = np.ones((2, 2), np.uint8), np.zeros((4, 4, 3), np.uint8)
    with pytest.raises(TypeError, match="takes params of type ThesisParams; got dict"):
        refine(depth, rgb, method="thesis", params={"n_clusters": 2})
    with pytest.raises(TypeError, match="takes params of type GbpParams; got ThesisParams.*method='thesis'"):
        refine(depth, rgb, params=ThesisParams())
    with pytest.raises(TypeError, match="'bilinear' takes no parameters"):
        refine(depth, rgb, method="bilinear", params=ThesisParams())


def test_default_method_is_gbp_and_thesis_stays_exact(small_scene):
    assert DEFAULT_METHOD == "gbp" and get_method(DEFAULT_METHOD).params_type is GbpParams
    a = refine(small_scene.depth_lr, small_scene.rgb_hr)
    assert a.tobytes() == upsample_gbp(small_scene.depth_lr, small_scene.rgb_hr).tobytes()
    b = refine(small_scene.depth_lr, small_scene.rgb_hr, method="thesis")
    assert b.tobytes() == refine_thesis(small_scene.depth_lr, small_scene.rgb_hr).tobytes()


@pytest.mark.parametrize("name", sorted(METHODS))
def test_every_registered_method_gives_float32_on_the_color_grid(name, small_scene):
    out = refine(small_scene.depth_lr, small_scene.rgb_hr, method=name)
    assert out.shape == small_scene.rgb_hr.shape[:2] and out.dtype == np.float32
    assert np.isfinite(out).all()


@pytest.mark.parametrize("name", ["gbp", "thesis"])
@pytest.mark.parametrize("color_dtype", [np.uint16, np.float64])
def test_big_endian_inputs_give_the_native_result(name, color_dtype, small_scene):
    """A .npy written on a big-endian machine (or with dtype '>u2') is the same image: same result."""
    rgb = small_scene.rgb_hr.astype(color_dtype) * (257 if color_dtype == np.uint16 else 1 / 255)
    expected = refine(small_scene.depth_lr, rgb, method=name)
    swapped = rgb.astype(rgb.dtype.newbyteorder(">" if rgb.dtype.byteorder != ">" else "<"))
    out = refine(small_scene.depth_lr.astype(small_scene.depth_lr.dtype.newbyteorder(">")), swapped, method=name)
    assert np.array_equal(out, expected)


def test_register_a_new_method_and_call_it_by_name(registry, small_scene):
    entry = register_method("offset-nearest", offset_nearest, params_type=OffsetParams, summary="test", guided=False)
    assert METHODS["offset-nearest"] is entry and get_method("offset-nearest") is entry
    calls = []
    out = refine(small_scene.depth_lr, small_scene.rgb_hr, method="offset-nearest", params=OffsetParams(2.5),
                 progress=lambda done, total: calls.append((done, total)))
    nearest = refine(small_scene.depth_lr, small_scene.rgb_hr, method="nearest")
    np.testing.assert_array_equal(out, nearest + np.float32(2.5))
    assert calls == [(1, 1)]
    with pytest.raises(TypeError, match="OffsetParams"):
        refine(small_scene.depth_lr, small_scene.rgb_hr, method="offset-nearest", params=ThesisParams())


def test_a_taken_name_needs_replace(registry):
    with pytest.raises(ValueError, match="already registered; pass replace=True"):
        register_method("bilinear", offset_nearest)
    assert METHODS["bilinear"].func is not offset_nearest
    register_method("bilinear", offset_nearest, params_type=OffsetParams, replace=True)
    assert METHODS["bilinear"].func is offset_nearest


def test_the_registry_fixture_restores_the_methods():
    # Runs after the tests above (file order): their registrations are gone.
    assert "offset-nearest" not in METHODS
    assert METHODS["bilinear"].func is not offset_nearest


@pytest.mark.parametrize("name", ["", "two words", "a/b", 3, None])
def test_method_names_must_be_words(registry, name):
    with pytest.raises(ValueError, match="method name"):
        register_method(name, offset_nearest)  # type: ignore[arg-type]
