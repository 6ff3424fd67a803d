"""gbp's kernels in C (``depthrefine._native``) give numba's bits, and a fresh gbp process needs no numba.

The numba kernels (``methods/_wls_jit.py``, ``_resample_jit.py``,
``gbp/_offsets_jit.py``) are the reference; each C kernel is run on the
same arguments and compared bit for bit, on random inputs that reach every
branch (borders, one-row and one-column images, odd and even sizes, 1, 3
and 4 channels, zero and capped couplings, strided tiles). Skipped where
the C library is not built (no compiler at install): gbp then runs numba's.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from depthrefine import _native

lib = _native.library()
needs_c = pytest.mark.skipif(lib is None, reason=f"depthrefine's C kernels: {_native.why_not()}")


def _jit(name: str):
    import importlib

    return importlib.import_module(name)


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal bits (NaN included)."""
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def _both(kernel: str, module: str, make_args, part):
    """Run numba's ``kernel`` over the range ``part`` and C's over it in two pieces (as two threads would), on fresh
    copies of ``make_args()``; returns both argument tuples after."""
    c = _native.kernels("depthrefine.methods._wls_jit")   # the C namespace holds every kernel
    args_jit, args_c = make_args(), make_args()
    getattr(_jit(module), kernel)(*args_jit, *part)
    start, stop = part
    middle = (start + stop + 1) // 2
    for piece in ((start, middle), (middle, stop)):
        getattr(c, kernel)(*args_c, *piece)
    return args_jit, args_c


@needs_c
def test_exp_of_a_float32_is_numbas_to_the_bit():
    from depthrefine._numba import expf32

    rng = np.random.default_rng(1)
    xs = np.concatenate([rng.uniform(-110, 95, 3000), rng.normal(0, 2, 2000), -np.abs(rng.normal(0, 0.01, 500)),
                         [0.0, -0.0, -np.inf, np.inf, np.nan, 88.72, 88.73, -103.28, -103.98, -104.0, -87.34,
                          float.fromhex("0x1.62e42ep6"), -float.fromhex("0x1.9fe368p6"),
                          -float.fromhex("0x1.9d1d9ep6")]]).astype(np.float32)
    ours = np.array([_native.kernels("depthrefine.methods._wls_jit").expf32(float(x)) for x in xs], np.float32)
    reference = np.array([expf32(x) for x in xs], np.float32)
    assert _same(ours, reference)


@needs_c
def test_exp_over_millions_of_depth_steps_is_numbas():
    """exp(-|dx| / sigma) as the depth weights take it (weights of 1): 8 million arguments from 0 to -110."""
    rng = np.random.default_rng(2)
    x = rng.uniform(0, 110, (2000, 2000)).astype(np.float32)
    ones = np.ones_like(x)

    def make():
        return x, np.float32(1.0), ones, ones, np.empty_like(x), np.empty_like(x)

    jit, c = _both("depth_weight_rows", "depthrefine.methods._wls_jit", make, (0, x.shape[0]))
    assert _same(jit[4], c[4]) and _same(jit[5], c[5])


@needs_c
@pytest.mark.parametrize("rows", [1, 2, 3, 57])
@pytest.mark.parametrize("lam", [0.0, 0.7, 250.0, 1e30])
def test_the_sweep_on_a_strided_tile_is_numbas(rows, lam):
    def make():
        rng = np.random.default_rng(rows)
        u = rng.normal(500, 80, (rows, 80)).astype(np.float32)
        w = rng.random((rows, 80)).astype(np.float32)
        w[rng.random(w.shape) < 0.2] = 0.0
        return u[:, 5:69], w[:, 3:67], np.float32(lam)     # row strides wider than the rows, as the tiles

    jit, c = _both("sweep_columns", "depthrefine.methods._wls_jit", make, (3, 61))
    assert _same(np.ascontiguousarray(jit[0]), np.ascontiguousarray(c[0]))
    assert _same(jit[0].base, c[0].base)                       # the columns outside 3:61 are untouched


