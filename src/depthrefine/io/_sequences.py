"""Sequences of depth + color frames: a folder, a CSV manifest, a ROS bag or an Azure Kinect recording.

:func:`open_sequence` finds and pairs the frames of an input without
decoding any image; :meth:`Sequence.load` then decodes them one after the
other, in order, as the batch needs them. ``docs/recordings.md`` describes
every format for users.

- **Folder**: ``depth/`` and ``color/`` subfolders whose files pair by stem
  (``depth/000123.png`` with ``color/000123.jpg``). Stems sort in natural
  order (``2`` before ``10``).
- **Manifest**: a CSV file with columns ``depth,color`` (a header row; paths
  relative to the manifest's folder, or absolute). Rows keep their order.
- **ROS bag** (:mod:`._bags`): a ROS 1 ``.bag`` (also a RealSense SDK
  recording), a ROS 2 bag (a folder with ``metadata.yaml``, or one ``.db3``
  or ``.mcap`` file, with or without ``metadata.yaml``).
- **Azure Kinect recording** (:mod:`._mkv`): the ``.mkv`` of ``k4arecorder``.

Time-stamped inputs (bags, recordings) pair each depth frame with the color
frame nearest in time within ``max_dt``, each color frame used once,
closest pairs first; the output stem is the depth frame's time in
nanoseconds. A frame of either stream without a partner is listed in
:attr:`Sequence.unpaired` (streams at different rates are normal), not
as a failed frame. In a folder, a depth file without a color file of its
stem is a failed frame (:attr:`Frame.problem`); extra color files are listed
in :attr:`Sequence.notes`.

Every frame's output keeps the depth's dtype: the depth file's own format
for folders and manifests, ``.png`` for 8/16-bit and ``.tif`` for float
depth from bags and recordings.
"""

from __future__ import annotations

import csv
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Iterable, Iterator

import numpy as np

from ._files import InputFileError
from ._images import DEPTH_SUFFIXES, read_depth, read_rgb
from ._names import DEFAULT_MAX_DT

if TYPE_CHECKING:
    from ..rig.camera import StereoRig

__all__ = ["Frame", "Sequence", "open_sequence", "COLOR_SUFFIXES"]

#: Color file extensions a folder's ``color/`` may hold.
COLOR_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".npy", ".ppm", ".webp")

#: What ``(depth_lr, rgb_hr)`` or the reason a frame cannot be read looks like.
Loaded = Iterator[tuple["Frame", "tuple[np.ndarray, np.ndarray] | InputFileError"]]


@dataclass(frozen=True)
class Frame:
    """One depth + color pair of a sequence.

    Attributes
    ----------
    key : str
        The output stem (file stem, or the depth time in ns for bags and recordings).
    depth, color : str
        Where the images come from, for messages and ``batch.json``.
    suffix : str
        Extension of the output file (keeps the depth's dtype).
    problem : str or None
        Why the frame cannot be processed (a folder's depth file without a
        color file), else ``None``.
    stamp_ns : int or None
        The depth frame's time stamp, ns (None for folders and manifests).
    """

    key: str
    depth: str
    color: str
    suffix: str
    problem: str | None = None
    depth_ref: Any = field(default=None, repr=False, compare=False)
    color_ref: Any = field(default=None, repr=False, compare=False)
    stamp_ns: int | None = None


