"""Start-up time of the ``depthrefine`` command beside a bare Python interpreter.

Prints the median wall time of ``python -c pass``, ``python -m depthrefine
--version``, ``python -m depthrefine COMMAND --help`` for refine, run, batch
and bench (every command with ``--all-commands``) and ``python -c "import
depthrefine"``, each run in a fresh process, alternated so that all share the
machine's noise, and each one's excess over ``python -c pass`` measured in the
same run. Target (issue 13): ``--version`` and every ``--help`` within 0.3 s of
``python -c pass``; the last column says which are.

With ``--first-call`` it measures instead the first call (issue 22): ``depthrefine
refine`` of the shipped Art scene at x4 (1376x1088, 1.5 MP) in a fresh process
(numba's cache warm: one run first), against the same refine's second call in one
process plus a bare ``python -c "import numpy, cv2"``; target: the fresh process
within 1.5 times that sum. It also says where a fresh process's extra time goes
(loading depthrefine's C kernels, or importing numba and numba's first use of a
compiled kernel with ``--kernels numba`` or where the C kernels are not built).

Usage::

    python benchmarks/bench_startup.py [--repeats 11] [--all-commands]
    python benchmarks/bench_startup.py --first-call [--methods gbp,gbp-fast] [--repeats 5] [--kernels numba]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

#: The commands whose ``--help`` is always measured (``--all-commands`` adds the others).
HELP_COMMANDS = ("refine", "run", "batch", "bench")


def startup_commands(all_commands: bool = False) -> dict[str, list[str]]:
    """name -> argv after the interpreter: the bare interpreter first, ``import depthrefine`` last."""
    names = list(HELP_COMMANDS)
    if all_commands:
        from depthrefine.cli import build_parser

        every = build_parser()._subparsers._group_actions[0].choices
        names += [c for c in every if c not in names] + ["rig import"]
    commands = {"python -c pass": ["-c", "pass"], "depthrefine --version": ["-m", "depthrefine", "--version"]}
    commands.update({f"depthrefine {c} --help": ["-m", "depthrefine", *c.split(), "--help"] for c in names})
    commands["import depthrefine"] = ["-c", "import depthrefine"]
    return commands


#: The default set (see :func:`startup_commands`).
COMMANDS = startup_commands()

#: Largest excess over ``python -c pass`` the target allows, in seconds.
TARGET_EXCESS = 0.3


def measure_startup(repeats: int = 11, commands: dict[str, list[str]] | None = None) -> dict[str, float]:
    """Median seconds of each command of ``commands`` (:data:`COMMANDS`), fresh processes, alternated."""
    commands = COMMANDS if commands is None else commands
    times: dict[str, list[float]] = {name: [] for name in commands}
    for name, args in commands.items():  # warm the file cache
        subprocess.run([sys.executable, *args], capture_output=True, check=True)
    for _ in range(repeats):
        for name, args in commands.items():
            t0 = time.perf_counter()
            subprocess.run([sys.executable, *args], capture_output=True, check=True)
            times[name].append(time.perf_counter() - t0)
    return {name: statistics.median(v) for name, v in times.items()}


def format_startup(medians: dict[str, float]) -> list[str]:
    """Lines of a small table: median ms, excess over ``python -c pass``, the ratio to it, and the target."""
    base = medians["python -c pass"]
    lines = [f"{'start-up (fresh process)':44s} {'median ms':>10s} {'- bare ms':>10s} {'/ bare':>7s}  target"]
    for name, seconds in medians.items():
        excess = seconds - base
        verdict = ("" if not name.startswith("depthrefine ") else
                   "within" if excess <= TARGET_EXCESS else "OVER")
        lines.append(f"{name:44s} {seconds * 1e3:10.0f} {excess * 1e3:10.0f} {seconds / base:7.2f}  {verdict}")
    lines.append(f"target: --version and every --help within {TARGET_EXCESS * 1e3:.0f} ms of python -c pass "
                 "(the '- bare ms' column)")
    if sys.flags.dont_write_bytecode:
        lines.append("note: PYTHONDONTWRITEBYTECODE is set, so every run compiles depthrefine's modules again "
                     "(an installed package has them compiled); unset it to measure what users see")
    return lines


#: The first call's target: a fresh process within this many times (second call + bare import of numpy, cv2).
FIRST_CALL_FACTOR = 1.5

#: Run in one process: two refines through the command line's own entry point; prints the second one's seconds.
_TWO_CALLS = """
import sys, time
from depthrefine.cli import main
args = sys.argv[1:]
main(args)
t0 = time.perf_counter()
main(args)
print(time.perf_counter() - t0)
"""

#: Run in a fresh process: where the first call's extra time goes (seconds per stage, JSON).
_STAGES = """
import json, sys, time
stages = {}
t = time.perf_counter()
import numpy, cv2
stages["import numpy, cv2"] = time.perf_counter() - t; t = time.perf_counter()
from depthrefine.cli import main
import depthrefine.methods.registry
stages["import depthrefine and its registry"] = time.perf_counter() - t; t = time.perf_counter()
from depthrefine import _native
if _native.library() is not None:
    stages["load depthrefine's C kernels"] = time.perf_counter() - t; t = time.perf_counter()
else:
    import numba
    stages["import numba"] = time.perf_counter() - t; t = time.perf_counter()
