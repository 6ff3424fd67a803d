"""Weighted least-squares smoothing with any edge weights (compiled kernels): the solver of ``gbp``.

The fast global smoother of Min et al. (2014), as OpenCV-contrib's
``ximgproc.fastGlobalSmootherFilter`` implements it, solves
``(I + lambda * L_w) u = f`` approximately by alternating exact 1-D solves
(a tridiagonal system per row, then per column), ``iterations`` times, with
``lambda`` multiplied by ``attenuation`` after each. OpenCV derives the
weights ``w`` of the 1-D Laplacians ``L_w`` from a color guide only
(``exp(-|dc| / sigma_color)``, ``|dc|`` the Euclidean distance of two
neighbours' colors); here they are any non-negative array, so that ``gbp``
can also weight by the current depth's own gradients and vary the smoothing
strength per pixel. With the color weights alone the result equals OpenCV's
up to float rounding (tests/test_wls.py).

The Thomas algorithm (``sweep_columns`` in :mod:`._wls_jit` and its C twin) is written without the
subtraction of OpenCV's pivot, which cancels when ``lambda * w`` is large
(in float32 a constant came back off by 1e-2 at ``lambda * w = 3e6``, by
1e4 at ``1e7``, and at ``1e8`` the pivot was zero, a division by zero);
here every step adds positive terms or interpolates between two values, so a
constant stays exactly constant, a zero weight exactly separates two
neighbours, and any ``lambda`` up to ``inf`` gives a finite result (each
coupling ``lambda * w`` is capped at :data:`MAX_COUPLING`).

Each row (column) is solved on its own and in the same order of operations
whatever the thread count, so the result is bit-identical on any number of
cores or threads (OpenCV's filter splits its rows into per-thread stripes
whose tails take a scalar path, which changed the last bits with the core
count). The rows are solved as the columns of the transposed image (a
column solve vectorises across neighbouring columns). Large images are cut
into contiguous runs of blocks of columns, one per thread, by :func:`depthrefine._threads.run_split` (plain
Python threads; no numba ``parallel=True`` pool), so any number of threads
may call the solver at once, e.g. the frames of ``depthrefine.batch`` on
Dask threads, and a forked child works too, with the same bits.

Imported only when ``gbp`` runs (never at ``import depthrefine``): importing
this module imports neither numba nor the kernels. The kernels are
depthrefine's C library when it was built at install (:mod:`depthrefine._native`),
else numba's (:mod:`._wls_jit`, the reference; same bits); without either, a
``ModuleNotFoundError`` (the command line and ``depthrefine.batch`` turn it
into "pip install numba"). No
``fastmath``.

Reference: D. Min, S. Choi, J. Lu, B. Ham, K. Sohn, M. N. Do, "Fast global
image smoothing based on weighted least squares", IEEE TIP 23(12), 2014.
"""

from __future__ import annotations

import functools
import threading

import numpy as np

from .._native import kernels
from .._threads import run_split, worth_splitting
from .._validate import check_int, check_number

__all__ = ["color_weights", "depth_weights", "edge_weights", "smooth", "guided_smooth", "smooth_with_gradient",
           "scratch"]

#: Columns (rows) solved together by one thread (one vectorised sweep).
_BLOCK = 64
#: The largest coupling ``lam * w`` of two neighbours: larger ones (and an infinite ``lam``) count as this.
#: At it the two are already tied to float32 precision (their gap shrinks as ``1 / sqrt(lam * w)``).
MAX_COUPLING = 1e30


def _kernels():
    """The solver's kernels: the C ones when built (:mod:`depthrefine._native`), else numba's (:mod:`._wls_jit`)."""
    return kernels(__package__ + "._wls_jit")


def _blocks(n: int) -> int:
    """The number of blocks of ``_BLOCK`` rows (columns) in ``n``."""
    return (n + _BLOCK - 1) // _BLOCK


def _parallel(shape: tuple[int, ...]) -> bool:
    """Threads pay off only on larger images (:func:`depthrefine._threads.worth_splitting`)."""
    return worth_splitting(shape[0] * shape[1])


@functools.lru_cache(maxsize=8)
def _color_lut(channels: int, sigma_color: float) -> np.ndarray:
    """``exp(-sqrt(d2) / sigma_color)`` for every squared color distance ``d2`` of 8-bit channels."""
    levels = np.arange(channels * 255 * 255 + 1, dtype=np.float32)
    lut = np.exp(-np.sqrt(levels) / np.float32(sigma_color)).astype(np.float32)
    lut.flags.writeable = False
    return lut


