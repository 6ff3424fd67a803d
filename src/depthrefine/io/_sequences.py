"""Sequences of depth + color frames: a folder, a CSV manifest or a ROS bag.

:func:`open_sequence` finds and pairs the frames of an input without
decoding any image; :meth:`Sequence.load` then decodes them one after the
other, in order, as the batch needs them.

- **Folder**: ``depth/`` and ``color/`` subfolders whose files pair by stem
  (``depth/000123.png`` with ``color/000123.jpg``). Stems sort in natural
  order (``2`` before ``10``).
- **Manifest**: a CSV file with columns ``depth,color`` (a header row; paths
  relative to the manifest's folder, or absolute). Rows keep their order.
- **ROS bag**: a ROS 1 ``.bag`` file, or a ROS 2 bag (a folder with
  ``metadata.yaml`` and ``.db3`` or ``.mcap`` files, or one such file), read
  with the pure-Python ``rosbags`` package. Depth and color topics hold
  ``sensor_msgs/Image`` (depth ``16UC1``/``mono16`` in millimetres or
  ``32FC1`` in metres, as ROS REP 118 defines them; color ``rgb8``,
  ``bgr8``, ``rgba8``, ``bgra8``, ``mono8`` and their 16-bit forms) or
  ``sensor_msgs/CompressedImage`` (JPEG or PNG). Each depth frame pairs with
  the color frame nearest in time (header stamps; the recording time when a
  stamp is 0) within ``max_dt``; each color frame is used once, closest
  pairs first. The output stem is the depth frame's time in nanoseconds.

Every frame's output keeps the depth's dtype: the depth file's own format
for folders and manifests, ``.png`` for 8/16-bit and ``.tif`` for float
depth from bags. A depth frame without a partner is reported as a failed
frame (:attr:`Frame.problem`); extra color frames are listed in
:attr:`Sequence.notes`.
"""

from __future__ import annotations

import csv
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Iterator

import numpy as np

from .._validate import check_rgb
from ._files import InputFileError
from ._images import DEPTH_SUFFIXES, read_depth, read_rgb
from ._names import DEFAULT_MAX_DT

__all__ = ["Frame", "Sequence", "open_sequence", "COLOR_SUFFIXES"]

#: Color file extensions a folder's ``color/`` may hold.
COLOR_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".npy", ".ppm", ".webp")


@dataclass(frozen=True)
class Frame:
    """One depth + color pair of a sequence.

    Attributes
    ----------
    key : str
        The output stem (file stem, or the depth time in ns for bags).
    depth, color : str
        Where the images come from, for messages and ``batch.json``.
    suffix : str
        Extension of the output file (keeps the depth's dtype).
    problem : str or None
        Why the frame cannot be processed (no partner), else ``None``.
    """

    key: str
    depth: str
    color: str
    suffix: str
    problem: str | None = None
    depth_ref: Any = field(default=None, repr=False, compare=False)
    color_ref: Any = field(default=None, repr=False, compare=False)


@dataclass
class Sequence:
    """The paired frames of one input (see :func:`open_sequence`)."""

    source: Path
    kind: str  # "folder", "manifest", "ros1", "ros2"
    frames: list[Frame]
    notes: list[str] = field(default_factory=list)
    topics: dict[str, str] = field(default_factory=dict)
    folders: tuple[Path, ...] = ()  # folders the input lives in (an output folder may not be inside)

    def describe(self) -> dict[str, Any]:
        """JSON-ready description for ``batch.json``."""
        out: dict[str, Any] = {"path": str(self.source), "kind": self.kind, "frames": len(self.frames)}
        if self.topics:
            out["topics"] = dict(self.topics)
        if self.notes:
            out["notes"] = list(self.notes)
        return out

    def load(self, frames: Iterable[Frame], *, saturated_invalid: bool = False
             ) -> Iterator[tuple[Frame, tuple[np.ndarray, np.ndarray] | InputFileError]]:
        """Decode ``frames`` (in the order given): yield ``(frame, (depth_lr, rgb_hr))``.

        A frame that cannot be read yields ``(frame, InputFileError)``
        instead; the others go on. Bags are read in one pass in recording
        order, so ``frames`` must keep the sequence's order.
        """
        frames = list(frames)
        if self.kind in ("ros1", "ros2"):
            yield from _load_bag(self, frames)
            return
        for frame in frames:
            if frame.problem is not None:
                yield frame, InputFileError(frame.problem)
                continue
            try:
                depth = read_depth(frame.depth_ref, saturated_invalid=saturated_invalid)
                rgb = read_rgb(frame.color_ref)
            except InputFileError as exc:
                yield frame, exc
                continue
            yield frame, (depth, rgb)


