"""depthrefine.io: formats, atomic outputs, no overwrite without asking, header sizes."""

from __future__ import annotations

import os
import stat
from pathlib import Path

import cv2
import numpy as np
import pytest
import tifffile

from depthrefine.io import (
    InputFileError,
    atomic_directory,
    atomic_write,
    check_output,
    check_output_dir,
    image_shape,
    read_depth,
    read_rgb,
    write_depth,
    write_rgb,
)
from depthrefine.io import _images


def _listing(folder: Path) -> dict[str, bytes]:
    """Every file under folder (hidden ones too) with its bytes."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


DEPTH = np.array([[np.nan, 0.4, 1.6], [200.2, 300.0, 7.0]], np.float32)


# ----------------------------------------------------------------------------
# Round trips
# ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("name", "dtype", "expected"),
    [
        ("d.png", np.uint8, [[0, 1, 2], [200, 255, 7]]),  # valid never becomes 0; clipped to the dtype
        ("d.png", np.uint16, [[0, 1, 2], [200, 300, 7]]),
        ("d.tif", np.float32, [[0.0, 0.4, 1.6], [200.2, 300.0, 7.0]]),
        ("d.npy", np.float64, [[0.0, 0.4, 1.6], [200.2, 300.0, 7.0]]),
    ],
)
def test_write_read_round_trip(tmp_path, name, dtype, expected):
    path = write_depth(tmp_path / name, DEPTH, dtype=dtype)
    back = read_depth(path)
    assert back.dtype == dtype
    np.testing.assert_allclose(back, np.array(expected, dtype=dtype), rtol=1e-6)
    assert _listing(tmp_path).keys() == {name}  # no temporary file left


def test_written_file_has_normal_permissions(tmp_path):
    path = write_depth(tmp_path / "d.png", DEPTH, dtype=np.uint8)
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~mask  # not mkstemp's 0600


def test_read_rgb_is_rgb_order(tmp_path):
    bgr = np.zeros((2, 3, 3), np.uint8)
    bgr[:, :, 2] = 255  # red in OpenCV's BGR
    cv2.imwrite(str(tmp_path / "red.png"), bgr)
    rgb = read_rgb(tmp_path / "red.png")
    assert rgb[0, 0].tolist() == [255, 0, 0]
    write_rgb(tmp_path / "again.png", rgb)
    assert read_rgb(tmp_path / "again.png")[0, 0].tolist() == [255, 0, 0]


def test_read_depth_saturated_invalid(tmp_path):
    depth = np.array([[10, 65535], [65534, 0]], np.uint16)
    cv2.imwrite(str(tmp_path / "d.png"), depth)
    np.testing.assert_array_equal(read_depth(tmp_path / "d.png"), depth)
    np.testing.assert_array_equal(read_depth(tmp_path / "d.png", saturated_invalid=True), [[10, 0], [65534, 0]])
    np.save(tmp_path / "f.npy", np.array([[1.5, np.inf]], np.float32))  # floats: the option changes nothing
    np.testing.assert_array_equal(read_depth(tmp_path / "f.npy", saturated_invalid=True), [[1.5, np.inf]])


def test_read_depth_no_valid_pixel(tmp_path):
    np.save(tmp_path / "z.npy", np.array([[0, np.nan], [-1, np.inf]], np.float32))
    with pytest.raises(InputFileError, match=r"depth file .*z.npy has no valid pixel"):
        read_depth(tmp_path / "z.npy")
    cv2.imwrite(str(tmp_path / "s.png"), np.full((2, 2), 255, np.uint8))
    assert read_depth(tmp_path / "s.png").max() == 255
    with pytest.raises(InputFileError, match="has no valid pixel"):
        read_depth(tmp_path / "s.png", saturated_invalid=True)


# ----------------------------------------------------------------------------
# Sizes from headers
# ----------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["a.png", "a.jpg", "a.bmp", "a.tif", "a.npy", "p.jpg"])
def test_image_shape_from_header(tmp_path, name):
    image = np.zeros((37, 53, 3), np.uint8)
    path = tmp_path / name
    if name.endswith(".tif"):
        tifffile.imwrite(path, image, photometric="rgb")
    elif name.endswith(".npy"):
        np.save(path, image)
    elif name == "p.jpg":
        cv2.imwrite(str(path), image, [cv2.IMWRITE_JPEG_PROGRESSIVE, 1])
    else:
        cv2.imwrite(str(path), image)
    assert image_shape(path) == (37, 53)


def test_image_shape_unknown_or_damaged(tmp_path):
    (tmp_path / "x.webp").write_bytes(b"RIFF....WEBP")
    (tmp_path / "bad.jpg").write_bytes(b"\xff\xd8\xff\xe0\x00\x00")  # zero-length segment: no endless loop
    (tmp_path / "bad.tif").write_bytes(b"II*\x00garbage")
    for name in ("x.webp", "bad.jpg", "bad.tif"):
        assert image_shape(tmp_path / name) is None


def test_huge_header_refused_before_decoding(tmp_path, monkeypatch):
    header = (b"\x89PNG\r\n\x1a\n\x00\x00\x00\x0dIHDR" + (70000).to_bytes(4, "big") + (50000).to_bytes(4, "big")
              + b"\x10\x00\x00\x00\x00")
    (tmp_path / "big.png").write_bytes(header)
    monkeypatch.setattr(_images, "_read_any", lambda *a: pytest.fail("decoded a file that is too large"))
    with pytest.raises(InputFileError, match=r"depth file .*big.png is 70000x50000 = 3,500,000,000 pixels"):
        read_depth(tmp_path / "big.png")
    with pytest.raises(InputFileError, match="limit of 1,000"):
        read_rgb(tmp_path / "big.png", max_pixels=1000)


def test_decoder_messages_are_caught(tmp_path, capfd):
    """libpng's own complaint (printed by C code on fd 2) goes into our message, not onto the terminal."""
    ok, buf = cv2.imencode(".png", np.random.default_rng(0).integers(0, 255, (64, 64), dtype=np.uint8))
    data = bytearray(buf.tobytes())
    idat = data.index(b"IDAT")
    data[idat + 10: idat + 20] = bytes(10)  # damaged compressed data: CRC mismatch
    (tmp_path / "crc.png").write_bytes(bytes(data))
    with pytest.raises(InputFileError, match=r"crc.png cannot be read \(libpng error: IDAT"):
        read_depth(tmp_path / "crc.png")
    assert capfd.readouterr().err == ""
    (tmp_path / "cut.png").write_bytes(bytes(data[: len(data) // 2]))
    with pytest.raises(InputFileError, match=r"cut.png cannot be read \(the PNG has no IEND chunk"):
        read_depth(tmp_path / "cut.png")


# ----------------------------------------------------------------------------
# No overwrite, atomic files
# ----------------------------------------------------------------------------


def test_no_overwrite_without_permission(tmp_path):
    path = tmp_path / "d.png"
    path.write_bytes(b"old")
    with pytest.raises(InputFileError, match="exists; pass --overwrite"):
        write_depth(path, DEPTH, dtype=np.uint8)
    assert path.read_bytes() == b"old"
    write_depth(path, DEPTH, dtype=np.uint8, overwrite=True)
    assert read_depth(path).dtype == np.uint8
    assert _listing(tmp_path).keys() == {"d.png"}


@pytest.mark.parametrize("name", ["d.tif", "d.npy", "d.png"])
@pytest.mark.parametrize("exists", [False, True])
def test_failure_while_writing_leaves_nothing(tmp_path, monkeypatch, name, exists):
    """Writing the encoded file dies halfway (a full disk): no file (or the old file intact) and no temporary file."""
    path = tmp_path / name
    if exists:
        path.write_bytes(b"the previous result")
    before = _listing(tmp_path)
    real = Path.write_bytes
    seen = []

    def dies(self, data):
        real(self, bytes(data)[: len(data) // 2])
        seen.append(self)
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(Path, "write_bytes", dies)
    with pytest.raises(OSError, match="No space left"):
        write_depth(path, DEPTH, dtype=np.float32 if name != "d.png" else np.uint16, overwrite=True)
    monkeypatch.setattr(Path, "write_bytes", real)
    assert seen and seen[0] != path and seen[0].parent == tmp_path  # it wrote beside, not onto, the target
    assert _listing(tmp_path) == before


def test_interrupt_while_writing_leaves_nothing(tmp_path):
    def interrupted(tmp):
        tmp.write_bytes(b"partial")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        atomic_write(tmp_path / "x.png", interrupted)
    assert _listing(tmp_path) == {}


def test_atomic_write_does_not_clobber_a_file_that_appeared(tmp_path):
    """A file created by someone else after check_output is kept when overwrite is false."""
    path = tmp_path / "r.npy"

    def slow_writer(tmp):
        path.write_bytes(b"someone else's")  # appears while we write
        tmp.write_bytes(b"ours")

    with pytest.raises(InputFileError, match="exists; pass --overwrite"):
        atomic_write(path, slow_writer, overwrite=False)
    assert _listing(tmp_path) == {"r.npy": b"someone else's"}
    atomic_write(path, lambda tmp: tmp.write_bytes(b"ours"), overwrite=True)
    assert _listing(tmp_path) == {"r.npy": b"ours"}


def test_check_output(tmp_path):
    (tmp_path / "in.png").write_bytes(b"x")
    with pytest.raises(InputFileError, match="is a folder"):
        check_output(tmp_path)
    with pytest.raises(InputFileError, match="also an input file"):
        check_output(tmp_path / "in.png", overwrite=True, inputs=(tmp_path / "." / "in.png",))
    with pytest.raises(InputFileError, match=r"unknown format '.jpg'; use one of .png"):
        check_output(tmp_path / "r.jpg", suffixes=(".png", ".npy"))
    with pytest.raises(InputFileError, match="does not exist; create it first"):
        check_output(tmp_path / "no" / "r.png")
    assert check_output(tmp_path / "r.png", suffixes=(".png",), inputs=(tmp_path / "in.png",)) == tmp_path / "r.png"
    assert check_output(tmp_path / "in.png", overwrite=True) == tmp_path / "in.png"


# ----------------------------------------------------------------------------
# Atomic folders
# ----------------------------------------------------------------------------


def test_atomic_directory_appears_whole(tmp_path):
    target = tmp_path / "steps"
    with atomic_directory(target) as tmp:
        (tmp / "a.png").write_bytes(b"a")
        assert not target.exists()
    assert _listing(tmp_path) == {"steps/a.png": b"a"}


def test_atomic_directory_failure_leaves_nothing(tmp_path):
    with pytest.raises(RuntimeError):
        with atomic_directory(tmp_path / "steps") as tmp:
            (tmp / "a.png").write_bytes(b"a")
            raise RuntimeError("bug")
    assert list(tmp_path.iterdir()) == []


def test_atomic_directory_overwrite_replaces_only_at_the_end(tmp_path):
    target = tmp_path / "steps"
    target.mkdir()
    (target / "a.png").write_bytes(b"old a")
    (target / "keep.txt").write_bytes(b"mine")
    with pytest.raises(InputFileError, match="not empty; pass --overwrite"):
        with atomic_directory(target):
            pytest.fail("must refuse before the block runs")
    with pytest.raises(RuntimeError):
        with atomic_directory(target, overwrite=True) as tmp:
            (tmp / "a.png").write_bytes(b"new a")
            raise RuntimeError("bug")
    assert _listing(tmp_path) == {"steps/a.png": b"old a", "steps/keep.txt": b"mine"}
    with atomic_directory(target, overwrite=True) as tmp:
        (tmp / "a.png").write_bytes(b"new a")
    assert _listing(tmp_path) == {"steps/a.png": b"new a", "steps/keep.txt": b"mine"}


def test_check_output_dir(tmp_path):
    (tmp_path / "f").write_bytes(b"x")
    with pytest.raises(InputFileError, match="is not a folder"):
        check_output_dir(tmp_path / "f")
    with pytest.raises(InputFileError, match="its parent .* does not exist"):
        check_output_dir(tmp_path / "a" / "b")
    (tmp_path / "empty").mkdir()
    assert check_output_dir(tmp_path / "empty") == tmp_path / "empty"
    assert check_output_dir(tmp_path / "new") == tmp_path / "new"
