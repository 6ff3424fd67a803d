"""The benchmark protocols, one :class:`Protocol` entry each, in a registry.

A protocol says which dataset folder it reads and how (``folder``, ``layout``,
``reader``: a reader of :mod:`depthrefine.io`), how a scene becomes a case at
a scale (``build_case``), which scenes were tuned on and are left out of the
means, its units, its title and the published numbers to put beside ours.
The ``bench`` command, the report and the data readers all read
:data:`PROTOCOLS`; adding a protocol is one :func:`register_protocol` call.

``park``
    Noisy Middlebury 2005 (Park et al., ICCV 2011): the given noisy
    low-resolution inputs ``noisy_x{4,8,16}.png``, guide ``color.png``, RMSE
    against ``gt_disp.png`` over the whole grid, in disparity levels.
``middlebury30``, ``lu``
    The 30-image Middlebury set and the Lu set (Lu et al., CVPR 2014), as
    in DKN / DCTNet / JIIF: the ground truth cropped to a multiple of the
    scale, min-max normalised, the low-resolution input made by PIL bicubic
    downsampling (:func:`bicubic_downsample`), mapped back to 0..255 units;
    RMSE in those units after a 6-pixel border crop.
``tof``, ``sensor``
    Simulated ToF (ours) from the Park ground truth and color, scored like ``park``: degraded on
    the color grid (:mod:`.simulate`), or seen by a depth camera beside it (:mod:`.sensor`).
``realtof``
    A self-benchmark on real ToF captures (``real_tof/``): the real depth is
    the target, the input is its valid-aware block mean at x4 and x8
    (:func:`realtof_case`); RMSE in millimetres over the target's valid pixels.

The scenes in :data:`TUNING_SCENES` are the ones the peers' parameters were
tuned on, and the same scenes seen under another protocol (``tof`` shares the
Park scenes; Park's Dolls and Laundry are ``Middlebury_14`` and ``_18`` of the
30-image set); their rows are marked ``split="tune"`` and the summaries leave
them out, saying why (:func:`left_out_reason`).
"""

from __future__ import annotations

import functools
import os
import zlib
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable, Mapping, Protocol as _Typing

# numpy, the runner and the simulator load on first use: ``depthrefine bench --help`` lists the
# protocols (names, titles) without them (fast start-up).
from .._lazy import numpy as np
from .sensor import SENSOR_PEER_PARAMS, SENSOR_TUNING_SCENES, sensor_protocol_cases

if TYPE_CHECKING:
    from .runner import BenchCase
    from .simulate import ToFModel

__all__ = [
    "Protocol",
    "PROTOCOLS",
    "register_protocol",
    "get_protocol",
    "load_cases",
    "TUNING_SCENES",
    "LEFT_OUT_WHY",
    "left_out_reason",
    "tuned_on_scenes",
    "LU_BORDER",
    "bicubic_downsample",
    "crop_to_multiple",
    "gt_float",
    "park_case",
    "lu_case",
    "tof_case",
    "tof_seed",
    "pairs_protocol",
    "PAIRS",
    "realtof_case",
    "realtof_guide",
    "REALTOF_SCALES",
]

#: Border crop of the middlebury30 / lu protocols, pixels.
LU_BORDER = 6


class Scene(_Typing):
    """What a reader of :mod:`depthrefine.io` returns per scene (``io.DatasetScene``)."""

    name: str
    rgb_hr: np.ndarray
    depth_gt: np.ndarray
    inputs: Mapping[int, np.ndarray]
    source: os.PathLike


