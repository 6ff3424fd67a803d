"""Frames read per second from Azure Kinect recordings (demux + decode, no refinement).

Two inputs, both from the shared recording ``../shared/data/real_tof/azure_kinect_mug/recording.mkv``
(one capture: depth NFOV_UNBINNED 640x576 b16g, color MJPG 1280x720):

- the shared file itself: ``open_sequence`` (demux, pairing, calibration) and
  ``Sequence.load`` of its one frame, each repeated and timed;
- a longer recording made of the same capture repeated ``--frames`` times at
  30 fps (its packets copied with PyAV, tracks and tags as in the original):
  ``open_sequence`` once, then ``load`` of every frame in one pass.

Prints medians of ``--repeats`` runs: wall time, and the process's CPU time (what the reading
costs on a machine shared with other work). Usage::

    python benchmarks/bench_readers.py [--frames 90] [--repeats 5]
"""

from __future__ import annotations

import argparse
import statistics
import struct
import tempfile
import time
from fractions import Fraction
from pathlib import Path

SHARED = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "real_tof" / "azure_kinect_mug" / "recording.mkv"


def repeat_recording(source: Path, target: Path, frames: int, fps: int = 30) -> Path:
    """``source``'s COLOR and DEPTH packets repeated ``frames`` times, ``1/fps`` apart, with its tags and attachment."""
    import av

    src = av.open(str(source))
    out = av.open(str(target), "w", format="matroska", options={"allow_raw_vfw": "1"})
    out.metadata.update(src.metadata)
    streams, packets = {}, {}
    for s in src.streams.video:
        if s.metadata.get("title") in ("COLOR", "DEPTH"):
            streams[s.index] = out.add_stream_from_template(s)
            streams[s.index].metadata.update(s.metadata)
    for a in src.streams.attachments:
        out.add_attachment(a.name, a.mimetype, bytes(a.data))
    for p in src.demux(*[src.streams[i] for i in streams]):
        if p.size:
            packets[p.stream.index] = (bytes(p), p.stream.time_base)
    src.close()
    for i in range(frames):
        for index, (data, tb) in packets.items():
            p = av.Packet(data)
            p.stream = streams[index]
            p.time_base = tb
            p.pts = p.dts = int(Fraction(i, fps) / tb)
            out.mux(p)
    out.close()
    # FFmpeg's Matroska muxer writes raw video as a top-down Video-for-Windows track without a FOURCC;
    # the recorder's header is bottom-up-sized with FOURCC b16g (the bytes of the frames are the same).
    data = target.read_bytes()
    for s in streams.values():
        if s.codec_context.name == "rawvideo":
            w, h = s.codec_context.width, s.codec_context.height
            old = struct.pack("<IiiHHI", 40, w, -h, 1, 16, 0)
            if data.count(old) == 1:
                data = data.replace(old, struct.pack("<IiiHH", 40, w, h, 1, 16) + b"b16g")
    target.write_bytes(data)
    return target


def _time(fn) -> tuple[float, float]:
    """Wall and CPU seconds of ``fn()``."""
    t0, c0 = time.perf_counter(), time.process_time()
    fn()
    return time.perf_counter() - t0, time.process_time() - c0


def _median(runs: list[tuple[float, float]]) -> tuple[float, float]:
    return statistics.median(r[0] for r in runs), statistics.median(r[1] for r in runs)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--frames", type=int, default=90, help="frames of the repeated recording (default 90)")
    parser.add_argument("--repeats", type=int, default=5, help="timed runs; medians are printed (default 5)")
    args = parser.parse_args(argv)
    if not SHARED.is_file():
        print(f"shared recording not found: {SHARED}")
        return 2
    from depthrefine.io import open_sequence

    seq = open_sequence(SHARED)
    opens = [_time(lambda: open_sequence(SHARED)) for _ in range(args.repeats)]
    loads = [_time(lambda: list(seq.load(seq.frames))) for _ in range(args.repeats * 4)]
    print(f"{SHARED.name}: {len(seq.frames)} frame, {seq.describe()['topics']}, depth units {seq.depth_units}, "
          f"{seq.frame_rate:g} fps")
    (open_wall, open_cpu), (load_wall, load_cpu) = _median(opens), _median(loads)
    print(f"  open_sequence {open_wall * 1000:.1f} ms wall, {open_cpu * 1000:.1f} ms CPU; load of its frame "
          f"{load_wall * 1000:.1f} ms wall ({1 / load_wall:.1f} frames/s), {load_cpu * 1000:.1f} ms CPU "
          f"({1 / load_cpu:.1f} frames/s)")
    with tempfile.TemporaryDirectory() as tmp:
        long = repeat_recording(SHARED, Path(tmp) / "long.mkv", args.frames)
        opens, reads = [], []
        for _ in range(args.repeats):
            opens.append(_time(lambda: open_sequence(long)))
            seq = open_sequence(long)
            reads.append(_time(lambda: [data for _, data in seq.load(seq.frames)]))
        assert len(seq.frames) == args.frames and not seq.unpaired
        (open_wall, open_cpu), (read_wall, read_cpu) = _median(opens), _median(reads)
        print(f"repeated recording ({args.frames} frames at 30 fps, {long.stat().st_size / 1e6:.1f} MB): "
              f"open_sequence {open_wall * 1000:.1f} ms wall, {open_cpu * 1000:.1f} ms CPU; load of every frame "
              f"(depth 640x576 + MJPEG 1280x720 decoded) {read_wall:.2f} s wall = {args.frames / read_wall:.1f} "
              f"frames/s, {read_cpu:.2f} s CPU = {args.frames / read_cpu:.1f} frames/s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
