"""Shared validators: one place for the checks and messages of array inputs.

Every public function checks its arrays here, once, and raises ``TypeError``
(wrong kind of thing) or ``ValueError`` (right kind, wrong value) with a
message that names the argument, says what was received and what to do.
"""

from __future__ import annotations

import contextlib
import math
import contextvars
import os
import sys
from typing import Any, Iterator

import numpy as np

__all__ = [
    "as_depth",
    "check_depth",
    "check_rgb",
    "guide_uint8",
    "check_int",
    "check_choice",
    "is_int",
    "check_number",
    "valid_range",
    "no_valid_pixel_message",
    "too_deep_message",
    "largest_beyond_limit",
    "MAX_DEPTH",
    "available_memory",
    "check_pixels",
    "pixel_limit",
    "PEAK_BYTES_PER_PIXEL",
]

#: Peak memory of the hungriest library path, in bytes per color pixel: the
#: thesis method with every intermediate and a single patch measured
#: 164 B/px (4 Mpx, ``docs/robustness.md``); the default 4 x 4 grid needs
#: 21-58 B/px and the baselines 2 B/px. Rounded up for headroom.
PEAK_BYTES_PER_PIXEL = 200

# The pixel limit a command line run set (``--max-pixels``), see pixel_limit().
_MAX_PIXELS: contextvars.ContextVar[int | None] = contextvars.ContextVar("depthrefine_max_pixels", default=None)

_DEPTH_DTYPES = (np.uint8, np.uint16, np.int16, np.int32, np.float32, np.float64)

#: The largest depth value the library takes, in any unit. The methods square depth differences and sum squares in
#: float32, which overflows from about 1e18 on (every method failed on a map reaching 2.5e20, all ran alike up to
#: 2.5e18); no camera's depth comes near this in any sensible unit (1e15 mm is a thousand times the Moon's distance).
MAX_DEPTH = 1e15


def check_depth(depth: object, name: str = "depth_lr") -> np.ndarray:
    """Check that ``depth`` is a 2-D numeric array without values beyond :data:`MAX_DEPTH`."""
    if not isinstance(depth, np.ndarray):
        raise TypeError(f"{name} must be a numpy array; got {type(depth).__name__}.")
    # a plain array: a masked array's masked pixels are no measurement (0), a matrix its values (numpy.ma only where
    # it is imported already: a masked array needs it, and its import costs 37 ms of a first call)
    ma = sys.modules.get("numpy.ma")
    depth = ma.filled(depth, 0) if ma is not None and isinstance(depth, ma.MaskedArray) else np.asarray(depth)
    if depth.ndim == 3 and depth.shape[2] == 1:
        depth = depth[:, :, 0]
    if depth.ndim != 2:
        raise ValueError(
            f"{name} must be 2-D (rows, cols); got shape {depth.shape}. "
            "Pass a single-channel depth map (squeeze or select the channel first)."
        )
    if depth.dtype.type not in _DEPTH_DTYPES:
        raise TypeError(
            f"{name} has dtype {depth.dtype}; expected uint8, uint16, int16, int32, float32 or float64. "
            "Convert it first."
        )
    if depth.shape[0] < 1 or depth.shape[1] < 1:
        raise ValueError(f"{name} is empty (shape {depth.shape}); give a non-empty depth map.")
    largest = largest_beyond_limit(depth)
    if largest is not None:
        raise ValueError(too_deep_message(name, largest))
    return depth


def as_depth(depth: object, name: str = "depth_lr") -> np.ndarray:
    """Return a new float32 copy of ``depth`` with every invalid pixel as NaN.

    Invalid: 0 (no measurement, any dtype), NaN, +-inf and negative values.
    The input is never modified. Raises ``ValueError`` if no pixel is valid,
    or if a value exceeds :data:`MAX_DEPTH` (:func:`check_depth`).
    """
    depth = check_depth(depth, name)
    out = depth.astype(np.float32, copy=True)
    with np.errstate(invalid="ignore"):
        out[~(np.isfinite(out) & (out > 0))] = np.nan
    if not np.isfinite(out).any():
        raise ValueError(no_valid_pixel_message(name))
    return out


def no_valid_pixel_message(name: str) -> str:
    """The message for a depth map without any valid pixel (shared with :mod:`depthrefine.io`)."""
    return (
        f"{name} has no valid pixel (all are 0, NaN, inf or negative); "
        "there is no depth to refine. Check the depth file or its units."
    )


