"""The exact min/max-network median (methods/thesis/median.py) against OpenCV and SciPy."""

from __future__ import annotations

import itertools
from pathlib import Path

import cv2
import numpy as np
import pytest
from scipy import ndimage

from depthrefine.methods.thesis import median as median_module
from depthrefine.methods.thesis.median import median_filter, median_network


def _evaluate(size: int, inputs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Run the network's table on ``inputs`` ((size + 1, lanes) array); the two output rows."""
    table, n_slots, (out0, out1) = median_network(size)
    lanes = inputs.shape[1] - 3 * size
    buf = np.zeros((n_slots, inputs.shape[1]), inputs.dtype)
    buf[:size + 1] = inputs
    for kind, dst, a, a_off, b, b_off, extra in table.tolist():
        n = lanes + extra
        (np.minimum if kind == 0 else np.maximum)(buf[a, a_off:a_off + n], buf[b, b_off:b_off + n],
                                                 out=buf[dst, :n])
    return buf[out0, :lanes], buf[out1, :lanes]


def _zero_one_windows(size: int, patterns: np.ndarray) -> None:
    """Each pattern ((size + 1) x size bits) in its own group of lanes; check both outputs."""
    n = len(patterns)
    grid = np.zeros((size + 1, (n + 3) * size), np.uint8)
    grid[:, :n * size] = patterns.reshape(n, size + 1, size).transpose(1, 0, 2).reshape(size + 1, n * size)
    top, bottom = _evaluate(size, grid)
    half = size * size // 2
    blocks = patterns.reshape(n, size + 1, size)
    # The median of 0/1 values is 1 exactly when more than half of them are 1.
    np.testing.assert_array_equal(top[::size][:n], blocks[:, :size].sum(axis=(1, 2)) > half)
    np.testing.assert_array_equal(bottom[::size][:n], blocks[:, 1:].sum(axis=(1, 2)) > half)


def test_network_is_exact_on_every_zero_one_input_of_the_3x3_pair():
    # 0-1 principle: a min/max network that selects the median of every 0/1 input
    # selects it for every input. 4 rows x 3 columns: all 4096 patterns.
    patterns = np.array(list(itertools.product((0, 1), repeat=12)), np.uint8)
    _zero_one_windows(3, patterns)


@pytest.mark.parametrize("size", [5, 7, 9])
def test_network_is_exact_on_random_zero_one_inputs(size):
    rng = np.random.default_rng(size)
    n_bits = (size + 1) * size
    # Densities near one half are where a miscounted rank would show.
    density = rng.uniform(0.3, 0.7, (20_000, 1))
    patterns = (rng.random((20_000, n_bits)) < density).astype(np.uint8)
    _zero_one_windows(size, patterns)


@pytest.mark.parametrize("size", [3, 5, 7, 9])
@pytest.mark.parametrize("shape", [(1, 1), (1, 9), (2, 3), (3, 1), (8, 8), (13, 9), (70, 41)])
@pytest.mark.parametrize("levels", [256, 3])
def test_median_filter_equals_opencv_and_scipy(size, shape, levels):
    rng = np.random.default_rng(sum(shape) + size + levels)
    img8 = rng.integers(0, levels, shape).astype(np.uint8)
    img16 = (img8.astype(np.uint16) * 257 + rng.integers(0, 2, shape)).astype(np.uint16)
    out8, out16 = median_filter(img8, size), median_filter(img16, size)
    assert out8.dtype == np.uint8 and out16.dtype == np.uint16 and out8.shape == shape
    np.testing.assert_array_equal(out8, cv2.medianBlur(img8, size))
    np.testing.assert_array_equal(out16, ndimage.median_filter(img16, size=size, mode="nearest"))


@pytest.mark.parametrize("size", [3, 7])
@pytest.mark.parametrize("shape", [(1, 1, 3), (5, 2, 3), (31, 40, 3), (12, 9, 4)])
def test_median_filter_filters_each_channel(size, shape):
    rng = np.random.default_rng(sum(shape) + size)
    img = rng.integers(0, 256, shape).astype(np.uint8)
    out = median_filter(img, size)
    assert out.shape == shape and out.dtype == np.uint8
    for ch in range(shape[2]):
        np.testing.assert_array_equal(out[:, :, ch], cv2.medianBlur(np.ascontiguousarray(img[:, :, ch]), size))


def test_median_filter_in_row_bands_and_chunks_equals_one_pass(monkeypatch):
    # Tall image: split into row bands for threads; odd height: one padded row dropped;
    # chunks of lanes that end inside a pixel.
    rng = np.random.default_rng(3)
    img = rng.integers(0, 256, (301, 37, 3)).astype(np.uint8)
    expected = cv2.medianBlur(img, 7)
    monkeypatch.setattr("depthrefine.methods.thesis.median._MIN_PAIRS_PER_TASK", 4)
    monkeypatch.setattr("depthrefine.methods.thesis.median._CHUNK", 20)
    np.testing.assert_array_equal(median_filter(img, 7), expected)


def test_generated_kernels_are_current():
    # _median_kernels.py is generated (python -m depthrefine.methods.thesis.median > .../_median_kernels.py).
    path = Path(median_module.__file__).with_name("_median_kernels.py")
    assert path.read_text() == median_module.kernels_module()


def test_generated_c_kernels_are_current():
    # kernels.c's median section is generated
    # (python -m depthrefine.methods.thesis.median --c src/depthrefine/_native/kernels.c).
    text = (Path(median_module.__file__).parents[2] / "_native" / "kernels.c").read_text()
    begin, end = text.index(median_module.C_BEGIN), text.index(median_module.C_END) + len(median_module.C_END)
    assert text[begin:end] == median_module.c_kernels_source()


@pytest.mark.parametrize("size", [3, 5, 7])
@pytest.mark.parametrize(("shape", "dtype"), [((6, 700), np.uint8), ((6, 700), np.uint16), ((5, 300, 3), np.uint8),
                                              ((4, 90, 3), np.uint8)])
def test_generated_kernels_across_strips(size, shape, dtype):
    # Rows wider than one strip of lanes (the last strip partial, ending inside a pixel), few rows.
    # (3-channel uint16 runs the same code as uint8; left out to spare its compile time.)
    rng = np.random.default_rng(size + shape[1])
    img = rng.integers(0, np.iinfo(dtype).max, shape, endpoint=True).astype(dtype)
    assert size in median_module.GENERATED_SIZES and (img.shape + (1,))[2] in median_module.GENERATED_CHANNELS
    out = median_filter(img, size)
    planes = img if img.ndim == 3 else img[:, :, None]
    expected = np.stack([ndimage.median_filter(planes[:, :, c], size=size, mode="nearest")
                         for c in range(planes.shape[2])], axis=2).reshape(img.shape)
    np.testing.assert_array_equal(out, expected)


@pytest.mark.parametrize("size", [1, 4, -3])
def test_median_filter_rejects_even_or_small_sizes(size):
    with pytest.raises(ValueError, match="odd"):
        median_filter(np.zeros((4, 4), np.uint8), size)