def _guide(guide: np.ndarray) -> np.ndarray:
    """A checked guide as a C-contiguous (H, W, C) uint8 array (an (H, W) guide is one channel)."""
    guide = np.asarray(guide)
    if guide.ndim not in (2, 3):
        raise ValueError(f"guide must be an (H, W) or (H, W, C) array; got shape {guide.shape}.")
    if guide.dtype != np.uint8:  # a cast would wrap 16-bit values around 256 instead of scaling them
        raise ValueError(f"guide must be uint8 (8-bit channels); got {guide.dtype}: scale it to 0..255 first.")
    return np.ascontiguousarray(guide if guide.ndim == 3 else guide[:, :, None], dtype=np.uint8)


def color_weights(guide: np.ndarray, sigma_color: float) -> tuple[np.ndarray, np.ndarray]:
    """Edge weights ``exp(-|dc| / sigma_color)`` of an (H, W, C) uint8 guide, as OpenCV's fast global smoother.

    Returns ``(wx, wy)``, two (H, W) float32 arrays: ``wx[i, j]`` links pixel
    ``(i, j)`` to ``(i, j + 1)``, ``wy[i, j]`` to ``(i + 1, j)`` (0 in the last
    column / row). ``|dc|`` is the Euclidean distance of the two colors.
    An (H, W) guide is one channel.
    """
    guide = _guide(guide)
    sigma_color = check_number("sigma_color", sigma_color, positive=True)
    lut = _color_lut(guide.shape[2], sigma_color)
    wx = np.empty(guide.shape[:2], np.float32)
    wy = np.empty(guide.shape[:2], np.float32)
    run_split(_kernels().color_weight_rows, guide.shape[0], guide, lut, wx, wy, parallel=_parallel(guide.shape))
    return wx, wy


