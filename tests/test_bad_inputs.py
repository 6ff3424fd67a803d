"""Bad input, faults and trust (issue 5): clear errors, nothing lost.

The core is one table of bad inputs, generated in ``tmp_path``. Each case runs
``depthrefine refine`` (in-process through :func:`depthrefine.cli.main`; a
few also as a real ``python -m depthrefine`` process) and checks:

- exit status 2, exactly one line on stderr, no traceback;
- the line names the file or argument and says what to do;
- the input files and the output folder are byte-for-byte unchanged (no
  output, no partial or temporary file left behind);
- where a library call does the same thing, it raises ``ValueError`` or
  ``TypeError`` with the same message.

Then: internal failures (exit 1, traceback only with ``--debug``), the memory
guard, inputs users feed that must work (RGBA, gray, 16-bit), and depth maps
with holes and saturated pixels.
"""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import cv2
import numpy as np
import pytest
import tifffile

import depthrefine
from depthrefine import ThesisParams, cli
from depthrefine import _validate
from depthrefine.io import _images as images
from depthrefine.io import fetch_dataset, read_depth, read_mapping, read_patch_layout, read_rgb, sample_folder
from depthrefine.methods.params import params_from_mapping

# ----------------------------------------------------------------------------
# The scene every case starts from: 16 x 20 depth, 64 x 80 color (x4)
# ----------------------------------------------------------------------------

DEPTH_SHAPE = (16, 20)
SCALE = 4


def _depth_u8() -> np.ndarray:
    depth = np.full(DEPTH_SHAPE, 60, np.uint8)
    depth[:, 10:] = 180
    return depth


def _color_u8() -> np.ndarray:
    rgb = np.zeros((DEPTH_SHAPE[0] * SCALE, DEPTH_SHAPE[1] * SCALE, 3), np.uint8)
    rgb[:, :40] = (200, 40, 40)
    rgb[:, 40:] = (30, 60, 210)
    return rgb


def _write_png(path: Path, image: np.ndarray) -> Path:
    if image.ndim == 3:
        image = cv2.cvtColor(image, cv2.COLOR_RGB2BGR if image.shape[2] == 3 else cv2.COLOR_RGBA2BGRA)
    assert cv2.imwrite(str(path), image)
    return path


@dataclass
class Workspace:
    """Input files in ``inputs/``, an output folder ``out/`` holding one earlier result."""

    root: Path
    inputs: Path = field(init=False)
    out: Path = field(init=False)

    def __post_init__(self) -> None:
        self.inputs = self.root / "inputs"
        self.out = self.root / "out"
        self.inputs.mkdir()
        self.out.mkdir()
        _write_png(self.inputs / "depth.png", _depth_u8())
        _write_png(self.inputs / "color.png", _color_u8())
        (self.out / "earlier.png").write_bytes(b"an earlier result that must survive")

    @property
    def depth(self) -> Path:
        return self.inputs / "depth.png"

    @property
    def color(self) -> Path:
        return self.inputs / "color.png"

    @property
    def result(self) -> Path:
        return self.out / "result.png"

    def file(self, name: str, data: bytes | np.ndarray | str) -> Path:
        """Write an input file: raw bytes, text, or an array (format by extension)."""
        path = self.inputs / name
        if isinstance(data, bytes):
            path.write_bytes(data)
        elif isinstance(data, str):
            path.write_text(data, encoding="utf-8")
        elif path.suffix == ".npy":
            np.save(path, data, allow_pickle=data.dtype == object)
        elif path.suffix in (".tif", ".tiff"):
            tifffile.imwrite(path, data, photometric="rgb" if data.ndim == 3 else "minisblack")
        else:
            _write_png(path, data)
        return path

    def refine(self, depth=None, color=None, *extra: str, out=None) -> list[str]:
        """``refine`` argv; the thesis method unless ``extra`` names one (its options are the ones checked)."""
        method = [] if "--method" in extra else ["--method", "thesis"]
        return ["refine", str(depth or self.depth), str(color or self.color), "-o", str(out or self.result),
                *method, *map(str, extra)]


@dataclass
class Case:
    """One bad input: the command line, what its error line must contain, and the library call."""

    argv: list[str]
    expect: list[str]  # substrings of the error line: the file/argument, and what to do
    lib: Callable[[], object] | None = None  # the library doing the same; must raise ValueError/TypeError
    lib_subject: tuple[str, str] | None = None  # (library's name, CLI's name) to compare the two messages


def _snapshot(root: Path) -> dict[str, str]:
    """Every file and folder under root (hidden ones too) with the SHA-256 of its bytes."""
    state = {}
    for path in sorted(root.rglob("*")):
        key = str(path.relative_to(root))
        state[key] = "dir" if path.is_dir() else hashlib.sha256(path.read_bytes()).hexdigest()
    return state


def _run(argv: list[str], capsys) -> tuple[int, str]:
    code = cli.main(argv)
    return code, capsys.readouterr().err


def _one_line(text: str) -> str:
    return " ".join(text.split())


# ----------------------------------------------------------------------------
# The table
# ----------------------------------------------------------------------------

_BIG_PNG_HEADER = (  # a PNG that claims 100000 x 100000 pixels: only the signature and IHDR
    b"\x89PNG\r\n\x1a\n" + b"\x00\x00\x00\x0dIHDR" + (100000).to_bytes(4, "big") * 2 + b"\x08\x02\x00\x00\x00"
    + b"\x00\x00\x00\x00"
)


def _png_bytes(image: np.ndarray) -> bytes:
    ok, buf = cv2.imencode(".png", image)
    assert ok
    return buf.tobytes()


def _jpeg_bytes(image: np.ndarray) -> bytes:
    ok, buf = cv2.imencode(".jpg", image)
    assert ok
    return buf.tobytes()


def _corrupt_png(image: np.ndarray) -> bytes:
    data = bytearray(_png_bytes(image))
    idat = data.index(b"IDAT")
    data[idat + 10: idat + 20] = bytes(10)  # damage the compressed data: CRC mismatch
    return bytes(data)


def _toml(ws: Workspace, text: str, name: str = "params.toml") -> Path:
    return ws.file(name, text)


def _depth_case(ws: Workspace, name: str, data, expect: list[str], *extra: str) -> Case:
    path = ws.file(name, data)
    return Case(ws.refine(path, None, *extra), [str(path), *expect],
                lib=lambda: read_depth(path, saturated_invalid="--saturated-invalid" in extra))


def _color_case(ws: Workspace, name: str, data, expect: list[str]) -> Case:
    path = ws.file(name, data)
    return Case(ws.refine(None, path), [str(path), *expect], lib=lambda: read_rgb(path))


def _no_valid(ws: Workspace, name: str, data: np.ndarray, *extra: str) -> Case:
    path = ws.file(name, data)
    arr = data  # the library gets the same array (saturation marked as the option does)
    if "--saturated-invalid" in extra:
        arr = np.where(arr == np.iinfo(arr.dtype).max, 0, arr).astype(arr.dtype)
    rgb = _color_u8()
    return Case(ws.refine(path, None, *extra), [str(path), "has no valid pixel", "Check the depth file"],
                lib=lambda: depthrefine.refine(arr, rgb, method="thesis"), lib_subject=("depth_lr", f"depth file {path}"))