@dataclass
class Sequence:
    """The paired frames of one input (see :func:`open_sequence`).

    Attributes
    ----------
    source : Path
        The input.
    kind : str
        ``"folder"``, ``"manifest"``, ``"ros1"``, ``"ros2"``, ``"realsense"`` or ``"k4a"``.
    frames : list of Frame
        The pairs, in time (or file) order.
    notes : list of str
        Remarks for the user (extra color files of a folder).
    topics : dict
        ``{"depth": ..., "color": ...}``: the bag topics or the recording's tracks.
    folders : tuple of Path
        Folders the input lives in (an output folder may not be inside).
    rig : StereoRig or None
        The recording's own calibration (depth camera, color camera, extrinsics).
    depth_units : float or None
        Metres per depth unit of the stored depth (0.001 for millimetres).
    frame_rate : float or None
        Frames per second of the depth stream.
    unpaired : list of dict
        ``{"stream": "depth" | "color", "stamp_ns": int, "why": str}`` for each
        frame without a partner within ``max_dt`` (not failures).
    raw : bool
        True when depth and color are not registered: each frame must go through
        the rig chain (undistort, align) before it is refined.
    rig_source : str or None
        Where :attr:`rig` comes from, for messages.
    rig_problem : str or None
        Why a raw input has no :attr:`rig` and what to pass instead (see :meth:`require_rig`).
    """

    source: Path
    kind: str
    frames: list[Frame]
    notes: list[str] = field(default_factory=list)
    topics: dict[str, str] = field(default_factory=dict)
    folders: tuple[Path, ...] = ()
    rig: StereoRig | None = None
    depth_units: float | None = None
    frame_rate: float | None = None
    unpaired: list[dict] = field(default_factory=list)
    raw: bool = False
    rig_source: str | None = None
    rig_problem: str | None = None
    reader: Callable[[Sequence, list[Frame]], Iterator[tuple[Frame, Any]]] | None = field(
        default=None, repr=False, compare=False)

    def describe(self) -> dict[str, Any]:
        """JSON-ready description for ``batch.json``."""
        out: dict[str, Any] = {"path": str(self.source), "kind": self.kind, "frames": len(self.frames)}
        if self.topics:
            out["topics"] = dict(self.topics)
        if self.kind not in ("folder", "manifest"):
            out["raw"] = self.raw
            out["rig"] = _rig_summary(self.rig, self.rig_source)
            out["depth_units"] = self.depth_units
            out["frame_rate"] = None if self.frame_rate is None else round(self.frame_rate, 3)
            out["unpaired"] = len(self.unpaired)
        if self.notes:
            out["notes"] = list(self.notes)
        return out

    def require_rig(self) -> StereoRig:
        """The recording's rig, or an :class:`InputFileError` saying what is missing and what to pass."""
        if self.rig is not None:
            return self.rig
        raise InputFileError(self.rig_problem or f"input {self.source} holds no calibration of its cameras; pass "
                                                 "--rig rig.json (from `depthrefine calibrate-stereo` or "
                                                 "`depthrefine rig import`).")

    def load(self, frames: Iterable[Frame], *, saturated_invalid: bool = False) -> Loaded:
        """Decode ``frames`` (in the order given): yield ``(frame, (depth_lr, rgb_hr))``.

        Depth comes as stored (uint16 for Kinect and RealSense, float32 for
        metric bags), color as RGB. A frame that cannot be read yields
        ``(frame, InputFileError)`` instead; the others go on. Bags and
        recordings are read in one pass in recording order over the span the
        frames cover, so ``frames`` must keep the sequence's order.
        """
        frames = list(frames)
        if self.reader is not None:
            for frame, data in self.reader(self, frames):
                if saturated_invalid and not isinstance(data, BaseException) and data[0].dtype.kind in "ui":
                    depth = data[0]
                    data = (np.where(depth == np.iinfo(depth.dtype).max, depth.dtype.type(0), depth), data[1])
                yield frame, data
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


def _rig_summary(rig: StereoRig | None, source: str | None) -> dict[str, Any] | None:
    if rig is None:
        return None
    return {
        "source": source,
        "depth": "x".join(map(str, rig.depth_camera.image_size)),
        "color": "x".join(map(str, rig.color_camera.image_size)),
        "baseline_mm": round(float(np.linalg.norm(rig.t)) * 1000, 2),
        "rotation_deg": round(rig.rotation_degrees, 3),
    }