def open_sequence(
    path: str | os.PathLike,
    *,
    depth_topic: str | None = None,
    color_topic: str | None = None,
    max_dt: float = DEFAULT_MAX_DT,
) -> Sequence:
    """Find and pair the frames of a folder, CSV manifest or ROS bag (no decoding).

    Raises
    ------
    InputFileError
        A missing or empty input, a folder without ``depth/`` and ``color/``,
        a manifest without ``depth`` and ``color`` columns, two frames with
        the same output stem, a bag without the topics (the message lists the
        bag's topics), or topics given for a non-bag input.
    """
    p = Path(path)
    if not p.exists():
        raise InputFileError(f"input {p} does not exist; give a folder with depth/ and color/, a CSV manifest "
                             "or a ROS bag.")
    bag = _bag_kind(p)
    if bag is None and (depth_topic or color_topic):
        raise InputFileError(f"input {p} is not a ROS bag; --depth-topic and --color-topic are for bags only.")
    if bag is not None:
        if not depth_topic or not color_topic:
            raise InputFileError(f"input {p} is a ROS bag; give --depth-topic and --color-topic "
                                 f"(its topics: {_topic_list(p)}).")
        if not (max_dt >= 0):
            raise InputFileError(f"--max-dt must be >= 0 seconds; got {max_dt}.")
        return _open_bag(p, bag, depth_topic, color_topic, max_dt)
    if p.is_dir():
        return _open_folder(p)
    if p.suffix.lower() == ".csv":
        return _open_manifest(p)
    raise InputFileError(f"input {p} is neither a folder with depth/ and color/, a .csv manifest nor a ROS bag "
                         "(.bag, or a ROS 2 bag folder with metadata.yaml).")


# ----------------------------------------------------------------------------
# folders and manifests
# ----------------------------------------------------------------------------


def _natural_key(text: str) -> list:
    return [(0, int(part), "") if part.isdigit() else (1, 0, part) for part in re.split(r"(\d+)", text) if part]


def _stems(folder: Path, suffixes: tuple[str, ...], what: str) -> dict[str, Path]:
    found: dict[str, Path] = {}
    for item in folder.iterdir():
        if item.name.startswith(".") or not item.is_file() or item.suffix.lower() not in suffixes:
            continue
        if item.stem in found:
            raise InputFileError(f"{what} files {found[item.stem].name} and {item.name} in {folder} have the same "
                                 "stem; keep one of them.")
        found[item.stem] = item
    return found