def depth_weights(x: np.ndarray, sigma: float, wx: np.ndarray, wy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(wx, wy)`` multiplied by ``exp(-|dx| / sigma)``, the current depth's own gradients (``sigma > 0``)."""
    x = np.ascontiguousarray(x, dtype=np.float32)
    if x.ndim != 2:
        raise ValueError(f"x must be a 2-D array; got shape {x.shape}.")
    wx, wy = _weights(x.shape, wx, wy)
    sigma = check_number("sigma", sigma, positive=True)
    out_x = np.empty_like(wx)
    out_y = np.empty_like(wy)
    run_split(_kernels().depth_weight_rows, x.shape[0], x, np.float32(1.0 / sigma), wx, wy, out_x, out_y,
              parallel=_parallel(x.shape))
    return out_x, out_y


def edge_weights(guide: np.ndarray, sigma_color: float, x: np.ndarray, sigma: float
                 ) -> tuple[np.ndarray, np.ndarray]:
    """:func:`depth_weights` of :func:`color_weights`, in one pass: ``exp(-|dc| / sigma_color - |dx| / sigma)``.

    The same bits as the two calls one after the other (each weight is the
    color weight times the depth factor, rounded once), without the color
    weights' own arrays.

    Examples
    --------
    >>> guide = np.zeros((4, 6, 3), np.uint8); guide[:, 3:] = 255
    >>> x = np.tile(np.arange(6, dtype=np.float32), (4, 1))
    >>> wx, wy = edge_weights(guide, 4.0, x, 2.0)
    >>> ref = depth_weights(x, 2.0, *color_weights(guide, 4.0))
    >>> bool((wx == ref[0]).all() and (wy == ref[1]).all())
    True
    """
    guide = _guide(guide)
    x = np.ascontiguousarray(x, dtype=np.float32)
    if x.shape != guide.shape[:2]:
        raise ValueError(f"x must have the guide's shape {guide.shape[:2]}; got {x.shape}.")
    lut = _color_lut(guide.shape[2], check_number("sigma_color", sigma_color, positive=True))
    sigma = check_number("sigma", sigma, positive=True)
    wx = np.empty(x.shape, np.float32)
    wy = np.empty(x.shape, np.float32)
    run_split(_kernels().edge_weight_rows, x.shape[0], guide, lut, x, np.float32(1.0 / sigma), wx, wy,
              parallel=_parallel(x.shape))
    return wx, wy


def _weights(shape: tuple[int, int], wx: np.ndarray, wy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``wx``, ``wy`` as C-contiguous float32, checked to be of ``shape`` (a ``ValueError`` naming the array)."""
    out = []
    for name, w in (("wx", wx), ("wy", wy)):
        w = np.ascontiguousarray(w, dtype=np.float32)
        if w.shape != shape:
            raise ValueError(f"{name} must have the shape of the image, {shape}; got {w.shape}.")
        out.append(w)
    return out[0], out[1]


def _check_in_place(x: np.ndarray, done: str, name: str = "x") -> None:
    """A ``ValueError`` unless ``x`` is a writeable, C-contiguous 2-D float32 array (it is ``done`` in place)."""
    if not (isinstance(x, np.ndarray) and x.dtype == np.float32 and x.ndim == 2 and x.flags.c_contiguous
            and x.flags.writeable):
        raise ValueError(f"{name} must be a writeable, C-contiguous 2-D float32 array (it is {done} in place).")


def smooth(src: np.ndarray, wx: np.ndarray, wy: np.ndarray, lam: float, *, iterations: int = 3,
           attenuation: float = 0.25, out: np.ndarray | None = None) -> np.ndarray:
    """Weighted least-squares smoothing of ``src`` with edge weights ``wx``, ``wy`` (see the module docstring).

    Parameters
    ----------
    src : (H, W) ndarray
        Values to smooth (converted to float32), all finite.
    wx, wy : (H, W) float32 ndarray
        Non-negative weights between horizontal / vertical neighbours
        (:func:`color_weights`; their last column / row is not used).
    lam : float
        Smoothing strength of the first iteration, ``>= 0``. Each coupling
        ``lam * w`` counts as at most :data:`MAX_COUPLING` (``1e30``), so any
        larger ``lam``, ``inf`` included, gives the same finite result.
    iterations, attenuation : int, float
        As OpenCV's ``num_iter`` (3, ``>= 1``) and ``lambda_attenuation``
        (0.25, ``>= 0``).
    out : (H, W) float32 ndarray, optional
        Where to solve (writeable, C-contiguous; ``src`` itself to solve in
        place): no new image-sized array.

    Returns
    -------
    (H, W) float32 ndarray
        ``out`` when given. Bit-identical for the same input, whatever the
        number of cores and of threads calling at once.

    Raises
    ------
    ValueError
        ``src`` not 2-D or not finite (NaN or infinite values would spread
        along their rows and columns; ``gbp`` fills holes before it smooths),
        ``wx`` / ``wy`` of another shape, negative or NaN, ``lam`` NaN or
        negative, ``iterations < 1``, ``attenuation`` negative or not finite.

    Examples
    --------
    >>> guide = np.zeros((4, 6, 3), np.uint8); guide[:, 3:] = 255
    >>> wx, wy = color_weights(guide, 4.0)
    >>> src = np.tile(np.array([0, 1, 0, 10, 11, 10], np.float32), (4, 1))
    >>> out = smooth(src, wx, wy, 100.0)
    >>> bool(out[:, :3].max() < 1 and out[:, 3:].min() > 10)
    True
    """
    src = np.asarray(src)
    if src.ndim != 2:
        raise ValueError(f"src must be a 2-D array; got shape {src.shape}.")
    wx, wy = _weights(src.shape, wx, wy)
    lam = check_number("lam", lam, nonnegative=True, finite=False)
    iterations = check_int("iterations", iterations, minimum=1)
    attenuation = check_number("attenuation", attenuation, nonnegative=True)
    if src.size:
        for name, w in (("wx", wx), ("wy", wy)):
            low = w.min()
            if not low >= 0:
                raise ValueError(f"{name} must be >= 0 everywhere, without NaN; got min {low}.")
        _check_finite(src, "src")
    u = _target(src, out, wx, wy)   # every check first: a refused call leaves out as it was
    if u.size == 0:
        return u
    return _solve(u, wx, wy, np.float32(min(lam, MAX_COUPLING)), iterations, np.float32(attenuation))


def _check_finite(values: np.ndarray, name: str) -> None:
    """A ``ValueError`` unless ``values`` are finite, and within float32's range (the solve's type)."""
    low, high = values.min(), values.max()      # NaN propagates into both; no bool array
    if not (np.isfinite(low) and np.isfinite(high)) or max(-float(low), float(high)) > float(np.finfo(np.float32).max):
        raise ValueError(f"{name} must be finite everywhere (float32); got NaN or infinite values (fill them first).")


def _target(src: np.ndarray, out: np.ndarray | None, *apart: np.ndarray) -> np.ndarray:
    """The float32 array a solve of ``src`` works in: a C-contiguous copy, or ``out`` holding ``src``'s values.

    ``out`` must share no memory with ``apart`` (the weights the solve reads, its guide): a solve in place
    would write over them as it reads them.
    """
    if out is None:
        return np.array(src, dtype=np.float32, order="C")
    _check_in_place(out, "solved", "out")
    if np.shape(src) != out.shape:
        raise ValueError(f"out must have src's shape {np.shape(src)}; got {out.shape}.")
    _check_apart(out, "out", *apart)
    if src is not out:
        np.copyto(out, src, casting="same_kind")
    return out


def _check_apart(u: np.ndarray, name: str, *others: np.ndarray) -> None:
    """A ``ValueError`` if ``u``, solved in place, shares memory with any of ``others``."""
    if any(np.may_share_memory(u, other) for other in others):
        raise ValueError(f"{name} must not share memory with the weights, the guide or this module's scratch arrays "
                         "(scratch()): give it an array of its own.")


#: Per thread: scratch arrays of the last shapes solved (:func:`_scratch`).
_local = threading.local()
#: Uses and shapes whose scratch arrays a thread keeps (gbp-fast solves on two grids, each also transposed).
_SCRATCH_SHAPES = 8


def _scratch(use: str, shape: tuple[int, int], count: int = 2) -> list[np.ndarray]:
    """``count`` float32 arrays of ``shape`` for ``use``, kept per thread for the next call of that use and shape.

    A new array of megabytes costs a page fault per 4 KiB page when first
    written (glibc maps large blocks afresh each time), which took more time
    than the transposes they hold; kept, they are written in place. A thread
    keeps those of its last :data:`_SCRATCH_SHAPES` uses and shapes. Only this
    module's functions use them, never beyond their own call.
    """
    cache = getattr(_local, "scratch", None)
    if cache is None:
        cache = _local.scratch = {}
    arrays = cache.pop((use, shape), [])
    arrays += [np.empty(shape, np.float32) for _ in range(count - len(arrays))]
    cache[use, shape] = arrays                              # most recent last
    while len(cache) > _SCRATCH_SHAPES:
        del cache[next(iter(cache))]
    return arrays[:count]


def scratch(shape: tuple[int, int], count: int = 2) -> list[np.ndarray]:
    """``count`` (at most 2) float32 arrays of ``shape`` that this module's solves use as scratch, in this thread.

    For a caller's own image-sized temporaries between two solves: no new
    array (its page faults) and no more memory than the solves hold anyway.
    Their contents are undefined, and the next :func:`guided_smooth` or
    :func:`smooth_with_gradient` in this thread overwrites them.
    """
    if not 1 <= count <= 2:
        raise ValueError(f"count must be 1 or 2; got {count}.")
    return _scratch("weights", (int(shape[0]), int(shape[1])))[:count]


def guided_smooth(src: np.ndarray, guide: np.ndarray, sigma_color: float, sigma: float, lam: float, *,
                  iterations: int = 1, attenuation: float = 0.25, out: np.ndarray | None = None) -> np.ndarray:
    """:func:`smooth` of ``src`` with the weights :func:`edge_weights` of ``guide`` and ``src`` itself, fused.

    The same result as ``smooth(src, *edge_weights(guide, sigma_color, src,
    sigma), lam, ...)``, bit for bit, without handing out the weights: they
    are made in this thread's scratch arrays, so a call on the shape of the
    previous one allocates only its result. With ``out`` (as :func:`smooth`'s:
    ``src`` itself solves in place) it allocates nothing. ``src`` must be
    finite (it is converted to float32).

    Examples
    --------
    >>> guide = np.zeros((4, 6, 3), np.uint8); guide[:, 3:] = 255
    >>> src = np.tile(np.array([0, 1, 0, 10, 11, 10], np.float32), (4, 1))
    >>> out = guided_smooth(src, guide, 4.0, 5.0, 100.0, iterations=3)
    >>> bool((out == smooth(src, *edge_weights(guide, 4.0, src, 5.0), 100.0)).all())
    True
    """
    guide = _guide(guide)
    src = np.asarray(src)
    if src.shape != guide.shape[:2]:
        raise ValueError(f"src must have the guide's shape {guide.shape[:2]}; got {src.shape}.")
    lut = _color_lut(guide.shape[2], check_number("sigma_color", sigma_color, positive=True))
    sigma, lam32, iterations, attenuation32 = _solve_arguments(src, "src", sigma, lam, iterations, attenuation)
    if src.size == 0:
        return _target(src, out)
    wx, wy = _scratch("weights", src.shape)
    u = _target(src, out, wx, wy, guide)     # every check first: a refused call leaves out as it was
    run_split(_kernels().edge_weight_rows, u.shape[0], guide, lut, u, np.float32(1.0 / sigma), wx, wy,
              parallel=_parallel(u.shape))
    return _solve(u, wx, wy, lam32, iterations, attenuation32)


def _solve_arguments(u: np.ndarray, name: str, sigma: float, lam: float, iterations: int, attenuation: float
                     ) -> tuple[float, np.float32, int, np.float32]:
    """The checked ``sigma``, ``lam`` (float32, capped at ``MAX_COUPLING``), ``iterations`` and ``attenuation``
    (float32) of a solve of ``u`` (called ``name`` in the errors), which must be finite."""
    sigma = check_number("sigma", sigma, positive=True)
    lam = check_number("lam", lam, nonnegative=True, finite=False)
    iterations = check_int("iterations", iterations, minimum=1)
    attenuation = check_number("attenuation", attenuation, nonnegative=True)
    if u.size:
        _check_finite(u, name)
    return sigma, np.float32(min(lam, MAX_COUPLING)), iterations, np.float32(attenuation)


def smooth_with_gradient(x: np.ndarray, wx: np.ndarray, wy: np.ndarray, sigma: float, lam: float, *,
                         iterations: int = 3, attenuation: float = 0.25) -> np.ndarray:
    """:func:`smooth` of ``x`` with the weights :func:`depth_weights` of ``x`` itself, in place.

    The same bits as ``smooth(x, *depth_weights(x, sigma, wx, wy), lam,
    ...)``, but ``x`` (a C-contiguous, finite float32 array) is solved in
    place and returned, and the weights are made in this thread's scratch
    arrays: no new image-sized array (each new one costs a page fault per
    4 KiB page on first write).

    Examples
    --------
    >>> guide = np.zeros((4, 6, 3), np.uint8); guide[:, 3:] = 255
    >>> wx, wy = color_weights(guide, 4.0)
    >>> x = np.tile(np.array([0, 1, 0, 10, 11, 10], np.float32), (4, 1))
    >>> ref = smooth(x, *depth_weights(x, 5.0, wx, wy), 100.0)
    >>> smooth_with_gradient(x, wx, wy, 5.0, 100.0) is x, bool((x == ref).all())
    (True, True)
    """
    _check_in_place(x, "solved")
    wx, wy = _weights(x.shape, wx, wy)
    sigma, lam32, iterations, attenuation32 = _solve_arguments(x, "x", sigma, lam, iterations, attenuation)
    if x.size == 0:
        return x
    out_x, out_y = _scratch("weights", x.shape)
    _check_apart(x, "x", out_x, out_y, wx, wy)
    run_split(_kernels().depth_weight_rows, x.shape[0], x, np.float32(1.0 / sigma), wx, wy, out_x, out_y,
              parallel=_parallel(x.shape))
    return _solve(x, out_x, out_y, lam32, iterations, attenuation32)


def _solve(u: np.ndarray, wx: np.ndarray, wy: np.ndarray, lam32: np.float32, iterations: int,
           attenuation32: np.float32) -> np.ndarray:
    """:func:`smooth`'s iterations on checked arrays: ``u`` is solved in place and returned."""
    parallel = _parallel(u.shape)
    rows, cols = u.shape
    for _ in range(iterations):
        run_split(_solve_rows, _blocks(rows), u, wx, lam32, parallel=parallel)
        run_split(_kernels().solve_columns, _blocks(cols), u, wy, lam32, _BLOCK, parallel=parallel)
        lam32 = np.float32(lam32 * attenuation32)
    return u


def _solve_rows(u: np.ndarray, wx: np.ndarray, lam32: np.float32, b0: int, b1: int) -> None:
    """The row solves of the strips ``b0:b1`` of ``_BLOCK`` rows: each strip as the columns of its transpose.

    A column solve vectorises over neighbouring columns; a strip of rows is
    transposed into a tile (``cv2.transpose``, at memory speed, where the
    element-wise copy it replaced took three times the solve), solved, and
    transposed back, the tile staying in the CPU's cache. Only two tiles per
    thread, not a transposed copy of the image. Releases the GIL in its
    parts, so threads run strips side by side.
    """
    import cv2

    rows, cols = u.shape
    sweep_columns = _kernels().sweep_columns
    tile_u, tile_w = _scratch("tiles", (cols, _BLOCK))
    for b in range(b0, b1):
        i0, i1 = b * _BLOCK, min(rows, (b + 1) * _BLOCK)
        n = i1 - i0
        t_u = cv2.transpose(u[i0:i1], dst=tile_u[:, :n] if n == _BLOCK else None)
        t_w = cv2.transpose(wx[i0:i1], dst=tile_w[:, :n] if n == _BLOCK else None)
        sweep_columns(t_u, t_w, lam32, 0, n)
        cv2.transpose(t_u, dst=u[i0:i1])

