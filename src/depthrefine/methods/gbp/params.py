"""The knobs of guided back-projection: :class:`GbpParams`.

Only what a user would turn is a field. Every other number of the method is
a named constant in the module of the step it belongs to (``measure``,
``solve``, ``trust``); how each default was chosen, with the figures and the
commands that reproduce them, is in ``docs/tuning.md``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Mapping

import numpy as np

from ..._validate import check_int, check_number
from . import measure as _measure, solve as _solve, trust as _trust
from ._options import check_sampling

__all__ = ["GbpParams"]


@dataclass(frozen=True)
class GbpParams:
    """Parameters of guided back-projection (``method="gbp"``).

    Lengths are in low-resolution (depth) pixels, color sensitivities in
    8-bit guide levels. The defaults were chosen on the benchmark's tuning
    scenes against their neighbours; each figure, and its command, is in
    ``docs/tuning.md``.

    Attributes
    ----------
    iterations : int
        Back-projection rounds, each one edge-aware smoothing of the whole
        image (8; the tuning mean fell up to 8 rounds, 10 gained nothing).
    lambda_lr : float
        Smoothness of the detail solve on a noise-free input, per squared
        depth pixel (0.06, the best of 0.03-0.1 with ``gradient_levels`` when
        chosen; it grows with the input's measured noise). Larger rounds
        depth edges, smaller keeps more of the input's noise.
    sigma_color : float
        Color sensitivity of the solves, 8-bit levels (4, better than 3 and 5;
        raised to 3 times the guide's own measured noise where that is more):
        a smaller value stops the smoothing at fainter color edges.
    flat_lambda_lr : float
        Smoothness of the flat-area solve, per depth pixel (32, better than 16
        and 64): how strongly noise is averaged over whole color segments
        where the input shows no depth edge.
    gradient_levels : float
        How far a depth jump of the current estimate stops the smoothing
        without a color edge, in 8-bit levels of the depth range per depth
        pixel (96, the best of 64-192 when chosen; 0 turns it off): smaller
        keeps the input's own edges more.
    guide_smoothing : float
        Color sigma, 8-bit levels, of the 3x3 bilateral filter the guide goes
        through before its edges are weighed (5, better than 0 and 3; 0 turns
        it off): texture and noise inside a color region make no edges.
    trust : bool
        Check the guide against the input one octave down and fall back to
        plain interpolation where the guide's detail is not confirmed (True;
        it made every real-ToF cell better): a guide whose texture is not depth
        does no harm.
    snap_edges : bool
        Move each large depth jump, within two depth pixels, onto the
        strongest color edge between its two surfaces, and mixed ("flying")
        values onto one of them (False): for real sensors whose depth edges
        sit off the color edges (direct-ToF fattening, calibration error).
        On the real iPhone LiDAR frame it brings the sofa's outline from a
        median 6.3 to 1.4 px off the color edges (``benchmarks/iphone_edges.py``;
        ``--snap-edges`` on the command line); on the benchmark's registered,
        textured inputs it follows texture edges (tuning mean 2.39 -> 6.10,
        ``docs/tuning.md``), hence off.
    sampling : {"auto", "point", "mean"}
        What each input pixel is: ``"mean"``, the mean depth over its
        footprint (a ToF pixel integrates; a block-mean or area
        downsampling); ``"point"``, the depth at its block's centre, color
        pixel ``(i*s + s//2, j*s + s//2)`` for a whole factor ``s``
        (``depth[s//2::s, s//2::s]`` of a map; ``floor((i + 0.5) * s)`` for
        any factor, as ``cv2.INTER_NEAREST_EXACT`` takes it); ``"auto"``
        (the default) measures it from the share of mixed pixels at the
        input's jumps (:func:`~.measure.footprint_share`). Say it when you
        know it: the input cannot show it when the map was smooth before it
        was sampled. The real iPhone LiDAR frame subsampled x4 still
        measures as footprint means, and there ``"point"`` takes gbp from
        37.1 to 32.2 mm (bilinear 35.6; ``depthrefine demo --scene
        bookshelf``). Samples taken elsewhere in the block do worse told
        ``"point"``: ``depth[::4, ::4]`` of that frame 59.6 -> 63.5 mm,
        ``depth[1::4, 1::4]`` 36.1 -> 39.7.
    reprojected : bool or None
        The input was reprojected onto the color camera from a depth camera
        beside it. None (the default) leaves it unsaid: ``refine`` takes it
        as False, the rig chain (``depthrefine run``, ``batch`` with a rig,
        :func:`depthrefine.rig.chain.refine_pair`), which reprojected the
        depth itself, as True; ``--reprojected`` says True for a depth map
        your camera's SDK aligned to the color image, and ``reprojected =
        false`` in a parameter file keeps it False everywhere. A reprojected
        sample sits a fraction of a depth pixel off where the
        back-projection assumes it (the calibration's error, the parallax
        between two surfaces), which no input noise shows: the detail solve
        smooths at least as much as ``lambda_lr = 2``
        (``solve.REPROJECTED_LAMBDA_LR``), and step 1b moves the input back
        by the shift its jumps show against the color edges
        (``fattening.edge_shift``, from ``fattening.SHIFT_MIN``). On the
        ``sensor`` protocol's test scenes it takes gbp from 5.37 / 6.26 /
        9.72 to 4.34 / 5.35 / 9.20 levels under direct ToF (x4 / x8 / x16)
        and from 5.03 / 5.86 / 6.55 to 4.44 / 5.26 / 6.33 under indirect ToF
        (``docs/bench.md``).
    """

    iterations: int = 8
    lambda_lr: float = 0.06
    sigma_color: float = 4.0
    flat_lambda_lr: float = 32.0
    gradient_levels: float = 96.0
    guide_smoothing: float = 5.0
    trust: bool = True
    snap_edges: bool = False
    sampling: str = "auto"
    reprojected: bool | None = None

    #: Former parameters (before 0.2) and the value the method now fixes them at.
    removed_parameters: ClassVar[Mapping[str, str]] = {
        "clip_rounds": "always on",
        "trust_radius": f"{_trust.TRUST_RADIUS}",
        "local_range": "always on",
        "residual_interp": "lanczos",
        "hole_margin": "0",
        "lambda_first": f"{_solve.LAMBDA_FIRST:g}",
        "lambda_last": f"{_solve.LAMBDA_LAST:g}",
        "noise_ref": f"{_solve.NOISE_REF:g}",
        "flat_sigma_color": f"{_solve.FLAT_SIGMA_COLOR:g}",
        "edge_low": f"{_solve.EDGE_LOW:g}",
        "edge_width": f"{_solve.EDGE_WIDTH:g}",
        "flat_noise": f"{_measure.FLAT_NOISE:g}",
        "trust_prior": f"{_trust.TRUST_PRIOR:g}",
        "trust_floor": f"{_trust.TRUST_FLOOR:g}",
        "jump_levels": f"{_measure.JUMP_LEVELS:g}",
        "jump_noise": f"{_measure.JUMP_NOISE:g}",
        "jump_margin": f"{_measure.JUMP_MARGIN:g}",
        "guide_noise": f"{_solve.GUIDE_NOISE:g}",
        "trust_guide_noise": f"{_trust.TRUST_GUIDE_NOISE:g}",
        "mixed_low": f"{_measure.MIXED_LOW:g}",
        "mixed_high": f"{_measure.MIXED_HIGH:g}",
        "point_lambda": f"{_solve.POINT_LAMBDA:g}",
    }

    def __post_init__(self) -> None:
        check_int("iterations", self.iterations, minimum=1)
        for name in ("lambda_lr", "sigma_color", "flat_lambda_lr"):
            check_number(name, getattr(self, name), positive=True)
        for name in ("gradient_levels", "guide_smoothing"):
            check_number(name, getattr(self, name), nonnegative=True)
        for name in ("trust", "snap_edges"):
            if not isinstance(getattr(self, name), (bool, np.bool_)):
                raise TypeError(f"{name} must be True or False; got {getattr(self, name)!r}.")
        check_sampling(self.sampling)
        if self.reprojected is not None and not isinstance(self.reprojected, (bool, np.bool_)):
            raise TypeError(f"reprojected must be True, False or None (unsaid); got {self.reprojected!r}.")
