"""Thesis 4.2: the patches, an automatic grid or manual rectangles snapped to the depth grid."""

from __future__ import annotations

import numpy as np

__all__ = ["patch_grid"]


def patch_grid(depth_shape: tuple[int, int], patches: tuple[int, int]) -> list[tuple[int, int, int, int]]:
    """Even patch grid on the depth grid: ``(row0, row1, col0, col1)`` per patch.

    ``patches`` is ``(across, down)``. Each patch holds whole depth pixels;
    a grid finer than the depth map collapses to one patch per depth pixel.

    Examples
    --------
    >>> patch_grid((10, 8), (2, 2))
    [(0, 5, 0, 4), (0, 5, 4, 8), (5, 10, 0, 4), (5, 10, 4, 8)]
    """
    h, w = depth_shape
    across, down = patches
    # the distinct bounds, in order (a set, not np.unique: its first call imports numpy.ma, 37 ms of a fresh process)
    rows = sorted({int(v) for v in np.floor(np.linspace(0, h, down + 1) + 0.5)})
    cols = sorted({int(v) for v in np.floor(np.linspace(0, w, across + 1) + 0.5)})
    return [(r0, r1, c0, c1) for r0, r1 in zip(rows[:-1], rows[1:]) for c0, c1 in zip(cols[:-1], cols[1:])]


def _manual_patches(
    layout: tuple[tuple[int, int, int, int], ...], depth_shape: tuple[int, int], color_shape: tuple[int, int]
) -> tuple[list[tuple[int, int, int, int]], np.ndarray]:
    """Snap manual rectangles (color pixels) to the depth grid; return them and the owner map."""
    h, w = depth_shape
    H, W = color_shape
    owner = np.full((h, w), -1, dtype=np.int32)
    out = []
    for i, (x, y, width, height) in enumerate(layout):
        if x + width > W or y + height > H:
            raise ValueError(
                f"manual patch {i} (patch_layout / --patch-file: x={x}, y={y}, width={width}, height={height}) reaches outside the "
                f"color image ({W}x{H}); keep every rectangle inside it."
            )
        c0 = int(np.floor(x * w / W + 0.5))
        c1 = int(np.floor((x + width) * w / W + 0.5))
        r0 = int(np.floor(y * h / H + 0.5))
        r1 = int(np.floor((y + height) * h / H + 0.5))
        c1, r1 = max(c1, c0 + 1), max(r1, r0 + 1)
        c0, r0 = min(c0, w - 1), min(r0, h - 1)
        c1, r1 = min(c1, w), min(r1, h)
        owner[r0:r1, c0:c1] = i
        out.append((r0, r1, c0, c1))
    missing = np.argwhere(owner < 0)
    if len(missing):
        r, c = missing[0]
        s_r, s_c = H / h, W / w
        raise ValueError(
            f"the manual patches (patch_layout / --patch-file) leave {len(missing)} depth pixels uncovered, the first near color pixel "
            f"x={int(c * s_c)}, y={int(r * s_r)}; the rectangles must cover the whole image."
        )
    return out, owner


# ----------------------------------------------------------------------------
# Step 6.3-6.4: histogram statistics and correction
# ----------------------------------------------------------------------------
