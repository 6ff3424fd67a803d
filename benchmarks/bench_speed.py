"""Speed and memory of ``depthrefine.refine`` beside OpenCV-contrib's fast global smoother.

Prints, per input, the median wall time of ``refine`` (thesis method) and of
the peer (bilinear enlargement + ``cv2.ximgproc.fastGlobalSmootherFilter``
guided by the same color image), timed alternately in the same run, their
ratio, and the peak memory that ``refine`` adds, as a multiple of the output
depth map's bytes. Targets (issue 2): ratio <= 3, memory < 20x.

Inputs: the thesis geometry (176x144 depth, x7, color 1232x1008, made from
the shipped Art scene: color resized, ground truth area-averaged to 176x144
plus Gaussian noise of 2 levels), and the shipped Art scene at x4, x8, x16.

Usage::

    python benchmarks/bench_speed.py [--repeats 9] [--method thesis]
    python benchmarks/bench_speed.py --method gbp     # the default method: target <= 1 s per 1376x1088 image

Peak memory is measured in a fresh subprocess per input: the kernel's peak
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


def time_pair(depth_lr, rgb_hr, method: str, repeats: int) -> tuple[float, float]:
    """Median seconds of refine and of the peer, calls alternated to share the machine's noise."""
    ours, peer = [], []
    depthrefine.refine(depth_lr, rgb_hr, method=method)  # warm-up (imports, thread pools)
    fgs_peer(depth_lr, rgb_hr)
    for _ in range(repeats):
        t0 = time.perf_counter()
        depthrefine.refine(depth_lr, rgb_hr, method=method)
        t1 = time.perf_counter()
        fgs_peer(depth_lr, rgb_hr)
        t2 = time.perf_counter()
        ours.append(t1 - t0)
        peer.append(t2 - t1)
    return statistics.median(ours), statistics.median(peer)


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
    ap.add_argument("--method", default="thesis", choices=sorted(depthrefine.METHODS))
    ap.add_argument("--no-memory", action="store_true", help="skip the peak-memory measurement")
    args = ap.parse_args(argv)
    print(f"depthrefine {depthrefine.__version__}, OpenCV {cv2.__version__}, {cv2.getNumThreads()} OpenCV threads, "
          f"method {args.method}, {args.repeats} alternated repeats; FGS lambda={FGS_LAMBDA}, sigma_color={FGS_SIGMA_COLOR}")
    header = f"{'input':44s} {'refine ms':>10s} {'FGS ms':>8s} {'ratio':>6s} {'peak MB':>8s} {'x output':>9s}"
    print(header)
    print("-" * len(header))
    for name, load in INPUTS.items():
        depth, rgb = load()
        ours, peer = time_pair(depth, rgb, args.method, args.repeats)
        mem = "" if args.no_memory else peak_memory(name, args.method)
        mem_txt = "" if not mem else f"{mem['added'] / 2**20:8.1f} {mem['added'] / mem['out_bytes']:9.1f}"
        print(f"{name:44s} {ours * 1e3:10.1f} {peer * 1e3:8.1f} {ours / peer:6.2f} {mem_txt}", flush=True)
    if args.method == "gbp":
        print("targets (issue 9): at most 1000 ms per 1376x1088 image (the Middlebury Art rows), "
              "peak memory < 20x the output depth map's bytes")
    else:
        print("targets: ratio <= 3.0 (refine / FGS), peak memory < 20x the output depth map's bytes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
