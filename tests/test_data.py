"""``depthrefine data``: the data set catalog, ``data verify`` and ``data fetch`` against a loopback server.

The fetch tests serve files from a local HTTP server on 127.0.0.1 laid out as
raw.githubusercontent.com (``OWNER/REPO/COMMIT/PATH``): the iPhone LiDAR frame
shipped in the package (byte-identical to the upstream files, so the
catalog's real checksums apply), and, when ``../shared/data`` is there, the
Azure Kinect recording whose frames ``fetch`` derives with PyAV. No other
network is used.
"""

from __future__ import annotations

import functools
import http.server
import re
import shutil
import threading
from pathlib import Path

import pytest

from conftest import how_to_get, shared_data_path
from depthrefine.bench.protocols import PAIRS, PROTOCOLS
from depthrefine.cli import main
from depthrefine.io import DATASETS, file_sha256, sample_folder, verify_data

BOOKSHELF = DATASETS["iphone_lidar_bookshelf"]
#: The shipped bookshelf files under their names in the data set.
SHIPPED = {"image.jpg": "color.jpg", "arkit_depth.png": "depth.png", "LICENSE.PromptDA-Apache-2.0.txt": "LICENSE"}


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):  # no request log on stderr
        pass


@pytest.fixture
def server(tmp_path):
    """``(url, root)``: an HTTP server on 127.0.0.1 serving ``root``, stopped after the test."""
    root = tmp_path / "www"
    root.mkdir()
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(_Quiet, directory=str(root)))
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{httpd.server_address[1]}", root
    finally:
        httpd.shutdown()
        httpd.server_close()


def _serve(root: Path, dataset, files: dict[str, Path]) -> None:
    """Lay ``files`` ({file in the data set: source file}) out under ``root`` as the upstream repository."""
    for source in dataset.sources:
        for local, remote in source.files.items():
            if local in files:
                target = root / source.repo / source.commit / remote
                target.parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(files[local], target)


def _bookshelf_files() -> dict[str, Path]:
    return {local: sample_folder("bookshelf") / shipped for local, shipped in SHIPPED.items()}


def test_catalog_covers_every_protocol_and_every_fetched_file():
    folders = {d.folder.split("/")[0] for d in DATASETS.values()}
    for name, protocol in PROTOCOLS.items():
        if name != PAIRS:
            assert protocol.folder in folders, name
            assert any(name in d.protocols for d in DATASETS.values()), name
    for dataset in DATASETS.values():
        checksums = dataset.checksums
        assert checksums and all(re.fullmatch(r"[0-9a-f]{64}", h) for h in checksums.values()), dataset.name
        assert dataset.licence and dataset.original.startswith("http"), dataset.name
        if not dataset.fetch_refused:  # every file comes from a source or is derived from them
            fetched = {f for s in dataset.sources for f in s.files}
            assert fetched | set(dataset.derived) == set(checksums), dataset.name
    for dataset in DATASETS.values():  # every file the benchmark reads can be got: a URL, or made from fetched ones
        if dataset.protocols:
            assert set(dataset.file_urls()) | set(dataset.derived) == set(dataset.checksums), dataset.name
    assert {d.name for d in DATASETS.values() if not d.fetch_refused} == {
        "azure_kinect_mug", "iphone_lidar_bookshelf", "azure_kinect_charuco"}  # the MIT / Apache-2.0 captures


def test_data_lists_sources_licences_and_checksums(capsys):
    assert main(["data"]) == 0
    out = capsys.readouterr().out
    for dataset in DATASETS.values():
        assert f"{dataset.name}  ({dataset.folder}/, {len(dataset.checksums)} files)" in out
    assert "licence:   Apache-2.0 (DepthAnything/PromptDA)" in out and "fetch:     refused: " in out
    assert main(["data", "list", "iphone_lidar_bookshelf", "--files"]) == 0
    out = capsys.readouterr().out
    assert f"{BOOKSHELF.checksums['arkit_depth.png']}  arkit_depth.png" in out and "lu6" not in out
    # where to get a refused data set's files by hand, renamed ones too (Park's x8 input is the repository's depth_3)
    assert main(["data", "list", "middlebury2005_park", "--sources"]) == 0
    out = capsys.readouterr().out
    assert "by hand: depthrefine data list middlebury2005_park --sources" in out
    assert ("  books/noisy_x8.png  https://raw.githubusercontent.com/wliusjtu/Robust-Color-Guided-Depth-Map-Restoration/"
            "7fdec2b589f139728eb74f4eeeda2e92bd54ea23/Input%20%26%20Results/Input/book_depth_3_n.png\n") in out
    assert len([line for line in out.splitlines() if "  https://raw.githubusercontent.com/" in line]) == 37
    assert main(["data", "list", "azure_kinect_mug", "--sources"]) == 0
    assert "  derived/ir_640x576.png  (the IR packet" in capsys.readouterr().out


