"""gbp's and the thesis method's kernels compiled ahead of time (``kernels.c``, built at install), or numba's when
they are not built.

A fresh process that runs gbp through numba spends about half a second
before its first kernel (numba's import and the set-up of its CPU target:
``docs/speed.md``). The same kernels in plain C, compiled when the package is
installed (``setup.py``), load in a millisecond. They are the numba kernels
operation for operation and give the same bits (``tests/test_native.py``);
numba's remain the reference and the fallback.

:func:`kernels` gives a kernel module's functions: this package's C ones
(called through ctypes, which releases the GIL around each call, so
:func:`depthrefine._threads.run_split` runs their parts side by side) when
the library is built, current and usable on this CPU, else the numba module
itself. ``DEPTHREFINE_KERNELS=numba`` in the environment forces numba's.

The wrappers below take the numba kernels' arguments, in their order. They
check what would make C read or write out of bounds or round otherwise than
numba in the arrays' layout (dtypes, C-contiguity, float32 scalars),
not the shapes' agreement, which the modules that call them check
(``methods/_wls.py``, ``methods/_resample.py``, ``methods/gbp/_offsets.py``,
``methods/gbp/fattening.py``, ``_geodesic.py``). The thesis method's
(``methods/thesis/_jit.py``: every kernel but ``median_rows``, the table
interpreter for window sizes without a generated kernel) check their shapes
too, and hand the dtypes the method never gives them to numba's kernel
(``quantize_lab``, ``fill_missing``; the others refuse them). Neither checks
the values of index arrays (feature codes, labels, nearest rows and
columns), which their callers make in range: an index out of range that
numba would wrap or read past reads or writes past the array in C. These
are the package's internal kernels, not an API.
"""

from __future__ import annotations

import ctypes
import hashlib
import importlib
import os
import sys
import threading
from importlib.machinery import EXTENSION_SUFFIXES
from pathlib import Path
from types import ModuleType, SimpleNamespace

__all__ = ["kernels", "c_kernels", "library", "why_not", "describe"]

#: The environment variable that chooses the kernels: ``numba`` forces numba's, anything else means "the C ones
#: when built".
ENV = "DEPTHREFINE_KERNELS"

#: The C functions' signatures this module calls: kernels.c's DEPTHREFINE_KERNELS_ABI must say the same.
ABI = 4

_lock = threading.Lock()
_loaded: list = []          # [library or None, reason it is None]
_c_int64, _c_float, _c_double, _p = ctypes.c_int64, ctypes.c_float, ctypes.c_double, ctypes.c_void_p
_i = ctypes.c_ssize_t


def _cpu_supports_build() -> bool:
    """Whether this CPU runs the instructions the library was built with (AVX2 and FMA on x86-64 Linux)."""
    if sys.platform != "linux" or os.uname().machine not in ("x86_64", "AMD64"):
        return True             # built without extra instruction sets there (setup.py)
    try:
        with open("/proc/cpuinfo", encoding="ascii", errors="replace") as f:
            for line in f:
                if line.startswith("flags"):
                    flags = set(line.split(":", 1)[1].split())
                    return {"avx2", "fma"} <= flags
    except OSError:
        pass
    return False


def _find(here: Path = Path(__file__).parent) -> tuple[ctypes.CDLL | None, str]:
    """The library built in the folder ``here`` and checked against its ``kernels.c``, or None and why not."""
    built = [here / f"_kernels{suffix}" for suffix in EXTENSION_SUFFIXES if (here / f"_kernels{suffix}").exists()]
    if not built:
        return None, "not built (no C compiler when the package was installed?)"
    if not _cpu_supports_build():
        return None, "built for AVX2 and FMA, which this CPU lacks"
    lib = ctypes.CDLL(str(built[0]))
    source = here / "kernels.c"
    lib.dr_source_hash.restype = ctypes.c_char_p
    if source.exists() and lib.dr_source_hash().decode() != hashlib.sha256(source.read_bytes()).hexdigest():
        return None, f"{built[0].name} was built from another kernels.c: reinstall (pip install -e .)"
    if lib.dr_abi_version() != ABI:
        return None, f"{built[0].name} has other signatures (ABI {lib.dr_abi_version()}, not {ABI}): reinstall"
    _declare(lib)
    return lib, ""