def _too_deep(ws: Workspace, name: str, data: np.ndarray) -> Case:
    path = ws.file(name, data)
    rgb = _color_u8()
    return Case(ws.refine(path, None), [str(path), "holds depth values up to", "in a larger unit"],
                lib=lambda: depthrefine.refine(data, rgb, method="thesis"),
                lib_subject=("depth_lr", f"depth file {path}"))


def _params_case(ws: Workspace, text: str, expect: list[str], *, name="params.toml", mapping=None) -> Case:
    path = ws.file(name, text)

    def lib():
        data = read_mapping(path, what="parameter") if mapping is None else mapping
        return params_from_mapping(ThesisParams, data, source=f"parameter file {path}")

    return Case(ws.refine(None, None, "--params", path), [str(path), *expect], lib=lib)


def _patch_case(ws: Workspace, layout, expect: list[str], *, in_refine: bool) -> Case:
    path = ws.file("patches.json", json.dumps(layout) if not isinstance(layout, str) else layout)
    if in_refine:  # the layout reads fine but does not fit the image: the library says so
        rects = tuple(tuple(r) for r in layout)
        lib = lambda: depthrefine.refine(_depth_u8(), _color_u8(), params=ThesisParams(patch_layout=rects), method="thesis")  # noqa: E731
        return Case(ws.refine(None, None, "--patch-file", path), ["--patch-file", *expect], lib=lib)
    return Case(ws.refine(None, None, "--patch-file", path), [str(path), *expect],
                lib=lambda: read_patch_layout(path))


def _shape_case(ws: Workspace, depth: np.ndarray, color: np.ndarray, expect: list[str]) -> Case:
    dpath = ws.file("depth_other.png", depth)
    cpath = ws.file("color_other.png", color)
    return Case(ws.refine(dpath, cpath), expect, lib=lambda: depthrefine.refine(depth, color, method="thesis"))


