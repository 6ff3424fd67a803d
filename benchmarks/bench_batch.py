"""Frames per second of ``depthrefine.batch.refine_many`` with 1 and 2 workers and with ``temporal``; flicker.

A generated sequence (``make_sequence``: a disc moving over a static scene,
fresh depth and color noise per frame, uint16 mm) is refined on the local
clusters ``depthrefine batch --workers 1`` and ``--workers 2`` start
(``depthrefine.batch.local_client``: worker processes with one Dask thread
each; each worker caps its kernel threads at its share of the cores, so 1
worker on 2 cores runs 2 kernel threads, 2 workers 1 each), and with
``temporal=True`` (warm start, two chunks of half the frames, one per
worker) on 2 workers.
Each configuration runs ``--repeats`` times on a cluster that has already
refined a warm-up batch (imports and first-call costs excluded; the cluster
start is not timed), the configurations taking turns (1 worker, 2 workers, 2
workers temporal, then again), so that on a machine shared with other jobs
each sees the same load; the figures are medians. Beside them: the CPU
time per frame of the bench's own process (the Dask client and the local
scheduler: what ``depthrefine batch`` spends besides the workers, here
without reading or writing files) and of the workers, steadier than the
wall time on a shared machine, and the load average of the machine
(``os.getloadavg``): the ratio of 2 workers to 1 is only as good as the
free cores. Two reference lines follow: one
frame refined in the bench's own process with 1 and with 2 kernel threads
(what a lone worker gains inside a frame from the second core: were the
lone worker as fast as this process, a second worker could add at most
2 / that gain; it is slower, see docs/batch.md), and one-thread processes
refining frames in a
loop without Dask, 1 alone and 2 at once (what the machine gives two
workers at that moment; the last line sets the batch's rates against
these), started with the environment the bench started
with (a ``LocalCluster`` leaves Dask's worker variables, among them
``MALLOC_TRIM_THRESHOLD_``, in its parent's ``os.environ``).

Flicker (``depthrefine.bench.metrics.flicker``: mean absolute frame-to-frame
change on pixels whose ground truth did not change, in mm) and the mean RMSE
against the ground truth are printed for the frames refined independently and
with ``temporal``, on the timed sequence (ToF-like depth noise of 10 mm, new
in every frame, which no warm start can remove) and on the same sequence
without depth noise.

``--overheads`` prints only what docs/batch.md ("Parallel") says a worker's
allocator and an idle local cluster cost: one frame's CPU in a one-thread
process started as usual and with ``MALLOC_TRIM_THRESHOLD_=65536`` (as Dask
starts its workers), and the CPU per second of an idle local cluster of 2
workers with Dask's defaults and as ``local_client`` starts it.

Usage::

    python benchmarks/bench_batch.py [--frames 48] [--size 240x320] [--scale 4] [--repeats 5] [--method gbp]
                                     [--no-flicker | --no-speed | --overheads]
"""

from __future__ import annotations

import argparse
import contextlib
import logging
import os
import statistics
import time

import numpy as np


def _load() -> str:
    one, five, _ = os.getloadavg()
    return f"load {one:.2f} (1 min) {five:.2f} (5 min)"


def _parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                 formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    ap.add_argument("--frames", type=int, default=48, help="frames in the sequence")
    ap.add_argument("--size", default="240x320", help="color image ROWSxCOLS")
    ap.add_argument("--scale", type=int, default=4, help="color / depth resolution ratio")
    ap.add_argument("--repeats", type=int, default=5, help="timed runs per configuration (the median is reported)")
    ap.add_argument("--method", default="gbp", help="refinement method")
    only = ap.add_mutually_exclusive_group()
    only.add_argument("--no-flicker", action="store_true", help="only the frames per second")
    only.add_argument("--no-speed", action="store_true", help="only the flicker table (no timing)")
    only.add_argument("--overheads", action="store_true",
                      help="only what a worker's allocator and an idle local cluster cost (docs/batch.md, Parallel)")
    return ap


#: The environment the bench started with (starting a LocalCluster adds Dask's worker variables to os.environ).
_START_ENVIRON = dict(os.environ)


def _cluster(stack: contextlib.ExitStack, workers: int):
    """The local cluster ``depthrefine batch --workers N`` runs on (its client)."""
    from depthrefine.batch import local_client

    return stack.enter_context(local_client(workers))


def _cpu_seconds(processes) -> float:
    """User + system CPU seconds of ``processes`` (psutil), all their threads."""
    return sum(sum(p.cpu_times()[:2]) for p in processes)


def _refined(pairs, args, client, temporal: bool) -> list[np.ndarray]:
    from depthrefine.batch import refine_many

    chunk = (len(pairs) + 1) // 2  # two chunks: one per worker
    return [d for _, d in refine_many(pairs, method=args.method, client=client, temporal=temporal, chunk=chunk)]


