"""Speed and memory of every registered method beside OpenCV-contrib's fast global smoother, and every speed target.

Prints, per input and per method of ``depthrefine.METHODS`` (all of them, so a
newly registered method is timed without edits), the median wall time of
``refine``, the median time of the peer (bilinear enlargement +
``cv2.ximgproc.fastGlobalSmootherFilter`` guided by the same color image),
timed alternately in the same run, their ratio, the ratio of their CPU times
(all threads; steadier than wall time on a loaded machine), and the peak memory
that ``refine`` adds, as a multiple of the output depth map's bytes. Then the
time of each step of the thesis method (``depthrefine.methods.thesis.refine.step_times``;
steps solved per patch are summed over patches, which run in threads), every
target with its figure and verdict, the start-up time of the command and the
first call (``benchmarks/bench_startup.py``), and the machine's load average
(``os.getloadavg``) at the start and the end: the machine is shared, so quote
medians and ratios with it.

Targets (issues 2, 13, 22), all ratios to FGS in the same run:
gbp <= 10x and gbp-fast <= 3x on the thesis geometry and on Art 1376x1088,
the thesis method <= 3x; peak memory <= 10x the output for gbp and gbp-fast
(< 20x for every method); gbp-fast's frames per second on an Azure Kinect
frame (reported); a fresh ``depthrefine refine`` within 1.5x its second call
in one process plus a bare ``import numpy, cv2``; ``--version`` and every
``--help`` within 0.3 s of ``python -c pass``.

Inputs: the thesis geometry (SR4000 176x144 depth, x7, color 1232x1008, made
from the shipped Art scene: color resized, ground truth area-averaged to
176x144 plus Gaussian noise of 2 levels), the shipped Art scene (1376x1088) at
x4, x8, x16, and the shipped Azure Kinect capture (``load_capture("mug")``):
its NFOV 640x576 depth registered onto its 720p color at x2
(``depthrefine.rig.align_pair``: 640x360, 56 % valid) -> 1280x720.

Usage::

    python benchmarks/bench_speed.py [--repeats 9] [--methods thesis,fgs] [--no-memory] [--no-startup] [--kernels numba]
    python benchmarks/bench_speed.py --methods gbp,gbp-fast,thesis,fgs,bicubic    # the targets' methods

A slow method gets fewer repeats (at least 3) so that it takes about
``--budget`` seconds per input; the table says how many it got. Peak memory
is measured in a fresh subprocess per input and method, after a small first
call through the same code (a 32x32 input with holes: the modules a call loads
on first use, SciPy's for the holes, are the process's, not the call's): the
kernel's peak resident set (VmHWM) is reset just before the call
(``/proc/self/clear_refs``) and read just after; where that is not possible,
``ru_maxrss`` minus the resident set before the call is used.
"""

from __future__ import annotations

import argparse
import json
import os
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
    from benchmarks.bench_startup import (add_kernels_option, format_first_call, format_startup, measure_first_call,
                                          measure_startup, use_kernels)
except ImportError:  # run as a script from benchmarks/
    from bench_startup import (add_kernels_option, format_first_call, format_startup, measure_first_call,
                               measure_startup, use_kernels)

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


def _kinect() -> tuple[np.ndarray, np.ndarray]:
    """The shipped Azure Kinect capture: NFOV depth registered onto the 720p color at x2 (640x360 -> 1280x720)."""
    from depthrefine.io import load_capture
    from depthrefine.rig import AlignSettings, align_pair, rig_from_k4a

    capture = load_capture("mug")
    rig = rig_from_k4a(json.loads(capture.calibration.read_text()), depth_mode="NFOV_UNBINNED",
                       color_resolution="720P")
    pair = align_pair(capture.depth, capture.rgb, rig, settings=AlignSettings(depth_units=capture.depth_units,
                                                                               factor=2))
    return pair.depth_lr, pair.rgb_hr


THESIS = "thesis geometry 176x144 x7 -> 1232x1008"
ART = ("Middlebury Art x4 (344x272 -> 1376x1088)", "Middlebury Art x8 (172x136 -> 1376x1088)",
       "Middlebury Art x16 (86x68 -> 1376x1088)")
KINECT = "Azure Kinect NFOV on 720p (640x360 -> 1280x720)"

#: name -> loader of (depth_lr, rgb_hr); loaded one at a time.
INPUTS = {
    THESIS: _thesis_geometry,
    ART[0]: _middlebury(4),
    ART[1]: _middlebury(8),
    ART[2]: _middlebury(16),
    KINECT: _kinect,
}

