"""``depthrefine refine DEPTH COLOR -o OUT``: refine one depth map."""

from __future__ import annotations

import argparse
import contextlib
import sys
import threading
from pathlib import Path

from .. import __version__
from ._confidence import (add_confidence_options, apply_min_confidence, check_confidence_output, confidence_note,
                          refine_maybe_confident, wants_confidence)
from ._common import (add_depth_options, add_output, add_output_format_options, add_overwrite, add_params_options,
                      add_units_option, build_params, depth_units_label, output_depth, params_dict, progress_bar)
from ._picture_options import add_preview_option, check_window, write_preview


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "refine",
        help="refine a low-resolution depth map to the color image's resolution",
        description=(
            "Refine DEPTH (8/16-bit PNG, float TIFF or .npy; 0 = no measurement) to the height and width "
            "of COLOR. The output keeps DEPTH's dtype (unless --output-dtype); its format follows OUT's "
            "extension. A float result goes to a 16-bit PNG with an explicit scale: --output-scale 1000 "
            "--output-dtype uint16 stores metres as millimetres."
        ),
    )
    p.add_argument("depth", metavar="DEPTH", help="low-resolution depth map")
    p.add_argument("color", metavar="COLOR", help="registered high-resolution color image")
    add_output(p, help="output depth file (.png, .tif, .npy)")
    add_params_options(p)
    p.add_argument("--save-intermediate", metavar="DIR",
                   help="write the pictures of the intermediate steps (and the parameters) into DIR")
    add_preview_option(p)
    add_confidence_options(p)
    add_units_option(p)
    add_output_format_options(p)
    add_overwrite(p)
    add_depth_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    warm = [thread for thread in (_warm_up_numba(args.method, own_process=getattr(args, "own_process", False)),
                                  _warm_up_lab(args.method)) if thread is not None]
    try:
        return _run(args)
    finally:
        for thread in warm:
            thread.join()


def _warm_up_lab(method: str) -> threading.Thread | None:
    """For a method that converts the guide to L*a*b* (``methods._names.LAB_METHODS``), OpenCV's one-time
    conversion tables built in a thread while the images are read (OpenCV releases the GIL); else None."""
    from ..methods._names import LAB_METHODS

    if method not in LAB_METHODS:
        return None

    def warm() -> None:
        import cv2
        import numpy as np

        cv2.cvtColor(np.zeros((1, 1, 3), np.float32), cv2.COLOR_RGB2Lab)

    thread = threading.Thread(target=warm, name="depthrefine-lab-warm-up")
    thread.start()
    return thread


def _warm_up_numba(method: str, *, own_process: bool = False) -> threading.Thread | None:
    """For a method that runs numba's kernels, numba's one-time set-up in a thread (while the images are read).

    None for a method that runs none: not compiled, or all its kernels in
    depthrefine's C library (gbp, gbp-fast and the thesis method when it is
    built: ``methods._names.NATIVE_METHODS``). In the
    process's own command line (``own_process``), which runs only
    depthrefine's kernels, numba is imported without cffi and PyYAML and set
    up without its BLAS check (``cli._numba_lean``; ``_numba.warm_up``).
    """
    from ..methods._names import COMPILED_METHODS, NATIVE_METHODS

    if method not in COMPILED_METHODS:
        return None
    if method in NATIVE_METHODS:
        from .._native import library

        if library() is not None:
            return None
    if own_process:
        try:
            from ._numba_lean import import_numba_lean

            import_numba_lean()
        except Exception:   # no numba: the refine itself says what is wrong
            pass

    def warm() -> None:
        try:
            from .._numba import warm_up

            warm_up(skip_blas_check=own_process)
        except Exception:   # no numba, no cache: the refine itself says what is wrong
            pass

    thread = threading.Thread(target=warm, name="depthrefine-numba-warm-up")
    thread.start()
    return thread


