"""The real figures behind the ``sensor`` protocol's parameters, measured on the real ToF captures.

Prints, from ``../shared/data/real_tof`` (or ``--data``):

1. noise against distance: the standard deviation of the second difference
   ``(d[x] - (d[x-1] + d[x+1]) / 2) / sqrt(1.5)`` along rows and columns
   where it is within 50 mm (off the depth edges), per distance bin (eight
   bins of equal count), and the power law ``sigma = a * (Z / 1 m) ** p``
   fitted to the bins (least squares in logs), for the Azure Kinect mug and
   the iPhone bookshelf (``noise_mm_at_1m``, ``noise_exponent``; the integer
   millimetres make a median-based spread useless here);
2. the Azure Kinect's pixels between two surfaces: on the mug's left edge
   (mug < 320 mm, wall > 600 mm, rows 330-489), how many pixels per row lie
   between the last wall pixel and the first mug pixel, invalid or with a
   value in between (``footprint``, ``mixed_invalid``);
3. what the mug's holes are: the share of invalid pixels inside the mug's
   silhouette whose active IR is saturated (65535) or dark (< 200)
   (``dark_low`` / ``dark_high`` are not set from this capture).

::

    python benchmarks/sensor_figures.py
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
from scipy import ndimage as ndi

from depthrefine.io import read_depth


def noise_by_distance(depth: np.ndarray, bins: int = 8) -> list[tuple[float, float, float, int]]:
    """``(lo, hi, sigma, n)`` per distance bin of the second-difference residual within 50 mm (mm)."""
    d = depth.astype(np.float64)
    d[d == 0] = np.nan
    centre, resid = [], []
    for axis in (0, 1):
        c = np.take(d, np.arange(1, d.shape[axis] - 1), axis=axis)
        left = np.take(d, np.arange(0, d.shape[axis] - 2), axis=axis)
        right = np.take(d, np.arange(2, d.shape[axis]), axis=axis)
        centre.append(c.ravel())
        resid.append(((c - (left + right) / 2) / np.sqrt(1.5)).ravel())
    c, e = np.concatenate(centre), np.concatenate(resid)
    ok = np.isfinite(c) & np.isfinite(e) & (np.abs(e) < 50)
    c, e = c[ok], e[ok]
    edges = np.percentile(c, np.linspace(0, 100, bins + 1))
    out = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = e[(c >= lo) & (c < hi)]
        out.append((float(lo), float(hi), float(sel.std()), int(sel.size)))
    return out


def pixels_between(depth: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per row of the mug's left edge: (invalid, in-between) pixels between the wall and the mug."""
    invalid, mixed = [], []
    for row in depth[330:490, 40:200].astype(np.float64):
        mug = np.flatnonzero((row > 0) & (row < 320))
        if mug.size == 0:
            continue
        wall = np.flatnonzero(row[:mug[0]] > 600)
        if wall.size == 0:
            continue
        between = row[wall[-1] + 1:mug[0]]
        invalid.append(int((between == 0).sum()))
        mixed.append(int(((between >= 320) & (between <= 600)).sum()))
    return np.array(invalid), np.array(mixed)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", default=str(Path(__file__).resolve().parents[1].parent / "shared" / "data"))
    args = parser.parse_args(argv)
    real = Path(args.data) / "real_tof"
    kinect = read_depth(real / "azure_kinect_mug" / "derived" / "depth_640x576_mm.png")
    iphone = read_depth(real / "iphone_lidar_bookshelf" / "arkit_depth.png")
    for name, depth in (("Azure Kinect mug", kinect), ("iPhone bookshelf", iphone)):
        print(f"{name}: noise (std of the second difference within 50 mm) by distance")
        rows = noise_by_distance(depth)
        for lo, hi, sigma, n in rows:
            print(f"  {lo:6.0f}-{hi:6.0f} mm: {sigma:5.2f} mm ({n} samples)")
        z = np.log([(lo + hi) / 2000 for lo, hi, _, _ in rows])
        p, log_a = np.polyfit(z, np.log([sigma for _, _, sigma, _ in rows]), 1)
        print(f"  fit: sigma = {np.exp(log_a):.2f} mm * (Z / 1 m) ** {p:.2f}")
    invalid, mixed = pixels_between(kinect)
    both = invalid + mixed
    print(f"Azure Kinect, the mug's left edge ({invalid.size} rows): pixels between wall and mug per row: "
          f"{dict(zip(*np.unique(both, return_counts=True)))} (invalid {invalid.sum()}, in between {mixed.sum()})")
    ir = read_depth(real / "azure_kinect_mug" / "derived" / "ir_640x576.png")
    near = (kinect > 0) & (kinect < 400)
    mug = ndi.binary_erosion(ndi.binary_fill_holes(ndi.binary_closing(near, np.ones((9, 9)), iterations=2)),
                             np.ones((5, 5)))
    holes = mug & (kinect == 0)
    print(f"Azure Kinect, inside the mug's silhouette: {holes.sum()} of {mug.sum()} pixels invalid; of those "
          f"{(ir[holes] == 65535).mean():.0%} IR-saturated (65535), {(ir[holes] < 200).mean():.0%} with IR < 200")
    return 0


if __name__ == "__main__":
    sys.exit(main())
