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
- :func:`median_filter` runs the program with the channels interleaved
  (lane ``x * channels + c``) in row bands on threads (the kernels release
  the GIL). For the sizes in :data:`GENERATED_SIZES` and the channel counts
  in :data:`GENERATED_CHANNELS` it runs a kernel generated from the program
  (:mod:`._median_kernels`, made by :func:`kernels_module`): the program cut
  into a few stages, each one vectorised loop over a strip of lanes whose
  intermediate values stay in registers, with only the values later stages
  read in small row buffers that stay in the L1 cache (about twice as fast as
  the interpreted table at 7x7). Other sizes and channel counts run the
  table itself (:func:`._jit.median_rows`), one lane-wise loop per operation
  on chunks of lanes small enough to stay in the CPU cache.

A network of ``min`` and ``max`` selects the same element as sorting does
(for any input, by the 0-1 principle), so the result is the exact median,
ties included. Borders replicate the edge pixel, as ``cv2.medianBlur`` and
``scipy.ndimage.median_filter(mode="nearest")`` do.
"""

from __future__ import annotations

import functools
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


def _program(size: int) -> tuple[int, list, list, dict]:
    """The live operations of the network of :func:`median_network`, before slots are assigned.

    Returns ``(n_inputs, ops, outputs, need)``: ``ops`` rows ``(value, kind,
    a, a_offset, b, b_offset)`` in execution order, ``outputs`` the two output
    values, ``need[v]`` the columns past the output width value ``v`` is read at.
    """
    net = _Network(size + 1)
    rows = [(i, 0) for i in range(size + 1)]
    k = size * size // 2
    core = net.sort_across(net.sort(rows[1:size]), size)
    outs = [net.select(core, net.sort_across([rows[r]], size), k) for r in (0, size)]
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
    assert all(off == 0 for _, off in outs)
    return net.n_inputs, [(net.n_inputs + i,) + net.ops[i] for i in live], [v for v, _ in outs], need


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
    n_inputs, ops, outs, need = _program(size)
    # Slots: a value's slot is free after its last use (outputs are kept to the end).
    last = {}
    for pos, (_, _, a, _, b, _) in enumerate(ops):
        last[a] = last[b] = pos
    for v in outs:
        last[v] = len(ops)
    slot = {i: i for i in range(n_inputs)}
    free: list[int] = []
    n_slots = n_inputs
    table = []
    for pos, (v, kind, a, a_off, b, b_off) in enumerate(ops):
        if free:
            dst = free.pop()
        else:
            dst, n_slots = n_slots, n_slots + 1
        table.append((kind, dst, slot[a], a_off, slot[b], b_off, need[v]))
        for u in {a, b}:
            if last[u] == pos:
                free.append(slot[u])
        slot[v] = dst
    return np.array(table, dtype=np.int32), n_slots, (slot[outs[0]], slot[outs[1]])


#: Window sizes and channel counts with a generated kernel in :mod:`._median_kernels`.
GENERATED_SIZES = (3, 5, 7)
GENERATED_CHANNELS = (1, 3)

#: Bytes of row buffers a generated kernel may use for uint8 (they stay in the L1 cache).
_STRIP_BYTES = 28 * 1024


def _kernel_source(size: int, channels: int) -> str:
    """Source of the generated kernel ``median{size}_c{channels}`` (see :mod:`._median_kernels`).

    The network is cut into stages: an operation that reads a value at a
    column offset runs one stage after that value. Each stage is one loop
    over the lanes of a strip whose body is the stage's operations as local
    variables (LLVM vectorises it: ``vpminub``/``vpmaxub`` on whole
    registers); only values read by a later stage, the inputs and the outputs
    go through a row buffer. All rows live in one array at constant offsets,
    so the vectoriser sees every dependence distance and needs no run-time
    alias checks. A row is reused once its value's last stage has run.
    """
    n_in, ops, outs, need = _program(size)
    level: dict[int, int] = {}
    for v, _, a, a_off, b, b_off in ops:
        level[v] = max([0] + [level[u] + (off != 0) for u, off in ((a, a_off), (b, b_off)) if u >= n_in])
    n_stages = max(level.values()) + 1
    stored = set(range(n_in)) | set(outs)
    last: dict[int, int] = {v: n_stages for v in outs}
    for v, _, a, _, b, _ in ops:
        for u in (a, b):
            if u >= n_in and level[u] != level[v]:
                stored.add(u)
            last[u] = max(last.get(u, -1), level[v])

    # Rows of the buffer: a value keeps its row from its stage to its last reader's stage.
    row: dict[int, int] = {}
    free: list[int] = []
    released: set[int] = set()
    n_rows = 0
    for st in range(-1, n_stages):
        for v in [v for v in row if last.get(v, -1) < st and v not in released]:
            free.append(row[v])
            released.add(v)
        for v in range(n_in) if st < 0 else [op[0] for op in ops if level[op[0]] == st and op[0] in stored]:
            if free:
                row[v] = free.pop()
            else:
                row[v], n_rows = n_rows, n_rows + 1
    half, span = size // 2, (size - 1) * channels
    strip = 256
    while strip > 32 and n_rows * ((strip + span + 63) // 32 * 32) > _STRIP_BYTES:
        strip //= 2
    width = (strip + span + 63) // 32 * 32  # lanes per row, a multiple of 32 with room for 32 more
    lines = []
    for st in range(n_stages):
        stage = [op for op in ops if level[op[0]] == st]
        lanes = -(-(strip + max(need[op[0]] for op in stage) * channels) // 32) * 32
        lines.append(f"            for x in range({lanes}):")
        for v, kind, a, a_off, b, b_off in stage:
            args = [f"t{u}" if u >= n_in and level[u] == st else f"buf[{row[u] * width + off * channels} + x]"
                    for u, off in ((a, a_off), (b, b_off))]
            lines.append(f"                t{v} = {'min' if kind == _MIN else 'max'}({args[0]}, {args[1]})")
            if v in stored:
                lines.append(f"                buf[{row[v] * width} + x] = t{v}")
    o0, o1 = row[outs[0]] * width, row[outs[1]] * width
    pad = half * channels
    head = f"""

