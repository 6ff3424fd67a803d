"""Start-up stays light: heavy modules are imported only where they are used (issue 13).

Timings live in ``benchmarks/bench_startup.py``; these tests check what is imported.
"""

from __future__ import annotations

import importlib
import json
import subprocess
import sys

import pytest

HEAVY = ("matplotlib", "cv2", "scipy", "numba", "tifffile", "dask")


def _imported_after(code: str) -> list[str]:
    probe = f"import json, sys\n{code}\nprint(json.dumps(sorted(m for m in {HEAVY + ('numpy',)!r} if m in sys.modules)))"
    res = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    return json.loads(res.stdout.strip().splitlines()[-1])


def test_import_depthrefine_imports_no_heavy_module():
    assert _imported_after("import depthrefine") == []


def test_public_api_without_plotting_or_scipy():
    # The registry probes OpenCV (is the fast bilateral solver usable?), so cv2 may load;
    # matplotlib and SciPy wait for the functions that use them.
    loaded = _imported_after("import depthrefine\ndepthrefine.refine, depthrefine.ThesisParams, depthrefine.METHODS")
    assert "matplotlib" not in loaded and "scipy" not in loaded and "numba" not in loaded


def test_version_imports_nothing_heavy():
    code = "from depthrefine.cli import main\nassert main(['--version']) == 0"
    assert _imported_after(code) == []


def test_refine_help_imports_nothing_heavy():
    # Not even numpy: the parser reads the method names from methods._names, not the registry.
    code = "from depthrefine.cli import main\nassert main(['refine', '--help']) == 0"
    assert _imported_after(code) == []


def test_every_command_help_imports_nothing_heavy():
    # Each command's --help (and the listing of all commands) in one fresh process, checking
    # after each which heavy module has appeared: the first command that pulls one in is named.
    probe = f"""
import contextlib, io, json, sys
from depthrefine.cli import build_parser, main

heavy = {HEAVY + ('numpy',)!r}
commands = sorted(build_parser()._subparsers._group_actions[0].choices)
loaded = {{}}
for argv in [["--help"]] + [[c, "--help"] for c in commands] + [["rig", "import", "--help"]]:
    with contextlib.redirect_stdout(io.StringIO()) as out:
        status = main(argv)
    assert status == 0 and "usage:" in out.getvalue(), argv
    loaded[" ".join(argv)] = sorted(m for m in heavy if m in sys.modules)
print(json.dumps([commands, loaded]))
"""
    res = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    commands, loaded = json.loads(res.stdout.strip().splitlines()[-1])
    assert {"refine", "run", "batch", "bench", "demo", "calibrate-stereo", "rig"} <= set(commands)
    assert len(loaded) == len(commands) + 2
    assert {argv: mods for argv, mods in loaded.items() if mods} == {}


def test_help_lists_the_registered_method_names():
    # --help lists the methods without importing the registry: the built-in names that need no
    # probe of the installed OpenCV. Once the registry is imported, exactly its METHODS.
    probe = """
import json
from depthrefine.methods._names import BUILTIN_METHODS, PROBED_METHODS, RegisteredMethodNames
names = RegisteredMethodNames()
before = list(names), list(RegisteredMethodNames(ordered=True))
from depthrefine.methods.registry import METHODS
from depthrefine.methods.peers import fast_bilateral_solver_status
after = list(names), list(RegisteredMethodNames(ordered=True))
print(json.dumps([before, after, list(METHODS), fast_bilateral_solver_status(), BUILTIN_METHODS, PROBED_METHODS]))
"""
    res = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    before, after, methods, fbs_status, builtin, probed = json.loads(res.stdout.strip().splitlines()[-1])
    assert after == [sorted(methods), methods]
    # The registry registers the built-in methods in BUILTIN_METHODS's order; fbs exactly when it works.
    assert methods == [m for m in builtin if m not in probed or (m == "fbs" and fbs_status == "")]
    assert before == [sorted(m for m in methods if m not in probed), [m for m in methods if m not in probed]]


@pytest.mark.parametrize("package", ["depthrefine", "depthrefine.io", "depthrefine.rig", "depthrefine.bench",
                                     "depthrefine.methods"])
def test_lazy_packages_resolve_every_public_name(package):
    # The packages import their names on first use; every name of __all__ must come from the
    # module the package says, and be the object that module defines.
    module = importlib.import_module(package)
    for name in module.__all__:
        if name == "__version__":
            continue
        value = getattr(module, name)
        assert name in dir(module)
        owner = getattr(value, "__module__", None)
        if owner is not None and owner.startswith("depthrefine.") and not isinstance(value, type(module)):
            assert getattr(importlib.import_module(owner), name, value) is value
    with pytest.raises(AttributeError, match="no_such_name"):
        module.no_such_name  # noqa: B018


def test_lazy_public_names_and_subpackages_resolve():
    import depthrefine

    assert depthrefine.refine is depthrefine.methods.registry.refine
    assert "ThesisParams" in dir(depthrefine) and "io" in dir(depthrefine)
    with pytest.raises(AttributeError, match="no_such_name"):
        depthrefine.no_such_name  # noqa: B018


def test_every_public_submodule_is_an_attribute_of_a_fresh_import():
    # ``depthrefine.batch`` (as ``depthrefine.io``) without importing it first, in a fresh interpreter
    probe = ("import json, pkgutil, depthrefine\n"
             "subs = [m.name for m in pkgutil.iter_modules(depthrefine.__path__) if not m.name.startswith('_')]\n"
             "print(json.dumps([[s, s in dir(depthrefine), hasattr(depthrefine, s)] for s in subs]))")
    res = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    found = json.loads(res.stdout)
    assert "batch" in [name for name, *_ in found]
    assert [name for name, listed, present in found if not (listed and present)] == []
