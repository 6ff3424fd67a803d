"""Speed and memory of every registered method beside OpenCV-contrib's fast global smoother.

Prints, per input and per method of ``depthrefine.METHODS`` (all of them, so a
newly registered method is timed without edits), the median wall time of
``refine``, the median time of the peer (bilinear enlargement +
``cv2.ximgproc.fastGlobalSmootherFilter`` guided by the same color image),
timed alternately in the same run, their ratio, and the peak memory that
``refine`` adds, as a multiple of the output depth map's bytes. Then the time
of each step of the thesis method (``depthrefine.methods.thesis.refine.step_times``;
steps solved per patch are summed over patches, which run in threads), and the
start-up time of the command (``benchmarks/bench_startup.py``).
Targets (issues 2, 13): thesis <= 3x FGS, memory < 20x the output.

Inputs: the thesis geometry (SR4000 176x144 depth, x7, color 1232x1008, made
from the shipped Art scene: color resized, ground truth area-averaged to
176x144 plus Gaussian noise of 2 levels), and the shipped Art scene
(1376x1088) at x4, x8, x16.

Usage::

    python benchmarks/bench_speed.py [--repeats 9] [--methods thesis,fgs] [--no-memory] [--no-startup]
    python benchmarks/bench_speed.py --methods gbp     # the default method: target <= 1 s per 1376x1088 image

A slow method gets fewer repeats (at least 3) so that it takes about
``--budget`` seconds per input; the table says how many it got. Peak memory
is measured in a fresh subprocess per input and method: the kernel's peak
resident set (VmHWM) is reset just before the call (``/proc/self/clear_refs``)
and read just after; where that is not possible, ``ru_maxrss`` minus the
resident set before the call is used.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time

import cv2
import numpy as np

import depthrefine
from depthrefine.io import load_sample
from depthrefine.methods.thesis.refine import step_times

try:
    from benchmarks.bench_startup import format_startup, measure_startup
except ImportError:  # run as a script from benchmarks/
    from bench_startup import format_startup, measure_startup

FGS_LAMBDA = 24.0
FGS_SIGMA_COLOR = 8.0


def _thesis_geometry() -> tuple[np.ndarray, np.ndarray]:
    scene = load_sample(8)
    rgb = cv2.resize(scene.rgb_hr, (1232, 1008), interpolation=cv2.INTER_LINEAR)
    gt = cv2.resize(scene.depth_gt.astype(np.float32), (176, 144), interpolation=cv2.INTER_AREA)
    rng = np.random.default_rng(7)
    depth = np.clip(np.round(gt + rng.normal(0, 2.0, gt.shape)), 1, 255).astype(np.uint8)
    return depth, rgb


def _middlebury(scale: int):
    def load() -> tuple[np.ndarray, np.ndarray]:
        scene = load_sample(scale)
        return scene.depth_lr, scene.rgb_hr
    return load


#: name -> loader of (depth_lr, rgb_hr); loaded one at a time.
INPUTS = {
    "thesis geometry 176x144 x7 -> 1232x1008": _thesis_geometry,
    "Middlebury Art x4 (344x272 -> 1376x1088)": _middlebury(4),
    "Middlebury Art x8 (172x136 -> 1376x1088)": _middlebury(8),
    "Middlebury Art x16 (86x68 -> 1376x1088)": _middlebury(16),
}


def fgs_peer(depth_lr: np.ndarray, rgb_hr: np.ndarray) -> np.ndarray:
    """The peer: bilinear enlargement, then the fast global smoother guided by the color image."""
    up = cv2.resize(depth_lr.astype(np.float32), (rgb_hr.shape[1], rgb_hr.shape[0]), interpolation=cv2.INTER_LINEAR)
    return cv2.ximgproc.fastGlobalSmootherFilter(rgb_hr, up, FGS_LAMBDA, FGS_SIGMA_COLOR)


def time_methods(depth_lr, rgb_hr, methods: list[str], repeats: int, budget: float
                 ) -> tuple[dict[str, tuple[float, int]], float]:
    """Median seconds (and repeats) of each method, and of the peer, calls alternated to share the noise."""
    times: dict[str, list[float]] = {}
    planned: dict[str, int] = {}
    for name in methods:  # warm-up (imports, thread pools) and a first measure for the budget
        t0 = time.perf_counter()
        depthrefine.refine(depth_lr, rgb_hr, method=name)
        first = time.perf_counter() - t0
        planned[name] = max(3, min(repeats, int(budget / max(first, 1e-6))))
        times[name] = []
    fgs_peer(depth_lr, rgb_hr)
    peer = []
    for i in range(repeats):
        for name in methods:
            if i < planned[name]:
                t0 = time.perf_counter()
                depthrefine.refine(depth_lr, rgb_hr, method=name)
                times[name].append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        fgs_peer(depth_lr, rgb_hr)
        peer.append(time.perf_counter() - t0)
    return {name: (statistics.median(v), len(v)) for name, v in times.items()}, statistics.median(peer)


def thesis_step_times(depth_lr, rgb_hr, repeats: int) -> tuple[dict[str, float], float]:
    """Median seconds of each step of the thesis method, and of the whole call."""
    per_step: dict[str, list[float]] = {}
    total = []
    for _ in range(repeats):
        with step_times() as steps:
            t0 = time.perf_counter()
            depthrefine.refine(depth_lr, rgb_hr, method="thesis")
            total.append(time.perf_counter() - t0)
        for name, seconds in steps.items():
            per_step.setdefault(name, []).append(seconds)
    return {name: statistics.median(v) for name, v in per_step.items()}, statistics.median(total)


_MEMORY_CHILD = r"""
import json, resource, sys, re
import numpy as np
sys.path[:0] = {path!r}
import depthrefine
from benchmarks.bench_speed import INPUTS
depth, rgb = INPUTS[{name!r}]()
depthrefine.refine(depth[:8, :8], rgb[:8 * (rgb.shape[0] // depth.shape[0]), :8 * (rgb.shape[1] // depth.shape[1])],
                   method={method!r})
def status(key):
    with open('/proc/self/status') as fh:
        for line in fh:
            if line.startswith(key):
                return int(line.split()[1]) * 1024
import ctypes, gc
gc.collect()
try:
    ctypes.CDLL('libc.so.6').malloc_trim(0)
except OSError:
    pass
before = status('VmRSS:')
try:
    with open('/proc/self/clear_refs', 'w') as fh:
        fh.write('5')
    how = 'VmHWM after reset'
except OSError:
    how = 'ru_maxrss'
out = depthrefine.refine(depth, rgb, method={method!r})
peak = status('VmHWM:') if how.startswith('VmHWM') else resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
print(json.dumps(dict(added=peak - before, out_bytes=out.nbytes, how=how)))
"""


def peak_memory(name: str, method: str) -> dict:
    """Peak resident memory added by one ``refine`` call, in a fresh process."""
    import os

    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    code = _MEMORY_CHILD.format(path=[root], name=name, method=method)
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(res.stdout.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=9)
    ap.add_argument("--methods", default="all",
                    help=f"comma-separated, of {sorted(depthrefine.METHODS)} (default: all)")
    ap.add_argument("--budget", type=float, default=30.0,
                    help="seconds per method and input that set a slow method's repeats (min 3)")
    ap.add_argument("--no-memory", action="store_true", help="skip the peak-memory measurement")
    ap.add_argument("--no-startup", action="store_true", help="skip the start-up measurement")
    args = ap.parse_args(argv)
    methods = list(depthrefine.METHODS) if args.methods == "all" else args.methods.split(",")
    unknown = sorted(set(methods) - set(depthrefine.METHODS))
    if unknown:
        ap.error(f"unknown methods {unknown}; choose of {sorted(depthrefine.METHODS)}")
    print(f"depthrefine {depthrefine.__version__}, OpenCV {cv2.__version__}, {cv2.getNumThreads()} OpenCV threads, "
          f"up to {args.repeats} alternated repeats; FGS peer lambda={FGS_LAMBDA}, sigma_color={FGS_SIGMA_COLOR}")
    header = (f"{'input':44s} {'method':8s} {'ms':>8s} {'FGS ms':>8s} {'ratio':>6s} {'runs':>4s} "
              f"{'peak MB':>8s} {'x output':>9s}")
    print(header)
    print("-" * len(header))
    steps = {}
    for name, load in INPUTS.items():
        depth, rgb = load()
        medians, peer = time_methods(depth, rgb, methods, args.repeats, args.budget)
        for method, (seconds, runs) in medians.items():
            mem = "" if args.no_memory else peak_memory(name, method)
            mem_txt = "" if not mem else f"{mem['added'] / 2**20:8.1f} {mem['added'] / mem['out_bytes']:9.1f}"
            print(f"{name:44s} {method:8s} {seconds * 1e3:8.1f} {peer * 1e3:8.1f} {seconds / peer:6.2f} {runs:4d} "
                  f"{mem_txt}", flush=True)
        if "thesis" in methods:
            steps[name] = thesis_step_times(depth, rgb, args.repeats)
    print("targets: thesis ratio <= 3.0 (refine / FGS), peak memory < 20x the output depth map's bytes")
    if "gbp" in methods:
        print("target (issue 9): gbp at most 1000 ms per 1376x1088 image (the Middlebury Art rows)")
    if steps:
        names = list(dict.fromkeys(step for per_step, _ in steps.values() for step in per_step))
        print()
        print("thesis steps, median ms (per-patch steps summed over patches):")
        print(f"{'input':44s} " + " ".join(f"{n[:13]:>13s}" for n in names) + f" {'call':>8s}")
        for name, (per_step, total) in steps.items():
            print(f"{name:44s} " + " ".join(f"{per_step.get(n, 0.0) * 1e3:13.1f}" for n in names)
                  + f" {total * 1e3:8.1f}")
    if not args.no_startup:
        print()
        print("\n".join(format_startup(measure_startup())))
    return 0


if __name__ == "__main__":
    sys.exit(main())