def _declare(lib: ctypes.CDLL) -> None:
    """The C functions' argument and result types."""
    signatures = {
        "dr_exp_f32": (_c_float, [_c_float]),
        "dr_abi_version": (ctypes.c_int, []),
        "dr_sweep_columns": (ctypes.c_int, [_p, _i, _p, _i, _i, _c_float, _i, _i]),
        "dr_solve_columns": (ctypes.c_int, [_p, _p, _i, _i, _c_float, _i, _i, _i]),
        "dr_color_weight_rows": (None, [_p, _i, _i, _i, _p, _p, _p, _i, _i]),
        "dr_edge_weight_rows": (None, [_p, _i, _i, _i, _p, _p, _c_float, _p, _p, _i, _i]),
        "dr_depth_weight_rows": (None, [_p, _i, _i, _c_float, _p, _p, _p, _p, _i, _i]),
        "dr_enlarge_rows": (None, [_p, _i, _i, _p, _p, _p, _p, _i, _p, _p, _i, _i]),
        "dr_clip_rows": (None, [_p, _i, _c_float, _c_float, _p, _p, _i, _p, _p, _i, _i]),
        "dr_clip_toward_rows": (None, [_p, _i, _p, _p, _p, _i, _p, _p, _i, _i]),
        "dr_hypot_rows": (None, [_p, _p, _p, _i, _i, _i]),
        "dr_nearest_seen": (ctypes.c_int, [_p, _i, _i, _c_double, ctypes.c_int, _p, _i, _i]),
        "dr_geodesic_sweeps": (None, [_p, _p, _p, _p, _p, _i, _i, _i]),
        "dr_search": (ctypes.c_int, [_p, _p, _p, _p, _p, _i, _i, _c_int64, _c_double, _p, _p, _p, _p, _i, _i]),
        # the thesis method's (methods/thesis/_jit.py)
        "dr_quantize_lab": (None, [_p, _i, _i, _c_float, _c_float, ctypes.c_int, _c_float, _c_float, _p, _p, _p, _p,
                                   _p, _p]),
        "dr_feature_codes": (None, [_p, _p, _p, _i, _c_int64, _c_int64, _c_int64, _c_int64, _c_int64, _p, _p, _i]),
        "dr_lookup": (None, [_p, _p, _i, _p]),
        "dr_lloyd": (_c_int64, [_p, _p, _i, _i, _p, _i, _c_int64, _p, _p]),
        "dr_grow_samples": (None, [_p, _i, _i, _i, _p, _p, _p]),
        "dr_interpolate_patch": (_c_int64, [_p, _i, _i, _p, _p, _i, _i, _p, _p, _p, _p, _p, _p, _p, _p, _p]),
        "dr_fill_missing": (None, [_p, _i, _i, _p, ctypes.c_int, _i, _p, _p]),
        "dr_correct_values": (ctypes.c_int, [_p, _i, _c_double, _c_double, _i, _c_double, _c_double, _p]),
        "dr_correct_patch": (ctypes.c_int, [_p, _i, _i, _p, _i, _i, _i, _i, _c_int64, ctypes.c_int, _c_double,
                                            _c_double, _i, _c_double, _c_double, _p]),
        "dr_median": (ctypes.c_int, [_p, _p, _i, _i, ctypes.c_int, ctypes.c_int, ctypes.c_int, _i, _i]),
    }
    for name, (restype, argtypes) in signatures.items():
        function = getattr(lib, name)
        function.restype, function.argtypes = restype, argtypes


def library() -> ctypes.CDLL | None:
    """The built C library, or None (:func:`why_not` says why); loaded once per process."""
    with _lock:
        if not _loaded:
            if os.environ.get(ENV, "").strip().lower() == "numba":
                _loaded[:] = [None, f"{ENV}=numba"]
            else:
                try:
                    _loaded[:] = list(_find())
                except Exception as exc:  # noqa: BLE001 - a file that does not load, or lacks a function: numba's
                    _loaded[:] = [None, f"does not load: {exc}"]
        return _loaded[0]


