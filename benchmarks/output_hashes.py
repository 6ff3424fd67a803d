"""SHA-256 of every deterministic method's output on the demo scenes and benchmark cases.

A refactoring that must not change results is checked by running this before
and after it and comparing the two files::

    python benchmarks/output_hashes.py -o before.json          # on the old commit
    python benchmarks/output_hashes.py -o after.json           # on the new one
    python benchmarks/output_hashes.py --compare before.json after.json

Inputs: the bundled registered scenes (Art x4/x8/x16, the iPhone bookshelf), up to ``--scenes`` test scenes of each benchmark protocol at each
of its scales (from ``../shared/data`` or ``--data``), and generated scenes
with holes and noise. Methods: every registered method whose output is
deterministic (``Method.deterministic``), each with its defaults, plus the
warm start of the methods that have one over a short generated sequence.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
import time
from pathlib import Path

import numpy as np


def _digest(array: np.ndarray) -> str:
    array = np.ascontiguousarray(array)
    return hashlib.sha256(str(array.dtype).encode() + str(array.shape).encode() + array.tobytes()).hexdigest()


def _inputs(data: Path | None, per_protocol: int):
    from depthrefine.bench.protocols import PROTOCOLS, load_cases
    from depthrefine.bench.synthetic import make_scene
    from depthrefine.io import InputFileError, read_depth, read_rgb
    from depthrefine.io._sample import sample_folder

    art = sample_folder("art")
    for scale in (4, 8, 16):
        yield f"art x{scale}", read_depth(art / f"noisy_x{scale}.png"), read_rgb(art / "color.png")
    for scene in ("bookshelf",):
        yield scene, read_depth(sample_folder(scene) / "depth.png"), read_rgb(sample_folder(scene) / "color.jpg")
    for seed, scale in ((1, 4), (2, 8)):
        scene = make_scene((96, 128), scale, n_objects=3, seed=seed, color_noise_std=4.0, noise_std=2.0,
                           hole_fraction=0.05)
        yield f"synthetic seed {seed} x{scale}", scene.depth_lr, scene.rgb_hr
    if data is None or not data.is_dir():
        print(f"no benchmark data at {data}: only the bundled and generated inputs", file=sys.stderr)
        return
    for name in PROTOCOLS:
        scales = (4, 8) if name == "realtof" else (4, 8, 16)
        try:
            cases = load_cases(data, name, scales)
        except (InputFileError, ValueError, OSError) as exc:
            print(f"{name}: skipped ({exc})", file=sys.stderr)
            continue
        for scale in scales:
            chosen = [c for c in cases if c.scale == scale and c.split == "test"][:per_protocol]
            for case in chosen:
                yield f"{name} {case.scene} x{scale}", case.depth_lr, case.rgb_hr


def compute(data: Path | None, per_protocol: int, methods: list[str] | None) -> dict[str, str]:
    import depthrefine
    from depthrefine.bench.synthetic import make_sequence

    entries = [m for m in depthrefine.METHODS.values() if m.deterministic and (methods is None or m.name in methods)]
    hashes: dict[str, str] = {}
    for label, depth_lr, rgb_hr in _inputs(data, per_protocol):
        t0 = time.perf_counter()
        for entry in entries:
            hashes[f"{entry.name} | {label}"] = _digest(depthrefine.refine(depth_lr, rgb_hr, method=entry.name))
        print(f"{label}: {len(entries)} methods, {time.perf_counter() - t0:.1f} s", file=sys.stderr, flush=True)
    frames = make_sequence(4, (96, 128), 4, seed=0)
    for entry in entries:
        if entry.refine_stateful is None:
            continue
        state = None
        for i, frame in enumerate(frames):
            out, state = entry.refine_stateful(frame.depth_lr, frame.rgb_hr, params=None, state=state)
            hashes[f"{entry.name} warm | sequence frame {i}"] = _digest(out)
    return hashes


def main(argv: list[str] | None = None) -> int:
    default = Path(__file__).resolve().parents[1].parent / "shared" / "data"
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument("-o", "--output", help="write the hashes to this JSON file")
    parser.add_argument("--data", type=Path, default=default, help="benchmark data folder")
    parser.add_argument("--scenes", type=int, default=2, help="test scenes per protocol and scale")
    parser.add_argument("--methods", help="comma-separated method names (default: every deterministic one)")
    parser.add_argument("--compare", nargs=2, metavar=("BEFORE", "AFTER"), help="compare two hash files and exit")
    args = parser.parse_args(argv)
    if args.compare:
        before, after = (json.loads(Path(p).read_text()) for p in args.compare)
        common = sorted(set(before) & set(after))
        changed = [k for k in common if before[k] != after[k]]
        for key in changed:
            print(f"changed: {key}")
        methods = sorted({k.split(" | ")[0] for k in common})
        inputs = {k.split(" | ")[1] for k in common}
        print(f"{len(common) - len(changed)} of {len(common)} hashes equal ({len(inputs)} inputs, methods "
              f"{', '.join(methods)}); only before: {len(set(before) - set(after))}, only after: "
              f"{len(set(after) - set(before))}")
        return 1 if changed else 0
    hashes = compute(args.data, args.scenes, args.methods.split(",") if args.methods else None)
    text = json.dumps(hashes, indent=1, sort_keys=True) + "\n"
    if args.output:
        Path(args.output).write_text(text)
        print(f"wrote {len(hashes)} hashes to {args.output}", file=sys.stderr)
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