def _open_folder(p: Path) -> Sequence:
    depth_dir, color_dir = p / "depth", p / "color"
    for sub in (depth_dir, color_dir):
        if not sub.is_dir():
            raise InputFileError(f"input folder {p} has no {sub.name}/ subfolder; a batch folder holds depth/ and "
                                 "color/ with files paired by stem (depth/000123.png, color/000123.jpg).")
    depth = _stems(depth_dir, DEPTH_SUFFIXES, "depth")
    color = _stems(color_dir, COLOR_SUFFIXES, "color")
    if not depth:
        raise InputFileError(f"input folder {depth_dir} holds no depth files ({', '.join(DEPTH_SUFFIXES)}); "
                             "nothing to refine.")
    frames = []
    for stem in sorted(depth, key=_natural_key):
        d = depth[stem]
        c = color.get(stem)
        problem = None if c is not None else f"depth file {d} has no color file of stem {stem!r} in {color_dir}"
        frames.append(Frame(stem, str(d), str(c) if c else "", d.suffix.lower(), problem, d, c))
    extra = sorted(set(color) - set(depth), key=_natural_key)
    notes = [_extra_note(len(extra), "color file", "no depth file of the same stem", extra)] if extra else []
    return Sequence(p, "folder", frames, notes, folders=(p,))


def _open_manifest(p: Path) -> Sequence:
    try:
        with open(p, newline="", encoding="utf-8-sig") as fh:
            rows = list(csv.reader(fh))
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise InputFileError(f"manifest {p} cannot be read ({exc}); give a CSV file with columns depth,color.") from None
    rows = [r for r in rows if any(cell.strip() for cell in r)]
    if not rows:
        raise InputFileError(f"manifest {p} is empty; give a CSV file with a header depth,color and one row per frame.")
    header = [cell.strip().lower() for cell in rows[0]]
    if "depth" not in header or "color" not in header:
        raise InputFileError(f"manifest {p}: the first row must name the columns depth and color; got "
                             f"{','.join(rows[0])!r}.")
    di, ci = header.index("depth"), header.index("color")
    if len(rows) == 1:
        raise InputFileError(f"manifest {p} lists no frames; add one row depth,color per frame.")
    base = p.parent
    frames, seen = [], {}
    for line, row in enumerate(rows[1:], start=2):
        if len(row) <= max(di, ci) or not row[di].strip() or not row[ci].strip():
            raise InputFileError(f"manifest {p}, row {line}: needs a depth and a color path; got {','.join(row)!r}.")
        d, c = base / row[di].strip(), base / row[ci].strip()
        if d.suffix.lower() not in DEPTH_SUFFIXES:
            raise InputFileError(f"manifest {p}, row {line}: depth file {d.name} is not one of "
                                 f"{', '.join(DEPTH_SUFFIXES)}.")
        if d.stem in seen:
            raise InputFileError(f"manifest {p}: rows {seen[d.stem]} and {line} both have depth stem {d.stem!r}, "
                                 "which names the output; rename one of them.")
        seen[d.stem] = line
        frames.append(Frame(d.stem, str(d), str(c), d.suffix.lower(), None, d, c))
    folders = tuple(dict.fromkeys(Path(f.depth_ref).parent for f in frames)) + tuple(
        dict.fromkeys(Path(f.color_ref).parent for f in frames))
    return Sequence(p, "manifest", frames, folders=folders)


def _extra_note(n: int, what: str, why: str, names: list) -> str:
    shown = ", ".join(str(x) for x in names[:5]) + (", ..." if n > 5 else "")
    return f"{n} {what}(s) with {why}, not used: {shown}"


# ----------------------------------------------------------------------------
# ROS bags
# ----------------------------------------------------------------------------


def _bag_kind(p: Path) -> str | None:
    if p.is_file() and p.suffix.lower() == ".bag":
        return "ros1"
    if p.is_dir() and (p / "metadata.yaml").is_file():
        return "ros2"
    if p.is_file() and p.suffix.lower() in (".db3", ".mcap"):
        return "ros2"
    return None


def _reader(p: Path):
    try:
        from rosbags.highlevel import AnyReader
        from rosbags.typesys import Stores, get_typestore
    except ImportError:  # pragma: no cover - a dependency
        raise InputFileError("reading ROS bags needs the rosbags package: pip install rosbags") from None
    target = p.parent if p.is_file() and p.suffix.lower() in (".db3", ".mcap") else p
    return AnyReader([target], default_typestore=get_typestore(Stores.LATEST))


