"""ThesisParams: thesis defaults, validation, round trip through a mapping."""

from __future__ import annotations

import dataclasses
import json

import pytest

from depthrefine.methods.thesis.params import ThesisParams, params_from_mapping


def test_defaults_are_the_thesis_values():
    p = ThesisParams()
    assert p.patches == (4, 4)                     # spec decision 4
    assert p.patch_layout is None
    assert p.median_size == 7                      # 4.3.1
    assert p.unify_lightness is True
    assert (p.black_bound, p.white_bound) == (0.20, 0.80)   # Fig. 32
    assert p.max_lightness == 100.0 and p.lightness_weight == 1.0
    assert p.n_clusters == 4                       # 4.3.3
    assert p.kmeans_iterations == 10
    assert p.correct_depth is True                 # 4.4.4
    assert p.dominant_fraction == 0.5 and p.tolerance_levels == 5.0
    assert p.histogram_bins == 256 and p.level_size is None
    assert p.expansion == 1                        # 4.5.2


def test_frozen_and_hashable():
    p = ThesisParams()
    with pytest.raises(dataclasses.FrozenInstanceError):
        p.n_clusters = 3  # type: ignore[misc]
    assert hash(p) == hash(ThesisParams())
    assert ThesisParams(patches=[2, 3]) == ThesisParams(patches=(2, 3))


def test_lists_become_tuples():
    p = ThesisParams(patches=[2, 3], patch_layout=[[0, 0, 8, 8], [8, 0, 8, 8]])
    assert p.patches == (2, 3)
    assert p.patch_layout == ((0, 0, 8, 8), (8, 0, 8, 8))


def test_round_trip_through_json():
    p = ThesisParams(patches=(2, 5), patch_layout=((0, 0, 4, 4),), n_clusters=3, level_size=0.5,
                     correct_depth=False)
    text = json.dumps(p.to_dict())
    assert ThesisParams.from_dict(json.loads(text)) == p


def test_unknown_key_lists_the_known_ones():
    with pytest.raises(ValueError, match=r"unknown parameter\(s\) 'clusters'.*known: patches"):
        ThesisParams.from_dict({"clusters": 3})


def test_mapping_errors_name_the_source():
    with pytest.raises(ValueError, match="^my.toml: n_clusters must be >= 1"):
        params_from_mapping(ThesisParams, {"n_clusters": 0}, source="my.toml")
    with pytest.raises(TypeError, match="must be a table"):
        params_from_mapping(ThesisParams, [("n_clusters", 3)])


@pytest.mark.parametrize(
    "kwargs, error, match",
    [
        (dict(patches=(0, 4)), ValueError, "patches"),
        (dict(patches=(4,)), TypeError, "patches"),
        (dict(patches=(4.0, 4)), TypeError, "integers"),
        (dict(patch_layout=()), ValueError, "at least one rectangle"),
        (dict(patch_layout=((0, 0, 0, 4),)), ValueError, r"patch_layout\[0\]"),
        (dict(patch_layout=((-1, 0, 4, 4),)), ValueError, r"patch_layout\[0\]"),
        (dict(median_size=4), ValueError, "odd"),
        (dict(median_size=0), ValueError, "median_size"),
        (dict(n_clusters=0), ValueError, "n_clusters"),
        (dict(n_clusters=True), TypeError, "n_clusters"),
        (dict(n_clusters=2.0), TypeError, "n_clusters"),
        (dict(kmeans_iterations=-1), ValueError, "kmeans_iterations"),
        (dict(black_bound=0.9), ValueError, "black_bound"),
        (dict(white_bound=1.5), ValueError, "white_bound"),
        (dict(max_lightness=0), ValueError, "max_lightness"),
        (dict(lightness_weight=-1), ValueError, "lightness_weight"),
        (dict(dominant_fraction=0), ValueError, "dominant_fraction"),
        (dict(dominant_fraction=1.5), ValueError, "dominant_fraction"),
        (dict(tolerance_levels=-1), ValueError, "tolerance_levels"),
        (dict(tolerance_levels=float("nan")), ValueError, "finite"),
        (dict(tolerance_levels="5"), TypeError, "number"),
        (dict(histogram_bins=1), ValueError, "histogram_bins"),
        (dict(level_size=0.0), ValueError, "level_size"),
        (dict(expansion=-1), ValueError, "expansion"),
        (dict(correct_depth=1), TypeError, "correct_depth"),
        (dict(unify_lightness="yes"), TypeError, "unify_lightness"),
    ],
)
def test_invalid_values_are_rejected_with_the_field_name(kwargs, error, match):
    with pytest.raises(error, match=match):
        ThesisParams(**kwargs)


def test_accepted_edge_values():
    ThesisParams(median_size=1, kmeans_iterations=0, expansion=0, n_clusters=1, dominant_fraction=1.0,
                 tolerance_levels=0, black_bound=0.0, white_bound=1.0, lightness_weight=0)