def _check(status: int) -> None:
    if status != 0:
        raise MemoryError("depthrefine's C kernels could not allocate their scratch memory")


def describe() -> str:
    """Which compiled kernels gbp and the thesis method run, in a few words (``depthrefine --version``)."""
    return "compiled kernels: C" if library() is not None else f"compiled kernels: numba (C ones: {why_not()})"


def why_not() -> str:
    """Why :func:`library` is None ('' when it is not)."""
    library()
    return _loaded[1]


def kernels(jit_module: str) -> ModuleType | SimpleNamespace:
    """The kernels of the numba module ``jit_module`` (a full module name): the C ones when built, else that module.

    Imports numba only when the C library is not there.
    """
    c = c_kernels()
    return importlib.import_module(jit_module) if c is None else c


def c_kernels() -> SimpleNamespace | None:
    """The C kernels under the numba kernels' names and arguments (and ``hypot_rows`` and ``nearest_seen``, whose
    fallbacks are numpy's expressions), or None when the library is not there."""
    lib = library()
    return None if lib is None else _wrappers(lib)


_namespace: list[SimpleNamespace] = []


def _wrappers(lib: ctypes.CDLL) -> SimpleNamespace:
    """The C kernels under the numba kernels' names and arguments."""
    if _namespace:
        return _namespace[0]
    import numpy as np      # here, not at the top: ``depthrefine --version`` asks library() and imports no numpy

    def _ptr(a: np.ndarray, dtype=np.float32, *, rows_strided: bool = False) -> int:
        """The address of ``a``'s data, once it is checked to be ``dtype`` and C-contiguous (or, ``rows_strided``,
        its elements contiguous within each row): a wrong array must raise here, never reach C."""
        if a.dtype != dtype or not (a.flags.c_contiguous or rows_strided and a.ndim == 2
                                    and a.strides[1] == a.itemsize and a.strides[0] % a.itemsize == 0
                                    and a.strides[0] >= a.shape[1] * a.itemsize):
            raise TypeError(f"depthrefine's C kernels take C-contiguous {np.dtype(dtype)} arrays; got {a.dtype}, "
                            f"strides {a.strides}")
        return a.__array_interface__["data"][0]

    def _f32(value) -> float:
        """A float32 argument's value; anything else raises (numba would compile the kernel for float64 instead)."""
        if not isinstance(value, np.float32):
            raise TypeError(f"depthrefine's C kernels take np.float32 scalars where numba's got them; "
                            f"got {type(value)}")
        return float(value)

    def sweep_columns(u, w, lam, j0, j1):
        # u and w may be views of wider tiles: rows of `strides[0]` bytes, float32 elements side by side
        _check(lib.dr_sweep_columns(_ptr(u, rows_strided=True), u.strides[0] // 4, _ptr(w, rows_strided=True),
                                    w.strides[0] // 4, u.shape[0], _f32(lam), int(j0), int(j1)))

    def solve_columns(u, w, lam, block, b0, b1):
        if w.shape != u.shape:
            raise TypeError(f"w must have u's shape {u.shape}; got {w.shape}")
        _check(lib.dr_solve_columns(_ptr(u), _ptr(w), u.shape[0], u.shape[1], _f32(lam), int(block), int(b0),
                                    int(b1)))

    def color_weight_rows(guide, lut, wx, wy, i0, i1):
        rows, cols, channels = guide.shape
        lib.dr_color_weight_rows(_ptr(guide, np.uint8), rows, cols, channels, _ptr(lut), _ptr(wx), _ptr(wy),
                                 int(i0), int(i1))

    def edge_weight_rows(guide, lut, x, inv_sigma, wx, wy, i0, i1):
        rows, cols, channels = guide.shape
        lib.dr_edge_weight_rows(_ptr(guide, np.uint8), rows, cols, channels, _ptr(lut), _ptr(x), _f32(inv_sigma),
                                _ptr(wx), _ptr(wy), int(i0), int(i1))

    def depth_weight_rows(x, inv_sigma, wx, wy, out_x, out_y, i0, i1):
        lib.dr_depth_weight_rows(_ptr(x), x.shape[0], x.shape[1], _f32(inv_sigma), _ptr(wx), _ptr(wy),
                                 _ptr(out_x), _ptr(out_y), int(i0), int(i1))

    def enlarge_rows(x, s0, s1, s2, guide, lut, out, i0, i1):
        lib.dr_enlarge_rows(_ptr(x), x.shape[0], x.shape[1], _ptr(s0, np.uint8), _ptr(s1, np.uint8),
                            _ptr(s2, np.uint8), _ptr(guide, np.uint8), guide.shape[1], _ptr(lut), _ptr(out), int(i0),
                            int(i1))

    def clip_rows(x, low, high, lower, upper, rows, cols, i0, i1):
        lib.dr_clip_rows(_ptr(x), x.shape[1], _f32(low), _f32(high), _ptr(lower), _ptr(upper), lower.shape[1],
                         _ptr(rows, np.int32), _ptr(cols, np.int32), int(i0), int(i1))

    def clip_toward_rows(x, weight, lower, upper, rows, cols, i0, i1):
        lib.dr_clip_toward_rows(_ptr(x), x.shape[1], _ptr(weight), _ptr(lower), _ptr(upper), lower.shape[1],
                                _ptr(rows, np.int32), _ptr(cols, np.int32), int(i0), int(i1))

    def hypot_rows(x, y, out, i0, i1):
        if not x.shape == y.shape == out.shape:
            raise TypeError(f"x, y and out must have one shape; got {x.shape}, {y.shape}, {out.shape}")
        lib.dr_hypot_rows(_ptr(x), _ptr(y), _ptr(out), x.shape[1], int(i0), int(i1))

    def nearest_seen(depth, reach, direction, out, k0, k1):
        if out.shape != depth.shape:
            raise TypeError(f"out must have depth's shape {depth.shape}; got {out.shape}")
        _check(lib.dr_nearest_seen(_ptr(depth), depth.shape[0], depth.shape[1], float(reach), int(direction),
                                   _ptr(out), int(k0), int(k1)))

    def sweeps(cost_x, cost_y, free, distance, source, passes):
        if not cost_x.shape == cost_y.shape == free.shape == distance.shape == source.shape:
            raise TypeError("cost_x, cost_y, free, distance and source must have one shape")
        lib.dr_geodesic_sweeps(_ptr(cost_x), _ptr(cost_y), _ptr(free, np.bool_), _ptr(distance),
                               _ptr(source, np.int64), free.shape[0], free.shape[1], int(passes))

    def search(band, magnitude, gx, gy, edges, reach, peak_ratio, row_start, offsets, angles, found, i0, i1):
        _check(lib.dr_search(_ptr(band, np.bool_), _ptr(magnitude), _ptr(gx), _ptr(gy), _ptr(edges), band.shape[0],
                             band.shape[1], int(reach), float(peak_ratio), _ptr(row_start, np.int64),
                             _ptr(offsets, np.float64), _ptr(angles, np.float64), _ptr(found, np.int64), int(i0),
                             int(i1)))

    thesis = _thesis_wrappers(lib, np, _ptr, _f32)
    _namespace.append(SimpleNamespace(
        **thesis, sweep_columns=sweep_columns, solve_columns=solve_columns, color_weight_rows=color_weight_rows,
        edge_weight_rows=edge_weight_rows, depth_weight_rows=depth_weight_rows, enlarge_rows=enlarge_rows,
        clip_rows=clip_rows, clip_toward_rows=clip_toward_rows, hypot_rows=hypot_rows, nearest_seen=nearest_seen,
        sweeps=sweeps, search=search, expf32=lib.dr_exp_f32))
    return _namespace[0]


def _thesis_jit(name: str):
    """The numba kernel ``name`` of the thesis method, for arguments its C twin does not take (imports numba)."""
    return getattr(importlib.import_module("depthrefine.methods.thesis._jit"), name)


def _thesis_wrappers(lib: ctypes.CDLL, np, _ptr, _f32) -> dict:
    """The thesis method's C kernels under the names and arguments of ``methods/thesis/_jit.py``'s.

    The method gives them the dtypes below; other dtypes that numba's would compile a kernel for (a float64
    L*a*b* patch in :func:`~depthrefine.methods.thesis.segment.cluster_colors`, an integer fallback map) go to
    numba's kernel. A k-means round that keeps no cluster (no positive weight) raises ``ValueError``.
    """
    i64 = np.int64

    def _strides(a: np.ndarray, dtype) -> tuple[int, int, int]:
        """The address of a 2-D array of ``dtype`` and its strides in elements (any strides, as numba takes)."""
        if a.dtype != dtype or a.ndim != 2 or any(st % a.itemsize for st in a.strides):
            raise TypeError(f"depthrefine's C kernels take 2-D {np.dtype(dtype)} arrays; got {a.dtype}, "
                            f"strides {a.strides}")
        return a.__array_interface__["data"][0], a.strides[0] // a.itemsize, a.strides[1] // a.itemsize

    def quantize_lab(lab, inv_step, half, unify, black, white, qa, qb, first):
        if lab.dtype != np.float32 or not isinstance(black, np.float32) or not isinstance(white, np.float32):
            return _thesis_jit("quantize_lab")(lab, inv_step, half, unify, black, white, qa, qb, first)
        rows, cols = qa.shape
        if lab.shape != (rows, cols, 3) or not qa.shape == qb.shape == first.shape:
            raise TypeError(f"lab must be (rows, cols, 3) and qa, qb, first (rows, cols); got {lab.shape}, "
                            f"{qa.shape}, {qb.shape}, {first.shape}")
        ranges, n_cls, sum_l = np.empty(6, i64), np.empty(3, i64), np.empty(3, np.float64)
        lib.dr_quantize_lab(_ptr(lab), rows, cols, _f32(inv_step), _f32(half), int(bool(unify)), float(black),
                            float(white), _ptr(qa, np.int32), _ptr(qb, np.int32), _ptr(first, np.int32),
                            _ptr(ranges, i64), _ptr(n_cls, i64), _ptr(sum_l, np.float64))
        return (*(int(v) for v in ranges), n_cls, sum_l)

    def feature_codes(qa, qb, first, a0, na, b0, nb, f0, code, counts):
        if not qa.shape == qb.shape == first.shape == code.shape or counts.ndim != 1:
            raise TypeError("qa, qb, first and code must have one shape, counts one dimension")
        lib.dr_feature_codes(_ptr(qa, np.int32), _ptr(qb, np.int32), _ptr(first, np.int32), qa.size, int(a0),
                             int(na), int(b0), int(nb), int(f0), _ptr(code, np.int32), _ptr(counts, np.intp),
                             counts.shape[0])

    def lookup(table, index, out):
        if index.shape != out.shape:
            raise TypeError(f"out must have index's shape {index.shape}; got {out.shape}")
        lib.dr_lookup(_ptr(table, np.int16), _ptr(index, np.int32), index.size, _ptr(out, np.int16))

    def lloyd(x, w, means, iterations):
        n, dims = x.shape
        if w.shape != (n,) or means.ndim != 2 or means.shape[1] != dims:
            raise TypeError(f"w must be ({n},) and means (k, {dims}); got {w.shape}, {means.shape}")
        labels, out = np.empty(n, np.int32), np.empty(means.shape, np.float64)
        kept = lib.dr_lloyd(_ptr(x), _ptr(w, np.float64), n, dims, _ptr(means, np.float64), means.shape[0],
                            int(iterations), _ptr(labels, np.int32), _ptr(out, np.float64))
        if kept == -2:   # numba's kernel indexes empty arrays there: segment.kmeans refuses such weights first
            raise ValueError("k-means kept no cluster: every weight must be > 0")
        _check(0 if kept >= 0 else -1)
        return labels, out[:kept]

    def grow_samples(masks, corrected, values, grown):
        k, rows, cols = masks.shape
        if corrected.shape != (rows, cols) or not masks.shape == values.shape == grown.shape:
            raise TypeError("corrected must be (rows, cols) and masks, values, grown (k, rows, cols)")
        lib.dr_grow_samples(_ptr(masks, np.bool_), k, rows, cols, _ptr(corrected, np.float64),
                            _ptr(values, np.float64), _ptr(grown, np.bool_))

    def interpolate_patch(filled, cell_label, labels, weighted, present, i0, i1, fr, j0, j1, fc, out):
        rows, cols = labels.shape
        n_lr, w_lr = filled.shape
        if (cell_label.shape != filled.shape or weighted.shape != present.shape or weighted.shape[1:] != filled.shape
                or out.shape != labels.shape or not i0.shape == i1.shape == fr.shape == (rows,)
                or not j0.shape == j1.shape == fc.shape == (cols,)):
            raise TypeError("interpolate_patch: the arrays' shapes do not agree")
        bad = lib.dr_interpolate_patch(_ptr(filled), n_lr, w_lr, _ptr(cell_label, np.int16), _ptr(labels, np.int16),
                                       rows, cols, _ptr(weighted, np.float64), _ptr(present, np.float64),
                                       _ptr(i0, np.intp), _ptr(i1, np.intp), _ptr(fr, np.float64), _ptr(j0, np.intp),
                                       _ptr(j1, np.intp), _ptr(fc, np.float64), _ptr(out))
        _check(0 if bad >= 0 else -1)
        return bad

    def fill_missing(result, fallback, near_rows, near_cols):
        if fallback.dtype not in (np.float32, np.float64):
            return _thesis_jit("fill_missing")(result, fallback, near_rows, near_cols)
        rows, cols = result.shape
        if near_rows.shape != (rows,) or near_cols.shape != (cols,):
            raise TypeError("near_rows and near_cols must have result's rows and columns")
        address, row_stride, col_stride = _strides(fallback, fallback.dtype)
        if col_stride != 1 or row_stride < fallback.shape[1]:
            raise TypeError(f"fallback's rows must be contiguous; got strides {fallback.strides}")
        lib.dr_fill_missing(_ptr(result), rows, cols, address, int(fallback.dtype == np.float64), row_stride,
                            _ptr(near_rows, np.intp), _ptr(near_cols, np.intp))

    def correct_values(values, origin, level_size, bin_width, n_bins, dominant_fraction, tolerance, out):
        if values.ndim != 1 or out.shape != values.shape or int(n_bins) < 1:
            raise TypeError("values and out must be one-dimensional, of one shape, with n_bins >= 1")
        _check(lib.dr_correct_values(_ptr(values, np.float64), values.shape[0], float(origin), float(bin_width),
                                     int(n_bins), float(dominant_fraction), float(tolerance), _ptr(out, np.float64)))

    def correct_patch(depth, samples, k, correct, origin, level_size, bin_width, n_bins, dominant_fraction,
                      tolerance, out):
        if depth.shape != samples.shape or out.shape != depth.shape or int(n_bins) < 1:
            raise TypeError("depth, samples and out must have one shape, with n_bins >= 1")
        d, d_row, d_col = _strides(depth, np.float32)
        s, s_row, s_col = _strides(samples, np.int16)
        _check(lib.dr_correct_patch(d, d_row, d_col, s, s_row, s_col, depth.shape[0], depth.shape[1], int(k),
                                    int(bool(correct)), float(origin), float(bin_width), int(n_bins),
                                    float(dominant_fraction), float(tolerance), _ptr(out, np.float64)))

    def median_rows(flat, oflat, size, channels, y0, y1) -> bool:
        """Rows ``y0 .. y1-1`` of the median of ``median.median_filter``'s generated kernels into ``oflat``; False
        (nothing done) where kernels.c has no kernel for the size, channel count or dtype."""
        if flat.dtype not in (np.uint8, np.uint16) or oflat.shape != flat.shape:
            return False
        if not 0 <= int(y0) <= int(y1) <= flat.shape[0]:
            raise ValueError(f"rows {y0}..{y1} outside the image's {flat.shape[0]}")
        status = lib.dr_median(_ptr(flat, flat.dtype), _ptr(oflat, flat.dtype), flat.shape[0], flat.shape[1],
                               int(size), int(channels), flat.itemsize, int(y0), int(y1))
        _check(0 if status != -1 else -1)
        return status == 0

    return dict(median_rows=median_rows, quantize_lab=quantize_lab, feature_codes=feature_codes, lookup=lookup,
                lloyd=lloyd, grow_samples=grow_samples, interpolate_patch=interpolate_patch, fill_missing=fill_missing,
                correct_values=correct_values, correct_patch=correct_patch)