from depthrefine.methods import _wls
x = numpy.zeros((4, 4), numpy.float32)
_wls.smooth(x, x, x, 1.0)
stages["the first kernel call (with numba: its target set-up, cache load)"] = time.perf_counter() - t
stages["kernels"] = _native.describe()
stages["scipy.ndimage imported by the refine"] = None
t = time.perf_counter()
main(sys.argv[1:])
stages["the refine itself (first call, kernels loaded)"] = time.perf_counter() - t
stages["scipy.ndimage imported by the refine"] = "scipy.ndimage" in sys.modules
print(json.dumps(stages))
"""


def _sample_files() -> tuple[Path, Path]:
    """The shipped Art scene's x4 depth and its color image (1376x1088)."""
    from depthrefine.io import sample_folder

    folder = sample_folder()
    return folder / "noisy_x4.png", folder / "color.png"


def measure_first_call(repeats: int = 5, methods: tuple[str, ...] = ("gbp",)) -> dict:
    """Median seconds of a fresh ``depthrefine refine`` per method, its second call in one process, the bare import.

    Fresh processes and in-process pairs alternate, so that all share the
    machine's noise; each method runs once first (numba's cache warm).
    Returns ``{"bare": s, method: {"fresh": s, "second": s, "stages": {...}}}``.
    """
    depth, color = _sample_files()
    with tempfile.TemporaryDirectory() as tmp:
        def refine_args(method: str) -> list[str]:
            return ["refine", str(depth), str(color), "-o", os.path.join(tmp, f"{method}.png"), "--overwrite",
                    "--method", method]

        bare = [sys.executable, "-c", "import numpy, cv2"]
        for method in methods:   # warm numba's cache and the file cache
            subprocess.run([sys.executable, "-m", "depthrefine", *refine_args(method)], capture_output=True, check=True)
        times: dict = {"bare": [], **{m: {"fresh": [], "second": []} for m in methods}}
        for _ in range(repeats):
            t0 = time.perf_counter()
            subprocess.run(bare, check=True)
            times["bare"].append(time.perf_counter() - t0)
            for method in methods:
                t0 = time.perf_counter()
                subprocess.run([sys.executable, "-m", "depthrefine", *refine_args(method)], capture_output=True,
                               check=True)
                times[method]["fresh"].append(time.perf_counter() - t0)
                out = subprocess.run([sys.executable, "-c", _TWO_CALLS, *refine_args(method)], capture_output=True,
                                     text=True, check=True)
                times[method]["second"].append(float(out.stdout.strip().splitlines()[-1]))
        result: dict = {"bare": statistics.median(times["bare"])}
        for method in methods:
            out = subprocess.run([sys.executable, "-c", _STAGES, *refine_args(method)], capture_output=True,
                                 text=True, check=True)
            result[method] = {"fresh": statistics.median(times[method]["fresh"]),
                              "second": statistics.median(times[method]["second"]),
                              "stages": json.loads(out.stdout.strip().splitlines()[-1])}
    return result


def format_first_call(result: dict) -> list[str]:
    """Lines: per method the fresh process, the second call + bare import, their ratio and the target; the stages."""
    bare = result["bare"]
    lines = [f"first call: depthrefine refine, Art x4 -> 1376x1088 (1.5 MP); bare python -c 'import numpy, cv2' "
             f"{bare * 1e3:.0f} ms",
             f"{'method':10s} {'fresh ms':>9s} {'2nd call ms':>12s} {'2nd + bare':>11s} {'ratio':>6s}  target"]
    for method, r in result.items():
        if method == "bare":
            continue
        base = r["second"] + bare
        ratio = r["fresh"] / base
        verdict = "within" if ratio <= FIRST_CALL_FACTOR else "OVER"
        lines.append(f"{method:10s} {r['fresh'] * 1e3:9.0f} {r['second'] * 1e3:12.0f} {base * 1e3:11.0f} {ratio:6.2f}  "
                     f"{verdict}")
    lines.append(f"target: fresh process <= {FIRST_CALL_FACTOR} x (second call in one process + bare import)")
    if sys.flags.dont_write_bytecode:
        lines.append("note: PYTHONDONTWRITEBYTECODE is set, so every fresh process compiles depthrefine's modules again")
    for method, r in result.items():
        if method == "bare":
            continue
        stages = r["stages"]
        parts = ", ".join(f"{k} {v * 1e3:.0f} ms" for k, v in stages.items() if isinstance(v, float))
        scipy = "yes" if stages.get("scipy.ndimage imported by the refine") else "no"
        lines.append(f"  {method} in a fresh process ({stages['kernels']}): {parts}; "
                     f"scipy.ndimage imported: {scipy}")
    return lines


def add_kernels_option(ap: argparse.ArgumentParser) -> None:
    """``--kernels built|numba``: which kernels gbp runs in this process and every one it starts (:func:`use_kernels`)."""
    ap.add_argument("--kernels", choices=("built", "numba"), default="built",
                    help="the compiled kernels: the C ones when built (default), or numba's (DEPTHREFINE_KERNELS=numba)")


def use_kernels(choice: str) -> None:
    """``numba``: set ``DEPTHREFINE_KERNELS=numba`` for this process and every one it starts; ``built``: leave it."""
    if choice == "numba":
        os.environ["DEPTHREFINE_KERNELS"] = "numba"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=None, help="fresh processes per command (11; 5 with --first-call)")
    ap.add_argument("--all-commands", action="store_true", help="also every other command's --help")
    ap.add_argument("--first-call", action="store_true", help="measure the first refine call instead (issue 22)")
    ap.add_argument("--methods", default="gbp", help="with --first-call: comma-separated methods (default gbp)")
    add_kernels_option(ap)
    args = ap.parse_args(argv)
    use_kernels(args.kernels)
    if args.first_call:
        result = measure_first_call(args.repeats or 5, tuple(args.methods.split(",")))
        print("\n".join(format_first_call(result)))
        return 0
    print("\n".join(format_startup(measure_startup(args.repeats or 11, startup_commands(args.all_commands)))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