@_jit
def median{size}_c{channels}(flat, oflat, y0, y1):
    \"\"\"Rows ``y0 .. y1-1`` of the {size}x{size} median of ``flat`` ((rows, width * {channels}) lanes) into ``oflat``.\"\"\"
    rows, lanes = flat.shape
    buf = np.zeros({n_rows * width}, flat.dtype)
    for y in range(y0, y1, 2):
        for c0 in range(0, lanes, {strip}):
            m = min({strip}, lanes - c0)
            n_in = m + {span}
            lo = max(0, {pad} - c0)
            hi = min(n_in, {pad} + lanes - c0)
            for r in range({size + 1}):
                src = min(max(y + r - {half}, 0), rows - 1)
                o = r * {width}
                buf[o + lo:o + hi] = flat[src, c0 + lo - {pad}:c0 + hi - {pad}]
                for j in range(lo):
                    buf[o + j] = flat[src, (c0 + j) % {channels}]
                for j in range(hi, n_in):
                    buf[o + j] = flat[src, lanes - {channels} + (c0 + j) % {channels}]
"""
    tail = f"""
            oflat[y, c0:c0 + m] = buf[{o0}:{o0} + m]
            if y + 1 < rows:
                oflat[y + 1, c0:c0 + m] = buf[{o1}:{o1} + m]
"""
    return head.replace('\\"', '"') + "\n".join(lines) + tail


def kernels_module() -> str:
    """The text of :mod:`._median_kernels` (``python -m depthrefine.methods.thesis.median`` prints it)."""
    text = ('"""Min/max-network median kernels. GENERATED: do not edit by hand.\n\n'
            'Generated by :func:`depthrefine.methods.thesis.median.kernels_module` (one kernel per window size\n'
            'in ``GENERATED_SIZES`` and channel count in ``GENERATED_CHANNELS``). To regenerate, from the\n'
            'checkout\'s root::\n\n'
            '    python -m depthrefine.methods.thesis.median > src/depthrefine/methods/thesis/_median_kernels.py\n\n'
            '``tests/test_median.py::test_generated_kernels_are_current`` fails when this file is not current.\n'
            '"""\n\nimport numpy as np\n\nfrom ._jit import _jit\n')
    for size in GENERATED_SIZES:
        for channels in GENERATED_CHANNELS:
            text += _kernel_source(size, channels)
    return text


def median_filter(image: np.ndarray, size: int) -> np.ndarray:
    """Exact ``size`` x ``size`` median of each channel of an integer image, edges replicated.

    Identical to ``cv2.medianBlur(image, size)`` for uint8 and to
    ``scipy.ndimage.median_filter(channel, size, mode="nearest")`` per channel
    for any integer dtype. The network runs in a compiled kernel (numba; a
    generated one of :mod:`._median_kernels` for the sizes and channel counts
    it holds, else :func:`._jit.median_rows`) on bands of row pairs in threads.

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
    from ..._numba import threads
    from . import _jit

    if size < 3 or size % 2 == 0:
        raise ValueError(f"median size must be odd and >= 3; got {size}.")
    image = np.ascontiguousarray(image)
    planes = image if image.ndim == 3 else image[:, :, None]
    out = np.empty_like(planes)
    table, n_slots, (out0, out1) = median_network(size)
    rows = planes.shape[0]
    pairs = (rows + 1) // 2
    n_bands = max(1, min(threads(), pairs // _MIN_PAIRS_PER_TASK))
    bounds = [min(rows, 2 * (pairs * i // n_bands)) for i in range(n_bands + 1)]

    if size in GENERATED_SIZES and planes.shape[2] in GENERATED_CHANNELS:
        from . import _median_kernels

        kernel = getattr(_median_kernels, f"median{size}_c{planes.shape[2]}")
        flat, oflat = planes.reshape(rows, -1), out.reshape(rows, -1)

        def band(y0: int, y1: int) -> None:
            kernel(flat, oflat, y0, y1)
    else:
        def band(y0: int, y1: int) -> None:
            _jit.median_rows(planes, out, table, n_slots, out0, out1, size, y0, y1, _CHUNK)

    if n_bands > 1:
        with ThreadPoolExecutor(max_workers=n_bands) as pool:
            list(pool.map(band, bounds[:-1], bounds[1:]))
    else:
        band(0, rows)
    return out.reshape(image.shape)


if __name__ == "__main__":
    print(kernels_module(), end="")
