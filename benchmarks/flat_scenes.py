"""Every method on generated flat-colored scenes before a wall (point-sampled depth), mean RMSE.

The scenes are ``depthrefine.bench.synthetic.make_sequence``: flat-colored
objects and a moving disc before a wall, depth taken at each depth pixel's
centre (point samples, not footprint means), color noise in every frame, uint16
millimetres. They meet the thesis method's assumptions (every depth edge is a
color edge) and are the case where ``gbp`` must estimate that its input is
point-sampled (``depthrefine.methods.gbp.footprint_share``). Printed: the
mean RMSE (mm) over the frames, with the sequence's default depth noise and
without depth noise.

Usage::

    python benchmarks/flat_scenes.py [--frames 4] [--size 240x320] [--scale 4] [--seed 0] [--methods a,b]
"""

from __future__ import annotations

import argparse

import numpy as np


def main() -> None:
    import depthrefine
    from depthrefine.bench.synthetic import make_sequence
    from depthrefine.evaluate import rmse

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=4)
    parser.add_argument("--size", default="240x320", help="ROWSxCOLS of the color image")
    parser.add_argument("--scale", type=int, default=4)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--methods", default=None, help="comma-separated (default: every registered method)")
    args = parser.parse_args()
    rows, cols = (int(v) for v in args.size.lower().split("x"))
    methods = args.methods.split(",") if args.methods else list(depthrefine.METHODS)

    print(f"make_sequence({args.frames}, ({rows}, {cols}), {args.scale}, seed={args.seed}), uint16 mm, "
          "color noise 6 levels: mean RMSE (mm) over the frames")
    print(f"{'method':<10} {'depth noise':>12} {'no depth noise':>15}")
    sequences = {name: make_sequence(args.frames, (rows, cols), args.scale, seed=args.seed, **extra)
                 for name, extra in (("noisy", {}), ("clean", {"noise_std": 0.0}))}
    for method in methods:
        cells = []
        for frames in sequences.values():
            errors = [rmse(depthrefine.refine(f.depth_lr, f.rgb_hr, method=method), f.depth_hr_gt) for f in frames]
            cells.append(float(np.mean(errors)))
        print(f"{method:<10} {cells[0]:>12.1f} {cells[1]:>15.1f}")


if __name__ == "__main__":
    main()