def open_sequence(
    path: str | os.PathLike,
    *,
    depth_topic: str | None = None,
    color_topic: str | None = None,
    max_dt: float = DEFAULT_MAX_DT,
) -> Sequence:
    """Find and pair the frames of a folder, CSV manifest, ROS bag or Azure Kinect recording (no decoding).

    Parameters
    ----------
    path : path
        A folder with ``depth/`` and ``color/``, a ``.csv`` manifest, a ROS 1
        ``.bag`` (also RealSense), a ROS 2 bag folder, ``.db3`` or ``.mcap``
        file, or an Azure Kinect ``.mkv``.
    depth_topic, color_topic : str, optional
        Bags: the image topics; found automatically when the choice is unambiguous.
    max_dt : float
        Bags and recordings: the largest time between a depth frame and its
        color frame, seconds.

    Raises
    ------
    InputFileError
        A missing or empty input, a folder without ``depth/`` and ``color/``,
        a manifest without ``depth`` and ``color`` columns, two frames with
        the same output stem, a bag whose topics cannot be found (the message
        lists the candidates), a recording without a depth or color track,
        or topics given for an input that is not a bag.
    """
    p = Path(path)
    if not p.exists():
        raise InputFileError(f"input {p} does not exist; give a folder with depth/ and color/, a CSV manifest, "
                             "a ROS bag or an Azure Kinect .mkv recording.")
    from . import _bags, _mkv

    bag = _bags.bag_kind(p)
    if bag is None and (depth_topic or color_topic):
        raise InputFileError(f"input {p} is not a ROS bag; --depth-topic and --color-topic are for bags only.")
    if (bag is not None or _mkv.is_mkv(p)) and not (max_dt >= 0):
        raise InputFileError(f"--max-dt must be >= 0 seconds; got {max_dt}.")
    if bag is not None:
        return _bags.open_bag(p, bag, depth_topic, color_topic, max_dt)
    if _mkv.is_mkv(p):
        return _mkv.open_mkv(p, max_dt)
    if p.is_dir():
        return _open_folder(p)
    if p.suffix.lower() == ".csv":
        return _open_manifest(p)
    raise InputFileError(f"input {p} is none of the inputs batch reads: a folder with depth/ and color/, a .csv "
                         "manifest, a ROS bag (.bag, a ROS 2 bag folder, .db3 or .mcap) or an Azure Kinect "
                         "recording (.mkv).")


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
# time-stamped streams (bags, recordings): pairing and one-pass decoding
# ----------------------------------------------------------------------------


def pair_streams(
    depth: list[tuple[int, Any]],
    color: list[tuple[int, Any]],
    max_dt: float,
    *,
    names: tuple[str, str],
    suffix: str,
    color_shift_ns: int = 0,
) -> tuple[list[Frame], list[dict]]:
    """Frames of two time-stamped streams, and the frames left without a partner.

    Parameters
    ----------
    depth, color : list of (stamp_ns, ref)
        Each stream's frames; ``ref`` tells the reader where a frame is.
    max_dt : float
        Seconds.
    names : (str, str)
        The depth and color stream's names, for messages (topics, tracks).
    suffix : str
        Output extension.
    color_shift_ns : int
        Added to color stamps before pairing (a recorder's known delay).

    Examples
    --------
    >>> frames, unpaired = pair_streams([(0, "d0"), (100, "d1")], [(3, "c0")], 0.00001, names=("d", "c"),
    ...                                 suffix=".png")
    >>> [f.key for f in frames], [u["stream"] for u in unpaired]
    (['0'], ['depth'])
    """
    depth = sorted(depth, key=lambda item: item[0])
    color = sorted(color, key=lambda item: item[0])
    max_ns = int(round(max_dt * 1e9))
    depth_t = [t for t, _ in depth]
    color_t = [t + color_shift_ns for t, _ in color]
    pairs = _pair_nearest(depth_t, color_t, max_ns)
    window = f"{max_dt * 1000:g} ms"
    frames, unpaired = [], []
    for i, (t, ref) in enumerate(depth):
        j = pairs.get(i)
        if j is None:
            near = _within(color_t, t, max_ns)
            why = (f"no color frame on {names[1]} within {window}" if not near else
                   f"the color frames within {window} are paired with nearer depth frames")
            unpaired.append({"stream": "depth", "stamp_ns": int(t), "why": why})
            continue
        tc, cref = color[j]
        frames.append(Frame(str(t), f"{names[0]} @ {t}", f"{names[1]} @ {tc}", suffix, None, ref, cref, int(t)))
    used = set(pairs.values())
    for j, (tc, _) in enumerate(color):
        if j not in used:
            near = _within(depth_t, color_t[j], max_ns)
            why = (f"no depth frame on {names[0]} within {window}" if not near else
                   f"the depth frames within {window} are paired with nearer color frames")
            unpaired.append({"stream": "color", "stamp_ns": int(tc), "why": why})
    unpaired.sort(key=lambda u: (u["stamp_ns"], u["stream"]))
    if depth and color and not frames:
        span = lambda ts: f"{min(ts) / 1e9:.3f} to {max(ts) / 1e9:.3f} s"  # noqa: E731
        raise InputFileError(f"no depth frame on {names[0]} has a color frame on {names[1]} within {window} (depth "
                             f"stamps {span(depth_t)}, color {span(color_t)}); raise --max-dt, or check that both "
                             "streams use the same clock.")
    keys = [f.key for f in frames]
    if len(set(keys)) != len(keys):
        raise InputFileError(f"two depth frames on {names[0]} have the same time stamp; their outputs would "
                             "collide.")
    return frames, unpaired