@dataclass(frozen=True)
class Protocol:
    """One benchmark protocol.

    Attributes
    ----------
    name : str
        What ``--protocol`` takes.
    title : str
        One line for the report: data, input, scoring, units.
    folder : str
        The dataset folder it reads inside the data folder (as ``shared/data``).
    layout : str
        The files it expects, for error messages.
    reader : str
        The reader of :data:`depthrefine.io.DATASET_READERS` that reads ``folder``.
    build_case : callable
        ``build_case(protocol, scene, scale) -> BenchCase`` (or a list of cases); raises
        ``ValueError`` when the scene has no usable case at that scale (the message says why).
    units : str
        The units of the scores.
    tuning_scenes : tuple of str
        Scenes left out of the means (rows ``split="tune"``).
    left_out_why : mapping
        ``{scene: reason}`` for tuning scenes that were not tuned on directly.
    published_scenes : mapping
        ``{scale: {"scenes": (...), "rows": {name: {"source", "values": {scene: rmse}}}}}``.
    published_means : tuple of mapping
        ``({"name", "source", "images", "values": {scale: rmse}}, ...)``.
    reader_options : mapping
        Keyword arguments for the reader (e.g. ``invalid`` for ``triplets``).
    method_params : mapping
        ``{method: {field: value}}`` tuned for this protocol, used on its cases instead of the defaults.
    reprojected : bool
        The inputs came through the rig chain's reprojection onto the color camera (``sensor``): the methods
        whose parameters have ``reprojected`` are told so, as ``depthrefine run`` tells them
        (:func:`depthrefine.rig.chain.reprojected_params`).
    """

    name: str
    title: str
    folder: str
    layout: str
    reader: str
    build_case: Callable[["Protocol", Scene, int], BenchCase]
    units: str = "levels"
    tuning_scenes: tuple[str, ...] = ()
    left_out_why: Mapping[str, str] = field(default_factory=dict)
    published_scenes: Mapping[int, Mapping[str, Any]] = field(default_factory=dict)
    published_means: tuple[Mapping[str, Any], ...] = ()
    reader_options: Mapping[str, Any] = field(default_factory=dict)
    method_params: Mapping[str, Mapping[str, Any]] = field(default_factory=dict)
    reprojected: bool = False


#: The registered protocols, in report order.
PROTOCOLS: dict[str, Protocol] = {}
#: Scenes left out of every mean, per protocol (rows marked ``split="tune"``):
#: the scenes the peers were tuned on, and the same scenes under another
#: protocol (:data:`LEFT_OUT_WHY` says why each one is left out). Kept in step
#: with :data:`PROTOCOLS` by :func:`register_protocol`.
TUNING_SCENES: dict[str, tuple[str, ...]] = {}
#: Why a scene of :data:`TUNING_SCENES` is left out, ``{(protocol, scene): reason}``.
#: Scenes not listed here were tuned on directly.
LEFT_OUT_WHY: dict[tuple[str, str], str] = {}


def register_protocol(protocol: Protocol, *, replace: bool = False) -> Protocol:
    """Add ``protocol`` to :data:`PROTOCOLS` (``ValueError`` if its name is taken, unless ``replace``)."""
    if protocol.name in PROTOCOLS and not replace:
        raise ValueError(f"a protocol named {protocol.name!r} is already registered; pass replace=True.")
    PROTOCOLS[protocol.name] = protocol
    TUNING_SCENES.pop(protocol.name, None)
    for key in [k for k in LEFT_OUT_WHY if k[0] == protocol.name]:
        del LEFT_OUT_WHY[key]
    if protocol.tuning_scenes:
        TUNING_SCENES[protocol.name] = tuple(protocol.tuning_scenes)
    LEFT_OUT_WHY.update({(protocol.name, s): why for s, why in protocol.left_out_why.items()})
    return protocol


def get_protocol(name: str) -> Protocol:
    """The registered protocol called ``name`` (``ValueError`` listing the known ones)."""
    try:
        return PROTOCOLS[name]
    except (KeyError, TypeError):
        raise ValueError(f"unknown protocol {name!r}; choose one of {list(PROTOCOLS)}.") from None


def left_out_reason(protocol: str, scene: str) -> str:
    """Why ``scene`` is left out of ``protocol``'s means ("" if it is not).

    Examples
    --------
    >>> left_out_reason("middlebury30", "Middlebury_14")
    'Dolls (middlebury_lu30 README), a Park tuning scene'
    >>> left_out_reason("park", "dolls"), left_out_reason("park", "art")
    ('tuned on', '')
    """
    if scene not in TUNING_SCENES.get(protocol, ()):
        return ""
    return LEFT_OUT_WHY.get((protocol, scene), "tuned on")