def test_verify_names_each_missing_extra_and_changed_file(tmp_path, capsys):
    folder = tmp_path / "data" / "real_tof" / "iphone_lidar_bookshelf"
    folder.mkdir(parents=True)
    for local, source in _bookshelf_files().items():
        shutil.copyfile(source, folder / local)
    (folder / "README.md").write_text("notes")  # documentation: not checked
    assert main(["data", "verify", str(tmp_path / "data")]) == 0
    assert "ok: 3 files of 1 data set(s) match (iphone_lidar_bookshelf)" in capsys.readouterr().err
    assert main(["data", "verify", str(folder)]) == 0  # the data set's own folder
    (folder / "image.jpg").write_bytes(b"not the frame")
    (folder / "arkit_depth.png").unlink()
    (folder / "notes.txt").write_text("mine")
    assert main(["data", "verify", str(tmp_path / "data")]) == 2
    captured = capsys.readouterr()
    lines = captured.out.strip().splitlines()
    assert len(lines) == 3, lines
    assert lines[0] == "missing  real_tof/iphone_lidar_bookshelf/arkit_depth.png"
    assert lines[1].startswith("mismatch real_tof/iphone_lidar_bookshelf/image.jpg (SHA-256 ")
    assert lines[2] == "extra    real_tof/iphone_lidar_bookshelf/notes.txt (not a file of the data set)"
    assert "3 problem(s)" in captured.err
    assert main(["data", "verify", str(tmp_path / "data"), "lu6"]) == 2
    assert "has no lu6/" in capsys.readouterr().err
    assert main(["data", "verify", str(tmp_path)]) == 2
    assert "holds none of the data set folders" in capsys.readouterr().err


def test_fetch_downloads_checks_and_moves_the_folder_into_place(server, tmp_path, capsys):
    url, www = server
    _serve(www, BOOKSHELF, _bookshelf_files())
    data = tmp_path / "data"
    assert main(["data", "fetch", "iphone_lidar_bookshelf", "--to", str(data), "--from", url]) == 0
    err = capsys.readouterr().err
    assert err.count(f"downloading {url}/DepthAnything/PromptDA/") == 3 and "SHA-256 checked" in err
    folder = data / "real_tof" / "iphone_lidar_bookshelf"
    assert sorted(p.name for p in folder.iterdir()) == sorted(SHIPPED)
    assert verify_data(data)[1] == []
    # again: the folder exists, so only with --overwrite
    assert main(["data", "fetch", "iphone_lidar_bookshelf", "--to", str(data), "--from", url]) == 2
    assert "--overwrite" in capsys.readouterr().err


def test_fetch_failures_leave_nothing_behind(server, tmp_path, capsys, monkeypatch):
    url, www = server
    files = _bookshelf_files()
    bad = tmp_path / "bad.png"
    bad.write_bytes(files["arkit_depth.png"].read_bytes()[:-10])
    _serve(www, BOOKSHELF, dict(files, **{"arkit_depth.png": bad}))
    data = tmp_path / "data"
    monkeypatch.setenv("DEPTHREFINE_DATA_URL", url)  # the environment variable instead of --from
    assert main(["data", "fetch", "iphone_lidar_bookshelf", "--to", str(data)]) == 2
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert "arkit_depth.png has SHA-256" in err and "nothing was written" in err
    assert not data.exists()  # not even the data root or real_tof/
    shutil.rmtree(www / "DepthAnything")
    assert main(["data", "fetch", "iphone_lidar_bookshelf", "--to", str(data)]) == 2
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert "could not download" in err and "HTTP 404" in err and "nothing was written" in err, err
    assert not data.exists()
    assert main(["data", "fetch", "middlebury2005_park", "--to", str(data)]) == 2
    err = capsys.readouterr().err
    assert "is not downloaded: no licence grants the right to copy it" in err and "vision.middlebury.edu" in err
    assert "`depthrefine data list middlebury2005_park --sources` gives each file's source" in err
    assert len(err.strip().splitlines()) == 1 and not data.exists()
    assert main(["data", "fetch", "nope", "--to", str(data)]) == 2
    assert "unknown data set 'nope'" in capsys.readouterr().err


@pytest.mark.shared_data
def test_fetch_derives_the_kinect_frames_from_the_recording(server, tmp_path, capsys):
    pytest.importorskip("av")
    shared = shared_data_path("real_tof", "azure_kinect_mug")
    url, www = server
    mug = DATASETS["azure_kinect_mug"]
    _serve(www, mug, {local: shared / local for local in ("recording.mkv", "calibration.json",
                                                          "LICENSE.pyk4a-MIT.txt")})
    assert main(["data", "fetch", "azure_kinect_mug", "--to", str(tmp_path), "--from", url]) == 0
    folder = tmp_path / "real_tof" / "azure_kinect_mug"
    for name in mug.derived:  # byte-identical to the copies the benchmark ran on
        assert file_sha256(folder / name) == file_sha256(shared / name), name


@pytest.mark.shared_data
def test_the_shared_data_matches_the_catalog(capsys):
    root = shared_data_path("middlebury2005_park").parent
    assert main(["data", "verify", str(root)]) == 0
    assert "ok: " in capsys.readouterr().err


def test_a_test_skipped_for_missing_data_says_how_to_get_it():
    assert how_to_get("real_tof/azure_kinect_charuco/calibration").startswith(
        "get it with `depthrefine data fetch azure_kinect_charuco --to DIR`; then run the tests with "
        "DEPTHREFINE_TEST_SHARED_DATA=DIR")
    assert "`depthrefine data list middlebury2005_park --sources` says where to get each file" in how_to_get(
        "middlebury2005_park/art")
    assert how_to_get("").startswith("`depthrefine data` lists the data sets and how to get each")