def _within(times: list[int], t: int, max_ns: int) -> bool:
    lo = np.searchsorted(times, t - max_ns, "left")
    return bool(lo < len(times) and times[lo] <= t + max_ns)


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


def load_in_one_pass(
    frames: list[Frame],
    messages: Callable[[set], Iterable[tuple[Any, Any]]],
    decode: Callable[[str, Any, str], Any],
    source: str,
) -> Loaded:
    """Decode ``frames`` from one pass over a recording; yield them in the order given.

    Parameters
    ----------
    frames : list of Frame
        In the recording's order.
    messages : callable
        ``messages(refs)`` yields ``(ref, payload)`` in file order, at least
        for every ref of ``refs`` (it may restrict its pass to their span).
    decode : callable
        ``decode(role, payload, where)`` with role ``"depth"`` or ``"color"``:
        the image, or raises :class:`InputFileError`.
    source : str
        The recording, for messages.
    """
    want: dict[Any, list[tuple[int, str]]] = {}
    for n, frame in enumerate(frames):
        want.setdefault(frame.depth_ref, []).append((n, "depth"))
        want.setdefault(frame.color_ref, []).append((n, "color"))
    parts: dict[int, dict[str, Any]] = {}
    next_out = 0

    def ready():
        nonlocal next_out
        while next_out < len(frames):
            got = parts.get(next_out, {})
            if len(got) < 2:
                return
            del parts[next_out]
            bad = next((v for v in (got["depth"], got["color"]) if isinstance(v, InputFileError)), None)
            yield frames[next_out], bad if bad is not None else (got["depth"], got["color"])
            next_out += 1

    if want:
        try:
            for ref, payload in messages(set(want)):
                users = want.pop(ref, None)
                if not users:
                    continue
                for n, role in users:
                    where = frames[n].depth if role == "depth" else frames[n].color
                    try:
                        value = decode(role, payload, where)
                    except InputFileError as exc:
                        value = exc
                    except Exception as exc:  # noqa: BLE001 - a frame that does not decode is bad input
                        value = InputFileError(f"{role} frame {where} cannot be decoded ({type(exc).__name__}: "
                                               f"{exc}).")
                    parts.setdefault(n, {})[role] = value
                yield from ready()
                if not want:
                    break
        except InputFileError:
            raise
        except Exception as exc:  # noqa: BLE001 - the file broke while reading
            raise InputFileError(f"{source} cannot be read ({type(exc).__name__}: {exc}).") from None
    for n, frame in enumerate(frames[next_out:], start=next_out):  # frames the file did not deliver
        for role in ("depth", "color"):
            parts.setdefault(n, {}).setdefault(role, InputFileError(f"{role} frame of {frame.key} is missing "
                                                                    f"from {source}."))
    yield from ready()


def frame_rate_of(stamps_ns: list[int]) -> float | None:
    """Frames per second from time stamps (the median period); None with fewer than two.

    Examples
    --------
    >>> frame_rate_of([0, 33_333_333, 66_666_667, 100_000_000])
    30.0
    """
    if len(stamps_ns) < 2:
        return None
    period = float(np.median(np.diff(np.sort(np.asarray(stamps_ns, dtype=np.int64)))))
    return round(1e9 / period, 3) if period > 0 else None