#: method -> (largest ratio of its wall time to FGS's, the inputs it holds on): issue 22's speed targets.
RATIO_TARGETS = {"gbp": (10.0, (THESIS, *ART)), "gbp-fast": (3.0, (THESIS, *ART)), "thesis": (3.0, (THESIS, *ART))}
#: Largest peak memory, in output depth maps, per method (issue 22), and for every method (issue 2).
MEMORY_TARGETS = {"gbp": 10.0, "gbp-fast": 10.0}
MEMORY_ANY = 20.0


def fgs_peer(depth_lr: np.ndarray, rgb_hr: np.ndarray) -> np.ndarray:
    """The peer: bilinear enlargement, then the fast global smoother guided by the color image."""
    up = cv2.resize(depth_lr.astype(np.float32), (rgb_hr.shape[1], rgb_hr.shape[0]), interpolation=cv2.INTER_LINEAR)
    return cv2.ximgproc.fastGlobalSmootherFilter(rgb_hr, up, FGS_LAMBDA, FGS_SIGMA_COLOR)


def time_methods(depth_lr, rgb_hr, methods: list[str], repeats: int, budget: float
                 ) -> tuple[dict[str, tuple[float, int, float]], tuple[float, float]]:
    """Median wall seconds, repeats and median CPU seconds (all threads) of each method, and of the peer.

    The calls alternate (each method, then the peer, repeat after repeat) so that all share the machine's noise.
    """
    wall: dict[str, list[float]] = {}
    cpu: dict[str, list[float]] = {}
    planned: dict[str, int] = {}
    for name in methods:  # warm-up (imports, thread pools) and a first measure for the budget
        t0 = time.perf_counter()
        depthrefine.refine(depth_lr, rgb_hr, method=name)
        first = time.perf_counter() - t0
        planned[name] = max(3, min(repeats, int(budget / max(first, 1e-6))))
        wall[name], cpu[name] = [], []
    fgs_peer(depth_lr, rgb_hr)
    peer_wall, peer_cpu = [], []
    for i in range(repeats):
        for name in methods:
            if i < planned[name]:
                c0, t0 = time.process_time(), time.perf_counter()
                depthrefine.refine(depth_lr, rgb_hr, method=name)
                wall[name].append(time.perf_counter() - t0)
                cpu[name].append(time.process_time() - c0)
        c0, t0 = time.process_time(), time.perf_counter()
        fgs_peer(depth_lr, rgb_hr)
        peer_wall.append(time.perf_counter() - t0)
        peer_cpu.append(time.process_time() - c0)
    return ({name: (statistics.median(v), len(v), statistics.median(cpu[name])) for name, v in wall.items()},
            (statistics.median(peer_wall), statistics.median(peer_cpu)))


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
from benchmarks.bench_speed import INPUTS, warm_up
depth, rgb = INPUTS[{name!r}]()
warm_up(depth, rgb, {method!r})
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