RGB = _color_u8()
CASES: dict[str, Callable[[Workspace], Case]] = {
    # --- files that are missing, empty, damaged or of the wrong kind
    "depth missing": lambda ws: Case(ws.refine(ws.inputs / "nope.png"), ["nope.png", "does not exist", "check the path"],
                                     lib=lambda: read_depth(ws.inputs / "nope.png")),
    "color missing": lambda ws: Case(ws.refine(None, ws.inputs / "nope.jpg"), ["color file", "nope.jpg", "check the path"],
                                     lib=lambda: read_rgb(ws.inputs / "nope.jpg")),
    "depth is an empty folder": lambda ws: (
        (ws.inputs / "empty").mkdir(),
        Case(ws.refine(ws.inputs / "empty"), ["empty", "is a folder", "give an image file"],
             lib=lambda: read_depth(ws.inputs / "empty")))[1],
    "depth empty file": lambda ws: _depth_case(ws, "zero.png", b"", ["is empty (0 bytes)", "save it again"]),
    "depth not an image": lambda ws: _depth_case(ws, "notes.png", "these are my notes, not a PNG",
                                                 ["cannot be read", "check it or save it again"]),
    "depth truncated png": lambda ws: _depth_case(ws, "cut.png", _png_bytes(_depth_u8() * 1)[:60],
                                                  ["cannot be read", "IEND", "save it again"]),
    "depth truncated tiff": lambda ws: _depth_case(
        ws, "cut.tif", (ws.file("whole.tif", np.ones((64, 64), np.float32)).read_bytes())[:3000],
        ["cannot be read", "save it again"]),
    "depth truncated npy": lambda ws: _depth_case(
        ws, "cut.npy", (ws.file("whole.npy", np.ones((64, 64), np.float32)).read_bytes())[:3000],
        ["cannot be read", "save it again"]),
    "depth pickled npy": lambda ws: _depth_case(ws, "obj.npy", np.array([[{"a": 1}, None]], dtype=object),
                                                ["cannot be read", "save it again"]),
    "depth complex npy": lambda ws: _depth_case(ws, "complex.npy", np.ones((4, 5), np.complex64),
                                                ["unsupported dtype complex64", "use 8/16-bit PNG or float TIFF"]),
    "depth uint32 tiff": lambda ws: _depth_case(ws, "u32.tif", np.ones((4, 5), np.uint32),
                                                ["unsupported dtype uint32", "use 8/16-bit PNG or float TIFF"]),
    "depth 3-D npy": lambda ws: _depth_case(ws, "stack.npy", np.ones((4, 5, 2), np.float32),
                                            ["shape (4, 5, 2)", "one channel"]),
    "depth empty npy": lambda ws: _depth_case(ws, "none.npy", np.ones((0, 0), np.float32),
                                              ["is empty", "save the depth map again"]),
    # another color image (the same bytes as COLOR are refused before reading: see "refine: DEPTH is COLOR")
    "depth is the color image": lambda ws: _depth_case(ws, "rgb.png", RGB // 2,
                                                       ["shape (64, 80, 3)", "Is this the color image?"]),
    "color not an image": lambda ws: _color_case(ws, "photo.jpg", b"\xff\xd8 definitely not a JPEG",
                                                 ["cannot be read", "save it again"]),
    "color truncated jpeg": lambda ws: _color_case(ws, "cut.jpg", _jpeg_bytes(RGB)[:700],
                                                   ["cannot be read", "save it again"]),
    "color corrupt png": lambda ws: _color_case(ws, "crc.png", _corrupt_png(RGB), ["cannot be read", "save it again"]),
    "color two channels": lambda ws: _color_case(ws, "two.npy", np.zeros((64, 80, 2), np.uint8),
                                                 ["shape (64, 80, 2)", "Give an RGB (or gray) image"]),
    "color float out of range": lambda ws: _color_case(ws, "f.tif", RGB.astype(np.float32),
                                                       ["[30, 210]", "Divide by 255"]),
    "color float NaN": lambda ws: _color_case(ws, "nan.tif", np.full((64, 80, 3), np.nan, np.float32),
                                              ["NaN or inf", "finite numbers in [0, 1]"]),
    "color int32": lambda ws: _color_case(ws, "i32.npy", np.zeros((64, 80, 3), np.int32),
                                          ["dtype int32", "Convert it first"]),
    "absurdly large color (header only)": lambda ws: _color_case(
        ws, "huge.png", _BIG_PNG_HEADER, ["100000x100000", "GiB", "more than the", "Crop or downscale"]),
    # --- depth without any valid pixel
    "depth all zero": lambda ws: _no_valid(ws, "zeros.png", np.zeros(DEPTH_SHAPE, np.uint16)),
    "depth all NaN": lambda ws: _no_valid(ws, "nan.npy", np.full(DEPTH_SHAPE, np.nan, np.float32)),
    "depth all inf": lambda ws: _no_valid(ws, "inf.npy", np.full(DEPTH_SHAPE, np.inf, np.float64)),
    "depth all negative": lambda ws: _no_valid(ws, "neg.npy", np.full(DEPTH_SHAPE, -2.0, np.float32)),
    "depth all saturated (--saturated-invalid)": lambda ws: _no_valid(
        ws, "sat.png", np.full(DEPTH_SHAPE, 65535, np.uint16), "--saturated-invalid"),
    # --- depth beyond what float32's squares hold (it overflowed inside the methods; float64 beyond float32's range
    # became "no measurement")
    "depth of 1e20": lambda ws: _too_deep(ws, "e20.npy", np.where(_depth_u8() > 100, 1e20, 5.0).astype(np.float32)),
    "depth beyond float32": lambda ws: _too_deep(ws, "e300.npy", np.where(_depth_u8() > 100, 1e300, 5.0)),
    # --- depth and color that do not belong together
    "aspect ratio mismatch": lambda ws: _shape_case(ws, _depth_u8(), RGB[:, :60].copy(),
                                                    ["depth (20x16)", "color (60x64)", "crop them"]),
    "color smaller than depth": lambda ws: _shape_case(ws, np.full((64, 80), 9, np.uint8), RGB[:16, :20].copy(),
                                                       ["color image (20x16)", "Check the argument order"]),
    # --- outputs that cannot or must not be written
    "output exists": lambda ws: (ws.result.write_bytes(b"keep me"),
                                 Case(ws.refine(), [str(ws.result), "pass --overwrite"]))[1],
    "output is a folder": lambda ws: Case(ws.refine(out=ws.out), [str(ws.out), "is a folder", "give a file name"]),
    "output folder missing": lambda ws: Case(ws.refine(out=ws.out / "sub" / "r.png"), ["sub", "create it first"]),
    "output unknown format": lambda ws: Case(ws.refine(out=ws.out / "r.xyz"), ["r.xyz", "unknown format", ".tif"]),
    "output png for float depth": lambda ws: Case(
        ws.refine(ws.file("d.tif", _depth_u8().astype(np.float32))), ["result.png", "float32", "write .tif or .npy"]),
    "output is the depth input": lambda ws: Case(ws.refine(None, None, "--overwrite", out=ws.depth),
                                                 [str(ws.depth), "also an input file", "choose another"]),
    "save-intermediate folder not empty": lambda ws: Case(
        ws.refine(None, None, "--save-intermediate", ws.out), ["--save-intermediate", str(ws.out), "pass --overwrite"]),
    "save-intermediate is a file": lambda ws: Case(
        ws.refine(None, None, "--save-intermediate", ws.out / "earlier.png"), ["earlier.png", "give a folder name"]),
    # --- parameter files
    "params missing": lambda ws: Case(ws.refine(None, None, "--params", ws.inputs / "p.toml"),
                                      ["p.toml", "does not exist"], lib=lambda: read_mapping(ws.inputs / "p.toml")),
    "params unknown key": lambda ws: _params_case(ws, "n_clusters = 3\nclusterz = 4\n",
                                                  ["'clusterz'", "known: patches"]),
    "params wrong type": lambda ws: _params_case(ws, 'n_clusters = "four"\n', ["n_clusters", "must be an integer"]),
    "params bad value": lambda ws: _params_case(ws, "median_size = 4\n", ["median_size must be odd"]),
    "params bounds crossed": lambda ws: _params_case(ws, "black_bound = 0.9\nwhite_bound = 0.5\n",
                                                     ["black_bound and white_bound", "must satisfy"]),
    "params bad TOML": lambda ws: _params_case(ws, "n_clusters == 3\n", ["not valid TOML", "fix its syntax"]),
    "params JSON not a table": lambda ws: _params_case(ws, "[1, 2]", ["table of key = value"], name="p.json"),
    "params for a method without any": lambda ws: Case(
        ws.refine(None, None, "--method", "nearest", "--params", _toml(ws, "n_clusters = 3\n")),
        ["'nearest' takes no parameters", "drop n_clusters"]),
    # --- options
    "clusters 0": lambda ws: Case(ws.refine(None, None, "--clusters", "0"), ["--clusters", "must be a whole number >= 1"],
                                  lib=lambda: ThesisParams(n_clusters=0)),
    "clusters negative": lambda ws: Case(ws.refine(None, None, "--clusters", "-3"), ["--clusters", "'-3'"],
                                         lib=lambda: ThesisParams(n_clusters=-3)),
    "clusters not a number": lambda ws: Case(ws.refine(None, None, "--clusters", "four"), ["--clusters", "'four'"],
                                             lib=lambda: ThesisParams(n_clusters="four")),
    "patches 0x4": lambda ws: Case(ws.refine(None, None, "--patches", "0x4"), ["--patches", "COLSxROWS", "'0x4'"],
                                   lib=lambda: ThesisParams(patches=(0, 4))),
    "unknown method": lambda ws: Case(ws.refine(None, None, "--method", "magic"), ["--method", "'magic'", "choose from"],
                                      lib=lambda: depthrefine.refine(_depth_u8(), RGB, method="magic")),
    "missing -o": lambda ws: Case(["refine", str(ws.depth), str(ws.color)], ["-o/--output", "required"]),
    "max-pixels exceeded": lambda ws: Case(
        ws.refine(None, None, "--max-pixels", "1000"), [str(ws.color), "5,120 pixels", "limit of 1,000", "raise the limit"],
        lib=lambda: depthrefine.refine(_depth_u8(), RGB, max_pixels=1000, method="thesis"), lib_subject=("rgb_hr is", f"color file {ws.color} is")),
    "max-pixels 0": lambda ws: Case(ws.refine(None, None, "--max-pixels", "0"), ["--max-pixels", "positive"],
                                    lib=lambda: depthrefine.refine(_depth_u8(), RGB, max_pixels=0, method="thesis")),
    "max-pixels not a number": lambda ws: Case(ws.refine(None, None, "--max-pixels", "lots"), ["--max-pixels", "'lots'"]),
    # --- manual patches
    "patch outside the image": lambda ws: _patch_case(ws, [[0, 0, 40, 64], [40, 0, 60, 64]],
                                                      ["reaches outside the color image (80x64)", "keep every rectangle"],
                                                      in_refine=True),
    "patches leave a gap": lambda ws: _patch_case(ws, [[0, 0, 40, 64]], ["uncovered", "must cover the whole image"],
                                                  in_refine=True),
    "patch missing key": lambda ws: _patch_case(ws, [{"x": 0, "y": 0, "width": 80}],
                                                ["lacks key 'height'", "give x, y, width, height"], in_refine=False),
    "patch negative": lambda ws: _patch_case(ws, [[-4, 0, 80, 64]], ["needs x, y >= 0"], in_refine=False),
    "patch file not JSON": lambda ws: _patch_case(ws, "[[0, 0, 80, 64]", ["not valid JSON", "give a list"],
                                                  in_refine=False),
}


def _refused(case, command: str, folder, capsys) -> str:
    """Run a case; check exit 2, one error line naming what it should, and nothing changed. Return the line."""
    before = _snapshot(folder)
    code, err = _run(case.argv, capsys)
    lines = [line for line in err.splitlines() if line.strip()]
    assert code == 2, err
    assert "Traceback" not in err
    assert len(lines) == 1, err
    line = lines[0]
    assert line.startswith(f"depthrefine {command}: error:"), line
    for part in case.expect:
        assert part in line, f"{part!r} not in {line!r}"
    assert _snapshot(folder) == before, "the inputs or the output folder changed"
    return line


