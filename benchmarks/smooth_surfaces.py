"""Do no harm on smooth curved surfaces: methods against bicubic on generated smooth depth with a featureless guide.

A smooth surface (a wave, a bowl, a sphere before a wall) of 192x256 color
pixels, block means x4 and x8 as the depth input, and a guide without depth
edges: one flat gray, or gray with +-10 levels of pixel noise. There is
nothing for a guide to add, so a method is measured by how far it stays at
bicubic's RMSE. Printed per case: the RMSE of each method (depth units, the
wave's amplitude is 300) and gbp's measures of the input: the noise from the
Haar band that every step uses (``measure.estimate_noise``), the noise from
the fourth-order band of its fallback (``measure.noise_levels``), both in
levels of the depth range, and the share of input pixels its jump map marks.

Usage::

    python benchmarks/smooth_surfaces.py [--methods bicubic,gbp,gbp-fast]
"""

from __future__ import annotations

import argparse

import numpy as np

#: The color grid of every case (rows, columns).
SHAPE = (192, 256)


def surfaces() -> dict[str, np.ndarray]:
    """The smooth depth maps on the color grid, float32."""
    rows, cols = SHAPE
    y, x = np.mgrid[:rows, :cols].astype(np.float64)
    radius = 150.0
    return {
        "wave": 1000 + 300 * np.sin(x / 15) * np.cos(y / 19),
        "bowl": 1000 + 0.02 * ((x - cols / 2) ** 2 + (y - rows / 2) ** 2),
        "sphere": 1200 - np.sqrt(np.maximum(radius ** 2 - (x - cols / 2) ** 2 - (y - rows / 2) ** 2, 0.0)),
    }


def guides(seed: int = 0) -> dict[str, np.ndarray]:
    """The featureless guides, (rows, cols, 3) uint8."""
    rng = np.random.default_rng(seed)
    return {"flat": np.full((*SHAPE, 3), 100, np.uint8),
            "noisy": rng.integers(90, 111, (*SHAPE, 3)).astype(np.uint8)}


def main() -> None:
    import cv2

    import depthrefine
    from depthrefine.evaluate import rmse
    from depthrefine.methods.gbp import measure

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--methods", default="bicubic,gbp,gbp-fast", help="comma-separated registered methods")
    args = parser.parse_args()
    methods = args.methods.split(",")
    print(f"{'surface':<8} {'guide':<6} {'scale':>5} " + " ".join(f"{m:>9}" for m in methods)
          + f" {'haar':>6} {'fourth':>6} {'jump':>5}")
    for surface, truth in surfaces().items():
        truth = truth.astype(np.float32)
        for guide_name, guide in guides().items():
            for s in (4, 8):
                depth_lr = cv2.resize(truth, (SHAPE[1] // s, SHAPE[0] // s), interpolation=cv2.INTER_AREA)
                scores = [rmse(depthrefine.refine(depth_lr, guide, method=m), truth) for m in methods]
                m = measure.measure_input(depth_lr, guide)
                print(f"{surface:<8} {guide_name:<6} {'x' + str(s):>5} " + " ".join(f"{v:>9.2f}" for v in scores)
                      + f" {m.sigma_levels:>6.2f} {measure.noise_levels(m):>6.2f} {float(np.mean(m.jump > 0)):>5.2f}")


if __name__ == "__main__":
    main()