def warm_up(depth: np.ndarray, rgb: np.ndarray, method: str) -> None:
    """A small first call of ``method`` through the code a call on ``depth``, ``rgb`` takes, holes included.

    A 32x32 input of ``depth``'s type with one enclosed hole and one at the
    border, on a crop of ``rgb`` at the same factor: the modules a call loads
    on first use (SciPy's for the holes: 37 MB resident) load once per
    process, and are not counted as the measured call's memory; the call's
    own arrays (the solver's scratch arrays among them) are, as they are
    made for the larger input.
    """
    warm = (100 + np.arange(32 * 32).reshape(32, 32) % 7).astype(depth.dtype)
    warm[16, 16] = warm[0, 0] = 0
    depthrefine.refine(warm, rgb[:32 * (rgb.shape[0] // depth.shape[0]), :32 * (rgb.shape[1] // depth.shape[1])],
                       method=method)


def peak_memory(name: str, method: str) -> dict:
    """Peak resident memory added by one ``refine`` call, in a fresh process."""
    import os

    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    code = _MEMORY_CHILD.format(path=[root], name=name, method=method)
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(res.stdout.strip().splitlines()[-1])


def format_targets(rows: dict[tuple[str, str], dict], methods: list[str]) -> list[str]:
    """One line per target: its figure in this run (the ratios per input, the memory, the frame rate) and a verdict."""
    lines = ["targets (issue 22; ratios to FGS in this run, wall time):"]
    for method, (limit, inputs) in RATIO_TARGETS.items():
        if method not in methods:
            continue
        got = [(name, rows[name, method]["ratio"]) for name in inputs if (name, method) in rows]
        worst = max(r for _, r in got)
        figures = ", ".join(f"{name.split(' (')[0].replace('Middlebury ', '')} {r:.2f}x" for name, r in got)
        lines.append(f"  {method} <= {limit:g}x FGS: {figures} -> {'met' if worst <= limit else 'NOT met'} "
                     f"(worst {worst:.2f}x)")
    for method, limit in MEMORY_TARGETS.items():
        got = [rows[key]["memory"] for key in rows if key[1] == method and rows[key].get("memory") is not None]
        if got:
            lines.append(f"  {method} peak memory <= {limit:g}x the output: worst {max(got):.1f}x -> "
                         f"{'met' if max(got) <= limit else 'NOT met'}")
    every = [(key, row["memory"]) for key, row in rows.items() if row.get("memory") is not None]
    if every:
        (name, method), worst = max(every, key=lambda kv: kv[1])
        lines.append(f"  every method's peak memory < {MEMORY_ANY:g}x the output: worst {worst:.1f}x ({method}) -> "
                     f"{'met' if worst < MEMORY_ANY else 'NOT met'}")
    if (KINECT, "gbp-fast") in rows:
        seconds = rows[KINECT, "gbp-fast"]["seconds"]
        lines.append(f"  gbp-fast on {KINECT}: {1 / seconds:.1f} frames per second ({seconds * 1e3:.0f} ms median, "
                     f"one process, {os.cpu_count()} CPUs)")
    return lines


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=9)
    ap.add_argument("--methods", default="all",
                    help=f"comma-separated, of {sorted(depthrefine.METHODS)} (default: all)")
    ap.add_argument("--budget", type=float, default=30.0,
                    help="seconds per method and input that set a slow method's repeats (min 3)")
    ap.add_argument("--no-memory", action="store_true", help="skip the peak-memory measurement")
    ap.add_argument("--no-startup", action="store_true", help="skip the start-up and first-call measurements")
    add_kernels_option(ap)
    args = ap.parse_args(argv)
    use_kernels(args.kernels)
    from depthrefine import _native

    methods = list(depthrefine.METHODS) if args.methods == "all" else args.methods.split(",")
    unknown = sorted(set(methods) - set(depthrefine.METHODS))
    if unknown:
        ap.error(f"unknown methods {unknown}; choose of {sorted(depthrefine.METHODS)}")
    load = os.getloadavg()
    print(f"depthrefine {depthrefine.__version__}, OpenCV {cv2.__version__}, {cv2.getNumThreads()} OpenCV threads, "
          f"{os.cpu_count()} CPUs, up to {args.repeats} alternated repeats; FGS peer lambda={FGS_LAMBDA}, "
          f"sigma_color={FGS_SIGMA_COLOR}")
    print(_native.describe())
    print(f"load average at the start: {load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f} (1 / 5 / 15 min)")
    header = (f"{'input':48s} {'method':9s} {'ms':>8s} {'FGS ms':>8s} {'ratio':>6s} {'cpu':>6s} {'runs':>4s} "
              f"{'peak MB':>8s} {'x output':>9s}")
    print(header)
    print("-" * len(header))
    steps = {}
    rows: dict[tuple[str, str], dict] = {}
    for name, load_input in INPUTS.items():
        depth, rgb = load_input()
        medians, (peer, peer_cpu) = time_methods(depth, rgb, methods, args.repeats, args.budget)
        for method, (seconds, runs, cpu) in medians.items():
            mem = None if args.no_memory else peak_memory(name, method)
            memory = None if mem is None else mem["added"] / mem["out_bytes"]
            rows[name, method] = dict(seconds=seconds, ratio=seconds / peer, memory=memory)
            mem_txt = "" if mem is None else f"{mem['added'] / 2**20:8.1f} {memory:9.1f}"
            print(f"{name:48s} {method:9s} {seconds * 1e3:8.1f} {peer * 1e3:8.1f} {seconds / peer:6.2f} "
                  f"{cpu / peer_cpu:6.2f} {runs:4d} {mem_txt}", flush=True)
        if "thesis" in methods and name != KINECT:
            steps[name] = thesis_step_times(depth, rgb, args.repeats)
    print("(ratio: wall time / FGS's; cpu: CPU seconds of all threads / FGS's)")
    if steps:
        names = list(dict.fromkeys(step for per_step, _ in steps.values() for step in per_step))
        print()
        print("thesis steps, median ms (per-patch steps summed over patches):")
        print(f"{'input':48s} " + " ".join(f"{n[:13]:>13s}" for n in names) + f" {'call':>8s}")
        for name, (per_step, total) in steps.items():
            print(f"{name:48s} " + " ".join(f"{per_step.get(n, 0.0) * 1e3:13.1f}" for n in names)
                  + f" {total * 1e3:8.1f}")
    print()
    print("\n".join(format_targets(rows, methods)))
    if not args.no_startup:
        print()
        print("\n".join(format_startup(measure_startup())))
        print()
        first = [m for m in ("gbp", "gbp-fast") if m in methods] or ["gbp"]
        print("\n".join(format_first_call(measure_first_call(methods=tuple(first)))))
    load = os.getloadavg()
    print(f"\nload average at the end: {load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f} (1 / 5 / 15 min)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