def _topic_list(p: Path) -> str:
    try:
        with _reader(p) as reader:
            topics = {c.topic: c.msgtype for c in reader.connections}
    except Exception as exc:  # noqa: BLE001 - any failure of the bag reader is a bad bag
        raise InputFileError(f"ROS bag {p} cannot be read ({type(exc).__name__}: {exc}).") from None
    return ", ".join(f"{t} ({m})" for t, m in sorted(topics.items())) or "none"


_IMAGE = "sensor_msgs/msg/Image"
_COMPRESSED = "sensor_msgs/msg/CompressedImage"


def _stamp(msg, logtime: int) -> int:
    header = getattr(msg, "header", None)
    if header is not None:
        ns = int(header.stamp.sec) * 1_000_000_000 + int(header.stamp.nanosec)
        if ns > 0:
            return ns
    return int(logtime)


def _open_bag(p: Path, kind: str, depth_topic: str, color_topic: str, max_dt: float) -> Sequence:
    try:
        reader_cm = _reader(p)
        with reader_cm as reader:
            topics = {c.topic: c.msgtype for c in reader.connections}
            for name, topic in (("--depth-topic", depth_topic), ("--color-topic", color_topic)):
                if topic not in topics:
                    listed = ", ".join(f"{t} ({m})" for t, m in sorted(topics.items())) or "none"
                    raise InputFileError(f"ROS bag {p} has no topic {topic!r} ({name}); its topics: {listed}.")
                if topics[topic] not in (_IMAGE, _COMPRESSED):
                    raise InputFileError(f"ROS bag {p}: topic {topic} holds {topics[topic]}; {name} needs "
                                         "sensor_msgs/Image or sensor_msgs/CompressedImage.")
            conns = [c for c in reader.connections if c.topic in (depth_topic, color_topic)]
            stamps: dict[str, list[tuple[int, int]]] = {depth_topic: [], color_topic: []}
            counters = {depth_topic: 0, color_topic: 0}
            encodings: dict[str, str] = {}
            for conn, logtime, raw in reader.messages(connections=conns):
                msg = reader.deserialize(raw, conn.msgtype)
                index = counters[conn.topic]
                counters[conn.topic] += 1
                stamps[conn.topic].append((_stamp(msg, logtime), index))
                if conn.topic == depth_topic and depth_topic not in encodings:
                    encodings[depth_topic] = getattr(msg, "encoding", None) or getattr(msg, "format", "")
    except InputFileError:
        raise
    except Exception as exc:  # noqa: BLE001 - any failure of the bag reader is a bad bag
        raise InputFileError(f"ROS bag {p} cannot be read ({type(exc).__name__}: {exc}).") from None
    if not stamps[depth_topic]:
        raise InputFileError(f"ROS bag {p}: topic {depth_topic} holds no messages; nothing to refine.")
    suffix = ".tif" if encodings.get(depth_topic, "").lower() in ("32fc1", "64fc1") else ".png"
    depth_st = sorted(stamps[depth_topic])
    color_st = sorted(stamps[color_topic])
    pairs = _pair_nearest([t for t, _ in depth_st], [t for t, _ in color_st], int(round(max_dt * 1e9)))
    frames = []
    for i, (t, index) in enumerate(depth_st):
        where = f"{depth_topic} @ {t}"
        j = pairs.get(i)
        if j is None:
            frames.append(Frame(str(t), where, "", suffix,
                                f"depth frame {where} ns has no color frame on {color_topic} within "
                                f"{max_dt * 1000:g} ms (raise --max-dt to pair it)", (depth_topic, index), None))
        else:
            tc, cindex = color_st[j]
            frames.append(Frame(str(t), where, f"{color_topic} @ {tc}", suffix, None,
                                (depth_topic, index), (color_topic, cindex)))
    keys = [f.key for f in frames]
    if len(set(keys)) != len(keys):
        raise InputFileError(f"ROS bag {p}: two depth frames on {depth_topic} have the same time stamp; "
                             "their outputs would collide.")
    used = set(pairs.values())
    extra = [color_st[j][0] for j in range(len(color_st)) if j not in used]
    notes = [_extra_note(len(extra), f"color frame on {color_topic}", "no depth frame within "
                         f"{max_dt * 1000:g} ms", extra)] if extra else []
    return Sequence(p, kind, frames, notes, topics={"depth": depth_topic, "color": color_topic},
                    folders=(p,) if p.is_dir() else ())


