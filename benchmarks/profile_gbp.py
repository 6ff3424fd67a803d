"""Where gbp's time goes: the median wall time of each step of one ``refine`` call, per input.

The step functions of ``depthrefine.methods.gbp`` (and gbp-fast's, and the
solver's kernels in ``methods/_wls.py``) are wrapped in timers for the run,
so the figures follow the code as it is: a step that calls another step
(the trust check runs steps 1-4 one octave down) shows the inner one
indented below it, and a step's own time excludes nothing (it is the wall
time of its calls). The solver's calls are listed per call in order (a
round's depth weights and smooth), so each round shows on its own line.
``rest`` is the call's time outside the listed steps.

Usage::

    python benchmarks/profile_gbp.py [--method gbp] [--repeats 5] [--inputs thesis,art4] [--cpu | --memory | --faults]

``--memory`` says instead, per step, the peak of the memory the call holds
(``tracemalloc``: NumPy's and OpenCV's arrays), in multiples of the output
depth map's bytes, between the end of the step before and the end of this one; after a
small first call (``bench_speed.warm_up``), so the arrays the call makes for this input (the
solver's scratch arrays among them) count, as in ``bench_speed.py``'s peak memory.

``--faults`` counts, per step, the process's minor page faults instead of
the time (``getrusage``): each first touch of a page the allocator took from
the system, a few microseconds apiece on a virtual machine.

``--cpu`` runs everything in one thread (OpenCV and the solver's threads
off) and times the CPU seconds of that thread (``time.thread_time``): on a
shared, loaded machine these vary far less than wall times, and they add up
to what one core spends.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import statistics
import sys
import time
from collections import defaultdict

import depthrefine

try:
    from benchmarks.bench_speed import INPUTS, warm_up
except ImportError:  # run as a script from benchmarks/
    from bench_speed import INPUTS, warm_up

#: Short names of the inputs of :data:`bench_speed.INPUTS`.
SHORT = {"thesis": "thesis geometry 176x144 x7 -> 1232x1008", "art4": "Middlebury Art x4 (344x272 -> 1376x1088)",
         "art8": "Middlebury Art x8 (172x136 -> 1376x1088)", "art16": "Middlebury Art x16 (86x68 -> 1376x1088)",
         "kinect": "Azure Kinect NFOV on 720p (640x360 -> 1280x720)"}

#: (module, function names) wrapped in timers; a name missing from a module is skipped.
STEPS = {
    "depthrefine.methods.gbp.upsample": ("measure_input", "thin_if_fattened", "make_solver", "local_bounds",
                                         "back_project", "flat_blend", "measured_trust", "blend_fallback",
                                         "clip_to_bounds"),
    "depthrefine.methods.gbp.trust": ("measure_input", "make_solver", "local_bounds", "back_project", "flat_blend",
                                      "clamped_bicubic", "noise_levels", "reduce"),
    "depthrefine.methods.gbp.solve": ("clamped_bicubic", "local_bounds", "reduce", "resize_to_scratch",
                                      "clip_to_bounds"),
    "depthrefine.methods.gbp.fast": ("measure_input", "thin_if_fattened", "make_solver", "local_bounds",
                                     "back_project", "flat_blend", "clamped_bicubic", "reduce", "blend_fallback",
                                     "measured_trust", "resize"),
    "depthrefine.methods._wls": ("color_weights", "depth_weights", "edge_weights", "smooth", "guided_smooth",
                                 "smooth_with_gradient"),
    "depthrefine.methods._resample": ("guided_enlarge",),
}

#: Solver functions whose calls are listed one by one (the rounds).
PER_CALL = {"depth_weights", "edge_weights", "smooth", "guided_smooth", "smooth_with_gradient"}


#: The clock of the timers: wall time, or with ``--cpu`` the calling thread's CPU time (``--faults``: :func:`faults`).
clock = time.perf_counter


def faults() -> float:
    """The process's minor page faults so far (all threads)."""
    import resource

    return float(resource.getrusage(resource.RUSAGE_SELF).ru_minflt)


class StepRecorder:
    """Wraps the step functions of :data:`STEPS`; subclasses say what they record at a step's start and end."""

    def __init__(self):
        self.stack: list[str] = []
        self.counts: dict[tuple[str, ...], int] = defaultdict(int)

    def start(self, path: tuple[str, ...]) -> object:
        raise NotImplementedError

    def end(self, path: tuple[str, ...], token: object) -> None:
        raise NotImplementedError

    def wrap(self, name: str, func):
        @functools.wraps(func)
        def recorded(*args, **kwargs):
            parent = tuple(self.stack)
            label = name
            if name in PER_CALL:
                self.counts[parent + (name,)] += 1
                label = f"{name}#{self.counts[parent + (name,)]}"
            self.stack.append(label)
            path = tuple(self.stack)
            token = self.start(path)
            try:
                return func(*args, **kwargs)
            finally:
                self.end(path, token)
                self.stack.pop()
        return recorded

    @contextlib.contextmanager
    def installed(self):
        import importlib

        saved = []
        for module_name, names in STEPS.items():
            try:
                module = importlib.import_module(module_name)
            except ImportError:
                continue
            for name in names:
                if hasattr(module, name):
                    saved.append((module, name, getattr(module, name)))
                    setattr(module, name, self.wrap(name, getattr(module, name)))
        try:
            yield self
        finally:
            for module, name, func in saved:
                setattr(module, name, func)


