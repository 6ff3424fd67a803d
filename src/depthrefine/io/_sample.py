"""The sample scene shipped with the package (Middlebury 2005 Art, Park et al. noisy inputs)."""

from __future__ import annotations

from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

from ._images import read_depth, read_rgb

__all__ = ["SampleScene", "load_sample", "SAMPLE_SCALES", "sample_folder"]

#: Scale factors of the shipped low-resolution inputs.
SAMPLE_SCALES = (4, 8, 16)


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


def sample_folder() -> Path:
    """Folder of the shipped sample scene (inside the installed package)."""
    return Path(str(resources.files("depthrefine") / "data" / "art"))


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
