"""One frame on a worker: align it (raw captures of a rig), refine it, and make what is written beside it.

A :class:`FramePlan` travels with every task; :func:`solve_frame` is a pure
function of the plan and the frame's arrays, so a frame that a lost worker
did not finish gives the same bits on any other worker. For a batch job the
worker also encodes the frame's files (:func:`encode_files`): the command's
process, one for the whole cluster, only writes their bytes, and a 640x480
16-bit PNG comes back as about 0.2 MB instead of 1.2 MB of float32.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._validate import as_depth
from ..methods.confidence import apply_min_confidence, confidence_of, confidence_on_grid, method_with_confidence
from ..methods.registry import Method, check_call

__all__ = ["FramePlan", "FrameOutput", "solve_frame", "encode_files"]


@dataclass(frozen=True)
class FramePlan:
    """What a worker does with each frame of a batch.

    Attributes
    ----------
    method : Method
        The refinement method's registry entry (sent along, so methods
        registered at run time work on the workers too).
    params : dataclass or None
        The method's parameters.
    rig : StereoRig, optional
        ``None``: the frames are registered pairs ``(depth_lr, rgb_hr)``, refined
        as they are (bit for bit :func:`depthrefine.refine`). Given: the frames
        are raw captures of this rig, undistorted and aligned first as
        ``depthrefine run`` does (:func:`depthrefine.rig.chain.align_pair`).
    align : AlignSettings, optional
        The alignment settings with ``rig`` (default ``AlignSettings()``).
    fill_holes : bool
        With ``rig``: keep the refinement's depth where nothing was measured;
        false (the default, as ``run``): those pixels stay NaN
        (:func:`depthrefine.rig.chain.keep_unmeasured`).
    color : bool
        Return the color image the refined depth lies on (undistorted with ``rig``).
    points : bool
        Return a colored point cloud of the refined depth (needs ``rig`` and
        the depth's units in ``align``).
    stride : int
        Point cloud: every ``stride``-th row and column.
    preview : bool
        Return the color image and the (aligned) input depth, for a preview video.
    confidence : bool
        Return the confidence map of the refined depth
        (:func:`depthrefine.refine_with_confidence`; with a warm start,
        :func:`depthrefine.methods.confidence.confidence_of`), 0 where there is no depth.
    min_confidence : float, optional
        NaN (no measurement) in the depth where the confidence is below it
        (needs ``confidence``).
    output_scale, output_dtype
        The depth file holds ``depth * output_scale`` as ``output_dtype``
        (:func:`depthrefine.io.output_values`; default: the depth as
        refined, in the input depth's dtype), for :func:`encode_files`.
    """

    method: Method
    params: Any = None
    rig: Any = None
    align: Any = None
    fill_holes: bool = False
    color: bool = False
    points: bool = False
    stride: int = 1
    preview: bool = False
    confidence: bool = False
    min_confidence: float | None = None
    output_scale: float | None = None
    output_dtype: str | None = None

    def __post_init__(self) -> None:
        if self.points and self.rig is None:
            raise ValueError("a point cloud needs the rig's color camera: give the rig.")
        if self.min_confidence is not None and not self.confidence:
            raise ValueError("min_confidence needs the confidence map: set confidence=True.")

    def told_params(self) -> Any:
        """The method's parameters as the frames are refined: with ``rig``, told the depth is reprojected.

        (:func:`depthrefine.rig.chain.reprojected_params`: an unsaid ``reprojected`` becomes True, as in ``run``.)
        """
        if self.rig is None:
            return self.params
        from ..rig.chain import reprojected_params

        return reprojected_params(self.method, self.params)


@dataclass(eq=False)
class FrameOutput:
    """What a worker returns for one frame.

    Attributes
    ----------
    depth_hr : (H, W) float32 ndarray or None
        The refined depth, input units, NaN = no measurement (``None`` once
        :func:`encode_files` made the file, unless ``plan.preview``).
    rgb_hr : (H, W, 3) ndarray or None
        The color image it lies on (``plan.color`` or ``plan.preview``).
    depth_lr : ndarray or None
        The (aligned) low-resolution input depth, NaN = invalid (``plan.preview``).
    points, colors : ndarray or None
        The point cloud (``plan.points``), as :func:`depthrefine.rig.pointcloud.depth_to_points`.
    notes : tuple of str
        What the chain did (with a rig), one line each.
    confidence : (H, W) float32 ndarray or None
        The confidence map in [0, 1] on ``depth_hr``'s grid (``plan.confidence``).
    files : dict or None
        The frame's files as bytes by kind (``"depth"``, ``"color"``,
        ``"ply"``, ``"confidence"``), made by :func:`encode_files`; the
        arrays they were made of are then dropped (``depth_hr`` too, unless
        ``plan.preview`` needs it).
    """

    depth_hr: np.ndarray | None
    rgb_hr: np.ndarray | None = None
    depth_lr: np.ndarray | None = None
    points: np.ndarray | None = None
    colors: np.ndarray | None = None
    notes: tuple[str, ...] = field(default=())
    confidence: np.ndarray | None = None
    files: dict[str, bytes] | None = None


def solve_frame(plan: FramePlan, depth: np.ndarray, rgb: np.ndarray, state: Any = None, *,
                stateful: bool = False) -> tuple[FrameOutput, Any]:
    """Refine one frame as ``plan`` says; with ``stateful``, warm-start from ``state`` (the method's own).

    Returns the output and the state for the next frame (``None`` without ``stateful``).

    Raises
    ------
    ValueError, TypeError
        The frame is bad input (sizes that do not match each other or the rig).

    Examples
    --------
    >>> from depthrefine.methods.registry import get_method
    >>> out, _ = solve_frame(FramePlan(get_method("nearest")), np.full((2, 2), 5, np.uint16), np.zeros((4, 4, 3), np.uint8))
    >>> out.depth_hr.shape, float(out.depth_hr[0, 0])
    ((4, 4), 5.0)
    """
    notes: tuple[str, ...] = ()
    camera = None
    if plan.rig is not None:
        from ..rig.chain import AlignSettings, align_pair

        pair = align_pair(depth, rgb, plan.rig, settings=plan.align or AlignSettings())
        depth, rgb, camera, notes = pair.depth_lr, pair.rgb_hr, pair.camera, pair.notes
    params = plan.told_params()
    check_call(plan.method, depth, rgb, params)
    states = [state]
    confidences: list[np.ndarray | None] = [None]

    def solve(depth_in: np.ndarray, rgb_in: np.ndarray) -> np.ndarray:
        if stateful:
            out, states[0] = plan.method.refine_stateful(depth_in, rgb_in, params=params, state=states[0])
            if plan.confidence:
                confidences[0] = confidence_of(plan.method, depth_in, rgb_in, out, params=params)
            return out
        states[0] = None
        if plan.confidence:
            out, confidences[0] = method_with_confidence(plan.method, depth_in, rgb_in, params=params)
            return out
        return plan.method.func(depth_in, rgb_in, params=params, progress=None)

    if plan.rig is not None:   # as run does: the method upsamples the aligned grid onto the color image
        from ..rig.chain import refine_pair

        depth_hr, _ = refine_pair(depth, rgb, method=plan.method.name, solve=solve)
    else:
        depth_hr = solve(depth, rgb)
    state = states[0]
    if plan.rig is not None:
        from ..rig.chain import keep_unmeasured

        depth_hr = keep_unmeasured(depth_hr, depth, fill_enclosed=plan.fill_holes, rgb_hr=rgb)
    confidence = None
    if plan.confidence:
        confidence = confidence_on_grid(confidences[0], depth_hr)
        depth_hr, confidence = apply_min_confidence(depth_hr, confidence, plan.min_confidence)
    out = FrameOutput(depth_hr, notes=notes, confidence=confidence)
    if plan.color or plan.preview:
        out.rgb_hr = rgb
    if plan.preview:
        out.depth_lr = as_depth(depth)
    if plan.points:
        from ..rig.pointcloud import depth_to_points

        align = plan.align
        out.points, out.colors = depth_to_points(depth_hr, camera, rgb=rgb, depth_units=align.depth_units,
                                                 inverse_scale=align.inverse_scale, stride=plan.stride)
    return out, state



def encode_files(plan: FramePlan, output: FrameOutput, suffixes: dict[str, str], *, input_dtype: Any,
                 key: Any) -> FrameOutput:
    """``output`` with its files encoded (``output.files``: bytes by kind) and the arrays only they needed dropped.

    ``suffixes`` names the files by kind (``{"depth": ".png", "color":
    ".png", "ply": ".ply", "confidence": ".tif"}``); the bytes are those
    :func:`depthrefine.io.write_depth`, ``write_rgb``, ``write_ply`` and
    ``write_confidence`` write. The depth file holds the depth in
    ``input_dtype`` (the frame's depth as read) or as ``plan.output_scale``
    and ``plan.output_dtype`` say.

    Raises
    ------
    ValueError
        The output type cannot hold the depth (``output_scale``/``output_dtype``).

    Examples
    --------
    >>> from depthrefine.methods.registry import get_method
    >>> plan = FramePlan(get_method("nearest"))
    >>> out, _ = solve_frame(plan, np.full((2, 2), 5, np.uint16), np.zeros((4, 4, 3), np.uint8))
    >>> out = encode_files(plan, out, {"depth": ".png"}, input_dtype=np.uint16, key="0001")
    >>> out.files["depth"][1:4], out.depth_hr is None
    (b'PNG', True)
    """
    from ..io import encode_confidence, encode_depth, encode_ply, encode_rgb, output_values

    files: dict[str, bytes] = {}
    if "depth" in suffixes:
        try:
            values, dtype = output_values(output.depth_hr, input_dtype, scale=plan.output_scale,
                                          dtype=plan.output_dtype)
        except ValueError as exc:
            raise ValueError(f"output scale {plan.output_scale or 1:g}, dtype {plan.output_dtype}: {exc}") from None
        files["depth"] = encode_depth(values, suffixes["depth"], dtype=dtype)
    if "color" in suffixes:
        from ..viz import to_rgb8

        rgb = output.rgb_hr if output.rgb_hr.dtype in (np.uint8, np.uint16) else to_rgb8(output.rgb_hr)
        files["color"] = encode_rgb(rgb, suffixes["color"])
    if "ply" in suffixes:
        files["ply"] = encode_ply(output.points, output.colors,
                                  comments=(f"depthrefine batch frame {key}",
                                            "metres, color camera frame: X right, Y down, Z forward"))
    if "confidence" in suffixes:
        files["confidence"] = encode_confidence(output.confidence, suffixes["confidence"])
    keep = plan.preview  # the preview video is made where the files are written
    return FrameOutput(output.depth_hr if keep else None, rgb_hr=output.rgb_hr if keep else None,
                       depth_lr=output.depth_lr if keep else None, notes=output.notes, files=files)