def speed(pairs, args) -> dict[bool, list[np.ndarray]]:
    """Print the frames per second of each configuration; return the outputs of 2 workers (key: temporal)."""
    import psutil

    configs = (("1 worker", 1, False), ("2 workers", 2, False), ("2 workers --temporal", 2, True))
    times: dict[str, list[float]] = {label: [] for label, _, _ in configs}
    loads: dict[str, list[float]] = {label: [] for label, _, _ in configs}
    cpu: dict[str, list[tuple[float, float]]] = {label: [] for label, _, _ in configs}  # ms/frame: here, workers
    outputs: dict[str, list] = {}
    here = [psutil.Process()]
    with contextlib.ExitStack() as stack:
        clients = {workers: _cluster(stack, workers) for workers in (1, 2)}
        workers_of = {n: [psutil.Process(pid) for pid in client.run(os.getpid).values()] for n, client in clients.items()}
        for workers, client in clients.items():
            _refined(pairs[:4 * workers], args, client, False)  # warm-up: imports, compilation, first calls
        for _ in range(args.repeats):  # the configurations take turns, so that each sees the same load
            for label, workers, temporal in configs:
                before = _cpu_seconds(here), _cpu_seconds(workers_of[workers])
                start = time.perf_counter()
                outputs[label] = _refined(pairs, args, clients[workers], temporal)
                times[label].append(time.perf_counter() - start)
                after = _cpu_seconds(here), _cpu_seconds(workers_of[workers])
                cpu[label].append(tuple(1000 * (b - a) / len(pairs) for a, b in zip(before, after)))
                loads[label].append(os.getloadavg()[0])
    fps = {}
    for label, _, _ in configs:
        fps[label] = len(pairs) / statistics.median(times[label])
        client_ms, workers_ms = (statistics.median(c[i] for c in cpu[label]) for i in (0, 1))
        print(f"  {label:22s} {fps[label]:7.2f} frames/s   CPU per frame: {client_ms:4.1f} ms here, "
              f"{workers_ms:5.1f} ms in the workers   (runs: {', '.join(f'{len(pairs) / t:.2f}' for t in times[label])}; "
              f"1-min load after each: {', '.join(f'{v:.1f}' for v in loads[label])})", flush=True)
    print(f"  2 workers / 1 worker: {fps['2 workers'] / fps['1 worker']:.2f}x;  temporal / independent (2 workers): "
          f"{fps['2 workers --temporal'] / fps['2 workers']:.2f}x")
    one, two = (_frame_ms(pairs, args, threads) for threads in (1, 2))
    print(f"  one frame in this process: {one:.1f} ms with 1 kernel thread, {two:.1f} ms with 2 ({one / two:.2f}x: "
          f"what 1 worker on 2 cores gains inside a frame; were it as fast as this process, 2 workers could gain "
          f"at most {2 * two / one:.2f}x over it)")
    (alone, alone_ms, _), (pair, pair_ms, _) = (_processes_rate(args, n) for n in (1, 2))
    print(f"  without Dask, one-thread processes refining frames in a loop: 1 process {alone:.2f} frames/s "
          f"({alone_ms:.1f} ms CPU per frame), 2 at once {pair:.2f} frames/s ({pair_ms:.1f} ms) "
          f"({pair / alone:.2f}x: what this machine gives 2 workers now)")
    print(f"  the batch against these: 1 worker at {fps['1 worker'] * two / 1000:.0%} of one frame at a time in this "
          f"process with 2 kernel threads, 2 workers at {fps['2 workers'] / pair:.0%} of 2 plain processes")
    return {False: outputs["2 workers"], True: outputs["2 workers --temporal"]}


def _processes_rate(args, processes: int, seconds: float = 5.0, extra_environ: dict | None = None) -> tuple[float, float]:
    """Frames per second of ``processes`` one-thread processes refining frames at once, in total, and their
    median CPU milliseconds per frame (and of that, in the kernel)."""
    import multiprocessing

    ctx = multiprocessing.get_context("spawn")
    queue, start = ctx.Queue(), ctx.Event()
    workers = [ctx.Process(target=_refine_loop, args=(args.method, args.size, args.scale, seconds, queue, start))
               for _ in range(processes)]
    environ = dict(os.environ)
    os.environ.clear()
    os.environ.update(_START_ENVIRON)  # as the bench started: without what a LocalCluster left in os.environ
    os.environ.update(extra_environ or {})
    try:
        for w in workers:
            w.start()
    finally:
        os.environ.clear()
        os.environ.update(environ)
    for _ in workers:
        queue.get()  # ready: imported, compiled, warmed up
    start.set()
    results = [queue.get() for _ in workers]
    for w in workers:
        w.join()
    return (sum(rate for rate, _, _ in results), statistics.median(ms for _, ms, _ in results),
            statistics.median(ms for _, _, ms in results))


def _refine_loop(method: str, size: str, scale: int, seconds: float, queue, start) -> None:
    import cv2

    from depthrefine import _numba
    from depthrefine.bench.synthetic import make_sequence
    from depthrefine.methods.registry import refine

    cv2.setNumThreads(1)
    _numba.set_threads(1)
    rows, cols = (int(v) for v in size.lower().split("x"))
    frames = make_sequence(4, (rows, cols), scale, seed=3, color_noise_std=8.0)
    refine(frames[0].depth_lr, frames[0].rgb_hr, method=method)
    queue.put("ready")
    start.wait()
    begin, cpu, done = time.perf_counter(), os.times(), 0
    while time.perf_counter() - begin < seconds:
        frame = frames[done % len(frames)]
        refine(frame.depth_lr, frame.rgb_hr, method=method)
        done += 1
    end = os.times()
    queue.put((done / (time.perf_counter() - begin), 1000 * (end.user + end.system - cpu.user - cpu.system) / done,
               1000 * (end.system - cpu.system) / done))


