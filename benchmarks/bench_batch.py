"""Frames per second of ``depthrefine.batch.refine_many`` with 1 and 2 workers and with ``temporal``; flicker.

A generated sequence (``make_sequence``: a disc moving over a static scene,
fresh depth and color noise per frame, uint16 mm) is refined on Dask
``LocalCluster``s of 1 and 2 worker processes (one thread each), and with
``temporal=True`` (warm start, two chunks of half the frames, one per worker) on 2 workers. Each
configuration runs ``--repeats`` times on a cluster that has already refined
a warm-up batch (imports and first-call costs excluded; the cluster start is
not timed); the figures are medians. The work per frame is independent, so 2
workers should give close to 2x the frames per second of 1 on a machine with 2
free cores (the thesis method also uses threads inside a frame, which 1
worker can use too: expect less than 2x).

Flicker (``depthrefine.bench.metrics.flicker``: mean absolute frame-to-frame
change on pixels whose ground truth did not change, in mm) and the mean RMSE
against the ground truth are printed for the frames refined independently and
with ``temporal``, on the timed sequence (ToF-like depth noise of 10 mm, new
in every frame, which no warm start can remove) and on the same sequence
without depth noise (what is left is the clustering's flicker).

Usage::

    python benchmarks/bench_batch.py [--frames 48] [--size 240x320] [--scale 4] [--repeats 3] [--method thesis]
"""

from __future__ import annotations

import argparse
import logging
import statistics
import time

import numpy as np


def main() -> None:
    from distributed import Client, LocalCluster

    from depthrefine.batch import refine_many
    from depthrefine.bench.metrics import flicker, rmse
    from depthrefine.bench.synthetic import make_sequence

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--frames", type=int, default=48)
    ap.add_argument("--size", default="240x320", help="color image ROWSxCOLS (default 240x320)")
    ap.add_argument("--scale", type=int, default=4)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--method", default="thesis")
    args = ap.parse_args()
    rows, cols = (int(v) for v in args.size.lower().split("x"))
    seq = make_sequence(args.frames, (rows, cols), args.scale, seed=3, color_noise_std=8.0)
    pairs = [(i, f.depth_lr, f.rgb_hr) for i, f in enumerate(seq)]
    gts = [f.depth_hr_gt for f in seq]
    print(f"{args.frames} frames, color {cols}x{rows}, depth {cols // args.scale}x{rows // args.scale} "
          f"(x{args.scale}), method {args.method}, {args.repeats} repeats, medians")

    chunk = (args.frames + 1) // 2
    results: dict[str, tuple[float, list]] = {}
    for label, workers, temporal in (("1 worker", 1, False), ("2 workers", 2, False),
                                     ("2 workers --temporal", 2, True)):
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                          dashboard_address=":0", silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
            list(refine_many(pairs[:2 * workers], method=args.method, client=client))  # warm-up
            times, outputs = [], None
            for _ in range(args.repeats):
                start = time.perf_counter()
                outputs = [d for _, d in refine_many(pairs, method=args.method, client=client, temporal=temporal,
                                                     chunk=chunk)]
                times.append(time.perf_counter() - start)
        fps = args.frames / statistics.median(times)
        results[label] = (fps, outputs)
        print(f"  {label:22s} {fps:7.2f} frames/s   (runs: {', '.join(f'{args.frames / t:.2f}' for t in times)})",
              flush=True)
    one, two = results["1 worker"][0], results["2 workers"][0]
    print(f"  2 workers / 1 worker: {two / one:.2f}x;  temporal / independent (2 workers): "
          f"{results['2 workers --temporal'][0] / two:.2f}x")
    quiet = make_sequence(args.frames, (rows, cols), args.scale, seed=3, color_noise_std=8.0, noise_std=0.0)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=":0",
                      silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
        quiet_pairs = [(i, f.depth_lr, f.rgb_hr) for i, f in enumerate(quiet)]
        quiet_out = {temporal: [d for _, d in refine_many(quiet_pairs, method=args.method, client=client,
                                                          temporal=temporal, chunk=chunk)]
                     for temporal in (False, True)}
    rows_out = [("depth noise 10 mm", gts, {False: results["2 workers"][1], True: results["2 workers --temporal"][1]}),
                ("no depth noise", [f.depth_hr_gt for f in quiet], quiet_out)]
    for name, truth, outs in rows_out:
        for temporal in (False, True):
            mean_rmse = float(np.mean([rmse(o, g) for o, g in zip(outs[temporal], truth)]))
            print(f"  {name:18s} {'temporal' if temporal else 'independent':12s} flicker "
                  f"{flicker(outs[temporal], truth):7.3f} mm   mean RMSE {mean_rmse:7.2f} mm")


if __name__ == "__main__":
    main()
