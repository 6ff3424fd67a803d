"""gbp's step 1b on the benchmark inputs: the measured edge offset and shift of each case, and where each acts.

For every case of the protocols given, prints the offset of the color edges
from the input's depth jumps (``depthrefine.methods.gbp.fattening.edge_offset``,
depth pixels, positive when the larger values spill over the smaller) and
whether it reaches ``FATTEN_MIN`` (step 1b thins the input there); then, per
protocol, the largest offset of the cases it leaves alone and how many it
thins. A registered input must stay below the threshold (its output is then
bit-identical to gbp without step 1b); the ``sensor`` protocol's direct-ToF
cases should reach it. The column ``check`` gives the verdict of step 1b's cheap
check (``fattening.check_skips``: ``clearly_unfattened`` on the guide reduced
by ``work_shape``): ``skip`` where it spares the full measure; a case it
skips that the full measure would thin is counted as a miss (there should be
none: the output would differ from the full measure's). Beside it, the shift of the whole map from the color
edges (``fattening.edge_shift``, depth pixels, (dy, dx)) and whether it reaches
``SHIFT_MIN``: step 1b moves the input back by it only when the input is
reprojected (the ``sensor`` protocol's cases, ``run``'s); on the registered
protocols it shows what the measure reads where there is no shift::

    python benchmarks/edge_offsets.py                       # every protocol
    python benchmarks/edge_offsets.py --protocols sensor    # one
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path


def main(argv: list[str] | None = None) -> int:
    from depthrefine._validate import as_depth, check_rgb, guide_uint8
    from depthrefine.bench.protocols import load_cases
    from depthrefine.methods.gbp.fattening import (FATTEN_MIN, SHIFT_MIN, check_skips, edge_offset, edge_shift,
                                                   sector_medians)
    from depthrefine.methods.gbp.measure import measure_input

    default = Path(__file__).resolve().parents[1].parent / "shared" / "data"
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", type=Path, default=default, help="benchmark data folder (default: ../shared/data)")
    parser.add_argument("--protocols", default="park,middlebury30,lu,tof,realtof,sensor",
                        help="comma-separated protocols (default: all)")
    args = parser.parse_args(argv)
    for protocol in args.protocols.split(","):
        scales = (4, 8) if protocol == "realtof" else (4, 8, 16)
        left, thinned, shifts, skipped, missed = 0.0, [], [], 0, 0
        for case in load_cases(args.data, protocol, scales):
            guide = guide_uint8(check_rgb(case.rgb_hr))
            m = measure_input(as_depth(case.depth_lr), guide)
            medians = sector_medians(m, guide)
            offset = edge_offset(m, guide, medians)
            dy, dx = edge_shift(m, guide, medians)
            applied = abs(offset) >= FATTEN_MIN
            skip = check_skips(m, guide)
            skipped += skip
            missed += skip and applied
            if applied:
                thinned.append(f"{case.scene} x{case.scale}")
            else:
                left = max(left, abs(offset))
            shifts.append(math.hypot(dy, dx))
            print(f"{protocol:12s} {case.scene:16s} x{case.scale:<3d} {offset:+.3f}{'  thinned' if applied else '':9s}"
                  f" check {'skip' if skip else 'full'}{'  MISSED' if skip and applied else ''}"
                  f" shift ({dy:+.2f}, {dx:+.2f}){'  moved if reprojected' if shifts[-1] >= SHIFT_MIN else ''}",
                  flush=True)
        print(f"{protocol}: thinned {len(thinned)} case(s); largest |offset| left alone {left:.3f} "
              f"(threshold {FATTEN_MIN}); shift >= {SHIFT_MIN} in {sum(v >= SHIFT_MIN for v in shifts)} of "
              f"{len(shifts)} case(s), largest {max(shifts, default=0.0):.2f}; the check skips {skipped} case(s), "
              f"{missed} of them the full measure would thin", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
