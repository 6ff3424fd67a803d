"""The command line's lean numba import: without cffi and PyYAML, both importable again afterwards."""

from __future__ import annotations

import subprocess
import sys
import textwrap

_CHILD = textwrap.dedent("""
    import importlib.util, os, sys
    os.chdir(sys.argv[1])
    from depthrefine.cli._numba_lean import import_numba_lean
    import_numba_lean()
    import numba
    print("cffi" in sys.modules, "yaml" in sys.modules)
    for name in ("cffi", "yaml"):   # afterwards they import as usual
        if importlib.util.find_spec(name) is not None:
            __import__(name)
    print(numba.njit(lambda x: x + 1)(1))
""")


def _run_child(folder) -> list[str]:
    done = subprocess.run([sys.executable, "-c", _CHILD, str(folder)], capture_output=True, text=True, check=True)
    return done.stdout.split()


def test_numba_imported_without_cffi_and_yaml(tmp_path):
    assert _run_child(tmp_path) == ["False", "False", "2"]


def test_numba_config_file_keeps_yaml(tmp_path):
    (tmp_path / ".numba_config.yaml").write_text("# empty\n")
    cffi_loaded, yaml_loaded, result = _run_child(tmp_path)
    assert cffi_loaded == "False" and result == "2"
    try:
        import yaml  # noqa: F401
    except ImportError:
        return   # without PyYAML numba reads no config file either way
    assert yaml_loaded == "True"


def test_noop_once_numba_is_imported():
    import numba  # noqa: F401

    from depthrefine.cli._numba_lean import import_numba_lean

    modules = dict(sys.modules)
    import_numba_lean()
    assert sys.modules.keys() == modules.keys()
