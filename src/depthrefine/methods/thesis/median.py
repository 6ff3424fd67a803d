"""Exact square median filter of integer images, as a min/max network run on lanes of whole rows.

The thesis filters R, G and B with a 7x7 median (4.3.1). ``cv2.medianBlur``
gives the exact result; this module gives the same result, bit for bit, in
less time (``benchmarks/bench_speed.py`` prints the step):

- :func:`median_network` builds, once per window size, a program of
  lane-wise ``min`` / ``max`` operations on row vectors: lane ``x`` belongs
  to the window whose leftmost column is ``x``, so one operation advances
  every window of a row at once.
- Two output rows are made together: the ``size - 1`` rows their windows
  share are sorted once per column, the columns of a window are merged into
  one sorted list (Batcher's odd-even merge), and a sorted run of ``m``
  adjacent columns is merged once and shared by every window that holds it
  (runs of 1, 2, 3, 4, then 7 columns for size 7).
- Each output row adds its own one row, sorted across the window the same
  way; the median is then the middle of two sorted lists, given by the split
  formula ``k-th of (a, b) = min over i of max(a[i-1], b[k-i])``.
- Only the operations the two outputs depend on are kept (184 per output
  pixel and channel for size 7).
- :func:`median_filter` runs the program in a compiled kernel
  (:func:`._jit.median_rows`, numba) with the channels interleaved (lane
  ``x * channels + c``), on chunks of lanes small enough to stay in the CPU
  cache, in row bands on threads (the kernel releases the GIL).

A network of ``min`` and ``max`` selects the same element as sorting does
(for any input, by the 0-1 principle), so the result is the exact median,
ties included. Borders replicate the edge pixel, as ``cv2.medianBlur`` and
``scipy.ndimage.median_filter(mode="nearest")`` do.
"""

from __future__ import annotations

import functools
import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np

__all__ = ["median_filter", "median_network"]

_MIN, _MAX = 0, 1

#: Lanes per chunk of a row pair: the network's rows stay in the CPU cache
#: (measured 1024 against 256-4096 on 1232x1008x3).
_CHUNK = 1024

#: Row pairs per band when threads share one image.
_MIN_PAIRS_PER_TASK = 32


class _Network:
    """Builds an SSA list of lane-wise min/max operations.

    A reference is ``(value id, lane offset)``: value ``v`` read at lane
    ``x + offset``. Inputs are values ``0 .. n_inputs - 1``.
    """

    def __init__(self, n_inputs: int):
        self.n_inputs = n_inputs
        self.ops: list[tuple[int, int, int, int, int]] = []

    def op(self, kind: int, a: tuple[int, int], b: tuple[int, int]) -> tuple[int, int]:
        self.ops.append((kind, a[0], a[1], b[0], b[1]))
        return self.n_inputs + len(self.ops) - 1, 0

    def merge(self, a: list, b: list) -> list:
        """Batcher's odd-even merge of two sorted lists of references (any lengths)."""
        if not a or not b:
            return list(a or b)
        if len(a) == 1 and len(b) == 1:
            return [self.op(_MIN, a[0], b[0]), self.op(_MAX, a[0], b[0])]
        even = self.merge(a[0::2], b[0::2])
        odd = self.merge(a[1::2], b[1::2])
        out = [even[0]]
        i = 0
        while i < len(odd) and i + 1 < len(even):
            out += [self.op(_MIN, odd[i], even[i + 1]), self.op(_MAX, odd[i], even[i + 1])]
            i += 1
        return out + odd[i:] + even[i + 1:]

    def sort(self, refs: list) -> list:
        """Odd-even merge sort."""
        if len(refs) <= 1:
            return list(refs)
        half = len(refs) // 2
        return self.merge(self.sort(refs[:half]), self.sort(refs[half:]))

    def sort_across(self, column: list, n: int) -> list:
        """Sorted union of ``n`` adjacent sorted columns (lanes ``x .. x+n-1``); runs are shared."""
        runs = {1: list(column)}

        def run(m: int) -> list:
            if m not in runs:
                half = m // 2
                runs[m] = self.merge(run(half), [(v, off + half) for v, off in run(m - half)])
            return runs[m]

        return run(n)

    def select(self, a: list, b: list, k: int) -> tuple[int, int]:
        """The k-th smallest (0-based) of sorted lists ``a`` and ``b`` together."""
        terms = []
        for i in range(max(0, k + 1 - len(b)), min(len(a), k + 1) + 1):
            j = k + 1 - i
            terms.append(b[j - 1] if i == 0 else a[i - 1] if j == 0 else self.op(_MAX, a[i - 1], b[j - 1]))
        out = terms[0]
        for term in terms[1:]:
            out = self.op(_MIN, out, term)
        return out


