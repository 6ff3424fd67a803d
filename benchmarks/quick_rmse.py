"""RMSE of the thesis method and the plain baselines on the noisy Middlebury 2005 scenes.

Reads ``../shared/data/middlebury2005_park`` (or the folder given as the first
argument) and prints, per scene and scale, the RMSE against ``gt_disp.png`` (whole
grid, disparity levels) of: thesis, thesis without the histogram correction,
nearest, bilinear; then the mean per scale. This is the table in the README.

Usage::

    python benchmarks/quick_rmse.py [DATA_DIR]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

import depthrefine
from depthrefine import ThesisParams
from depthrefine.evaluate import rmse
from depthrefine.io import read_depth, read_rgb

SCENES = ("art", "books", "dolls", "laundry", "moebius")
RUNS = (
    ("thesis", "thesis", None),
    ("thesis, no correction", "thesis", ThesisParams(correct_depth=False)),
    ("nearest", "nearest", None),
    ("bilinear", "bilinear", None),
)


def main(argv: list[str]) -> int:
    default = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "middlebury2005_park"
    root = Path(argv[0]) if argv else default
    if not root.is_dir():
        print(f"data folder {root} not found; pass the middlebury2005_park folder", file=sys.stderr)
        return 2
    table: dict[tuple[str, int], list[float]] = {}
    print(f"{'scene':8s} {'x':>3s} " + " ".join(f"{name:>22s}" for name, _, _ in RUNS))
    for scene in SCENES:
        if not (root / scene).is_dir():
            continue
        rgb = read_rgb(root / scene / "color.png")
        gt = read_depth(root / scene / "gt_disp.png").astype(np.float32)
        for s in (4, 8, 16):
            depth = read_depth(root / scene / f"noisy_x{s}.png")
            row = []
            for _, method, params in RUNS:
                t0 = time.perf_counter()
                out = depthrefine.refine(depth, rgb, method=method, params=params)
                row.append((rmse(out, gt), time.perf_counter() - t0))
            table[(scene, s)] = [r for r, _ in row]
            print(f"{scene:8s} {s:3d} " + " ".join(f"{r:15.2f} ({t:4.2f}s)" for r, t in row), flush=True)
    print("mean over scenes:")
    for s in (4, 8, 16):
        rows = [v for (sc, sx), v in table.items() if sx == s]
        if rows:
            means = np.mean(rows, axis=0)
            print(f"  x{s:<3d} " + " ".join(f"{name}: {m:.2f}" for (name, _, _), m in zip(RUNS, means)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