def _frame_ms(pairs, args, threads: int, runs: int = 10) -> float:
    """Median milliseconds of one frame refined here with ``threads`` kernel threads (numba and OpenCV)."""
    import cv2

    from depthrefine import _numba
    from depthrefine.methods.registry import refine

    before = _numba.set_threads(threads), cv2.getNumThreads()
    cv2.setNumThreads(threads)
    try:
        times = []
        for i in range(runs + 1):
            _, depth, rgb = pairs[i % len(pairs)]
            start = time.perf_counter()
            refine(depth, rgb, method=args.method)
            times.append(time.perf_counter() - start)
    finally:
        _numba.set_threads(before[0])
        cv2.setNumThreads(before[1])
    return 1000 * statistics.median(times[1:])


def flicker_table(sequences, outputs) -> None:
    """Flicker and mean RMSE of each sequence's outputs, each frame on its own and with the warm start."""
    from depthrefine.bench.metrics import flicker, rmse

    for name, seq in sequences.items():
        truth = [f.depth_hr_gt for f in seq]
        for temporal in (False, True):
            mean_rmse = float(np.mean([rmse(o, g) for o, g in zip(outputs[name][temporal], truth)]))
            print(f"  {name:18s} {'temporal' if temporal else 'independent':12s} flicker "
                  f"{flicker(outputs[name][temporal], truth):7.3f} mm   mean RMSE {mean_rmse:7.2f} mm")


def overheads(args) -> None:
    """Print one frame's CPU in a one-thread process started as Dask starts its workers (MALLOC_TRIM_THRESHOLD_)
    and as usual, and the idle CPU per second of a local cluster of 2 workers with Dask's defaults and as
    ``local_client`` starts it."""
    for label, extra in (("as usual", None), ("with MALLOC_TRIM_THRESHOLD_=65536", {"MALLOC_TRIM_THRESHOLD_": "65536"})):
        _, cpu, system = _processes_rate(args, 1, extra_environ=extra)
        print(f"  one frame in a one-thread process started {label}: {cpu:.1f} ms CPU, {system:.1f} ms of it in the "
              "kernel", flush=True)
    import psutil
    from distributed import Client, LocalCluster

    from depthrefine.batch import local_client

    def dask_defaults():
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address=":0", silence_logs=logging.ERROR)
        return contextlib.closing(cluster), Client(cluster)

    for label in ("Dask's defaults", "local_client"):
        with contextlib.ExitStack() as stack:
            if label == "local_client":
                client = stack.enter_context(local_client(2))
            else:
                closing, client = dask_defaults()
                stack.enter_context(closing)
                stack.enter_context(client)
            here, workers = psutil.Process(), [psutil.Process(p) for p in client.run(os.getpid).values()]
            time.sleep(3)
            before = [_cpu_seconds([p]) for p in [here, *workers]]
            time.sleep(10)
            per_second = [100 * (_cpu_seconds([p]) - b) for p, b in zip([here, *workers], before)]
        print(f"  an idle local cluster of 2 workers ({label}): {per_second[0]:.0f} ms CPU per second in this process "
              f"(client, scheduler, nannies), {', '.join(f'{v:.0f}' for v in per_second[1:])} in the workers",
              flush=True)


def main() -> None:
    from depthrefine.bench.synthetic import make_sequence

    args = _parser().parse_args()
    if args.overheads:
        print(f"color {args.size}, method {args.method}; {_load()}")
        overheads(args)
        return
    rows, cols = (int(v) for v in args.size.lower().split("x"))
    sequences = {"depth noise 10 mm": make_sequence(args.frames, (rows, cols), args.scale, seed=3, color_noise_std=8.0),
                 "no depth noise": make_sequence(args.frames, (rows, cols), args.scale, seed=3, color_noise_std=8.0,
                                                 noise_std=0.0)}
    pairs = {name: [(i, f.depth_lr, f.rgb_hr) for i, f in enumerate(seq)] for name, seq in sequences.items()}
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    print(f"{args.frames} frames, color {cols}x{rows}, depth {cols // args.scale}x{rows // args.scale} "
          f"(x{args.scale}), method {args.method}, {args.repeats} repeats, medians; {cores} cores; {_load()}")
    outputs = {}
    if not args.no_speed:
        outputs["depth noise 10 mm"] = speed(pairs["depth noise 10 mm"], args)
    if args.no_flicker:
        return
    with contextlib.ExitStack() as stack:
        client = _cluster(stack, 2)
        for name in sequences:
            if name not in outputs:
                outputs[name] = {temporal: _refined(pairs[name], args, client, temporal) for temporal in (False, True)}
    flicker_table(sequences, outputs)


if __name__ == "__main__":
    main()