def largest_beyond_limit(depth: np.ndarray) -> float | None:
    """The largest finite value of a depth map when it exceeds :data:`MAX_DEPTH`, else None.

    Examples
    --------
    >>> largest_beyond_limit(np.array([[1.0, np.inf, 3e17]])), largest_beyond_limit(np.array([[1.0, np.inf]]))
    (3e+17, None)
    """
    values = np.asarray(depth)      # as check_depth passes a matrix on
    if values.size == 0 or values.dtype.kind not in "fiu":
        return None
    if values.dtype.kind == "f":
        largest = np.max(values, where=np.isfinite(values), initial=-np.inf)
    elif values.dtype.itemsize < 8:     # int32 and smaller top out at 2.1e9
        return None
    else:
        largest = values.max()
    return float(largest) if largest > MAX_DEPTH else None


def too_deep_message(name: str, largest: float) -> str:
    """The message for a depth map with values beyond :data:`MAX_DEPTH` (shared with :mod:`depthrefine.io`)."""
    return (
        f"{name} holds depth values up to {largest:.6g}; depthrefine takes depth up to {MAX_DEPTH:.0e} (in any "
        "unit). Give it in a larger unit (e.g. metres instead of millimetres), and mark pixels without a "
        "measurement with 0, NaN or inf rather than a large number."
    )


def valid_range(depth: np.ndarray) -> tuple[float, float]:
    """Min and max of the valid (finite) pixels of a float depth map."""
    return float(np.nanmin(depth)), float(np.nanmax(depth))


def check_rgb(rgb: object, name: str = "rgb_hr") -> np.ndarray:
    """Check a color image: (H, W, 3) uint8/uint16/float, RGB order.

    A single-channel (H, W) or (H, W, 1) guide is accepted and repeated to
    three channels; an alpha channel (H, W, 4) is dropped. Float images must
    lie in [0, 1].
    """
    if not isinstance(rgb, np.ndarray):
        raise TypeError(f"{name} must be a numpy array; got {type(rgb).__name__}.")
    if rgb.ndim == 2:
        rgb = np.repeat(rgb[:, :, None], 3, axis=2)
    elif rgb.ndim == 3 and rgb.shape[2] == 1:
        rgb = np.repeat(rgb, 3, axis=2)
    elif rgb.ndim == 3 and rgb.shape[2] == 4:
        rgb = rgb[:, :, :3]
    if rgb.ndim != 3 or rgb.shape[2] != 3:
        raise ValueError(
            f"{name} must be a color image of shape (rows, cols, 3); got shape {rgb.shape}. "
            "Give an RGB (or gray) image."
        )
    if rgb.shape[0] < 1 or rgb.shape[1] < 1:
        raise ValueError(f"{name} is empty (shape {rgb.shape}); give a non-empty image.")
    if not rgb.dtype.isnative:  # a big-endian .npy is the same image ('>u2' != np.uint16 here)
        rgb = rgb.astype(rgb.dtype.newbyteorder("="))
    if rgb.dtype == np.uint8 or rgb.dtype == np.uint16:
        return rgb
    if rgb.dtype in (np.float32, np.float64):
        if not np.isfinite(rgb).all():
            raise ValueError(f"{name} holds NaN or inf; color values must be finite numbers in [0, 1].")
        lo, hi = float(rgb.min()), float(rgb.max())
        if lo < 0.0 or hi > 1.0:
            raise ValueError(
                f"{name} is floating point with values in [{lo:g}, {hi:g}]; float color must lie in "
                "[0, 1]. Divide by 255 (8-bit) or 65535 (16-bit), or pass the integer image."
            )
        return rgb
    raise TypeError(f"{name} has dtype {rgb.dtype}; expected uint8, uint16, float32 or float64. Convert it first.")


def as_rgb_float(rgb: np.ndarray) -> np.ndarray:
    """float32 RGB in [0, 1] from a checked uint8/uint16/float image (new array)."""
    if rgb.dtype == np.uint8:
        return rgb.astype(np.float32) / np.float32(255.0)
    if rgb.dtype == np.uint16:
        return rgb.astype(np.float32) / np.float32(65535.0)
    return rgb.astype(np.float32, copy=True)


def guide_uint8(rgb: np.ndarray) -> np.ndarray:
    """A checked uint8/uint16/float RGB image as contiguous uint8 (rounded; uint8 input as it is), for OpenCV's guides."""
    if rgb.dtype == np.uint8:
        return np.ascontiguousarray(rgb)
    return np.clip(as_rgb_float(rgb) * 255.0 + 0.5, 0, 255).astype(np.uint8)


# ----------------------------------------------------------------------------
# Memory guard
# ----------------------------------------------------------------------------