@pytest.mark.parametrize("name", list(CASES))
def test_bad_input(name, tmp_path, capsys):
    """Exit 2, one clear line naming the culprit, nothing written, inputs untouched, same message as the library."""
    case = CASES[name](Workspace(tmp_path))
    line = _refused(case, "refine", tmp_path, capsys)
    if case.lib is not None:
        with pytest.raises((ValueError, TypeError)) as info:
            case.lib()
        message = _one_line(str(info.value))
        if case.lib_subject is not None:
            message = message.replace(*case.lib_subject)
        if not line.startswith("depthrefine refine: error: argument"):  # argparse words it its own way
            assert message in line, f"library: {message!r}\ncli: {line!r}"


def test_table_is_large_enough():
    assert len(CASES) >= 30


@pytest.mark.parametrize("name", ["depth truncated png", "color truncated jpeg", "color corrupt png", "depth all zero"])
def test_bad_input_real_process(name, tmp_path):
    """The same through ``python -m depthrefine``: C decoders must not add lines to stderr."""
    ws = Workspace(tmp_path)
    case = CASES[name](ws)
    before = _snapshot(tmp_path)
    proc = subprocess.run([sys.executable, "-m", "depthrefine", *case.argv], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr, proc.stderr
    assert all(part in proc.stderr for part in case.expect), proc.stderr
    assert proc.stdout == ""
    assert _snapshot(tmp_path) == before


# ----------------------------------------------------------------------------
# Internal failures, interruptions
# ----------------------------------------------------------------------------


def _boom(*args, **kwargs):
    raise RuntimeError("simulated bug")


def test_internal_error_exit_1_without_traceback(tmp_path, capsys, monkeypatch):
    ws = Workspace(tmp_path)
    monkeypatch.setattr("depthrefine.methods.thesis.refine.median_rgb", _boom)
    before = _snapshot(tmp_path)
    code, err = _run(ws.refine(), capsys)
    assert code == 1
    assert "Traceback" not in err
    assert err.count("\n") == 1
    assert "internal error: RuntimeError: simulated bug" in err and "--debug" in err
    assert _snapshot(tmp_path) == before


@pytest.mark.parametrize("where", ["before", "after"])
def test_internal_error_traceback_with_debug(tmp_path, capsys, monkeypatch, where):
    ws = Workspace(tmp_path)
    monkeypatch.setattr("depthrefine.methods.thesis.refine.median_rgb", _boom)
    argv = ws.refine()
    argv = ["--debug", *argv] if where == "before" else [*argv, "--debug"]
    before = _snapshot(tmp_path)
    code, err = _run(argv, capsys)
    assert code == 1
    assert "Traceback (most recent call last)" in err and "RuntimeError: simulated bug" in err
    assert _snapshot(tmp_path) == before


def test_missing_dependency_one_line_exit_2(tmp_path, capsys, monkeypatch, numba_kernels, no_numba):
    """numba not installed (or broken) where the thesis method needs it (its C kernels not built, here forced off):
    it says what to install, exit 2, no traceback, no output."""
    ws = Workspace(tmp_path)
    before = _snapshot(tmp_path)
    code, err = _run(ws.refine(), capsys)
    assert code == 2, err
    assert "Traceback" not in err and err.count("\n") == 1
    assert "error:" in err and "internal error" not in err and "pip install numba" in err
    assert _snapshot(tmp_path) == before


def test_internal_error_while_writing_intermediates_leaves_nothing(tmp_path, capsys, monkeypatch):
    """A bug in the middle of --save-intermediate: neither the folder nor the result appears."""
    ws = Workspace(tmp_path)
    monkeypatch.setattr("depthrefine.viz.spread_samples", _boom)
    before = _snapshot(tmp_path)
    code, err = _run(ws.refine(None, None, "--save-intermediate", tmp_path / "steps"), capsys)
    assert code == 1, err
    assert _snapshot(tmp_path) == before


def test_interrupt_exit_130_nothing_written(tmp_path, capsys, monkeypatch):
    ws = Workspace(tmp_path)

    def interrupt(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr("depthrefine.methods.thesis.refine.median_rgb", interrupt)
    before = _snapshot(tmp_path)
    code, err = _run(ws.refine(), capsys)
    assert code == 130 and "interrupted" in err and "Traceback" not in err
    assert _snapshot(tmp_path) == before


def test_disk_full_while_writing_exit_2_nothing_left(tmp_path, capsys, monkeypatch):
    ws = Workspace(tmp_path)
    real_write_bytes = Path.write_bytes

    def full_disk(path, data):
        real_write_bytes(path, b"partial")  # the encoded file got halfway to the disk
        raise OSError(28, "No space left on device")

    before = _snapshot(tmp_path)
    monkeypatch.setattr(Path, "write_bytes", full_disk)
    code, err = _run(ws.refine(), capsys)
    monkeypatch.setattr(Path, "write_bytes", real_write_bytes)
    assert code == 2 and "No space left on device" in err and "Traceback" not in err
    assert _snapshot(tmp_path) == before


# ----------------------------------------------------------------------------
# Memory guard
# ----------------------------------------------------------------------------


def test_memory_guard_refuses_up_front(tmp_path, capsys, monkeypatch):
    """With 0.6 MiB available, a 64 x 80 color image (about 1 MiB of work) is refused before decoding."""
    ws = Workspace(tmp_path)
    monkeypatch.setattr(_validate, "available_memory", lambda: 600_000)
    decoded = []
    real_read_any = images._read_any
    monkeypatch.setattr(images, "_read_any", lambda p, what: decoded.append(what) or real_read_any(p, what))
    before = _snapshot(tmp_path)
    code, err = _run(ws.refine(), capsys)
    assert code == 2, err
    assert f"color file {ws.color} is 80x64 = 5,120 pixels" in err
    assert "needs about 1.0 MiB of memory, more than the 0.6 MiB available" in err
    assert decoded == ["depth"], "the color image must be refused before it is decoded"
    assert _snapshot(tmp_path) == before
    with pytest.raises(ValueError, match=r"rgb_hr is 80x64 = 5,120 pixels; processing it needs about 1.0 MiB"):
        depthrefine.refine(_depth_u8(), RGB, method="thesis")
    with pytest.raises(ValueError, match="needs about"):
        depthrefine.methods.thesis.refine_with_intermediates(_depth_u8(), RGB)


def test_memory_guard_passes_normal_images():
    avail = _validate.available_memory()
    assert avail is None or avail > 0
    _validate.check_pixels((480, 640))  # a VGA frame must always pass
    with pytest.raises(ValueError, match="more than the limit of 100"):
        _validate.check_pixels((20, 10), max_pixels=100)
    with _validate.pixel_limit(50):
        with pytest.raises(ValueError, match="limit of 50"):
            depthrefine.refine(np.ones((4, 4), np.float32), np.zeros((8, 8, 3), np.uint8), method="thesis")
    assert depthrefine.refine(np.ones((4, 4), np.float32), np.zeros((8, 8, 3), np.uint8), method="thesis").shape == (8, 8)


def test_memory_estimate_covers_measured_peak(tmp_path):
    """The per-pixel figure of the guard is at least the measured peak of the hungriest path.

    In a fresh process: refine_with_intermediates with one patch (the most
    memory per pixel) on 1 Mpx; peak RSS growth / pixels <= PEAK_BYTES_PER_PIXEL.
    The peak is the call's own (the kernel's high-water mark is reset just before
    it, where Linux allows): the lifetime peak once counted numba compiling the
    kernels in the warm-up and read 204 B/px in a clean clone's first run.
    """
    script = r"""
import resource, sys, numpy as np, depthrefine
rng = np.random.default_rng(0)
h, w, s = 128, 128, 8
depth = rng.uniform(0.5, 5, (h, w)).astype(np.float32)
rgb = np.repeat(np.repeat(rng.integers(0, 255, (h // 4, w // 4, 3)).astype(np.uint8), 4 * s, 0), 4 * s, 1)
params = depthrefine.ThesisParams(patches=(1, 1))
depthrefine.methods.thesis.refine_with_intermediates(depth[:16, :16], np.ascontiguousarray(rgb[:16 * s, :16 * s]), params=params)
import psutil
def high_water_mark():
    with open("/proc/self/status") as status:
        return next(int(line.split()[1]) * 1024 for line in status if line.startswith("VmHWM:"))
try:  # reset the peak, so that an earlier one (numba compiling kernels in the warm-up) is not counted
    with open("/proc/self/clear_refs", "w") as clear:
        clear.write("5")
    reset = True
except OSError:
    reset = False
base = psutil.Process().memory_info().rss
depthrefine.methods.thesis.refine_with_intermediates(depth, rgb, params=params)
peak = high_water_mark() if reset else resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
print((peak - base) / rgb.shape[0] / rgb.shape[1])
"""
    pytest.importorskip("psutil")
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    per_pixel = float(proc.stdout.split()[-1])
    assert 0 < per_pixel <= _validate.PEAK_BYTES_PER_PIXEL, per_pixel


# ----------------------------------------------------------------------------
# What users feed that must work
# ----------------------------------------------------------------------------


ACCEPTED = {
    "RGBA color": lambda ws: (ws.file("c.png", np.dstack([RGB, np.full(RGB.shape[:2], 128, np.uint8)])), ws.depth),
    "gray color": lambda ws: (ws.file("c.png", RGB[:, :, 2].copy()), ws.depth),
    "16-bit color": lambda ws: (ws.file("c.png", RGB.astype(np.uint16) * 257), ws.depth),
    "16-bit depth": lambda ws: (ws.color, ws.file("d.png", _depth_u8().astype(np.uint16) * 100)),
    "float depth with NaN holes": lambda ws: (ws.color, ws.file(
        "d.tif", np.where(np.eye(*DEPTH_SHAPE, dtype=bool), np.nan, _depth_u8() / 100.0).astype(np.float32))),
    "depth as 3 equal channels": lambda ws: (ws.color, ws.file("d3.png", np.dstack([_depth_u8()] * 3))),
}


@pytest.mark.parametrize("name", list(ACCEPTED))
def test_accepted_input(name, tmp_path, capsys):
    ws = Workspace(tmp_path)
    color, depth = ACCEPTED[name](ws)
    out = ws.out / ("r.tif" if str(depth).endswith(".tif") else "r.png")
    inputs = _snapshot(ws.inputs)
    code, err = _run(ws.refine(depth, color, out=out), capsys)
    assert code == 0, err
    result = read_depth(out)
    assert result.shape == RGB.shape[:2]
    assert result.dtype == read_depth(depth).dtype
    assert _snapshot(ws.inputs) == inputs


# ----------------------------------------------------------------------------
# Holes and saturated pixels
# ----------------------------------------------------------------------------


def _two_region_scene():
    """Left: red, depth 60; right: blue, depth 180; color edge at column 40 (depth edge at 10)."""
    return _depth_u8(), _color_u8()


def test_holes_filled_from_the_same_color_cluster():
    """Holes next to the edge take their own region's depth, never the other side's or a blend."""
    depth, rgb = _two_region_scene()
    holes = depth.copy()
    holes[3:7, 8:10] = 0  # left region, touching the edge
    holes[9:12, 10:13] = 0  # right region, touching the edge
    out = depthrefine.refine(holes, rgb, params=ThesisParams(patches=(1, 1), n_clusters=2), method="thesis")
    assert not np.isnan(out).any()
    np.testing.assert_array_equal(out[:, :40], 60)
    np.testing.assert_array_equal(out[:, 40:], 180)
    # bilinear fills holes from the nearest valid pixel too, but blends the two sides at the edge
    assert set(np.unique(depthrefine.refine(holes, rgb, method="bilinear"))) - {60.0, 180.0}


def test_cluster_without_valid_sample_takes_nearest_valid():
    """A whole region without depth (its cluster caught no valid sample): nearest valid sample, no NaN."""
    depth, rgb = _two_region_scene()
    depth[:, 10:] = 0
    out = depthrefine.refine(depth, rgb, params=ThesisParams(patches=(2, 2), n_clusters=2), method="thesis")
    assert out.dtype == np.float32 and not np.isnan(out).any()
    np.testing.assert_array_equal(out, 60)


def test_single_valid_pixel_fills_everything():
    depth = np.zeros((8, 8), np.uint16)
    depth[5, 2] = 1234
    for method in sorted(depthrefine.METHODS):
        out = depthrefine.refine(depth, np.zeros((32, 32, 3), np.uint8), method=method)
        assert out.shape == (32, 32) and not np.isnan(out).any(), method
        np.testing.assert_allclose(out, 1234, rtol=1e-5, err_msg=method)


def test_invalid_float_values_are_holes():
    """NaN, +inf, -inf and negative depths are no measurement: filled like 0, never averaged in."""
    depth, rgb = _two_region_scene()
    d = depth.astype(np.float32)
    d[2, 2], d[4, 4], d[6, 6], d[8, 8] = np.nan, np.inf, -np.inf, -5.0
    d[10, 14] = np.nan
    for method in sorted(depthrefine.METHODS):
        out = depthrefine.refine(d, rgb, method=method)
        assert np.isfinite(out).all(), method
        assert out.min() >= 60 - 1e-3 and out.max() <= 180 + 1e-3, method
    thesis = depthrefine.refine(d, rgb, params=ThesisParams(patches=(1, 1), n_clusters=2), method="thesis")
    np.testing.assert_array_equal(thesis[:, :40], 60)
    np.testing.assert_array_equal(thesis[:, 40:], 180)


def test_a_masked_arrays_masked_pixels_are_holes_and_a_matrix_its_values():
    """A masked array's masked pixels are no measurement (0), whatever value they hold; a matrix is its values."""
    depth, rgb = _two_region_scene()
    d = depth.astype(np.float32)
    plain = depthrefine.refine(d, rgb)
    holes = d.copy()
    holes[3:6, 4:9] = 0
    masked = np.ma.masked_array(np.where(holes == 0, 1e30, d), mask=holes == 0)   # a placeholder under the mask
    np.testing.assert_array_equal(depthrefine.refine(masked, rgb), depthrefine.refine(holes, rgb))
    with pytest.warns(PendingDeprecationWarning):
        matrix = np.matrix(d)
    np.testing.assert_array_equal(depthrefine.refine(matrix, rgb), plain)


def test_depth_beyond_the_limit_is_refused_by_every_reader(tmp_path):
    """check_depth refuses depth beyond MAX_DEPTH for every caller (the rig chain's helpers too, where float64
    beyond float32 silently became unmeasured), and read_depth for 64-bit integers, naming the file."""
    from depthrefine.rig import chain

    huge = np.full((4, 6), 5.0)
    huge[1, 2] = 1e300
    with pytest.raises(ValueError, match=r"depth_lr holds depth values up to 1e\+300"):
        chain.unmeasured_on_grid(huge, (8, 12))
    assert _validate.largest_beyond_limit(np.full((2, 2), 1e15)) is None          # the limit itself is taken
    path = tmp_path / "i64.npy"
    np.save(path, np.full((4, 6), 2 * 10**18, np.int64))
    with pytest.raises(ValueError, match=f"depth file {path} holds depth values up to 2e\\+18"):
        read_depth(path)


def test_saturated_code_valid_by_default_invalid_on_request(tmp_path):
    """uint16 65535 is a depth unless --saturated-invalid; then it is a hole filled from its cluster."""
    depth = (_depth_u8().astype(np.uint16) * 100)  # 6000 and 18000
    depth[4:6, 3:5] = 65535  # saturated, left region
    path = tmp_path / "sat.png"
    _write_png(path, depth)
    assert read_depth(path).max() == 65535
    marked = read_depth(path, saturated_invalid=True)
    assert marked.max() == 18000 and (marked == 0).sum() == 4
    assert read_depth(path).max() == 65535  # the file is not changed by reading
    params = ThesisParams(patches=(1, 1), n_clusters=2)
    out = depthrefine.refine(marked, _color_u8(), params=params, method="thesis")
    np.testing.assert_array_equal(out[:, :40], 6000)
    np.testing.assert_array_equal(out[:, 40:], 18000)
    # 8-bit 255 stays a valid (nearest) level by default: the thesis's depth intensity
    d8 = _depth_u8()
    d8[:, 10:] = 255
    assert depthrefine.refine(d8, _color_u8(), params=params, method="thesis")[:, 40:].min() == 255


def test_saturated_invalid_through_cli(tmp_path, capsys):
    ws = Workspace(tmp_path)
    depth = _depth_u8().astype(np.uint16) * 100
    depth[4:6, 3:5] = 65535
    dpath = ws.file("sat.png", depth)
    code, err = _run(ws.refine(dpath, None, "--saturated-invalid", "--patches", "1x1", "--clusters", "2"), capsys)
    assert code == 0, err
    out = read_depth(ws.result)
    assert out.dtype == np.uint16 and out.max() == 18000 and out[:, :40].max() == 6000


def test_no_valid_pixel_is_an_error_for_every_method():
    rgb = np.zeros((8, 8, 3), np.uint8)
    for method in sorted(depthrefine.METHODS):
        for depth in (np.zeros((4, 4), np.uint8), np.full((4, 4), np.nan, np.float32)):
            with pytest.raises(ValueError, match="has no valid pixel"):
                depthrefine.refine(depth, rgb, method=method)


def test_inputs_are_not_modified_by_the_library():
    depth, rgb = _two_region_scene()
    depth = depth.astype(np.float32)
    depth[2, 2] = np.nan
    d0, c0 = depth.copy(), rgb.copy()
    for method in sorted(depthrefine.METHODS):
        depthrefine.refine(depth, rgb, method=method)
        np.testing.assert_array_equal(depth, d0)
        np.testing.assert_array_equal(rgb, c0)


if os.name == "posix" and hasattr(os, "geteuid") and os.geteuid() != 0:

    def test_output_folder_not_writable(tmp_path, capsys):
        ws = Workspace(tmp_path)
        locked = tmp_path / "locked"
        locked.mkdir()
        locked.chmod(0o500)
        try:
            before = _snapshot(tmp_path)
            code, err = _run(ws.refine(out=locked / "r.png"), capsys)
            assert code == 2 and "is not writable" in err and "choose another folder" in err
            assert _snapshot(tmp_path) == before
        finally:
            locked.chmod(0o700)


# ----------------------------------------------------------------------------
# Second pass: the other subcommands (demo, calibrate, calibrate-stereo, align,
# undistort, run, export-ply, bench), same checks
# ----------------------------------------------------------------------------

_DEPTH_CAMERA = {"K": [[100.0, 0, 9.5], [0, 100.0, 7.5], [0, 0, 1]], "dist": [0.0] * 5, "image_size": [20, 16]}
_COLOR_CAMERA = {"K": [[400.0, 0, 39.5], [0, 400.0, 31.5], [0, 0, 1]], "dist": [0.0] * 5, "image_size": [80, 64]}
_RIG = {"depth_camera": _DEPTH_CAMERA, "color_camera": _COLOR_CAMERA,
        "R": [[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]], "t": [-0.05, 0.0, 0.0]}


def _json(ws: Workspace, name: str, data) -> Path:
    return ws.file(name, json.dumps(data))


def _rig_case(ws: Workspace, command: str, rig: dict | str, expect: list[str]) -> Case:
    from depthrefine.io import read_chain_settings

    path = ws.file("rig.json", rig if isinstance(rig, str) else json.dumps(rig))
    if command == "align":
        argv = ["align", str(ws.depth), "-o", str(ws.out / "a.png"), "--rig", str(path), "--inverse-depth-scale", "255"]
    else:
        argv = ["run", str(ws.depth), str(ws.color), "-o", str(ws.result), "--rig", str(path),
                "--inverse-depth-scale", "255"]
    return Case(argv, [str(path), *expect], lib=lambda: read_chain_settings(path))


def _camera_case(ws: Workspace, camera: dict, expect: list[str]) -> Case:
    from depthrefine.io import read_camera

    path = _json(ws, "camera.json", camera)
    return Case(["undistort", str(ws.depth), "--camera", str(path), "-o", str(ws.out / "u.png")], [str(path), *expect],
                lib=lambda: read_camera(path))


def _with(mapping: dict, **changes) -> dict:
    return {**mapping, **changes}


def _without(mapping: dict, key: str) -> dict:
    return {k: v for k, v in mapping.items() if k != key}


OTHER_CASES: dict[str, Callable[[Workspace], Case]] = {
    # demo
    "demo: output is a file": lambda ws: Case(["demo", "-o", str(ws.out / "earlier.png")], ["earlier.png", "give a folder name"]),
    "demo: output folder not empty": lambda ws: Case(["demo", "-o", str(ws.out)], [str(ws.out), "pass --overwrite"]),
    "demo: scale 3": lambda ws: Case(["demo", "-o", str(ws.out / "d"), "--scale", "3"], ["--scale", "invalid choice"]),
    "demo: unknown scene": lambda ws: Case(["demo", "-o", str(ws.out / "d"), "--scene", "kitchen"],
                                           ["--scene", "invalid choice"]),
    # rig import, board
    "rig: calibration file of the wrong kind": lambda ws: Case(
        ["rig", "import", str(ws.color), "-o", str(ws.out / "rig.json")], [str(ws.color), "not a text file"]),
    "rig: K4A file without the mode": lambda ws: Case(
        ["rig", "import", str(ws.file("calibration.json", (sample_folder("mug") / "calibration.json").read_text())),
         "-o", str(ws.out / "rig.json")], ["calibration.json", "give --depth-mode"]),
    "board: too large for the page": lambda ws: Case(
        ["board", "--board", "charuco:14x9", "--square", "40mm", "--marker", "30mm", "-o", str(ws.out / "b.pdf")],
        ["560 x 360 mm", "does not fit on A4"]),
    "board: unknown dictionary": lambda ws: Case(
        ["board", "--board", "charuco:5x7", "--square", "30mm", "--marker", "22mm", "--dictionary", "DICT_5X5",
         "-o", str(ws.out / "b.png")], ["--dictionary", "unknown ArUco dictionary 'DICT_5X5'"]),
    # refine, show, run: DEPTH and COLOR must be two files (issue 24)
    "refine: DEPTH is COLOR": lambda ws: Case(ws.refine(ws.color, ws.color), ["DEPTH and COLOR are the same file"]),
    "refine: COLOR has DEPTH's bytes": lambda ws: Case(
        ws.refine(ws.depth, ws.file("copy.png", ws.depth.read_bytes())), ["copy.png", "identical bytes"]),
    "refine: --full without --preview": lambda ws: Case(ws.refine(None, None, "--full"), ["--full", "--preview PNG"]),
    "show: crop outside the map": lambda ws: Case(
        ["show", str(ws.depth), "-o", str(ws.out / "s.png"), "--crop", "0,0,1000,10"], ["--crop", "must lie inside"]),
    # data
    "data: verify a folder without data sets": lambda ws: Case(["data", "verify", str(ws.inputs)],
                                                               [str(ws.inputs), "none of the data set folders"]),
    "data: fetch a data set without an open licence": lambda ws: Case(
        ["data", "fetch", "lu6", "--to", str(ws.out / "d")], ["lu6 is not downloaded", "no licence"],
        lib=lambda: fetch_dataset("lu6", ws.out / "d")),
    "data: unknown data set": lambda ws: Case(["data", "fetch", "nope", "--to", str(ws.out / "d")],
                                              ["unknown data set 'nope'"]),
    # show
    "show: depth missing": lambda ws: Case(["show", str(ws.inputs / "none.png"), "-o", str(ws.out / "s.png")],
                                           ["none.png", "does not exist"]),
    "show: color image as depth": lambda ws: Case(["show", str(ws.color), "-o", str(ws.out / "s.png")],
                                                  ["depth map is one channel"]),
    "show: output not png": lambda ws: Case(["show", str(ws.depth), "-o", str(ws.out / "s.tif")], ["s.tif", ".png"]),
    "show: range reversed": lambda ws: Case(["show", str(ws.depth), "-o", str(ws.out / "s.png"), "--range", "5,1"],
                                            ["--range", "MIN < MAX"]),
    # calibrate, calibrate-stereo
    "calibrate: images missing": lambda ws: Case(
        ["calibrate", str(ws.inputs / "b1.png"), "--board", "9x6", "--square", "25mm", "-o", str(ws.out / "cam.json")],
        ["b1.png", "does not exist"]),
    "calibrate: no board in any image": lambda ws: Case(
        ["calibrate", str(ws.color), str(ws.file("c2.png", RGB)), str(ws.file("c3.png", RGB)), "--board", "9x6",
         "--square", "25mm", "-o", str(ws.out / "cam.json")], ["found in 0 of 3 images", "Check --board"]),
    "calibrate: board 0x6": lambda ws: Case(
        ["calibrate", str(ws.color), "--board", "0x6", "--square", "25mm", "-o", str(ws.out / "cam.json")], ["--board"]),
    "calibrate: negative square": lambda ws: Case(
        ["calibrate", str(ws.color), "--board", "9x6", "--square", "-3mm", "-o", str(ws.out / "cam.json")], ["--square"]),
    "calibrate: output not JSON": lambda ws: Case(
        ["calibrate", str(ws.color), "--board", "9x6", "--square", "25mm", "-o", str(ws.out / "cam.txt")],
        ["cam.txt", "unknown format", ".json"]),
    "calibrate: image is an empty folder": lambda ws: (
        (ws.inputs / "shots").mkdir(),
        Case(["calibrate", str(ws.inputs / "shots"), "--board", "9x6", "--square", "25mm", "-o",
              str(ws.out / "cam.json")], ["shots", "is a folder"]))[1],
    "calibrate-stereo: unpaired images": lambda ws: Case(
        ["calibrate-stereo", "--depth-images", str(ws.depth), str(ws.depth), "--color-images", str(ws.color),
         "--board", "9x6", "--square", "25mm", "-o", str(ws.out / "rig.json")],
        ["2 depth images and 1 color images", "give them in pairs"]),
    "calibrate-stereo: no board in any pair": lambda ws: Case(
        ["calibrate-stereo", "--depth-images", *[str(ws.file(f"d{i}.png", RGB)) for i in range(3)],
         "--color-images", *[str(ws.file(f"c{i}.png", RGB)) for i in range(3)], "--board", "9x6",
         "--square", "25mm", "-o", str(ws.out / "rig.json")], ["0 of 3 pairs", "Check --board"]),
    "calibrate-stereo: camera file missing keys": lambda ws: Case(
        ["calibrate-stereo", "--depth-images", str(ws.depth), "--color-images", str(ws.color), "--board", "9x6",
         "--square", "25mm", "--depth-camera", str(_json(ws, "cam.json", _without(_DEPTH_CAMERA, "K"))),
         "-o", str(ws.out / "rig.json")], ["cam.json", "lacks key(s) K"]),
    # align, undistort, run, export-ply: rig and camera files
    "align: rig missing": lambda ws: Case(
        ["align", str(ws.depth), "-o", str(ws.out / "a.png"), "--rig", str(ws.inputs / "rig.json"),
         "--inverse-depth-scale", "255"], ["rig.json", "does not exist"]),
    "align: rig with singular R": lambda ws: _rig_case(ws, "align", _with(_RIG, R=[[1, 0, 0], [0, 1, 0], [0, 0, 0]]),
                                                       ["R must be a rotation matrix"]),
    "align: rig lacks t": lambda ws: _rig_case(ws, "align", _without(_RIG, "t"), ["lacks key(s) t"]),
    "align: rig not JSON": lambda ws: _rig_case(ws, "align", "{depth_camera: ", ["not valid JSON", "fix its syntax"]),
    "align: camera with fx = 0": lambda ws: _rig_case(
        ws, "align", _with(_RIG, depth_camera=_with(_DEPTH_CAMERA, K=[[0, 0, 9.5], [0, 100, 7.5], [0, 0, 1]])),
        ["K must be"]),
    "align: depth all zero": lambda ws: Case(
        ["align", str(ws.file("z.png", np.zeros(DEPTH_SHAPE, np.uint8))), "-o", str(ws.out / "a.png"),
         "--rig", str(_json(ws, "rig.json", _RIG)), "--inverse-depth-scale", "255"], ["z.png", "has no valid pixel"]),
    "align: output exists": lambda ws: Case(
        ["align", str(ws.depth), "-o", str(ws.out / "earlier.png"), "--rig", str(_json(ws, "rig.json", _RIG)),
         "--inverse-depth-scale", "255"], ["earlier.png", "pass --overwrite"]),
    "undistort: camera lacks dist": lambda ws: _camera_case(ws, _without(_DEPTH_CAMERA, "dist"), ["lacks key(s) dist"]),
    "undistort: camera image_size wrong": lambda ws: _camera_case(ws, _with(_DEPTH_CAMERA, image_size=[20]),
                                                                  ["image_size must be two positive integers"]),
    "run: rig with singular R": lambda ws: _rig_case(ws, "run", _with(_RIG, R=[[0, 0, 0]] * 3),
                                                     ["R must be a rotation matrix"]),
    "run: color missing": lambda ws: Case(
        ["run", str(ws.depth), str(ws.inputs / "nope.png"), "-o", str(ws.result), "--rig",
         str(_json(ws, "rig.json", _RIG)), "--inverse-depth-scale", "255"], ["nope.png", "does not exist"]),
    "run: clusters 0": lambda ws: Case(
        ["run", str(ws.depth), str(ws.color), "-o", str(ws.result), "--rig", str(_json(ws, "rig.json", _RIG)),
         "--inverse-depth-scale", "255", "--clusters", "0"], ["--clusters", "must be a whole number >= 1"]),
    "run: params unknown key": lambda ws: Case(
        ["run", str(ws.depth), str(ws.color), "-o", str(ws.result), "--rig", str(_json(ws, "rig.json", _RIG)),
         "--inverse-depth-scale", "255", "--params", str(_toml(ws, "clusterz = 3\n"))], ["'clusterz'"]),
    "run: max-pixels": lambda ws: Case(
        ["run", str(ws.depth), str(ws.color), "-o", str(ws.result), "--rig", str(_json(ws, "rig.json", _RIG)),
         "--inverse-depth-scale", "255", "--max-pixels", "1000"], ["color.png", "limit of 1,000"]),
    "export-ply: output not PLY": lambda ws: Case(
        ["export-ply", str(ws.depth), str(ws.color), "-o", str(ws.out / "cloud.txt"), "--rig",
         str(_json(ws, "rig.json", _RIG)), "--inverse-depth-scale", "255"], ["cloud.txt", "unknown format"]),
    # batch (more in test_batch.py: bags, unpaired and unreadable frames)
    "batch: input missing": lambda ws: Case(["batch", str(ws.inputs / "seq"), "-o", str(ws.root / "b")],
                                            ["seq", "does not exist"]),
    "batch: folder without depth/": lambda ws: Case(["batch", str(ws.inputs), "-o", str(ws.root / "b")],
                                                    [str(ws.inputs), "has no depth/ subfolder"]),
    "batch: manifest without a color column": lambda ws: Case(
        ["batch", str(ws.file("list.csv", "depth\ndepth.png\n")), "-o", str(ws.root / "b")],
        ["list.csv", "depth and color"]),
    "batch: output inside the input": lambda ws: Case(
        ["batch", str(ws.file("list.csv", "depth,color\ndepth.png,color.png\n")), "-o", str(ws.inputs / "b")],
        ["is inside the input", "outside"]),
    "batch: output folder of something else": lambda ws: Case(
        ["batch", str(ws.file("list.csv", "depth,color\ndepth.png,color.png\n")), "-o", str(ws.out)],
        [str(ws.out), "holds no batch.json"]),
    "batch: topics for a folder": lambda ws: Case(
        ["batch", str(ws.file("list.csv", "depth,color\ndepth.png,color.png\n")), "-o", str(ws.root / "b"),
         "--depth-topic", "/d"], ["list.csv", "not a ROS bag", "--depth-topic"]),
    "batch: chunk without temporal": lambda ws: Case(
        ["batch", str(ws.inputs), "-o", str(ws.root / "b"), "--chunk", "4"], ["--chunk", "--temporal"]),
    "batch: workers with a scheduler": lambda ws: Case(
        ["batch", str(ws.inputs), "-o", str(ws.root / "b"), "--workers", "2", "--scheduler", "tcp://127.0.0.1:9"],
        ["--workers", "drop --workers"]),
    "batch: max-dt not a duration": lambda ws: Case(
        ["batch", str(ws.inputs), "-o", str(ws.root / "b"), "--max-dt", "soon"], ["--max-dt", "20ms"]),
    # bench
    "bench: data folder missing": lambda ws: Case(["bench", "--data", str(ws.inputs / "nodata")], ["--data", "nodata"]),
    "bench: data folder empty": lambda ws: (
        (ws.inputs / "emptydata").mkdir(),
        Case(["bench", "--data", str(ws.inputs / "emptydata")], ["emptydata", "none of the dataset", "pass --data"]))[1],
    "bench: unknown method": lambda ws: Case(["bench", "--data", str(ws.inputs), "--methods", "thesis,magic"],
                                             ["'magic'", "choose one of"]),
    "bench: scale 0": lambda ws: Case(["bench", "--data", str(ws.inputs), "--scales", "0"], ["--scales"]),
    "bench: report folder not empty": lambda ws: Case(
        ["bench", "--data", str(ws.inputs), "--report", str(ws.out)], ["report folder", str(ws.out), "pass --overwrite"]),
}


@pytest.mark.parametrize("name", list(OTHER_CASES))
def test_bad_input_other_commands(name, tmp_path, capsys):
    """The other subcommands keep the same promises: exit 2, one line, nothing written, inputs untouched."""
    case = OTHER_CASES[name](Workspace(tmp_path))
    line = _refused(case, case.argv[0], tmp_path, capsys)
    if case.lib is not None:
        with pytest.raises((ValueError, TypeError)) as info:
            case.lib()
        assert _one_line(str(info.value)) in line, f"library: {info.value}\ncli: {line}"


def test_other_cases_cover_every_command():
    """Every subcommand of the CLI has at least one case in the second table (or the first, for refine)."""
    commands = set(cli.build_parser()._subparsers._group_actions[0].choices)
    covered = {"refine"} | {name.split(":")[0] for name in OTHER_CASES}
    assert commands <= covered, f"no bad-input case for {sorted(commands - covered)}"


def test_missing_dependency_in_batch_says_what_to_install(monkeypatch, numba_kernels, no_numba):
    """A frame that needs a missing package (numba for the thesis method without its C kernels) fails with the pip
    advice, not an internal error."""
    from distributed import Client, LocalCluster

    from depthrefine.batch import refine_many

    frames = {0: (np.full((8, 8), 100, np.uint8), np.zeros((32, 32, 3), np.uint8))}
    with LocalCluster(n_workers=1, processes=False) as cluster, Client(cluster) as client:
        with pytest.raises(RuntimeError) as info:
            list(refine_many(frames, method="thesis", client=client))
    message = str(info.value)
    assert "pip install numba" in message and "internal error" not in message and "\n" not in message

