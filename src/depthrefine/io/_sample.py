"""The sample scenes shipped with the package.

``art``: Middlebury 2005 Art with the noisy inputs of Park et al. (ground
truth); ``mug``: a real Azure Kinect ToF capture with its factory
calibration; ``bookshelf``: a real iPhone LiDAR frame registered to its RGB
image. Each folder under ``data/`` has a README (source, licence) and SHA256SUMS.
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

from ._images import read_depth, read_rgb
from ._names import SAMPLE_SCALES, SCENES

__all__ = ["SampleScene", "load_sample", "SAMPLE_SCALES", "sample_folder", "SCENES", "RealCapture", "load_capture"]


@dataclass(frozen=True)
class SampleScene:
    """A scene with ground truth.

    Attributes
    ----------
    name : str
    scale : int
    rgb_hr : (H, W, 3) uint8 RGB
    depth_lr : (H/scale, W/scale) uint8 noisy low-resolution disparity
    depth_gt : (H, W) uint8 ground-truth disparity (no holes)
    citation : str
    """

    name: str
    scale: int
    rgb_hr: np.ndarray
    depth_lr: np.ndarray
    depth_gt: np.ndarray
    citation: str


def sample_folder(scene: str = "art") -> Path:
    """Folder of a shipped sample scene (inside the installed package)."""
    if scene not in SCENES:
        raise ValueError(f"scene must be one of {SCENES}; got {scene!r}.")
    return Path(str(resources.files("depthrefine") / "data" / scene))


@dataclass(frozen=True)
class RealCapture:
    """A real capture without ground truth.

    Attributes
    ----------
    name : str
    depth : (h, w) uint16 ndarray
        Raw depth in millimetres, 0 = no measurement.
    rgb : (H, W, 3) uint8 RGB
    depth_units : float
        Metres per depth unit (0.001).
    calibration : Path or None
        The factory calibration file (``mug``: Azure Kinect K4A JSON), None
        when the depth is already registered to the color image.
    citation : str
    """

    name: str
    depth: np.ndarray
    rgb: np.ndarray
    depth_units: float
    calibration: Path | None
    citation: str


_CAPTURES = {
    "mug": ("calibration.json", "Azure Kinect DK capture from github.com/etiennedub/pyk4a (tests/assets, commit "
            "8c15316), MIT licence, Copyright (c) 2019 etiennedub."),
    "bookshelf": (None, "iPhone LiDAR (ARKit) frame from github.com/DepthAnything/PromptDA (assets/example_images, "
                  "commit b05523c), Apache License 2.0."),
}


def load_capture(name: str) -> RealCapture:
    """Load a shipped real capture: ``"mug"`` (Azure Kinect) or ``"bookshelf"`` (iPhone LiDAR).

    Examples
    --------
    >>> cap = load_capture("mug")
    >>> cap.depth.shape, cap.rgb.shape, cap.calibration.name
    ((576, 640), (720, 1280, 3), 'calibration.json')
    """
    if name not in _CAPTURES:
        raise ValueError(f"the real captures are {tuple(_CAPTURES)}; got {name!r}.")
    folder = sample_folder(name)
    calibration, citation = _CAPTURES[name]
    return RealCapture(
        name=name,
        depth=read_depth(folder / "depth.png"),
        rgb=read_rgb(folder / "color.jpg"),
        depth_units=0.001,
        calibration=None if calibration is None else folder / calibration,
        citation=citation,
    )


def load_sample(scale: int = 8) -> SampleScene:
    """Load the shipped Middlebury 2005 Art scene at ``scale`` 4, 8 or 16.

    Examples
    --------
    >>> scene = load_sample(16)
    >>> scene.depth_lr.shape, scene.rgb_hr.shape
    ((68, 86), (1088, 1376, 3))
    """
    if scale not in SAMPLE_SCALES:
        raise ValueError(f"the sample scene has scales {SAMPLE_SCALES}; got {scale!r}.")
    folder = sample_folder()
    return SampleScene(
        name="art",
        scale=scale,
        rgb_hr=read_rgb(folder / "color.png"),
        depth_lr=read_depth(folder / f"noisy_x{scale}.png"),
        depth_gt=read_depth(folder / "gt_disp.png"),
        citation=(
            "Middlebury 2005 Art (Scharstein & Pal, CVPR 2007; Hirschmüller & Scharstein, CVPR 2007), "
            "noisy inputs and hole-filled GT of Park et al., ICCV 2011. Research use only."
        ),
    )
