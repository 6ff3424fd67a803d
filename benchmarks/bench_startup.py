"""Start-up time of the ``depthrefine`` command beside a bare Python interpreter.

Prints the median wall time of ``python -c pass``, ``python -m depthrefine
--version``, ``python -m depthrefine COMMAND --help`` for refine, run, batch
and bench (every command with ``--all-commands``) and ``python -c "import
depthrefine"``, each run in a fresh process, alternated so that all share the
machine's noise, and each one's excess over ``python -c pass`` measured in the
same run. Target (issue 13): ``--version`` and every ``--help`` within 0.3 s of
``python -c pass``; the last column says which are.

Usage::

    python benchmarks/bench_startup.py [--repeats 11] [--all-commands]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time

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


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=11)
    ap.add_argument("--all-commands", action="store_true", help="also every other command's --help")
    args = ap.parse_args(argv)
    print("\n".join(format_startup(measure_startup(args.repeats, startup_commands(args.all_commands)))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