@needs_c
@pytest.mark.parametrize("shape", [(1, 5), (40, 1), (70, 150), (129, 64)])
def test_the_column_blocks_are_numbas(shape):
    def make():
        rng = np.random.default_rng(shape[1])
        return (rng.normal(0, 1e3, shape).astype(np.float32), rng.random(shape).astype(np.float32),
                np.float32(40.0), 64)

    blocks = -(-shape[1] // 64)
    jit, c = _both("solve_columns", "depthrefine.methods._wls_jit", make, (0, blocks))
    assert _same(jit[0], c[0])


@needs_c
@pytest.mark.parametrize("channels", [1, 3, 4])
@pytest.mark.parametrize("shape", [(1, 9), (9, 1), (31, 47), (5, 300)])
def test_the_weights_are_numbas(channels, shape):
    from depthrefine.methods._wls import _color_lut

    rng = np.random.default_rng(channels)
    guide = rng.integers(0, 256, (*shape, channels), dtype=np.uint8)
    x = rng.normal(1000, 300, shape).astype(np.float32)
    x[rng.random(shape) < 0.1] += 5000                          # jumps: exp far below 1, and underflow
    lut = _color_lut(channels, 9.0)
    wx0, wy0 = rng.random(shape).astype(np.float32), rng.random(shape).astype(np.float32)
    rows = shape[0]

    def empty():
        return np.full(shape, np.nan, np.float32), np.full(shape, np.nan, np.float32)

    jit, c = _both("color_weight_rows", "depthrefine.methods._wls_jit", lambda: (guide, lut, *empty()), (0, rows))
    assert _same(jit[2], c[2]) and _same(jit[3], c[3])
    for inv_sigma in (np.float32(1 / 7), np.float32(30.0)):
        jit, c = _both("edge_weight_rows", "depthrefine.methods._wls_jit",
                       lambda: (guide, lut, x, inv_sigma, *empty()), (0, rows))
        assert _same(jit[4], c[4]) and _same(jit[5], c[5])
        jit, c = _both("depth_weight_rows", "depthrefine.methods._wls_jit",
                       lambda: (x, inv_sigma, wx0, wy0, *empty()), (0, rows))
        assert _same(jit[4], c[4]) and _same(jit[5], c[5])


@needs_c
@pytest.mark.parametrize("sigma", [12.0, 0.3])       # 0.3: most colors' likeness underflows, the bilinear fallback
@pytest.mark.parametrize("shape", [(1, 1), (1, 2), (2, 1), (2, 2), (3, 5), (8, 8), (33, 50), (50, 33), (16, 16),
                                   (3, 21), (4, 22), (17, 301), (64, 130)])   # 21, 22: the first vector step
@pytest.mark.parametrize("colors", ["random", "smooth"])     # smooth: the small guide the guide's reduction
def test_the_guided_enlargement_is_numbas(shape, sigma, colors):
    import cv2

    from depthrefine.methods._wls import _color_lut

    H, W = shape
    h, w = -(-H // 2), -(-W // 2)
    rng = np.random.default_rng(H * W)
    if colors == "random":
        guide = rng.integers(0, 256, (H, W, 3), dtype=np.uint8)
        small = rng.integers(0, 256, (h, w, 3), dtype=np.uint8)
    else:
        guide = cv2.resize(rng.integers(0, 256, (max(1, H // 6), max(1, W // 6), 3), dtype=np.uint8), (W, H))
        small = cv2.resize(guide, (w, h), interpolation=cv2.INTER_AREA)
    x = rng.normal(0, 100, (h, w)).astype(np.float32)
    planes = cv2.split(small)
    jit, c = _both("enlarge_rows", "depthrefine.methods._resample_jit",
                   lambda: (x, *planes, guide, _color_lut(3, sigma), np.full((H, W), np.nan, np.float32)), (0, H))
    assert _same(jit[6], c[6])


_GUARDED = r"""
import ctypes, mmap, sys
import numpy as np
from depthrefine import _native
from depthrefine.methods._wls import _color_lut

libc = ctypes.CDLL(None)
libc.mmap.restype = ctypes.c_void_p
libc.mmap.argtypes = [ctypes.c_void_p, ctypes.c_size_t, ctypes.c_int, ctypes.c_int, ctypes.c_int, ctypes.c_long]
libc.mprotect.argtypes = [ctypes.c_void_p, ctypes.c_size_t, ctypes.c_int]
PAGE, kept = mmap.PAGESIZE, []


def guarded(a, after):
    # a copy of a flush against an inaccessible page, after its last byte or before its first
    n = max(a.nbytes, 1)
    pages = (n + PAGE - 1) // PAGE + 2
    base = libc.mmap(None, pages * PAGE, 3, 0x22, -1, 0)   # PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS
    if after:
        libc.mprotect(base + (pages - 1) * PAGE, PAGE, 0)
        address = base + (pages - 1) * PAGE - n
    else:
        libc.mprotect(base, PAGE, 0)
        address = base + PAGE
    kept.append(base)
    copy = np.frombuffer((ctypes.c_char * n).from_address(address), a.dtype, a.size).reshape(a.shape)
    copy[...] = a
    return copy


c = _native.kernels("depthrefine.methods._wls_jit")
rng = np.random.default_rng(7)
lut = _color_lut(3, 6.0)
for H, W in [(h, w) for h in (1, 2, 3) for w in range(1, 40)] + [(5, 301), (4, 130)]:
    guide = rng.integers(0, 256, (H, W, 3), dtype=np.uint8)
    h, w = -(-H // 2), -(-W // 2)
    small = rng.integers(0, 256, (h, w, 3), dtype=np.uint8)
    x = rng.normal(0, 100, (h, w)).astype(np.float32)
    planes = [np.ascontiguousarray(small[:, :, k]) for k in range(3)]
    wx, wy, out = (np.zeros((H, W), np.float32) for _ in range(3))
    c.color_weight_rows(guide, lut, wx, wy, 0, H)
    c.enlarge_rows(x, *planes, guide, lut, out, 0, H)
    for after in (True, False):
        g = guarded(guide, after)
        gx, gy, gout = (guarded(np.zeros((H, W), np.float32), after) for _ in range(3))
        c.color_weight_rows(g, guarded(lut, after), gx, gy, 0, H)
        c.enlarge_rows(guarded(x, after), *(guarded(p, after) for p in planes), g, lut, gout, 0, H)
        assert gx.tobytes() == wx.tobytes() and gy.tobytes() == wy.tobytes() and gout.tobytes() == out.tobytes()
print("ok")
"""


@needs_c
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="mmap and mprotect through ctypes: Linux")
def test_the_vector_paths_read_and_write_nothing_beyond_their_arrays():
    """The color weights' and the enlargement's eight-pixel steps, each array flush against a page that cannot be
    read (after it, then before it): a read or write past an array would end the process; same bits as usual."""
    done = subprocess.run([sys.executable, "-c", _GUARDED], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and done.stdout.strip() == "ok", (done.returncode, done.stderr[-2000:])


@needs_c
def test_the_clips_are_numbas():
    rng = np.random.default_rng(5)
    shape, small = (37, 53), (10, 14)
    x = rng.normal(0, 10, shape).astype(np.float32)
    lower = rng.normal(-5, 3, small).astype(np.float32)
    upper = lower + rng.random(small).astype(np.float32) * 8
    # ties, signed zeros and NaN bounds, where the order of min and max's arguments shows
    x[0, :6] = [0.0, -0.0, 0.0, -0.0, 3.0, 5.0]
    lower[0, :2], upper[0, :2] = [-0.0, 0.0], [0.0, -0.0]
    lower[1, 0], upper[1, 1] = np.nan, np.nan
    x[x.shape[0] // 10 + 1, :8] = np.round(x[x.shape[0] // 10 + 1, :8])
    lower[1:3] = np.round(lower[1:3])
    rows = (np.arange(shape[0]) * small[0] // shape[0]).astype(np.int32)
    cols = (np.arange(shape[1]) * small[1] // shape[1]).astype(np.int32)
    weight = rng.random(shape).astype(np.float32)
    for low, high in ((-12, 9), (0.0, 9), (-12, -0.0)):          # the signed zeros of x against the global bounds
        jit, c = _both("clip_rows", "depthrefine.methods._resample_jit",
                       lambda: (x.copy(), np.float32(low), np.float32(high), lower, upper, rows, cols), (0, shape[0]))
        assert _same(jit[0], c[0])
    jit, c = _both("clip_toward_rows", "depthrefine.methods._resample_jit",
                   lambda: (x.copy(), weight, lower, upper, rows, cols), (0, shape[0]))
    assert _same(jit[0], c[0])


@needs_c
@pytest.mark.parametrize("quantum", [0.0, 40.0, 400.0])   # values rounded to steps: profiles and ridges hold ties
@pytest.mark.parametrize("reach", [2, 4, 9])
@pytest.mark.parametrize("centre", [(55.3, 41.7), (8.3, 80.2)], ids=["inside", "cut by the border"])
def test_the_offset_search_is_numbas(reach, quantum, centre):
    """The C search (four samples at a time with AVX2, where built with it) gives numba's offsets to the bit;
    with the disc cut by the image's border, the profiles reach beyond it and are clamped."""
    import cv2

    yy, xx = np.mgrid[:90, :120]
    cx, cy = centre
    depth = np.where((xx - cx) ** 2 + (yy - cy) ** 2 < 30 ** 2, 900.0, 2000.0).astype(np.float32)
    depth = cv2.GaussianBlur(depth, (0, 0), 2.0)
    rng = np.random.default_rng(reach)
    luma = np.where((xx - cx - 2.8) ** 2 + (yy - cy + 2.5) ** 2 < 29 ** 2, 60.0, 190.0) + rng.normal(0, 4, depth.shape)
    luma = cv2.GaussianBlur(luma.astype(np.float32), (0, 0), 1.0)
    gx, gy = cv2.Sobel(depth, cv2.CV_32F, 1, 0), cv2.Sobel(depth, cv2.CV_32F, 0, 1)
    magnitude = np.sqrt(gx * gx + gy * gy)
    edges = np.sqrt(cv2.Sobel(luma, cv2.CV_32F, 1, 0) ** 2 + cv2.Sobel(luma, cv2.CV_32F, 0, 1) ** 2)
    if quantum:
        magnitude, edges = (np.round(a / quantum).astype(np.float32) * np.float32(quantum) for a in (magnitude, edges))
    band = magnitude > 100
    per_row = np.count_nonzero(band, axis=1)
    row_start = np.concatenate([[0], np.cumsum(per_row)[:-1]]).astype(np.int64)
    total = int(per_row.sum())

    def make():
        return (band, magnitude, gx, gy, edges, reach, 1.5, row_start, np.full(total, np.nan),
                np.full(total, np.nan), np.zeros(band.shape[0], np.int64))

    jit, c = _both("search", "depthrefine.methods.gbp._offsets_jit", make, (0, band.shape[0]))
    assert jit[10].sum() > (50 if centre == (55.3, 41.7) else 10)      # the search found edges
    for a, b in zip(jit[8:], c[8:]):
        assert _same(a, b)


@needs_c
def test_the_offset_search_skips_a_gradient_without_direction():
    """A depth gradient that overflowed float32 (inf / inf: no direction) is no ridge pixel, in C and in numba
    alike (C gathered from an index made of NaN and crashed); the finite pixels beside it are searched as usual."""
    gx = np.zeros((8, 9), np.float32)
    gy = np.zeros_like(gx)
    gx[4, 2:7] = [np.inf, 5.0, np.inf, -5.0, np.nan]
    magnitude = np.abs(gx)
    magnitude[4, 6] = np.inf
    band = magnitude > 0
    per_row = np.count_nonzero(band, axis=1)
    row_start = np.concatenate([[0], np.cumsum(per_row)[:-1]]).astype(np.int64)

    def make():
        total = int(per_row.sum())
        return (band, magnitude, gx, gy, np.ones_like(gx), 3, 1.5, row_start, np.full(total, np.nan),
                np.full(total, np.nan), np.zeros(band.shape[0], np.int64))

    jit, c = _both("search", "depthrefine.methods.gbp._offsets_jit", make, (0, band.shape[0]))
    for a, b in zip(jit[8:], c[8:]):
        assert _same(a, b)


@needs_c
def test_the_gradient_magnitude_is_numpys_expression_to_the_bit():
    from depthrefine.methods.gbp.fattening import _hypot

    rng = np.random.default_rng(8)
    x = (rng.normal(0, 1, (301, 413)) * 10.0 ** rng.integers(-20, 20, (301, 413))).astype(np.float32)
    y = rng.normal(0, 300, x.shape).astype(np.float32)
    x[0, :6], y[0, :6] = [0, -0.0, np.inf, 3e19, 1e-23, np.nan], [0, 0, 1, 3e19, 1e-23, 1]
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        reference = x * x
        reference += y * y
        reference = np.sqrt(reference)
        assert _same(_hypot(x, y), reference)


@needs_c
@pytest.mark.parametrize("shape", [(1, 9), (9, 1), (37, 53), (64, 300)])
@pytest.mark.parametrize("reach", [0.0, 1.0, 2.5, 7.0, 1e9])
def test_the_hole_rays_are_numpys(shape, reach, rng):
    """The four rays of enclosed_holes (depth of the nearest valid pixel each way within reach) in C, each direction
    run in two pieces of its rows or columns, give _fill._nearest_along's values to the bit."""
    from depthrefine._fill import _nearest_along

    depth = (rng.random(shape) * 1000).astype(np.float32)
    depth[rng.random(shape) < 0.4] = np.nan
    depth[rng.random(shape) < 0.05] = np.inf
    depth.flat[:3] = [np.nan, -0.0, np.nan][:depth.size]
    want = [_nearest_along(depth, reach, axis=1), _nearest_along(depth[:, ::-1], reach, axis=1)[:, ::-1],
            _nearest_along(depth, reach, axis=0), _nearest_along(depth[::-1], reach, axis=0)[::-1]]
    c = _native.c_kernels()
    for direction in range(4):
        n = shape[0] if direction < 2 else shape[1]
        out = np.full(shape, 7.0, np.float32)
        c.nearest_seen(depth, reach, direction, out, 0, n // 2)
        c.nearest_seen(depth, reach, direction, out, n // 2, n)
        assert _same(out, np.ascontiguousarray(want[direction], np.float32))


@needs_c
def test_enclosed_holes_are_the_same_without_the_c_kernels(rng, monkeypatch):
    from depthrefine._fill import enclosed_holes

    yy, xx = np.mgrid[:300, :400]
    depth = (1000 + 0.5 * xx + 0.2 * yy).astype(np.float32)
    depth[(xx - 200) ** 2 + (yy - 150) ** 2 < 60 ** 2] += 800           # a near disc
    depth[rng.random(depth.shape) < 0.02] = np.nan                      # specks
    depth[100:130, 50:90] = np.nan                                      # a hole in one surface
    depth[140:160, 130:150] = np.nan                                    # a hole across the disc's rim
    depth[:, :12] = np.nan                                              # the edge of the view
    with_c = enclosed_holes(depth)
    monkeypatch.setenv(_native.ENV, "numba")
    monkeypatch.setattr(_native, "_loaded", [])
    assert _native.c_kernels() is None
    without = enclosed_holes(depth)
    assert with_c.sum() > 1000 and np.array_equal(with_c, without)


@needs_c
def test_a_wrong_array_is_refused_before_it_reaches_c():
    c = _native.kernels("depthrefine.methods._wls_jit")
    x = np.zeros((4, 6), np.float32)
    with pytest.raises(TypeError, match="C-contiguous float32"):
        c.depth_weight_rows(x.astype(np.float64), np.float32(1), x, x, x, x, 0, 4)
    with pytest.raises(TypeError, match="C-contiguous float32"):
        c.depth_weight_rows(x[:, ::2], np.float32(1), x, x, x, x, 0, 4)


@needs_c
def test_a_build_from_another_source_is_not_used(tmp_path):
    folder = Path(_native.__file__).parent
    built = next(folder.glob("_kernels*"))
    shutil.copy(built, tmp_path / built.name)
    source = (folder / "kernels.c").read_text()
    (tmp_path / "kernels.c").write_text(source)
    assert _native._find(tmp_path)[0] is not None
    (tmp_path / "kernels.c").write_text(source + "\n/* changed */\n")
    found, why = _native._find(tmp_path)
    assert found is None and "reinstall" in why


def _fresh(code: str, **env) -> str:
    run_env = {k: v for k, v in os.environ.items() if k != _native.ENV}
    run_env.update(env)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=run_env, timeout=300)
    assert out.returncode == 0, out.stderr
    return out.stdout.strip()


_REFINE = ("import hashlib, sys, numpy as np, depthrefine; "       # 384x512 output: the kernels run on two threads
           "from depthrefine.bench.synthetic import make_scene; "
           "s = make_scene((384, 512), 4, n_objects=4, seed=5, color_noise_std=3.0, shading=0.2); "
           "outs = [depthrefine.refine(s.depth_lr, s.rgb_hr, method=m) for m in ('gbp', 'gbp-fast')]; "
           "print('numba' in sys.modules, [hashlib.sha256(o.tobytes()).hexdigest() for o in outs])")


@needs_c
def test_gbp_in_a_fresh_process_runs_without_numba_and_gives_numbas_result():
    native = _fresh(_REFINE).split(" ", 1)
    forced = _fresh(_REFINE, DEPTHREFINE_KERNELS="numba").split(" ", 1)
    assert native[0] == "False" and forced[0] == "True"
    assert native[1] == forced[1]


def test_the_kernels_are_numbas_when_asked_for():
    assert _fresh("from depthrefine import _native; k = _native.kernels('depthrefine.methods._wls_jit'); "
                  "print(k.__name__, _native.why_not())", DEPTHREFINE_KERNELS="numba") == \
        "depthrefine.methods._wls_jit DEPTHREFINE_KERNELS=numba"


@needs_c
def test_a_build_with_other_signatures_is_not_used(monkeypatch):
    monkeypatch.setattr(_native, "ABI", _native.ABI + 1)
    found, why = _native._find()
    assert found is None and "other signatures" in why


def test_a_library_that_fails_to_load_falls_back_to_numba(monkeypatch):
    def broken(*args):
        raise AttributeError("undefined symbol: dr_exp_f32")

    monkeypatch.setattr(_native, "_find", broken)
    monkeypatch.setattr(_native, "_loaded", [])
    monkeypatch.delenv(_native.ENV, raising=False)
    assert _native.library() is None and "undefined symbol" in _native.why_not()
    assert _native.kernels("depthrefine.methods._wls_jit").__name__ == "depthrefine.methods._wls_jit"


@needs_c
def test_a_python_float_is_refused_where_numba_would_compile_for_float64():
    c = _native.kernels("depthrefine.methods._wls_jit")
    x = np.zeros((4, 6), np.float32)
    with pytest.raises(TypeError, match="np.float32 scalars"):
        c.depth_weight_rows(x, 0.5, x, x, x.copy(), x.copy(), 0, 4)


@needs_c
@pytest.mark.parametrize("shape", [(1, 9), (9, 1), (40, 57)])
@pytest.mark.parametrize("passes", [1, 3])
def test_the_geodesic_sweeps_are_numbas(shape, passes):
    rng = np.random.default_rng(shape[0] * passes)
    free = rng.random(shape) < 0.9
    free.flat[::7] = False                                          # seeds everywhere
    cost_x = rng.integers(0, 4, shape).astype(np.float32)          # small integers: many equal paths (ties)
    cost_y = rng.integers(0, 4, shape).astype(np.float32)

    def make():
        distance = np.where(free, np.float32(np.inf), np.float32(0)).astype(np.float32)
        source = np.where(free, -1, np.arange(free.size, dtype=np.int64).reshape(shape))
        return cost_x, cost_y, free, distance, source, passes

    jit_args, c_args = make(), make()
    _jit("depthrefine._geodesic_jit").sweeps(*jit_args)
    _native.kernels("depthrefine._geodesic_jit").sweeps(*c_args)
    assert _same(jit_args[3], c_args[3]) and _same(jit_args[4], c_args[4])
    assert (c_args[4] >= 0).sum() > free.size // 2


def test_version_says_which_compiled_kernels_run():
    expected = "compiled kernels: C" if lib is not None else "compiled kernels: numba (C ones: "
    assert expected in _fresh("from depthrefine.cli import main; main(['--version'])")
    assert "compiled kernels: numba (C ones: DEPTHREFINE_KERNELS=numba)" in _fresh(
        "from depthrefine.cli import main; main(['--version'])", DEPTHREFINE_KERNELS="numba")
