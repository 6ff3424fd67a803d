"""The first-compile note: given when a kernel module's kernels are not in numba's disk cache, not after."""

from __future__ import annotations

import importlib.util
import sys
import warnings

import pytest

pytest.importorskip("numba")

from depthrefine import _numba  # noqa: E402
from depthrefine.cli import main  # noqa: E402

KERNEL_MODULE = '''
from depthrefine._numba import njit, note_first_compile

@njit
def add_one(x):
    return x + 1

@njit
def never_called(x):
    return x - 1

note_first_compile(__name__, what="the test kernels", seconds=0.5)
'''


def _import(path, name):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    finally:
        del sys.modules[name]
    return module


def test_note_on_a_cold_cache_only(tmp_path):
    path = tmp_path / "fresh_kernels.py"
    path.write_text(KERNEL_MODULE)
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        module = _import(path, "fresh_kernels")
    notes = [w for w in seen if issubclass(w.category, _numba.FirstCompileWarning)]
    assert len(notes) == 1 and "compiling the test kernels once, about 0.5 s" in str(notes[0].message)
    assert sorted(_numba.cold_kernels("fresh_kernels")) == ["add_one", "never_called"]
    assert module.add_one(1) == 2  # compiles and writes the cache
    assert _numba.cold_kernels("fresh_kernels") == ["never_called"]
    with warnings.catch_warnings(record=True) as seen:  # a later process: one kernel cached, no note
        warnings.simplefilter("always")
        _import(path, "fresh_kernels")
    assert not [w for w in seen if issubclass(w.category, _numba.FirstCompileWarning)]


def test_the_command_line_shows_the_note(monkeypatch, capsys, tmp_path):
    def refine_with_a_cold_cache(args):
        warnings.warn("compiling gbp's solver once, about 4 s (numba; cached on disk for the next runs)",
                      _numba.FirstCompileWarning)
        return 0

    monkeypatch.setattr("depthrefine.cli.show.run", refine_with_a_cold_cache)
    assert main(["show", str(tmp_path / "d.png"), "-o", str(tmp_path / "o.png")]) == 0
    assert capsys.readouterr().err == ("depthrefine: note: compiling gbp's solver once, about 4 s (numba; cached on "
                                       "disk for the next runs)\n")