def available_memory() -> int | None:
    """Bytes of memory the machine can give this process now, or ``None`` if unknown.

    Linux: ``MemAvailable`` of ``/proc/meminfo`` (free memory plus what the
    kernel can reclaim, without swap). Elsewhere: ``psutil`` when installed,
    else the total physical memory from ``os.sysconf``.
    """
    try:
        with open("/proc/meminfo", "rb") as fh:
            for line in fh:
                if line.startswith(b"MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        import psutil
    except ImportError:
        pass
    else:
        return int(psutil.virtual_memory().available)
    try:
        return int(os.sysconf("SC_PHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):
        return None


@contextlib.contextmanager
def pixel_limit(max_pixels: int | None) -> Iterator[None]:
    """Within the block, :func:`check_pixels` uses ``max_pixels`` when not given one.

    The command line wraps each command in it, so ``--max-pixels`` reaches
    every image it reads and every library call it makes. ``None`` keeps the
    memory-derived limit only.
    """
    token = _MAX_PIXELS.set(None if max_pixels is None else check_int("max_pixels", max_pixels, minimum=1))
    try:
        yield
    finally:
        _MAX_PIXELS.reset(token)


def check_pixels(
    shape: tuple[int, ...],
    *,
    max_pixels: int | None = None,
    name: str = "rgb_hr",
    bytes_per_pixel: int = PEAK_BYTES_PER_PIXEL,
) -> None:
    """Refuse, before any work, an image too large for the limit or the machine.

    Parameters
    ----------
    shape : tuple
        ``(rows, cols[, channels])`` of the image (the output grid).
    max_pixels : int, optional
        Largest ``rows * cols`` allowed. ``None``: the limit set by
        :func:`pixel_limit` (``--max-pixels``), if any.
    name : str
        What the image is, for the message (``"rgb_hr"``, ``"color file x.png"``).
    bytes_per_pixel : int
        Estimated peak memory per pixel of the work to come.

    Raises
    ------
    ValueError
        More pixels than ``max_pixels``, or an estimated peak
        (``rows * cols * bytes_per_pixel``) above :func:`available_memory`.

    Examples
    --------
    >>> check_pixels((480, 640), max_pixels=10**6)
    >>> check_pixels((2000, 1000), max_pixels=10**6)
    Traceback (most recent call last):
    ...
    ValueError: rgb_hr is 1000x2000 = 2,000,000 pixels, more than the limit of 1,000,000 (max_pixels / --max-pixels); use a smaller image or raise the limit.
    """
    rows, cols = int(shape[0]), int(shape[1])
    n = rows * cols
    limit = _MAX_PIXELS.get() if max_pixels is None else check_int("max_pixels", max_pixels, minimum=1)
    if limit is not None and n > limit:
        raise ValueError(
            f"{name} is {cols}x{rows} = {n:,} pixels, more than the limit of {limit:,} "
            "(max_pixels / --max-pixels); use a smaller image or raise the limit."
        )
    need = n * int(bytes_per_pixel)
    avail = available_memory()
    if avail is not None and need > avail:
        raise ValueError(
            f"{name} is {cols}x{rows} = {n:,} pixels; processing it needs about {_gib(need)} of memory, "
            f"more than the {_gib(avail)} available. Crop or downscale the image, or free memory."
        )


def _gib(n_bytes: int) -> str:
    return f"{n_bytes / 2**30:.1f} GiB" if n_bytes >= 2**30 else f"{n_bytes / 2**20:.1f} MiB"


def check_choice(name: str, value: Any, choices: tuple[str, ...]) -> str:
    """``value`` if it is one of ``choices``; else a ``ValueError`` naming ``name`` and the choices."""
    if value not in choices:
        raise ValueError(f"{name} must be one of {list(choices)}; got {value!r}.")
    return value


def check_number(name: str, value: Any, *, positive: bool = False, nonnegative: bool = False,
                 finite: bool = True) -> float:
    """``value`` as a float (``TypeError`` for a non-number; ``ValueError`` if out of range).

    Finite unless ``finite=False``, which lets ``inf`` (and ``-inf``, unless
    ``positive`` or ``nonnegative``) through; NaN is always refused.
    """
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a number; got {value!r}.")
    value = float(value)
    if math.isnan(value) or (finite and math.isinf(value)):
        raise ValueError(f"{name} must be {'finite' if finite else 'a number, not NaN'}; got {value}.")
    if positive and value <= 0:
        raise ValueError(f"{name} must be > 0; got {value}.")
    if nonnegative and value < 0:
        raise ValueError(f"{name} must be >= 0; got {value}.")
    return value


def is_int(value: Any) -> bool:
    """Whether ``value`` is an integer (Python or NumPy), not a bool."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool)


def check_int(name: str, value: Any, *, minimum: int | None = None) -> int:
    """``value`` as an int (Python or NumPy integer; ``TypeError`` otherwise, bools too), ``>= minimum``."""
    if not is_int(value):
        raise TypeError(f"{name} must be an integer; got {value!r} ({type(value).__name__}).")
    if minimum is not None and value < minimum:
        raise ValueError(f"{name} must be >= {minimum}; got {value}.")
    return int(value)
