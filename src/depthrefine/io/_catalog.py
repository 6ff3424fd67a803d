"""The benchmark data sets: where each comes from, under which terms, and the SHA-256 of every file.

Every folder the benchmark protocols read (``depthrefine bench``, laid out
as ``shared/data``) and the real captures have an entry in :data:`DATASETS`:
its original public source (repository and commit, or project page), its
licence, whether ``depthrefine data fetch`` may download it (only data
under an open licence is fetched; the others say why and where to get them
by hand), and the expected files with their SHA-256, read from
``data/catalog/<name>.sha256`` inside the package (``sha256sum`` format, so
``sha256sum -c`` checks a copy too). The checksums were computed from the
copies the project's benchmark ran on; ``README.md`` and ``SHA256SUMS``
files beside the data are documentation, neither expected nor extra.

This module only describes the data; :mod:`depthrefine.io._fetch` checks a
folder against it and downloads.
"""

from __future__ import annotations

import functools
import urllib.parse
from dataclasses import dataclass, field
from importlib import resources
from typing import Mapping

__all__ = ["DataSource", "Dataset", "DATASETS", "DOCUMENTATION_FILES", "RAW_BASE_URL", "get_dataset"]

#: Files beside the data that are documentation: neither expected nor extra.
DOCUMENTATION_FILES = ("README.md", "SHA256SUMS")
#: Where a :class:`DataSource`'s files are downloaded from (``{base}/{repo}/{commit}/{path}``).
RAW_BASE_URL = "https://raw.githubusercontent.com"


@dataclass(frozen=True)
class DataSource:
    """One public repository a data set's files were copied from, byte for byte.

    Attributes
    ----------
    repo : str
        ``owner/name`` on GitHub.
    commit : str
        The commit the files were taken at.
    files : mapping
        ``{file in the data set folder: path in the repository}``.
    """

    repo: str
    commit: str
    files: Mapping[str, str] = field(default_factory=dict)

    @property
    def url(self) -> str:
        """The repository at the commit, on GitHub."""
        return f"https://github.com/{self.repo}/tree/{self.commit}"


@dataclass(frozen=True)
class Dataset:
    """A benchmark data set (a folder of the data root, laid out as ``shared/data``).

    Attributes
    ----------
    name : str
        What ``depthrefine data fetch`` takes: the folder's own name.
    folder : str
        Its path inside the data root (``real_tof/azure_kinect_mug``).
    title : str
    protocols : tuple of str
        The ``bench`` protocols that read it (empty: not scored).
    licence : str
        The terms, in one line.
    original : str
        The original public source (a URL), and what the copy is.
    sources : tuple of DataSource
        The repositories its files come from (for ``fetch``, every file
        must come from one, or be in ``derived``).
    fetch_refused : str
        Why ``depthrefine data fetch`` does not download it ("" = it does).
    derived : mapping
        ``{file: how it is made}`` for files computed from fetched ones.
    """

    name: str
    folder: str
    title: str
    protocols: tuple[str, ...]
    licence: str
    original: str
    sources: tuple[DataSource, ...] = ()
    fetch_refused: str = ""
    derived: Mapping[str, str] = field(default_factory=dict)

    def file_urls(self, base_url: str = RAW_BASE_URL) -> dict[str, str]:
        """``{file: URL}`` of every file copied from a source: ``{base_url}/{repo}/{commit}/{path}`` (quoted).

        Also for a data set ``fetch`` refuses: where to get each file by hand.

        Examples
        --------
        >>> DATASETS["lu6"].file_urls()["Depth/RGBD_01_output_depth.png"]  # doctest: +ELLIPSIS
        'https://raw.githubusercontent.com/Zhaozixiang1228/GDSR-DCTNet/5243875.../RawDatasets/Lu/Depth/RGBD_01_output_depth.png'
        """
        base = base_url.rstrip("/")
        return {local: f"{base}/{source.repo}/{source.commit}/{urllib.parse.quote(remote)}"
                for source in self.sources for local, remote in source.files.items()}

    @property
    def sourced(self) -> bool:
        """Whether every expected file has a source URL (:meth:`file_urls`): a copy can be made by hand."""
        return set(self.file_urls()) == set(self.checksums)

    @property
    def checksums(self) -> dict[str, str]:
        """``{file: SHA-256 hex}`` of every expected file (package data ``data/catalog/<name>.sha256``)."""
        return dict(_checksums(self.name))


@functools.lru_cache(maxsize=None)
def _checksums(name: str) -> tuple[tuple[str, str], ...]:
    text = (resources.files("depthrefine") / "data" / "catalog" / f"{name}.sha256").read_text(encoding="utf-8")
    pairs = []
    for line in text.splitlines():
        if line.strip():
            digest, path = line.split(maxsplit=1)
            pairs.append((path.strip(), digest))
    return tuple(pairs)


_NO_LICENCE = ("no licence grants the right to copy it (the source repository has no licence file; the terms are "
               "research and evaluation use only)")