class StepTimer(StepRecorder):
    """Seconds per path of nested step calls (``back_project/smooth#3``), summed within one call."""

    def __init__(self):
        super().__init__()
        self.times: dict[tuple[str, ...], float] = defaultdict(float)

    def start(self, path):
        self.times.setdefault(path, 0.0)  # entry order: a parent before its children
        return clock()

    def end(self, path, token):
        self.times[path] += clock() - token


class StepMemory(StepRecorder):
    """Per path of nested step calls: the peak traced memory (bytes above the call's start) up to its end."""

    def __init__(self, start: int):
        super().__init__()
        self.origin = start
        self.peaks: dict[tuple[str, ...], int] = {}

    def start(self, path):
        self.peaks.setdefault(path, 0)

    def end(self, path, token):
        import tracemalloc

        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.reset_peak()
        self.peaks[path] = max(self.peaks[path], peak - self.origin)


def memory_profile(depth, rgb, method: str) -> tuple[dict[tuple[str, ...], int], int, int]:
    """Peak traced bytes per step path (above the call's start), the call's peak, and the output's bytes."""
    import tracemalloc

    warm_up(depth, rgb, method)     # as bench_speed's: the solver's scratch arrays for this input count
    tracemalloc.start()
    start = tracemalloc.get_traced_memory()[0]
    tracer = StepMemory(start)
    with tracer.installed():
        out = depthrefine.refine(depth, rgb, method=method)
    peak = max(tracer.peaks.values(), default=0)
    peak = max(peak, tracemalloc.get_traced_memory()[1] - start)
    tracemalloc.stop()
    return tracer.peaks, peak, out.nbytes


def profile(depth, rgb, method: str, repeats: int) -> tuple[dict[tuple[str, ...], float], float]:
    """Median seconds of each step path over ``repeats`` calls, and of the whole call."""
    depthrefine.refine(depth, rgb, method=method)  # warm-up
    per_path: dict[tuple[str, ...], list[float]] = defaultdict(list)
    total = []
    for _ in range(repeats):
        timer = StepTimer()
        with timer.installed():
            t0 = clock()
            depthrefine.refine(depth, rgb, method=method)
            total.append(clock() - t0)
        for path, seconds in timer.times.items():
            per_path[path].append(seconds)
    return {path: statistics.median(v) for path, v in per_path.items()}, statistics.median(total)


def format_profile(steps: dict[tuple[str, ...], float], total: float, unit: str = "ms") -> list[str]:
    """Indented lines ``step  ms  % of the call``, in call order, and the call's time outside its top steps
    (``unit="faults"``: counts, as :func:`profile` gives them with :func:`faults` as its clock)."""
    factor = 1e3 if unit == "ms" else 1.0
    total = total or 1e-30     # a call without a single page fault
    lines = []
    for path, seconds in steps.items():
        lines.append(f"  {'  ' * (len(path) - 1)}{path[-1]:{40 - 2 * len(path)}s} {seconds * factor:8.1f} {unit} "
                     f"{100 * seconds / total:5.1f} %")
    rest = total - sum(s for p, s in steps.items() if len(p) == 1)
    lines.append(f"  {'rest':38s} {rest * factor:8.1f} {unit} {100 * rest / total:5.1f} %")
    lines.append(f"  {'call':38s} {total * factor:8.1f} {unit}")
    return lines


def main(argv: list[str] | None = None) -> int:
    import os

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--method", default="gbp")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--inputs", default="thesis,art4", help=f"comma-separated, of {sorted(SHORT)}")
    measure = ap.add_mutually_exclusive_group()
    measure.add_argument("--cpu", action="store_true", help="one thread; CPU seconds of that thread")
    measure.add_argument("--memory", action="store_true", help="the peak memory per step instead of the time")
    measure.add_argument("--faults", action="store_true", help="minor page faults per step instead of the time")
    args = ap.parse_args(argv)
    if args.memory:
        for short in args.inputs.split(","):
            name = SHORT[short]
            depth, rgb = INPUTS[name]()
            peaks, peak, out_bytes = memory_profile(depth, rgb, args.method)
            print(f"{args.method}, {name}: peak {peak / 2**20:.1f} MB = {peak / out_bytes:.1f} x the output")
            for path, value in peaks.items():
                print(f"  {'  ' * (len(path) - 1)}{path[-1]:{40 - 2 * len(path)}s} {value / out_bytes:6.1f} x")
        return 0
    global clock
    if args.cpu:
        import cv2

        from depthrefine import _threads

        cv2.setNumThreads(1)
        _threads.set_threads(1)   # every compiled kernel in the calling thread
        clock = time.thread_time
    if args.faults:
        clock = faults
    what = "minor page faults" if args.faults else f"{'CPU' if args.cpu else 'wall'} time"
    print(f"{args.method}: median of {args.repeats} calls, {what}; load average "
          f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")
    for short in args.inputs.split(","):
        name = SHORT[short]
        depth, rgb = INPUTS[name]()
        steps, total = profile(depth, rgb, args.method, args.repeats)
        print(name)
        print("\n".join(format_profile(steps, total, "faults" if args.faults else "ms")))
    return 0


if __name__ == "__main__":
    sys.exit(main())