def tuned_on_scenes(protocol: str) -> tuple[str, ...]:
    """The scenes of ``protocol`` the peers' parameters were tuned on (not those left out as duplicates).

    Examples
    --------
    >>> tuned_on_scenes("middlebury30")
    ('Middlebury_03', 'Middlebury_10', 'Middlebury_19', 'Middlebury_25')
    """
    return tuple(s for s in TUNING_SCENES.get(protocol, ()) if (protocol, s) not in LEFT_OUT_WHY)


def crop_to_multiple(array: np.ndarray, scale: int) -> np.ndarray:
    """The top-left part of ``array`` whose rows and columns are multiples of ``scale`` (a view).

    Examples
    --------
    >>> crop_to_multiple(np.zeros((10, 13)), 4).shape
    (8, 12)
    """
    rows, cols = (array.shape[0] // scale) * scale, (array.shape[1] // scale) * scale
    if rows < scale or cols < scale:
        raise ValueError(f"an image of shape {array.shape[:2]} is smaller than one {scale}x{scale} block.")
    return array[:rows, :cols]


def gt_float(depth_gt: np.ndarray) -> np.ndarray:
    """Ground truth as float32 with NaN where it has no measurement (0, negative, not finite)."""
    gt = np.asarray(depth_gt).astype(np.float32)
    with np.errstate(invalid="ignore"):
        gt[~(np.isfinite(gt) & (gt > 0))] = np.nan
    return gt


def bicubic_downsample(depth_gt: np.ndarray, scale: int) -> np.ndarray:
    """Low-resolution input of the DKN / DCTNet / JIIF protocol, in the ground truth's units.

    The map is min-max normalised to [0, 1] (over all its pixels, as the
    published code does), resized to ``(W // scale, H // scale)`` with PIL's
    bicubic filter on a float ``'F'`` image, and mapped back with the same
    min and max. ``depth_gt`` should already be cropped to a multiple of
    ``scale``.

    Parameters
    ----------
    depth_gt : (H, W) ndarray
        Ground truth as stored (uint8 here).
    scale : int

    Returns
    -------
    (H // scale, W // scale) float32 ndarray

    Examples
    --------
    >>> bicubic_downsample(np.full((8, 8), 50, np.uint8), 4).tolist()
    [[50.0, 50.0], [50.0, 50.0]]
    """
    from PIL import Image

    raw = np.asarray(depth_gt, dtype=np.float64)
    lo, hi = float(raw.min()), float(raw.max())
    span = hi - lo if hi > lo else 1.0
    norm = ((raw - lo) / span).astype(np.float32)
    rows, cols = raw.shape[0] // scale, raw.shape[1] // scale
    small = Image.fromarray(norm).resize((cols, rows), Image.BICUBIC)
    return (np.asarray(small, dtype=np.float64) * span + lo).astype(np.float32)


def park_case(scene: str, scale: int, depth_lr: np.ndarray, rgb_hr: np.ndarray, depth_gt: np.ndarray,
              *, protocol: str = "park") -> BenchCase:
    """A case of the ``park`` protocol: the given noisy input, the whole ground-truth grid."""
    from .runner import BenchCase

    h, w = depth_lr.shape[:2]
    rows, cols = h * scale, w * scale
    if rows > depth_gt.shape[0] or cols > depth_gt.shape[1]:
        raise ValueError(
            f"{scene} x{scale}: the input ({w}x{h}) times {scale} is larger than the ground truth "
            f"({depth_gt.shape[1]}x{depth_gt.shape[0]})."
        )
    return BenchCase(protocol, scene, scale, depth_lr, rgb_hr[:rows, :cols], gt_float(depth_gt[:rows, :cols]),
                     border=0, split=_split(protocol, scene))


def lu_case(protocol: str, scene: str, scale: int, rgb_hr: np.ndarray, depth_gt: np.ndarray) -> BenchCase:
    """A case of the ``middlebury30`` / ``lu`` protocol (crop, PIL bicubic input, 6-pixel border)."""
    from .runner import BenchCase

    gt = crop_to_multiple(depth_gt, scale)
    rgb = rgb_hr[: gt.shape[0], : gt.shape[1]]
    return BenchCase(protocol, scene, scale, bicubic_downsample(gt, scale), rgb, gt_float(gt),
                     border=LU_BORDER, split=_split(protocol, scene))


def tof_seed(scene: str, scale: int) -> int:
    """The fixed seed of the simulated ToF input of a scene and scale.

    Examples
    --------
    >>> tof_seed("art", 8) == tof_seed("art", 8) != tof_seed("art", 4)
    True
    """
    return zlib.crc32(f"tof/{scene}/x{scale}".encode())


def tof_case(scene: str, scale: int, rgb_hr: np.ndarray, depth_gt: np.ndarray,
             *, model: ToFModel | None = None) -> BenchCase:
    """A case of the ``tof`` protocol: simulated ToF input (:func:`simulate_tof`), whole grid."""
    from .runner import BenchCase
    from .simulate import simulate_tof

    gt = crop_to_multiple(depth_gt, scale)
    rgb = rgb_hr[: gt.shape[0], : gt.shape[1]]
    depth_lr = simulate_tof(gt, rgb, scale=scale, model=model, seed=tof_seed(scene, scale))
    return BenchCase("tof", scene, scale, depth_lr, rgb, gt_float(gt), border=0, split=_split("tof", scene))


def _split(protocol: str, scene: str) -> str:
    return "tune" if scene in TUNING_SCENES.get(protocol, ()) else "test"


def load_cases(data_dir: str | os.PathLike, protocol: str, scales: tuple[int, ...], *,
               notes: list[str] | None = None) -> list[BenchCase]:
    """Every case of ``protocol`` at ``scales`` found under ``data_dir``, scene by scene.

    The files are read by the protocol's reader in :mod:`depthrefine.io`.

    Parameters
    ----------
    data_dir : path-like
        A folder laid out as ``shared/data`` (or the protocol's dataset folder).
    protocol : str
        A key of :data:`PROTOCOLS`.
    scales : tuple of int
        Empty: each scene at the scales of its given inputs (``--pairs``).
    notes : list of str, optional
        Each scene or scale skipped (a missing or unusable file) appends
        one line here, naming the protocol, the scene, the scale and why.

    Returns
    -------
    list of BenchCase
        Ordered by scene, then scale.

    Raises
    ------
    InputFileError
        The dataset folder is missing, or no case at all is usable (the
        message names the expected layout and the first reason).
    """
    from ..io import InputFileError, read_dataset

    entry = get_protocol(protocol)
    mine: list[str] = []
    folder, scenes = read_dataset(data_dir, entry.folder, entry.reader, protocol=entry.name, layout=entry.layout,
                                  scales=scales, notes=mine, options=dict(entry.reader_options))
    mine[:] = [f"{protocol}: {n}" for n in mine]
    cases: list[BenchCase] = []
    for scene in scenes:
        for s in scales or sorted(scene.inputs):
            try:  # a case, or a list of them (the sensor protocol: one per sensor model)
                built = entry.build_case(entry, scene, s)
                cases += built if isinstance(built, list) else [built]
            except (InputFileError, ValueError, OSError) as exc:
                mine.append(f"{protocol}: skipped {scene.name} x{s}: {exc}")
    if not cases:
        first = f" First problem: {mine[0]}" if mine else ""
        at = f" at x{','.join(map(str, scales))}" if scales else ""
        raise InputFileError(
            f"{folder}: no usable case for the {protocol!r} protocol{at}; expected {entry.layout}.{first}"
        )
    if notes is not None:
        notes.extend(mine)
    return cases


# ---------------------------------------------------------------- the protocols

def _park_build(protocol: Protocol, scene: Scene, scale: int) -> BenchCase:
    depth_lr = scene.inputs.get(scale)
    if depth_lr is None:
        raise ValueError(f"{os.fspath(scene.source)}/noisy_x{scale}.png is missing (the park protocol needs the "
                         "given noisy input).")
    return park_case(scene.name, scale, depth_lr, scene.rgb_hr, scene.depth_gt, protocol=protocol.name)


def _lu_build(protocol: Protocol, scene: Scene, scale: int) -> BenchCase:
    return lu_case(protocol.name, scene.name, scale, scene.rgb_hr, scene.depth_gt)


def _tof_build(protocol: Protocol, scene: Scene, scale: int) -> BenchCase:
    return tof_case(scene.name, scale, scene.rgb_hr, scene.depth_gt)


_PARK_README = "middlebury2005_park/README.md, sanity baseline computed by the dataset's authors"
_PARK_BICUBIC = {4: (5.60, 4.37, 4.31), 8: (6.86, 4.66, 4.55), 16: (9.28, 5.28, 5.06)}
_PARK_LAYOUT = "middlebury2005_park/<scene>/color.png, gt_disp.png (8-bit) and noisy_x<s>.png"

register_protocol(Protocol(
    name="park",
    title="Noisy Middlebury 2005 (Park et al. 2011): given noisy inputs, RMSE over the whole grid, disparity levels",
    folder="middlebury2005_park", layout=_PARK_LAYOUT, reader="scene_folders", build_case=_park_build,
    units="disparity levels",
    tuning_scenes=("dolls", "laundry"),
    # Published per-scene RMSE on the same protocol, quoted exactly from the
    # issue (Riegler et al. 2016, Table 2, noisy Middlebury x4) and the Park
    # README (its PIL-bicubic sanity row, Art / Books / Moebius).
    published_scenes={
        s: {
            "scenes": ("art", "books", "moebius"),
            "rows": {
                **({"TGV (Ferstl et al. 2013)": {
                    "source": "G. Riegler, M. Rüther, H. Bischof, \"ATGV-Net: Accurate depth super-resolution\", "
                              "ECCV 2016, Table 2 (noisy Middlebury, x4), as quoted in the issue; Art there is "
                              "Ferstl's noise draw (art/noisy_ferstl_x4.png, Park README), ours is noisy_x4.png",
                    "values": {"art": 4.06, "books": 2.21, "moebius": 2.03}}} if s == 4 else {}),
                "PIL bicubic (README sanity row)": {
                    "source": _PARK_README,
                    "values": dict(zip(("art", "books", "moebius"), _PARK_BICUBIC[s]))},
            },
        }
        for s in (4, 8, 16)
    },
))

register_protocol(Protocol(
    name="middlebury30",
    title="Middlebury 30-image set (Lu et al. 2014 package): PIL bicubic input, 6-px border, 0..255 units",
    folder="middlebury_lu30",
    layout="middlebury_lu30/RGB/<name>_output_color.png and middlebury_lu30/Depth/<name>_output_depth.png",
    reader="rgbd_pairs", build_case=_lu_build, units="0..255 units",
    tuning_scenes=("Middlebury_03", "Middlebury_10", "Middlebury_14", "Middlebury_18", "Middlebury_19",
                   "Middlebury_25"),
    left_out_why={"Middlebury_14": "Dolls (middlebury_lu30 README), a Park tuning scene",
                  "Middlebury_18": "Laundry (middlebury_lu30 README), a Park tuning scene"},
    published_means=(
        {"name": "DCTNet", "images": "30",
         "source": "DCTNet README, as quoted in middlebury_lu30/README.md",
         "values": {4: 1.10, 8: 2.05, 16: 4.19}},
        {"name": "Bicubic (DKN/JIIF-era tables)", "images": "30",
         "source": "middlebury_lu30/README.md (recalled there, not re-checked against the paper text)",
         "values": {4: 2.28, 8: 3.98, 16: 6.37}},
        {"name": "PIL bicubic (README sanity row)", "images": "28 (those here)",
         "source": "middlebury_lu30/README.md, computed by the dataset's authors; reproduced without the "
                   "6-px border crop (docs/bench.md)",
         "values": {4: 2.212, 8: 3.854, 16: 6.144}},
    ),
))

register_protocol(Protocol(
    name="lu",
    title="Lu RGB-D set (Lu et al. 2014): PIL bicubic input, 6-px border, 0..255 units",
    folder="lu6",
    layout="lu6/RGB/<name>_ouput_color.png (or _output_color.png) and lu6/Depth/<name>_output_depth.png",
    reader="rgbd_pairs", build_case=_lu_build, units="0..255 units",
    published_means=(
        {"name": "DCTNet", "images": "6",
         "source": "DCTNet README, as quoted in lu6/README.md",
         "values": {4: 0.88, 8: 1.85, 16: 4.39}},
        {"name": "Bicubic (DKN/JIIF-era tables)", "images": "6",
         "source": "lu6/README.md (recalled there, not re-checked against the paper text)",
         "values": {4: 2.42, 8: 4.54, 16: 7.38}},
        {"name": "PIL bicubic (README sanity row)", "images": "6 (5 here + 1 held out)",
         "source": "lu6/README.md, computed by the dataset's authors",
         "values": {4: 2.419, 8: 4.541, 16: 7.377}},
    ),
))

register_protocol(Protocol(
    name="tof",
    title="Simulated ToF (our model, see docs/bench.md) from the Park ground truth, RMSE over the whole grid, levels",
    folder="middlebury2005_park", layout="middlebury2005_park/<scene>/color.png and gt_disp.png (8-bit)",
    reader="scene_folders", build_case=_tof_build, units="disparity levels",
    tuning_scenes=("dolls", "laundry"),
    left_out_why={"dolls": "Park's Dolls, a tuning scene", "laundry": "Park's Laundry, a tuning scene"},
))

register_protocol(Protocol(
    name="sensor", title="Simulated real sensors (ours, docs/bench.md): the Park ground truth seen by an iToF and a "
                         "dToF camera beside the color camera, reprojected onto it; RMSE, whole grid, levels",
    folder="middlebury2005_park", layout="middlebury2005_park/<scene>/color.png and gt_disp.png (8-bit)",
    reader="scene_folders", build_case=sensor_protocol_cases, units="disparity levels",
    tuning_scenes=SENSOR_TUNING_SCENES, method_params=SENSOR_PEER_PARAMS, reprojected=True))


# ---------------------------------------------------------------- your own data: bench --pairs DIR

#: The name of the protocol :func:`pairs_protocol` builds.
PAIRS = "pairs"


def _pairs_build(protocol: Protocol, scene: Scene, scale: int, *, border: int = 0) -> BenchCase:
    from .runner import BenchCase

    depth_lr = scene.inputs[scale]
    gt = gt_float(scene.depth_gt)
    if 2 * border >= min(gt.shape):
        raise ValueError(f"--crop {border} leaves nothing of the {gt.shape[1]}x{gt.shape[0]} ground truth to score.")
    return BenchCase(protocol.name, scene.name, scale, depth_lr, scene.rgb_hr, gt, border=border, split="test")


def pairs_protocol(folder: str | os.PathLike, *, units: str | None = None, invalid: float = 0.0,
                   crop: int = 0) -> Protocol:
    """A protocol for a folder of your own triplets: ``folder/color``, ``folder/input``, ``folder/gt``.

    Files pair by stem (:func:`depthrefine.io.read_triplets`); each input
    is refined to its color image's grid and scored against its ground
    truth over the valid pixels, leaving ``crop`` pixels out on each side.

    Parameters
    ----------
    folder : path-like
        The folder holding ``color/``, ``input/`` and ``gt/``.
    units : str, optional
        A label for the tables and colorbars (default: "depth units as stored").
    invalid : float
        The stored value meaning "no measurement" (besides 0 and NaN).
    crop : int
        Border pixels left out of the scores, on each side.

    Returns
    -------
    Protocol
        Named :data:`PAIRS`; register it (``register_protocol(..., replace=True)``) to run it.
    """
    from pathlib import Path

    if crop < 0:
        raise ValueError(f"--crop must be >= 0 pixels; got {crop}.")
    folder = Path(folder)
    units = units or "depth units as stored"
    return Protocol(
        name=PAIRS,
        title=f"your triplets in {folder.name}/ (color, input, gt paired by stem): RMSE over the valid "
              f"ground-truth pixels{f' inside a {crop}-px border' if crop else ''}, {units}",
        folder=folder.name,
        layout=f"{folder.name}/color/<stem>.png, {folder.name}/input/<stem>.png and {folder.name}/gt/<stem>.png",
        reader="triplets", build_case=functools.partial(_pairs_build, border=int(crop)), units=units,
        reader_options={"invalid": float(invalid)},
    )


# ---------------------------------------------------------------- real ToF captures: the realtof self-benchmark

#: The factors of the ``realtof`` protocol (the real targets are small: 256x192 and 640x576).
REALTOF_SCALES = (4, 8)


def realtof_guide(scene: str, guide: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """The ``realtof`` guide of a capture, (rows, cols, 3) uint8 on the target's grid of ``shape``.

    ``iphone``: the RGB frame resized to the depth grid by area averaging
    (1920x1440 -> 256x192). ``kinect``: the active IR image (same grid as the
    depth, 16-bit) mapped to 8 bits with a log curve,
    ``round(255 * ln(1 + IR) / ln(65536))``, which spreads the IR's
    dynamic range (median about 250, saturated at 65535) over the 8 bits.

    Examples
    --------
    >>> ir = np.array([[0, 255, 65535]], np.uint16)
    >>> realtof_guide("kinect", np.repeat(ir[..., None], 3, axis=2), (1, 3))[0, :, 0].tolist()
    [0, 128, 255]
    """
    import cv2

    rows, cols = shape
    if scene == "kinect":
        ir = np.asarray(guide)[..., 0].astype(np.float64)
        gray = np.clip(np.round(255.0 * np.log1p(ir) / np.log1p(65535.0)), 0, 255).astype(np.uint8)
        return np.ascontiguousarray(np.repeat(gray[:rows, :cols, None], 3, axis=2))
    if scene == "iphone":
        rgb = np.asarray(guide)
        if rgb.dtype != np.uint8:
            raise ValueError(f"the iPhone guide must be an 8-bit RGB image; got {rgb.dtype}.")
        return np.ascontiguousarray(cv2.resize(rgb, (cols, rows), interpolation=cv2.INTER_AREA))
    raise ValueError(f"unknown real ToF capture {scene!r}; expected 'iphone' or 'kinect'.")


def realtof_case(scene: str, scale: int, guide: np.ndarray, depth: np.ndarray) -> BenchCase:
    """A case of the ``realtof`` protocol: the real depth as target, its valid-aware block mean as input.

    The target is ``depth`` (mm, 0 = no measurement, not scored) cropped to
    a multiple of ``scale``; the input is the mean of the valid target
    pixels of each ``scale x scale`` block (0 where a block has none); the
    guide is :func:`realtof_guide`. Scored over the whole grid.
    """
    from ..methods.gbp import block_mean_valid
    from .runner import BenchCase

    if scale not in REALTOF_SCALES:
        raise ValueError(f"the realtof protocol is defined at x{' and x'.join(map(str, REALTOF_SCALES))} only.")
    gt = gt_float(crop_to_multiple(np.asarray(depth), scale))
    depth_lr = np.nan_to_num(block_mean_valid(gt, scale), nan=0.0)
    rgb = realtof_guide(scene, guide, gt.shape)
    return BenchCase("realtof", scene, scale, depth_lr, rgb, gt, border=0, split=_split("realtof", scene))


def _realtof_build(protocol: Protocol, scene: Scene, scale: int) -> BenchCase:
    return realtof_case(scene.name, scale, scene.rgb_hr, scene.depth_gt)


register_protocol(Protocol(
    name="realtof",
    title="Real ToF self-benchmark: real iPhone LiDAR and Azure Kinect depth as target, its valid-aware block "
          "mean as input (x4, x8), RMSE in mm",
    folder="real_tof",
    layout="real_tof/iphone_lidar_bookshelf/{arkit_depth.png, image.jpg} and "
           "real_tof/azure_kinect_mug/derived/{depth_640x576_mm.png, ir_640x576.png}",
    reader="real_tof", build_case=_realtof_build, units="mm",
))
