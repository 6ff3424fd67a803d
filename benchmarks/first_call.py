"""What the first call of a compiled method costs: numba compiles its kernels once, then loads them from the cache.

For each method, three fresh processes with one empty ``NUMBA_CACHE_DIR``:
the first compiles the kernels (cold cache), the next two load them (warm).
Each process times one ``depthrefine.refine`` call on the shipped Art scene
at x8 (1376x1088), after the imports. Printed: the wall-clock and CPU
seconds of each call (on a loaded machine the CPU time is the better
measure of the cost) and whether the first-compile note was given.

Usage::

    python benchmarks/first_call.py [--methods gbp,thesis] [--scale 8]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile

_CHILD = """
import time, warnings
import depthrefine
from depthrefine._numba import FirstCompileWarning
from depthrefine.io import load_sample
scene = load_sample({scale})
with warnings.catch_warnings(record=True) as seen:
    warnings.simplefilter("always")
    start, cpu = time.perf_counter(), time.process_time()
    depthrefine.refine(scene.depth_lr, scene.rgb_hr, method="{method}")
    seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
noted = any(issubclass(w.category, FirstCompileWarning) for w in seen)
print(f"{{seconds:.2f}} {{cpu:.2f}} {{noted}}")
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--methods", default="gbp,thesis")
    parser.add_argument("--scale", type=int, default=8)
    args = parser.parse_args()
    print(f"one refine call on Art x{args.scale}, fresh process each, one empty NUMBA_CACHE_DIR per method")
    print(f"{'method':<8} {'cold: wall / CPU s':>19} {'warm: wall / CPU s':>19} {'warm: wall / CPU s':>19}  "
          "note on the cold run / warm runs")
    for method in args.methods.split(","):
        with tempfile.TemporaryDirectory(prefix="numba-cache-") as cache:
            env = dict(os.environ, NUMBA_CACHE_DIR=cache)
            runs = []
            for _ in range(3):
                done = subprocess.run([sys.executable, "-c", _CHILD.format(method=method, scale=args.scale)],
                                      env=env, capture_output=True, text=True)
                if done.returncode:
                    raise SystemExit(f"{method}: the child process failed:\n{done.stderr}")
                seconds, cpu, noted = done.stdout.split()
                runs.append((float(seconds), float(cpu), noted == "True"))
        cells = " ".join(f"{wall:10.2f} / {cpu:6.2f}" for wall, cpu, _ in runs)
        print(f"{method:<8} {cells}  {runs[0][2]} / {runs[1][2]}, {runs[2][2]}")


if __name__ == "__main__":
    main()