_DCTNET = ("Zhaozixiang1228/GDSR-DCTNet", "5243875223398fd7996bca2e54dc2792bb96862a")
_LU_SOURCE = DataSource(*_DCTNET)
#: Middlebury_01 (Aloe) and _24 (Reindeer) of the 30 pairs, and RGBD_06 of Lu's 6, are not in the benchmark's copies.
_LU30 = DataSource(*_DCTNET, {f"{kind}/Middlebury_{i:02d}_output_{what}.png":
                              f"RawDatasets/Middlebury/{kind}/Middlebury_{i:02d}_output_{what}.png"
                              for i in range(2, 31) if i != 24 for kind, what in (("RGB", "color"), ("Depth", "depth"))})
_LU6 = DataSource(*_DCTNET, {name: f"RawDatasets/Lu/{name}" for i in range(1, 6)
                             for name in (f"RGB/RGBD_{i:02d}_ouput_color.png", f"Depth/RGBD_{i:02d}_output_depth.png")})
_NYU = DataSource(*_DCTNET, {name: f"RawDatasets/NYUDepthv2_Test/{name}" for i in (1000, 1001, 1002)
                             for name in (f"RGB/{i}.jpg", f"Depth/{i}.npy")})
#: Park's scenes as the wliusjtu repository names them; ``<s>_depth_<k>_n.png`` is the x2**k input (its Main.m
#: runs depth_3_n as the 8X case).
_PARK_SCENES = {"art": "art", "books": "book", "dolls": "dolls", "laundry": "laundry", "moebius": "moebius"}
_PARK_INPUT = "Input & Results/Input/"
_PARK = DataSource("wliusjtu/Robust-Color-Guided-Depth-Map-Restoration", "7fdec2b589f139728eb74f4eeeda2e92bd54ea23", {
    **{f"{scene}/color.png": f"{_PARK_INPUT}{name}_color.png" for scene, name in _PARK_SCENES.items()},
    **{f"{scene}/gt_disp.png": f"{_PARK_INPUT}{name}_big.png" for scene, name in _PARK_SCENES.items()},
    **{f"{scene}/noisy_x{2 ** k}.png": f"{_PARK_INPUT}{name}_depth_{k}_n.png"
       for scene, name in _PARK_SCENES.items() for k in (1, 2, 3, 4)},
})
_MSGNET_VIEW1 = DataSource("twhui/MSG-Net", "852da0a093e530370ccb069507847220644df331", {
    f"{scene}/view1_fullsize.png": f"MSGNet-release/testing sets/A/RGB/{scene}.png" for scene in ("art", "books", "moebius")
})
_FERSTL = DataSource("RobVisLab/tofmark", "7a3404c52ece96c5af25e2398ef5650e5f64b118", {
    f"art/noisy_ferstl_x{2 ** k}.png": f"tgvl2/test_imgs/depth_{k}_n.png" for k in (1, 2, 3, 4)
})
_PYK4A = DataSource("etiennedub/pyk4a", "8c153164b484037bd7afc02db0c2be89e7bb8b38", {
    "recording.mkv": "tests/assets/recording.mkv",
    "calibration.json": "tests/assets/calibration.json",
    "LICENSE.pyk4a-MIT.txt": "LICENSE",
})
_PROMPTDA = DataSource("DepthAnything/PromptDA", "b05523cf9c27e2dbce578b9003a8906bf8ed2eb3", {
    "image.jpg": "assets/example_images/image.jpg",
    "arkit_depth.png": "assets/example_images/arkit_depth.png",
    "LICENSE.PromptDA-Apache-2.0.txt": "LICENSE",
})
_K4A_EXAMPLE = "examples/calibration_registration/"
_K4A_SDK = DataSource("microsoft/Azure-Kinect-Sensor-SDK", "8bb59caa9db1d5da32e382b87622c8cd91bbb8fe", {
    **{f"registration/{n}": f"{_K4A_EXAMPLE}example_files/registration/{n}"
       for n in ("color-0.jpg", "ir-0.png", "calib_color.yml", "calib_ir.yml")},
    **{f"calibration/{n}": f"{_K4A_EXAMPLE}example_files/calibration/{n}"
       for n in ["calib.yml"] + [f"color-{i}.jpg" for i in (1, 5, 8, 11, 12, 17, 19, 26)]},
    "plane.json": f"{_K4A_EXAMPLE}PlaneFiles/plane.json",
    "LICENSE.calibration_registration-MIT.txt": f"{_K4A_EXAMPLE}LICENSE",
    "LICENSE.Azure-Kinect-Sensor-SDK-MIT.txt": "LICENSE",
})