def _run(args: argparse.Namespace) -> int:
    from .._validate import as_depth
    from ..io import (DEPTH_SUFFIXES, atomic_directory, check_depth_format, check_distinct_inputs, check_output,
                      check_output_dir, read_depth, read_rgb, write_confidence, write_depth, write_intermediates)
    from ..methods.confidence import confidence_of
    from ..methods.registry import get_method, refine_intermediates
    from ..methods.scale import plan_scale

    out = check_output(args.output, overwrite=args.overwrite, suffixes=DEPTH_SUFFIXES,
                       inputs=(args.depth, args.color))
    check_distinct_inputs(args.depth, args.color)
    if args.save_intermediate:
        folder = Path(args.save_intermediate).resolve()
        if out.resolve() == folder:
            raise ValueError(
                f"-o {out} and --save-intermediate {args.save_intermediate} are the same path; "
                "give the intermediate pictures a folder of their own."
            )
        check_output_dir(args.save_intermediate, overwrite=args.overwrite, what="--save-intermediate folder")
    preview = None
    if args.preview:
        preview = check_output(args.preview, overwrite=args.overwrite, suffixes=(".png",),
                               inputs=(args.depth, args.color), what="--preview file")
        if preview.resolve() == out.resolve():
            raise ValueError(f"-o {out} and --preview {args.preview} are the same file; give the picture its own name.")
    confidence_out = check_confidence_output(args, inputs=(args.depth, args.color), taken=(out, preview))
    params = build_params(args)  # before reading the images: a bad parameter fails at once
    depth_lr = read_depth(args.depth, saturated_invalid=args.saturated_invalid)
    rgb_hr = read_rgb(args.color)
    check_window(args, rgb_hr.shape[:2])
    check_depth_format(out, args.output_dtype or depth_lr.dtype)
    step = plan_scale(depth_lr.shape, rgb_hr.shape)
    entry = get_method(args.method)
    update, close = progress_bar(f"refine ({entry.name})")
    try:
        if args.save_intermediate and entry.intermediates is not None:
            depth_hr, steps = refine_intermediates(depth_lr, rgb_hr, method=entry.name, params=params, progress=update)
            confidence = (confidence_of(entry, depth_lr, rgb_hr, depth_hr, params=params)
                          if wants_confidence(args) else None)
        else:
            steps = None
            depth_hr, confidence = refine_maybe_confident(args, depth_lr, rgb_hr, method=entry.name, params=params,
                                                          progress=update)
    finally:
        close()
    if confidence is not None:
        note = confidence_note(confidence, args.min_confidence)
        depth_hr, confidence = apply_min_confidence(depth_hr, confidence, args.min_confidence)

    record = {
        "depthrefine": __version__,
        "depth": str(args.depth),
        "color": str(args.color),
        "output": str(out),
        "method": entry.name,
        "params": params_dict(params),
        "scale": step.describe(direct=not entry.scale_step),
        "depth_shape": list(depth_lr.shape),
        "color_shape": list(rgb_hr.shape[:2]),
        "dtype": str(depth_lr.dtype),
    }
    stored, dtype = output_depth(args, depth_hr, depth_lr.dtype)
    if dtype != depth_lr.dtype or args.output_scale is not None:
        record.update(output_scale=args.output_scale or 1.0, output_dtype=str(dtype))
    units = depth_units_label(args.units, depth_lr.dtype)
    if args.output_scale not in (None, 1.0) and not args.units:
        units += f" x {args.output_scale:g}"
    shown = as_depth(stored, name="result") if stored is not depth_hr else depth_hr
    written: list[Path] = []

    def write_outputs() -> None:
        written.append(write_depth(out, stored, dtype=dtype, overwrite=args.overwrite))
        if confidence_out is not None:
            written.append(write_confidence(confidence_out, confidence, overwrite=args.overwrite))
        if preview is not None:
            written.append(write_preview(args, preview, shown, rgb_hr, units=units, title=f"{out.name} ({entry.name})",
                                         confidence=confidence))

    try:
        if args.save_intermediate:
            with atomic_directory(args.save_intermediate, overwrite=args.overwrite) as tmp:
                write_intermediates(tmp, steps, depth_hr=shown, rgb_hr=rgb_hr, record=record, units=units,
                                    factor=1.0 if args.output_scale is None else args.output_scale)
                write_outputs()
        else:
            write_outputs()
    except BaseException:
        for path in written:  # all or nothing
            with contextlib.suppress(OSError):
                path.unlink()
        raise
    h, w = depth_hr.shape
    scale_note = record["scale"]
    if entry.scale_step and step.resizes_color:
        scale_note = f"x{step.factor} after the thesis scale step (see the note above)"
    print(f"wrote {out} ({w}x{h}, {dtype}, method {entry.name}, {scale_note})", file=sys.stderr)
    if confidence is not None:
        print(f"{'wrote ' + str(confidence_out) + ': ' if confidence_out else ''}{note}", file=sys.stderr)
    if preview is not None:
        print(f"wrote {preview}", file=sys.stderr)
    return 0
