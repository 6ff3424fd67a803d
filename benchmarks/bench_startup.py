"""Start-up time of the ``depthrefine`` command beside a bare Python interpreter.

Prints the median wall time of ``python -c pass``, ``python -m depthrefine
--version``, ``python -m depthrefine refine --help`` and ``python -c "import
depthrefine"``, each run in a fresh process, alternated so that all share the
machine's noise, and each one's excess over ``python -c pass``. Target
(issue 13): ``--version`` and ``refine --help`` within 0.3 s of ``python -c pass``.

Usage::

    python benchmarks/bench_startup.py [--repeats 11]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time

#: name -> argv after the interpreter.
COMMANDS = {
    "python -c pass": ["-c", "pass"],
    "depthrefine --version": ["-m", "depthrefine", "--version"],
    "depthrefine refine --help": ["-m", "depthrefine", "refine", "--help"],
    "import depthrefine": ["-c", "import depthrefine"],
}

#: Largest excess over ``python -c pass`` the target allows, in seconds.
TARGET_EXCESS = 0.3


def measure_startup(repeats: int = 11) -> dict[str, float]:
    """Median seconds of each command of :data:`COMMANDS`, fresh processes, alternated."""
    times: dict[str, list[float]] = {name: [] for name in COMMANDS}
    for name, args in COMMANDS.items():  # warm the file cache
        subprocess.run([sys.executable, *args], capture_output=True, check=True)
    for _ in range(repeats):
        for name, args in COMMANDS.items():
            t0 = time.perf_counter()
            subprocess.run([sys.executable, *args], capture_output=True, check=True)
            times[name].append(time.perf_counter() - t0)
    return {name: statistics.median(v) for name, v in times.items()}


def format_startup(medians: dict[str, float]) -> list[str]:
    """Lines of a small table: median ms, excess over ``python -c pass`` and the ratio to it."""
    base = medians["python -c pass"]
    lines = [f"{'start-up (fresh process)':44s} {'median ms':>10s} {'- bare ms':>10s} {'/ bare':>7s}"]
    for name, seconds in medians.items():
        lines.append(f"{name:44s} {seconds * 1e3:10.0f} {(seconds - base) * 1e3:10.0f} {seconds / base:7.2f}")
    lines.append(f"target: --version and refine --help within {TARGET_EXCESS * 1e3:.0f} ms of python -c pass")
    if sys.flags.dont_write_bytecode:
        lines.append("note: PYTHONDONTWRITEBYTECODE is set, so every run compiles depthrefine's modules again "
                     "(an installed package has them compiled); unset it to measure what users see")
    return lines


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=11)
    args = ap.parse_args(argv)
    print("\n".join(format_startup(measure_startup(args.repeats))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