#: The data sets, in the order ``depthrefine data`` lists them.
DATASETS: dict[str, Dataset] = {d.name: d for d in (
    Dataset(
        "middlebury2005_park", "middlebury2005_park",
        "Middlebury 2005 (Art, Books, Dolls, Laundry, Moebius): hole-filled ground truth and the noisy x2-x16 "
        "inputs of Park et al. (ICCV 2011)",
        ("park", "tof", "sensor"),
        "research and evaluation use only: no licence file (wliusjtu); MSG-Net's view1 images non-commercial; "
        "Ferstl's Art inputs BSD-3-Clause (RobVisLab/tofmark)",
        "https://vision.middlebury.edu/stereo/data/ (scenes); inputs as in "
        "https://github.com/wliusjtu/Robust-Color-Guided-Depth-Map-Restoration/tree/"
        "7fdec2b589f139728eb74f4eeeda2e92bd54ea23 ('Input & Results/Input/')",
        (_PARK, _MSGNET_VIEW1, _FERSTL),
        fetch_refused=_NO_LICENCE + "; the files were also renamed from the source's",
    ),
    Dataset(
        "middlebury_lu30", "middlebury_lu30",
        "the 30-image Middlebury set of DKN / DCTNet / JIIF (Lu et al., CVPR 2014), 28 of the 30 pairs",
        ("middlebury30",),
        "research and evaluation use only: no licence file (GDSR-DCTNet); Lu et al. and Middlebury publish none",
        "http://web.cecs.pdx.edu/~fliu/project/depth-enhance/ (Depth_Enh.zip, 01_Middlebury_Dataset); copied from "
        f"{_LU_SOURCE.url} (RawDatasets/Middlebury/)",
        (_LU30,), fetch_refused=_NO_LICENCE,
    ),
    Dataset(
        "lu6", "lu6", "the Lu et al. (CVPR 2014) RGB-D captures, 5 of the 6 pairs", ("lu",),
        "research and evaluation use only: no licence file (GDSR-DCTNet); Lu et al. publish none",
        "http://web.cecs.pdx.edu/~fliu/project/depth-enhance/ (Depth_Enh.zip, 03_RGBD_Dataset); copied from "
        f"{_LU_SOURCE.url} (RawDatasets/Lu/)",
        (_LU6,), fetch_refused=_NO_LICENCE,
    ),
    Dataset(
        "azure_kinect_mug", "real_tof/azure_kinect_mug",
        "one real Azure Kinect ToF capture (depth 640x576 mm, IR, color 1280x720) with its factory calibration",
        ("realtof",), "MIT (etiennedub/pyk4a)", f"{_PYK4A.url} (tests/assets/)", (_PYK4A,),
        derived={"derived/color_1280x720.jpg": "the COLOR packet of recording.mkv, unchanged",
                 "derived/depth_640x576_mm.png": "the DEPTH packet (big-endian uint16) as a 16-bit PNG",
                 "derived/ir_640x576.png": "the IR packet (big-endian uint16) as a 16-bit PNG"},
    ),
    Dataset(
        "iphone_lidar_bookshelf", "real_tof/iphone_lidar_bookshelf",
        "one real iPhone LiDAR depth frame (256x192 mm) registered to its 1920x1440 RGB frame", ("realtof",),
        "Apache-2.0 (DepthAnything/PromptDA)", f"{_PROMPTDA.url} (assets/example_images/)", (_PROMPTDA,),
    ),
    Dataset(
        "azure_kinect_charuco", "real_tof/azure_kinect_charuco",
        "8 Azure Kinect color views of a ChArUco board with the upstream 30-view intrinsics, and one color + "
        "ToF-sensor IR pair (calibration tests)", (),
        "MIT (microsoft/Azure-Kinect-Sensor-SDK)", f"{_K4A_SDK.url} ({_K4A_EXAMPLE})", (_K4A_SDK,),
    ),
    Dataset(
        "middlebury2003_msgnet_c", "middlebury2003_msgnet_c",
        "Middlebury 2001/2003 Cones, Teddy, Tsukuba, Venus (MSG-Net testing set C)", (),
        "non-commercial use only (twhui/MSG-Net LICENSE)",
        "https://github.com/twhui/MSG-Net/tree/852da0a093e530370ccb069507847220644df331 ('MSGNet-release/testing "
        "sets/C/'), converted from .bmp/.mat to PNG",
        (DataSource("twhui/MSG-Net", "852da0a093e530370ccb069507847220644df331"),),
        fetch_refused="its licence is non-commercial only, and the files here were converted from the source's "
                      ".bmp and .mat (no public file has these bytes)",
    ),
    Dataset(
        "nyuv2_dctnet3", "nyuv2_dctnet3", "NYU Depth v2 test images 1000-1002 (metres, .npy)", (),
        "research and evaluation use only: no licence file (GDSR-DCTNet); NYU asks for a citation",
        "https://cs.nyu.edu/~silberman/datasets/nyu_depth_v2.html; copied from "
        f"{_LU_SOURCE.url} (RawDatasets/NYUDepthv2_Test/)",
        (_NYU,), fetch_refused=_NO_LICENCE,
    ),
)}


def get_dataset(name: str) -> Dataset:
    """The data set called ``name`` (``ValueError`` listing the known names)."""
    try:
        return DATASETS[name]
    except (KeyError, TypeError):
        raise ValueError(f"unknown data set {name!r}; choose one of {', '.join(DATASETS)} "
                         "(`depthrefine data` lists them).") from None