def _pair_nearest(depth_t: list[int], color_t: list[int], max_ns: int) -> dict[int, int]:
    """One color frame per depth frame, nearest in time within ``max_ns``; closest pairs first.

    Examples
    --------
    >>> _pair_nearest([0, 100, 200], [5, 98, 400], 10)
    {1: 1, 0: 0}
    """
    ct = np.asarray(color_t, dtype=np.int64)
    candidates = []
    for i, t in enumerate(depth_t):
        lo, hi = np.searchsorted(ct, t - max_ns, "left"), np.searchsorted(ct, t + max_ns, "right")
        candidates.extend((abs(int(ct[j]) - t), i, int(j)) for j in range(lo, hi))
    candidates.sort()
    pairs: dict[int, int] = {}
    taken: set[int] = set()
    for _, i, j in candidates:
        if i not in pairs and j not in taken:
            pairs[i] = j
            taken.add(j)
    return pairs


def _load_bag(seq: Sequence, frames: list[Frame]):
    """Decode ``frames`` in one pass over the bag; yield them in the order given."""
    want: dict[tuple[str, int], list[tuple[int, str]]] = {}
    for n, frame in enumerate(frames):
        if frame.problem is None:
            want.setdefault(frame.depth_ref, []).append((n, "depth"))
            want.setdefault(frame.color_ref, []).append((n, "color"))
    parts: dict[int, dict[str, Any]] = {}
    next_out = 0

    def ready():
        nonlocal next_out
        while next_out < len(frames):
            frame = frames[next_out]
            if frame.problem is not None:
                yield frame, InputFileError(frame.problem)
            else:
                got = parts.get(next_out, {})
                if len(got) < 2:
                    return
                del parts[next_out]
                bad = next((v for v in (got["depth"], got["color"]) if isinstance(v, InputFileError)), None)
                yield frame, bad if bad is not None else (got["depth"], got["color"])
            next_out += 1

    yield from ready()
    if want:
        topics = (seq.topics["depth"], seq.topics["color"])
        counters = dict.fromkeys(topics, 0)
        try:
            with _reader(seq.source) as reader:
                conns = [c for c in reader.connections if c.topic in topics]
                for conn, logtime, raw in reader.messages(connections=conns):
                    ref = (conn.topic, counters[conn.topic])
                    counters[conn.topic] += 1
                    users = want.pop(ref, None)
                    if not users:
                        continue
                    for n, role in users:
                        where = frames[n].depth if role == "depth" else frames[n].color
                        try:
                            msg = reader.deserialize(raw, conn.msgtype)
                            value = _decode_depth(msg, where) if role == "depth" else _decode_color(msg, where)
                        except InputFileError as exc:
                            value = exc
                        except Exception as exc:  # noqa: BLE001 - a message that does not decode is bad input
                            value = InputFileError(f"{role} frame {where} cannot be decoded "
                                                   f"({type(exc).__name__}: {exc}).")
                        parts.setdefault(n, {})[role] = value
                    yield from ready()
                    if not want:
                        break
        except InputFileError:
            raise
        except Exception as exc:  # noqa: BLE001 - the bag broke while reading
            raise InputFileError(f"ROS bag {seq.source} cannot be read ({type(exc).__name__}: {exc}).") from None
    for n, frame in enumerate(frames[next_out:], start=next_out):  # messages the bag did not deliver
        for role in ("depth", "color"):
            parts.setdefault(n, {}).setdefault(role, InputFileError(f"{role} frame of {frame.key} is missing "
                                                                    f"from ROS bag {seq.source}."))
    yield from ready()


