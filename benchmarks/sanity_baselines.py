"""The protocols against the data READMEs' plain-bicubic sanity numbers (docs/bench.md).

PIL bicubic upsampling of each protocol's input, scored as the protocol
scores: Park (per scene, x4 / x8 / x16, whole grid), and the mean over the
28 shared ``middlebury_lu30`` images without and with the protocol's 6-px
border crop; then OpenCV's ``INTER_CUBIC`` (our ``bicubic`` method) on Park
x4 for Art, Books, Moebius, beside PIL's.

Usage::

    python benchmarks/sanity_baselines.py [DATA_DIR]      # default ../shared/data
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image


def pil_bicubic_up(depth_lr: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    img = Image.fromarray(np.asarray(depth_lr, np.float32))
    return np.asarray(img.resize((shape[1], shape[0]), Image.BICUBIC), np.float64)


def main() -> None:
    from depthrefine.bench import load_cases
    from depthrefine.evaluate import score
    from depthrefine.methods.baselines import upsample_bicubic

    data = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[2] / "shared" / "data"
    park = load_cases(data / "middlebury2005_park", "park", (4, 8, 16))
    print("park, PIL bicubic (README sanity rows): RMSE x4 / x8 / x16")
    for scene in sorted({c.scene for c in park}):
        cells = [score(pil_bicubic_up(c.depth_lr, c.depth_gt.shape), c.depth_gt).rmse
                 for s in (4, 8, 16) for c in park if c.scene == scene and c.scale == s]
        print(f"  {scene:<8} " + " / ".join(f"{v:.2f}" for v in cells))
    print("park x4, OpenCV INTER_CUBIC (our bicubic) / PIL bicubic")
    for scene in ("art", "books", "moebius"):
        case = next(c for c in park if c.scene == scene and c.scale == 4)
        ours = score(upsample_bicubic(case.depth_lr, case.rgb_hr), case.depth_gt).rmse
        pil = score(pil_bicubic_up(case.depth_lr, case.depth_gt.shape), case.depth_gt).rmse
        print(f"  {scene:<8} {ours:.2f} / {pil:.2f}")
    cases = load_cases(data, "middlebury30", (4, 8, 16))
    print(f"middlebury30, {len({c.scene for c in cases})} images, PIL bicubic: mean RMSE x4 / x8 / x16")
    for border, label in ((0, "no crop"), (None, "the protocol's 6-px crop")):
        means = []
        for s in (4, 8, 16):
            mine = [c for c in cases if c.scale == s]
            means.append(np.mean([score(pil_bicubic_up(c.depth_lr, c.depth_gt.shape), c.depth_gt,
                                        border=c.border if border is None else border).rmse for c in mine]))
        print(f"  {label:<24} " + " / ".join(f"{v:.4f}" for v in means))


if __name__ == "__main__":
    main()
