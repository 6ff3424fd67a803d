"""Names and tables of :mod:`depthrefine.rig` that the command line shows, importable without numpy.

``depthrefine align --help``, ``run --help``, ``calibrate --help`` and ``rig
import --help`` list these without importing the rig's modules (fast
start-up, issue 13); the modules that use them import them from here
(``rig.chain.ALIGN_METHODS`` is this module's ``ALIGN_METHODS``).
"""

from __future__ import annotations

__all__ = ["ALIGN_METHODS", "COLOR_SIDES", "ENCODINGS", "K4A_DEPTH_MODES", "K4A_COLOR_RESOLUTIONS",
           "CALIBRATION_FORMATS", "MIN_VIEWS", "LENS_MODELS", "RECOMMENDED_VIEWS", "DEFAULT_MAX_RMS"]

#: Alignment methods of :func:`~depthrefine.rig.chain.align_pair` (keys of the chain settings' ``method``).
ALIGN_METHODS = ("reproject", "shift")

#: Where the color camera sits, seen from behind the depth camera.
COLOR_SIDES = ("right", "left")
#: How a depth value relates to distance: "inverse" (the thesis's depth
#: intensity, disparity: larger = nearer) or "distance" (mm, m: larger = farther).
ENCODINGS = ("inverse", "distance")

# mode: (calibration resolution (w, h), crop offset (x, y), output size (w, h)); the SDK's table.
#: Azure Kinect depth modes.
K4A_DEPTH_MODES: dict[str, tuple[tuple[int, int], tuple[int, int], tuple[int, int]]] = {
    "NFOV_2X2BINNED": ((512, 512), (96, 90), (320, 288)),
    "NFOV_UNBINNED": ((1024, 1024), (192, 180), (640, 576)),
    "WFOV_2X2BINNED": ((512, 512), (0, 0), (512, 512)),
    "WFOV_UNBINNED": ((1024, 1024), (0, 0), (1024, 1024)),
    "PASSIVE_IR": ((1024, 1024), (0, 0), (1024, 1024)),
}
#: Azure Kinect color resolutions.
K4A_COLOR_RESOLUTIONS: dict[str, tuple[tuple[int, int], tuple[int, int], tuple[int, int]]] = {
    "720P": ((1280, 960), (0, 120), (1280, 720)),
    "1080P": ((1920, 1440), (0, 180), (1920, 1080)),
    "1440P": ((2560, 1920), (0, 240), (2560, 1440)),
    "1536P": ((2048, 1536), (0, 0), (2048, 1536)),
    "2160P": ((3840, 2880), (0, 360), (3840, 2160)),
    "3072P": ((4096, 3072), (0, 0), (4096, 3072)),
}
#: The formats :func:`~depthrefine.rig.formats.calibration_format` recognises, with the name shown to users.
CALIBRATION_FORMATS = {
    "k4a": "Azure Kinect calibration (K4A calibration.json)",
    "opencv": "OpenCV FileStorage YAML (K, dist, img_size)",
    "ros": "ROS camera_info YAML",
}

#: Fewest board views a calibration accepts. Zhang's method needs three
#: views of a plane for the five intrinsic parameters; a stable lens fit
#: needs more (:data:`RECOMMENDED_VIEWS`).
MIN_VIEWS = 3

#: The lens models a calibration fits, with the coefficients each one fits
#: (OpenCV order; the others are held at 0).
LENS_MODELS = {
    "plain": "k1, k2, p1, p2; k3 held at 0",
    "k3": "k1, k2, p1, p2, k3",
    "rational": "k1, k2, p1, p2, k3, k4, k5, k6",
}

#: Views (pairs, for a stereo calibration that fits the cameras) below which
#: a fit of each lens model is reported as unstable: with fewer, the fitted
#: lens moves by pixels from one set of views to the next. From
#: ``benchmarks/calibration_views.py`` (simulated views) and the 8 real
#: Azure Kinect views against their 30-view reference; see docs/rig.md.
RECOMMENDED_VIEWS = {"plain": 15, "k3": 20, "rational": 20}

#: A fit whose RMS reprojection error is above this many pixels is refused
#: (``calibrate --max-rms``): a board found in the wrong place, a wrong
#: --board, or a lens the model cannot describe. Good fits reach 0.1-0.5 px.
DEFAULT_MAX_RMS = 1.0
