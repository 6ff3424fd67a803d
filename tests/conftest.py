"""Shared fixtures: a seeded generator, the shared-data location, small scenes."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest

from depthrefine.bench.synthetic import make_scene, make_two_planes

#: ../shared/data beside the repository (team rule); tests skip when it is missing.
#: ``DEPTHREFINE_TEST_SHARED_DATA=DIR`` points the tests elsewhere, e.g. at an empty folder to see
#: what a user's clone without the data runs: ``DEPTHREFINE_TEST_SHARED_DATA=$(mktemp -d) pytest -rs``.
DEFAULT_SHARED_DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"
SHARED_DATA = (Path(os.environ["DEPTHREFINE_TEST_SHARED_DATA"]) if os.environ.get("DEPTHREFINE_TEST_SHARED_DATA")
               else DEFAULT_SHARED_DATA)


def shared_data_path(*parts: str) -> Path:
    """A path under ../shared/data, or ``pytest.skip`` if it is not there (the reason says how to get it)."""
    path = SHARED_DATA.joinpath(*parts)
    if not path.exists():
        pytest.skip(f"shared data not available: {path}; {how_to_get('/'.join(parts))}")
    return path


def how_to_get(relative: str) -> str:
    """How a user gets the data set holding ``relative`` (a path under the data root) and runs the tests on it."""
    from depthrefine.io import DATASETS

    then = f"then run the tests with DEPTHREFINE_TEST_SHARED_DATA=DIR (without it they read {DEFAULT_SHARED_DATA})"
    for d in DATASETS.values():
        if relative == d.folder or relative.startswith(d.folder + "/"):
            if d.fetch_refused:
                return (f"its licence does not allow `depthrefine data fetch`: `depthrefine data list {d.name} "
                        f"--sources` says where to get each file, `depthrefine data verify DIR` checks the copy; "
                        f"{then}")
            return f"get it with `depthrefine data fetch {d.name} --to DIR`; {then}"
    return f"`depthrefine data` lists the data sets and how to get each; {then}"


@pytest.fixture
def no_numba(monkeypatch):
    """``import numba`` fails, as on a machine without it; modules that imported it are forgotten for the test.

    Importing a compiled-kernel module then fails at its first line
    (``depthrefine._numba`` imports numba), before any kernel is made or a
    first-compile note is given, whatever earlier tests imported.
    """
    def took_from_numba(module) -> bool:   # the kernel modules: ``from ..._numba import njit`` and the like
        return any(getattr(value, "__module__", None) == "depthrefine._numba" for value in vars(module).values())

    compiled = [name for name, module in list(sys.modules.items())
                if name == "depthrefine._numba" or (name.startswith("depthrefine.") and module is not None
                                                    and took_from_numba(module))]
    monkeypatch.setitem(sys.modules, "numba", None)
    for name in compiled:
        package, _, attribute = name.rpartition(".")
        monkeypatch.delitem(sys.modules, name)
        monkeypatch.delattr(sys.modules[package], attribute, raising=False)


@pytest.fixture
def numba_kernels(monkeypatch):
    """gbp and the thesis method run numba's kernels, not depthrefine's C ones (``DEPTHREFINE_KERNELS=numba``), for
    this test."""
    from depthrefine import _native

    monkeypatch.setenv(_native.ENV, "numba")
    monkeypatch.setattr(_native, "_loaded", [])


@pytest.fixture
def rng() -> np.random.Generator:
    """A fresh, seeded generator per test (never the global numpy state)."""
    return np.random.default_rng(20140701)


@pytest.fixture
def shared_data() -> Path:
    """The ../shared/data folder; skips the test when it is missing."""
    return shared_data_path()


@pytest.fixture
def two_planes():
    """16 x 32 color, 4 x 8 depth (x4): a vertical edge at column 13, between samples 10 and 14."""
    return make_two_planes((16, 32), 4, edge_col=13)


@pytest.fixture
def small_scene():
    """A 64 x 64, x4 scene: two flat objects before a wall, mild color noise and shading."""
    return make_scene((64, 64), 4, n_objects=2, seed=3, color_noise_std=4.0, shading=0.1)