@functools.lru_cache(maxsize=None)
def median_network(size: int) -> tuple[np.ndarray, int, tuple[int, int]]:
    """The program that makes two output rows of a ``size`` x ``size`` median.

    Inputs are ``size + 1`` consecutive rows of the edge-padded image (slots
    ``0 .. size``); the outputs are the medians of the windows on rows
    ``0 .. size-1`` and ``1 .. size``.

    Returns
    -------
    table : (n_ops, 7) int32 ndarray
        Rows ``(kind, dst, a, a_offset, b, b_offset, extra)``: for lanes
        ``x < width + extra``, ``slot[dst][x] = min (kind 0) or max (kind 1)
        of slot[a][x + a_offset] and slot[b][x + b_offset]``. ``dst`` is never
        ``a`` or ``b``.
    n_slots : int
        Row buffers the program needs.
    outputs : (int, int)
        The slots holding the two output rows.
    """
    net = _Network(size + 1)
    rows = [(i, 0) for i in range(size + 1)]
    k = size * size // 2
    core = net.sort_across(net.sort(rows[1:size]), size)
    outs = [net.select(core, net.sort_across([rows[r]], size), k) for r in (0, size)]

    # Keep only what the outputs depend on; lanes each value needs past the output width.
    need: dict[int, int] = {}
    for v, off in outs:
        need[v] = max(need.get(v, 0), off)
    live = []
    for idx in range(len(net.ops) - 1, -1, -1):
        v = net.n_inputs + idx
        if v in need:
            live.append(idx)
            _, a, a_off, b, b_off = net.ops[idx]
            need[a] = max(need.get(a, 0), need[v] + a_off)
            need[b] = max(need.get(b, 0), need[v] + b_off)
    live.reverse()

    # Slots: a value's slot is free after its last use (outputs are kept to the end).
    last = {}
    for pos, idx in enumerate(live):
        _, a, _, b, _ = net.ops[idx]
        last[a] = last[b] = pos
    for v, _ in outs:
        last[v] = len(live)
    slot = {i: i for i in range(net.n_inputs)}
    free: list[int] = []
    n_slots = net.n_inputs
    table = []
    for pos, idx in enumerate(live):
        kind, a, a_off, b, b_off = net.ops[idx]
        if free:
            dst = free.pop()
        else:
            dst, n_slots = n_slots, n_slots + 1
        table.append((kind, dst, slot[a], a_off, slot[b], b_off, need[net.n_inputs + idx]))
        for v in {a, b}:
            if last[v] == pos:
                free.append(slot[v])
        slot[net.n_inputs + idx] = dst
    return np.array(table, dtype=np.int32), n_slots, (slot[outs[0][0]], slot[outs[1][0]])


def median_filter(image: np.ndarray, size: int) -> np.ndarray:
    """Exact ``size`` x ``size`` median of each channel of an integer image, edges replicated.

    Identical to ``cv2.medianBlur(image, size)`` for uint8 and to
    ``scipy.ndimage.median_filter(channel, size, mode="nearest")`` per channel
    for any integer dtype. The network runs in a compiled kernel
    (:func:`._jit.median_rows`, numba) on bands of row pairs in threads.

    Parameters
    ----------
    image : (M, N) or (M, N, C) integer ndarray
    size : int
        Odd window side, >= 3.

    Returns
    -------
    ndarray
        Same shape and dtype.

    Examples
    --------
    >>> img = np.zeros((9, 9), np.uint8); img[4, 4] = 255   # one salt pixel
    >>> int(median_filter(img, 7).max())
    0
    """
    from . import _jit

    if size < 3 or size % 2 == 0:
        raise ValueError(f"median size must be odd and >= 3; got {size}.")
    image = np.ascontiguousarray(image)
    planes = image if image.ndim == 3 else image[:, :, None]
    out = np.empty_like(planes)
    table, n_slots, (out0, out1) = median_network(size)
    rows = planes.shape[0]
    pairs = (rows + 1) // 2
    n_bands = max(1, min(os.cpu_count() or 1, pairs // _MIN_PAIRS_PER_TASK))
    bounds = [min(rows, 2 * (pairs * i // n_bands)) for i in range(n_bands + 1)]

    def band(y0: int, y1: int) -> None:
        _jit.median_rows(planes, out, table, n_slots, out0, out1, size, y0, y1, _CHUNK)

    if n_bands > 1:
        with ThreadPoolExecutor(max_workers=n_bands) as pool:
            list(pool.map(band, bounds[:-1], bounds[1:]))
    else:
        band(0, rows)
    return out.reshape(image.shape)
