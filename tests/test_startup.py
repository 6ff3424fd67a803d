"""Start-up stays light: heavy modules are imported only where they are used (issue 13).

Timings live in ``benchmarks/bench_startup.py``; these tests check what is imported.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

HEAVY = ("matplotlib", "cv2", "scipy", "numba", "tifffile")


def _imported_after(code: str) -> list[str]:
    probe = f"import json, sys\n{code}\nprint(json.dumps(sorted(m for m in {HEAVY + ('numpy',)!r} if m in sys.modules)))"
    res = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    return json.loads(res.stdout.strip().splitlines()[-1])


def test_import_depthrefine_imports_no_heavy_module():
    assert _imported_after("import depthrefine") == []


def test_public_api_without_plotting_or_scipy():
    # The registry probes OpenCV (is the fast bilateral solver usable?), so cv2 may load;
    # matplotlib and SciPy wait for the functions that use them.
    loaded = _imported_after("import depthrefine\ndepthrefine.refine, depthrefine.RefineParams, depthrefine.METHODS")
    assert "matplotlib" not in loaded and "scipy" not in loaded and "numba" not in loaded


def test_version_imports_nothing_heavy():
    code = "from depthrefine.cli import main\nassert main(['--version']) == 0"
    assert _imported_after(code) == []


def test_refine_help_imports_neither_plotting_nor_scipy():
    code = "from depthrefine.cli import main\nassert main(['refine', '--help']) == 0"
    loaded = _imported_after(code)
    assert "matplotlib" not in loaded and "scipy" not in loaded and "numba" not in loaded


def test_lazy_public_names_and_subpackages_resolve():
    import depthrefine

    assert depthrefine.refine is depthrefine.methods.registry.refine
    assert "RefineParams" in dir(depthrefine) and "io" in dir(depthrefine)
    with pytest.raises(AttributeError, match="no_such_name"):
        depthrefine.no_such_name  # noqa: B018