# sensor_msgs/Image encodings: (dtype, channels, BGR order)
_ENCODINGS = {
    "16uc1": (np.uint16, 1, False), "mono16": (np.uint16, 1, False), "32fc1": (np.float32, 1, False),
    "64fc1": (np.float64, 1, False), "8uc1": (np.uint8, 1, False), "mono8": (np.uint8, 1, False),
    "rgb8": (np.uint8, 3, False), "bgr8": (np.uint8, 3, True), "rgba8": (np.uint8, 4, False),
    "bgra8": (np.uint8, 4, True), "rgb16": (np.uint16, 3, False), "bgr16": (np.uint16, 3, True),
    "rgba16": (np.uint16, 4, False), "bgra16": (np.uint16, 4, True), "8uc3": (np.uint8, 3, True),
}


def _raw_image(msg, where: str) -> tuple[np.ndarray, bool]:
    encoding = str(msg.encoding).lower()
    if encoding not in _ENCODINGS:
        raise InputFileError(f"frame {where} has image encoding {msg.encoding!r}; supported: "
                             f"{', '.join(sorted(_ENCODINGS))}.")
    dtype, channels, bgr = _ENCODINGS[encoding]
    dt = np.dtype(dtype).newbyteorder(">" if msg.is_bigendian else "<")
    h, w, step = int(msg.height), int(msg.width), int(msg.step)
    row_bytes = w * channels * dt.itemsize
    data = np.asarray(msg.data, dtype=np.uint8).ravel()
    if h < 1 or w < 1 or step < row_bytes or data.size < h * step:
        raise InputFileError(f"frame {where} is damaged: {w}x{h} {msg.encoding} with step {step} needs "
                             f"{h * max(step, row_bytes)} bytes, the message has {data.size}.")
    rows = np.ascontiguousarray(data[:h * step].reshape(h, step)[:, :row_bytes])
    arr = rows.view(dt).reshape(h, w, channels).astype(dtype, copy=False)
    return (arr[:, :, 0] if channels == 1 else arr), bgr


def _decode_depth(msg, where: str) -> np.ndarray:
    if not hasattr(msg, "encoding"):
        raise InputFileError(f"depth frame {where} is a CompressedImage ({msg.format!r}); record depth as a raw "
                             "sensor_msgs/Image (16UC1 or 32FC1).")
    depth, _ = _raw_image(msg, where)
    if depth.ndim != 2:
        raise InputFileError(f"depth frame {where} has {depth.shape[2]} channels ({msg.encoding}); depth is one "
                             "channel: 16UC1 (mm) or 32FC1 (m).")
    if depth.dtype == np.float64:
        depth = depth.astype(np.float32)
    return np.ascontiguousarray(depth)


def _decode_color(msg, where: str) -> np.ndarray:
    import cv2

    if hasattr(msg, "encoding"):
        rgb, bgr = _raw_image(msg, where)
        if bgr:
            rgb = rgb[:, :, [2, 1, 0]]
    else:
        buf = np.asarray(msg.data, dtype=np.uint8).ravel()
        img = cv2.imdecode(buf, cv2.IMREAD_UNCHANGED) if buf.size else None
        if img is None:
            raise InputFileError(f"color frame {where} ({msg.format!r}) cannot be decoded; it is damaged or not "
                                 "JPEG/PNG.")
        if img.ndim == 3:
            img = cv2.cvtColor(img, cv2.COLOR_BGRA2RGB if img.shape[2] == 4 else cv2.COLOR_BGR2RGB)
        rgb = img
    try:
        return np.ascontiguousarray(check_rgb(rgb, name=f"color frame {where}"))
    except (TypeError, ValueError) as exc:
        raise InputFileError(str(exc)) from None
