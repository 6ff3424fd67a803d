"""How gbp's compiled solver runs: from many threads at once, in a forked child, on Dask threads, without numba.

The solver splits its work over plain Python threads
(``depthrefine._numba.run_split``), not numba's ``parallel=True`` pool,
whose ``workqueue`` layer aborts the whole process when two Python threads
launch parallel kernels at once, and whose GNU OpenMP layer kills a child
forked after the parent used it. These cases guard against a return of
either: each runs in a fresh interpreter per numba threading layer; the
images are above the size where the solver starts threads
(``_threads.PARALLEL_PIXELS``).
"""

from __future__ import annotations

import subprocess
import sys
import textwrap

import numpy as np
import pytest

pytest.importorskip("numba")

_COMMON = """
import sys, threading
import numpy as np
import depthrefine
from depthrefine.bench.synthetic import make_scene
from depthrefine.methods import _wls

scenes = [make_scene((256, 320), 4, n_objects=2, seed=seed, color_noise_std=4.0, shading=0.1) for seed in (3, 4)]
assert _wls._parallel(scenes[0].rgb_hr.shape)

def gbp(scene):
    return depthrefine.refine(scene.depth_lr, scene.rgb_hr, method="gbp").tobytes()

alone = [gbp(scene) for scene in scenes]
"""

_THREADS = _COMMON + """
results = {}
def work(t):
    results[t] = [gbp(scenes[(t + k) % 2]) == alone[(t + k) % 2] for k in range(3)]
threads = [threading.Thread(target=work, args=(t,)) for t in range(4)]
for thread in threads:
    thread.start()
for thread in threads:
    thread.join()
assert sorted(results) == [0, 1, 2, 3], results
assert all(all(same) for same in results.values()), results
print("ok")
"""

_FORK = _COMMON + """
import multiprocessing
def child(queue):
    queue.put(gbp(scenes[0]))
ctx = multiprocessing.get_context("fork")
queue = ctx.Queue()
process = ctx.Process(target=child, args=(queue,))
process.start()
got = queue.get(timeout=120)
process.join(30)
assert process.exitcode == 0, process.exitcode
assert got == alone[0]
print("ok")
"""

_BATCH = _COMMON + """
from distributed import Client, LocalCluster
from depthrefine.batch import refine_many
if __name__ == "__main__":
    pairs = {k: (scenes[k % 2].depth_lr, scenes[k % 2].rgb_hr) for k in range(6)}
    with LocalCluster(n_workers=1, threads_per_worker=4, processes=False, dashboard_address=":0") as cluster, \\
            Client(cluster) as client:
        got = dict(refine_many(pairs, method="gbp", client=client, chunk=1))
    assert sorted(got) == list(range(6))
    assert all(got[k].tobytes() == alone[k % 2] for k in got)
    print("ok")
"""


def _run(script: str, layer: str, timeout: float = 600) -> None:
    env = {"NUMBA_THREADING_LAYER": layer} if layer != "default" else {}
    import os

    res = subprocess.run([sys.executable, "-c", textwrap.dedent(script)], capture_output=True, text=True,
                         timeout=timeout, env={**os.environ, **env})
    assert res.returncode == 0 and res.stdout.strip().endswith("ok"), (res.returncode, res.stdout, res.stderr[-2000:])


@pytest.mark.parametrize("layer", ["default", "workqueue"])
def test_gbp_from_four_threads_at_once_gives_the_bits_of_one_call(layer):
    _run(_THREADS, layer)


@pytest.mark.parametrize("layer", ["default", "workqueue"])
def test_a_child_forked_after_the_parent_ran_gbp_finishes_with_the_same_bits(layer):
    _run(_FORK, layer)


def test_refine_many_on_dask_threads_gives_the_bits_of_refine():
    pytest.importorskip("distributed")
    _run(_BATCH, "workqueue")


# --- without numba ----------------------------------------------------------------------------------------

@pytest.fixture
def scene():
    from depthrefine.bench.synthetic import make_scene

    return make_scene((64, 64), 4, n_objects=2, seed=3, color_noise_std=4.0, shading=0.1)


def test_refine_gbp_without_numba_names_numba(monkeypatch, scene, numba_kernels, no_numba):
    """Without the C kernels, as for the thesis method: numba's import error, which the CLI and batch turn into advice."""
    import depthrefine

    for method in ("gbp", "thesis"):
        with pytest.raises(ModuleNotFoundError) as info:
            depthrefine.refine(scene.depth_lr, scene.rgb_hr, method=method)
        assert info.value.name == "numba" and "numba" in str(info.value)


def test_the_cli_without_numba_says_pip_install_numba_exit_2(monkeypatch, scene, tmp_path, capsys, numba_kernels,
                                                             no_numba):
    from depthrefine.cli import main
    from depthrefine.io import write_depth, write_rgb

    write_depth(tmp_path / "depth.png", scene.depth_lr)
    write_rgb(tmp_path / "rgb.png", scene.rgb_hr)
    code = main(["refine", str(tmp_path / "depth.png"), str(tmp_path / "rgb.png"), "-o", str(tmp_path / "out.png"),
                 "--method", "gbp"])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "Traceback" not in err and err.count("\n") == 1
    assert "error:" in err and "internal error" not in err and "pip install numba" in err
    assert not (tmp_path / "out.png").exists()


def test_batch_without_numba_says_pip_install_numba(monkeypatch, scene, numba_kernels, no_numba):
    pytest.importorskip("distributed")
    from distributed import Client, LocalCluster

    from depthrefine.batch import refine_many

    frames = {0: (scene.depth_lr, scene.rgb_hr)}
    with LocalCluster(n_workers=1, processes=False, dashboard_address=":0") as cluster, Client(cluster) as client:
        with pytest.raises(RuntimeError) as info:
            list(refine_many(frames, method="gbp", client=client))
    message = str(info.value)
    assert "pip install numba" in message and "internal error" not in message and "\n" not in message


def test_gbp_runs_without_numba_on_the_c_kernels(scene, no_numba):
    """Where the C kernels are built, gbp, gbp-fast and the thesis method need no numba; a thesis median without a
    generated kernel (9x9) still does."""
    import depthrefine
    from depthrefine import _native

    if _native.library() is None:
        pytest.skip(f"depthrefine's C kernels: {_native.why_not()}")
    for method in ("gbp", "gbp-fast", "thesis"):
        out = depthrefine.refine(scene.depth_lr, scene.rgb_hr, method=method)
        assert out.shape == scene.rgb_hr.shape[:2] and np.isfinite(out).all()
    with pytest.raises(ModuleNotFoundError):
        depthrefine.refine(scene.depth_lr, scene.rgb_hr, method="thesis",
                           params=depthrefine.ThesisParams(median_size=9))
