"""Generated test scenes with known ground truth that meet the thesis's assumptions.

The thesis method (chapter 4) assumes that a depth edge is a color edge and
that the surfaces between edges have one depth each. :func:`make_scene` builds
exactly such a scene: a few flat-colored, fronto-parallel objects (rectangles,
discs, L-shapes) at distinct depths before a wall, with

- the high-resolution color image and ground-truth depth,
- the low-resolution depth sampled at the depth pixels' centres (spec step
  6.1: depth pixel ``(i, j)`` sees color pixel ``(i*s + s//2, j*s + s//2)``),
  plus Gaussian ToF-like noise and, optionally, holes.

:func:`make_two_planes` builds the smallest such scene, one vertical edge.
Everything is pure and seeded: the same arguments give the same arrays.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._lazy import ndimage

__all__ = ["SyntheticScene", "make_scene", "make_two_planes", "make_sequence", "PALETTE", "DEPTH_CONSTANT"]

#: Flat object colors (RGB uint8), chosen far apart in a*b* (>= 34 units) so
#: that they stay apart after the thesis's L* unification.
PALETTE = np.array(
    [
        (200, 40, 40),    # red
        (40, 160, 60),    # green
        (50, 80, 210),    # blue
        (230, 210, 50),   # yellow
        (190, 60, 190),   # magenta
        (60, 190, 200),   # cyan
        (235, 130, 30),   # orange
        (150, 150, 150),  # gray
    ],
    dtype=np.uint8,
)

#: Depth intensity ``d`` (8-bit, larger = nearer, as the thesis's SR4000
#: output) and distance ``z`` in metres are related by ``z = DEPTH_CONSTANT / d``.
DEPTH_CONSTANT = 180.0

_DTYPES = (np.uint8, np.uint16, np.float32)
#: Default noise standard deviation per output dtype, in its units.
_DEFAULT_NOISE = {np.uint8: 2.0, np.uint16: 10.0, np.float32: 0.01}
#: Wall and object depth intensities (levels): wall far, objects spaced apart.
_WALL_LEVELS = (36, 50)
_OBJECT_LEVELS = np.arange(70, 241, 25)
_SHAPES = ("rectangle", "disc", "L")


@dataclass(frozen=True)
class SyntheticScene:
    """A generated scene: color, ground-truth depth and the low-resolution input.

    Attributes
    ----------
    rgb_hr : (H, W, 3) uint8
        The color image, RGB.
    depth_hr_gt : (H, W) float32
        Ground-truth depth on the color grid, in the units of ``depth_lr``.
    depth_lr : (H // scale, W // scale) uint8, uint16 or float32
        The measured depth: ``depth_hr_gt`` at the depth pixels' centres plus
        noise; invalid pixels (holes) are 0 for integer dtypes, NaN for float.
    scale : int
        The integer factor ``s`` between the two grids.
    labels_hr : (H, W) int16
        Which surface each color pixel shows: 0 the wall, ``1..n`` the objects.
    depths : tuple of float
        The depth of each surface (wall first), in the units of ``depth_lr``.
    units : str
        ``"levels"`` (uint8 depth intensity, larger = nearer), ``"mm"`` (uint16)
        or ``"m"`` (float32), both distances.
    """

    rgb_hr: np.ndarray
    depth_hr_gt: np.ndarray
    depth_lr: np.ndarray
    scale: int
    labels_hr: np.ndarray
    depths: tuple[float, ...]
    units: str

    def edge_band(self, width: int = 1) -> np.ndarray:
        """Pixels within ``width`` pixels (chessboard distance) of a ground-truth depth edge.

        An edge runs between two pixels; ``width=1`` marks the pixels on both
        sides of it, each further unit one more ring.

        Returns
        -------
        (H, W) bool ndarray
            True on both sides of every place where neighbouring pixels of
            ``depth_hr_gt`` differ.

        Examples
        --------
        >>> scene = make_two_planes((8, 8), 4, edge_col=5)
        >>> scene.edge_band(1)[0].astype(int).tolist()
        [0, 0, 0, 0, 1, 1, 0, 0]
        >>> scene.edge_band(2)[0].astype(int).tolist()
        [0, 0, 0, 1, 1, 1, 1, 0]
        """
        if isinstance(width, bool) or not isinstance(width, (int, np.integer)) or width < 1:
            raise ValueError(f"width must be an integer >= 1 (pixels); got {width!r}.")
        gt = self.depth_hr_gt
        edge = np.zeros(gt.shape, dtype=bool)
        dr = gt[1:, :] != gt[:-1, :]
        dc = gt[:, 1:] != gt[:, :-1]
        edge[1:, :] |= dr
        edge[:-1, :] |= dr
        edge[:, 1:] |= dc
        edge[:, :-1] |= dc
        if width > 1:
            edge = ndimage.binary_dilation(edge, structure=np.ones((3, 3), bool), iterations=width - 1)
        return edge


def make_scene(
    shape_hr: tuple[int, int] = (128, 128),
    scale: int = 4,
    *,
    n_objects: int = 3,
    noise_std: float | None = None,
    hole_fraction: float = 0.0,
    shading: float = 0.0,
    color_noise_std: float = 0.0,
    dtype: type | np.dtype = np.uint8,
    seed: int = 0,
) -> SyntheticScene:
    """Generate flat-colored, fronto-parallel objects at distinct depths before a wall.

    Objects are rectangles, discs and L-shapes, each at least ``2 * scale``
    pixels across (so each holds depth samples), at least ``scale`` pixels
    from each other and from the image border (so the wall between them holds
    depth samples too), each of its own color from :data:`PALETTE` and at its
    own depth. Depth intensities are at least 20 levels apart (wall 36-50,
    objects 70-240), far beyond the thesis's +-5-level tolerance.

    Parameters
    ----------
    shape_hr : (int, int)
        ``(H, W)`` of the color image; both must be multiples of ``scale``.
    scale : int
        The integer factor ``s`` (>= 1).
    n_objects : int
        Number of objects, 0 to 7. Room permitting: a ``ValueError`` says when
        they do not fit.
    noise_std : float, optional
        Standard deviation of the Gaussian noise added to ``depth_lr``, in its
        units. Default: 2 levels (uint8), 10 mm (uint16), 0.01 m (float32).
    hole_fraction : float
        Fraction of depth pixels without a measurement (0 or NaN), in [0, 1).
    shading : float
        Amplitude of a smooth brightness ramp across the color image, in
        [0, 1): each pixel's color is multiplied by ``1 + shading * t`` with
        ``t`` in [-1, 1] along a random direction.
    color_noise_std : float
        Gaussian noise on R, G, B in 8-bit levels (what the median removes).
    dtype : np.uint8, np.uint16 or np.float32
        ``uint8``: depth intensity, larger = nearer (the thesis's input);
        ``uint16``: distance in mm; ``float32``: distance in metres
        (``z = DEPTH_CONSTANT / d`` for intensity ``d``).
    seed : int
        Seed of every random choice.

    Returns
    -------
    SyntheticScene

    Raises
    ------
    ValueError
        For a shape that is not a multiple of ``scale``, arguments out of
        range, or objects that do not fit.

    Examples
    --------
    >>> from depthrefine.bench.synthetic import make_scene
    >>> scene = make_scene((64, 96), 4, n_objects=2, seed=1)
    >>> scene.rgb_hr.shape, scene.depth_lr.shape, scene.depth_lr.dtype.name
    ((64, 96, 3), (16, 24), 'uint8')
    >>> len(scene.depths), scene.units
    (3, 'levels')
    """
    height, width, s = _check_grid(shape_hr, scale)
    dtype = _check_dtype(dtype)
    if isinstance(n_objects, bool) or not isinstance(n_objects, (int, np.integer)) or not 0 <= n_objects <= 7:
        raise ValueError(f"n_objects must be an integer from 0 to 7; got {n_objects!r}.")
    for name, value, top in (("hole_fraction", hole_fraction, 1.0), ("shading", shading, 1.0)):
        if not 0.0 <= float(value) < top:
            raise ValueError(f"{name} must be in [0, {top:g}); got {value}.")
    if float(color_noise_std) < 0:
        raise ValueError(f"color_noise_std must be >= 0; got {color_noise_std}.")
    rng = np.random.default_rng(seed)

    # Surfaces: depth intensities (levels) and colors, wall first.
    wall_level = int(rng.integers(_WALL_LEVELS[0], _WALL_LEVELS[1] + 1))
    object_levels = rng.choice(_OBJECT_LEVELS, size=n_objects, replace=False) + rng.integers(0, 5, n_objects)
    levels = np.concatenate([[wall_level], object_levels]).astype(np.float64)
    colors = PALETTE[rng.permutation(len(PALETTE))[: n_objects + 1]]

    labels = np.zeros((height, width), dtype=np.int16)
    blocked = np.zeros((height, width), dtype=bool)
    # Objects stay `s` pixels from the border and from each other.
    blocked[:s, :] = blocked[-s:, :] = True
    blocked[:, :s] = blocked[:, -s:] = True
    grow = np.ones((2 * s + 1, 2 * s + 1), dtype=bool)
    for index in range(1, n_objects + 1):
        mask = _place_object(rng, (height, width), s, blocked)
        if mask is None:
            raise ValueError(
                f"could not place {n_objects} objects of at least {2 * s} pixels in a {width}x{height} image "
                f"at scale {s}; use fewer objects or a larger image."
            )
        labels[mask] = index
        blocked |= ndimage.binary_dilation(mask, structure=grow)

    # Depth in the output's units.
    depths = _levels_to_units(levels, dtype)
    depth_hr_gt = depths[labels].astype(np.float32)

    # Color: flat, optionally shaded and noisy.
    rgb = colors[labels].astype(np.float64)
    if shading > 0:
        angle = rng.uniform(0, 2 * np.pi)
        rows, cols = np.mgrid[0:height, 0:width]
        ramp = (rows - (height - 1) / 2) * np.sin(angle) + (cols - (width - 1) / 2) * np.cos(angle)
        ramp /= max(np.abs(ramp).max(), 1e-12)
        rgb *= (1.0 + shading * ramp)[:, :, None]
    if color_noise_std > 0:
        rgb += rng.normal(0.0, color_noise_std, rgb.shape)
    rgb_hr = np.clip(np.floor(rgb + 0.5), 0, 255).astype(np.uint8)

    # The low-resolution depth: GT at the depth pixels' centres + noise, holes.
    noise_std = _DEFAULT_NOISE[dtype] if noise_std is None else float(noise_std)
    if noise_std < 0:
        raise ValueError(f"noise_std must be >= 0; got {noise_std}.")
    sampled = depth_hr_gt[s // 2::s, s // 2::s].astype(np.float64)
    measured = sampled + rng.normal(0.0, noise_std, sampled.shape) if noise_std > 0 else sampled
    holes = rng.random(sampled.shape) < hole_fraction if hole_fraction > 0 else np.zeros(sampled.shape, bool)
    depth_lr = _to_dtype(measured, holes, dtype)

    units = {np.uint8: "levels", np.uint16: "mm", np.float32: "m"}[dtype]
    return SyntheticScene(rgb_hr=rgb_hr, depth_hr_gt=depth_hr_gt, depth_lr=depth_lr, scale=s,
                          labels_hr=labels, depths=tuple(float(d) for d in depths), units=units)


def make_two_planes(
    shape_hr: tuple[int, int] = (16, 32),
    scale: int = 4,
    *,
    edge_col: int | None = None,
    depth_left: float = 200.0,
    depth_right: float = 60.0,
    dtype: type | np.dtype = np.uint8,
) -> SyntheticScene:
    """Two fronto-parallel planes meeting at a vertical color and depth edge, no noise.

    Columns ``< edge_col`` show the left plane (dark red, ``depth_left``), the
    others the right plane (light cyan, ``depth_right``). By default the edge
    lies one pixel right of the midpoint between depth-sample columns
    ``w // 4`` and ``w // 4 + 1`` (``w = W // scale``), so no sample sits on
    it and, for an even patch grid, no patch border either.

    Parameters
    ----------
    shape_hr : (int, int)
        ``(H, W)``, multiples of ``scale``.
    scale : int
        The integer factor ``s``.
    edge_col : int, optional
        First column of the right plane, in ``1 .. W-1``.
    depth_left, depth_right : float
        Depth of each plane, in the units of ``dtype`` (cast as in
        :func:`make_scene`: rounded for integers).
    dtype : np.uint8, np.uint16 or np.float32

    Returns
    -------
    SyntheticScene
        ``labels_hr`` is 0 left of the edge, 1 right of it.

    Examples
    --------
    >>> scene = make_two_planes((4, 16), 4, edge_col=9)
    >>> scene.depth_lr[0].tolist()
    [200, 200, 60, 60]
    >>> scene.depth_hr_gt[0, 7:11].tolist()
    [200.0, 200.0, 60.0, 60.0]
    """
    height, width, s = _check_grid(shape_hr, scale)
    dtype = _check_dtype(dtype)
    if edge_col is None:
        # One pixel right of the midpoint between sample columns w//4 and w//4 + 1.
        j = width // s // 4
        edge_col = min(width - 1, j * s + s // 2 + s // 2 + 1)
    if isinstance(edge_col, bool) or not isinstance(edge_col, (int, np.integer)) or not 1 <= edge_col < width:
        raise ValueError(f"edge_col must be an integer column in 1..{width - 1}; got {edge_col!r}.")
    labels = np.zeros((height, width), dtype=np.int16)
    labels[:, edge_col:] = 1
    depths = np.array([depth_left, depth_right], dtype=np.float64)
    if dtype != np.float32:
        depths = np.floor(depths + 0.5)
    if not (np.isfinite(depths).all() and (depths > 0).all()):
        raise ValueError(f"depth_left and depth_right must be positive; got {depth_left}, {depth_right}.")
    colors = np.array([(120, 20, 30), (150, 230, 230)], dtype=np.uint8)
    depth_hr_gt = depths[labels].astype(np.float32)
    sampled = depth_hr_gt[s // 2::s, s // 2::s].astype(np.float64)
    depth_lr = _to_dtype(sampled, np.zeros(sampled.shape, bool), dtype)
    units = {np.uint8: "levels", np.uint16: "mm", np.float32: "m"}[dtype]
    return SyntheticScene(rgb_hr=colors[labels], depth_hr_gt=depth_hr_gt, depth_lr=depth_lr, scale=s,
                          labels_hr=labels, depths=tuple(float(d) for d in depths), units=units)


# ----------------------------------------------------------------------------
# helpers
# ----------------------------------------------------------------------------


def _check_grid(shape_hr, scale) -> tuple[int, int, int]:
    if isinstance(scale, bool) or not isinstance(scale, (int, np.integer)) or scale < 1:
        raise ValueError(f"scale must be an integer >= 1; got {scale!r}.")
    try:
        height, width = (int(v) for v in shape_hr)
    except (TypeError, ValueError):
        raise ValueError(f"shape_hr must be (rows, cols); got {shape_hr!r}.") from None
    if height < scale or width < scale or height % scale or width % scale:
        raise ValueError(
            f"shape_hr {(height, width)} must be positive multiples of scale {scale} "
            f"(the depth map is shape_hr // scale)."
        )
    return height, width, int(scale)


def _check_dtype(dtype) -> type:
    kind = np.dtype(dtype).type
    if kind not in _DTYPES:
        raise ValueError(f"dtype must be uint8, uint16 or float32; got {np.dtype(dtype).name}.")
    return kind


def _levels_to_units(levels: np.ndarray, dtype: type) -> np.ndarray:
    """Depth intensities (levels) to the output's units: levels, mm or m."""
    if dtype == np.uint8:
        return levels
    metres = DEPTH_CONSTANT / levels
    return np.floor(metres * 1000.0 + 0.5) if dtype == np.uint16 else metres.astype(np.float32).astype(np.float64)


def _to_dtype(values: np.ndarray, holes: np.ndarray, dtype: type) -> np.ndarray:
    """Measured depth to ``dtype``: valid values stay valid (> 0), holes become 0 / NaN."""
    if dtype == np.float32:
        out = np.maximum(values, 1e-3).astype(np.float32)
        out[holes] = np.nan
        return out
    top = np.iinfo(dtype).max
    out = np.clip(np.floor(values + 0.5), 1, top).astype(dtype)
    out[holes] = 0
    return out


def _place_object(rng: np.random.Generator, shape: tuple[int, int], s: int, blocked: np.ndarray):
    """A random object mask that does not touch ``blocked``; ``None`` after 200 tries."""
    height, width = shape
    lo_size = 2 * s
    for _ in range(200):
        kind = _SHAPES[int(rng.integers(len(_SHAPES)))]
        hi_h, hi_w = max(lo_size, int(0.45 * height)), max(lo_size, int(0.45 * width))
        obj_h = int(rng.integers(min(max(lo_size, int(0.2 * height)), hi_h), hi_h + 1))
        obj_w = int(rng.integers(min(max(lo_size, int(0.2 * width)), hi_w), hi_w + 1))
        if kind == "disc":
            obj_h = obj_w = min(obj_h, obj_w)
        if obj_h > height - 2 * s or obj_w > width - 2 * s:
            continue
        top = int(rng.integers(s, height - s - obj_h + 1))
        left = int(rng.integers(s, width - s - obj_w + 1))
        rows, cols = np.ogrid[0:obj_h, 0:obj_w]
        if kind == "rectangle":
            local = np.ones((obj_h, obj_w), dtype=bool)
        elif kind == "disc":
            radius = obj_h / 2.0
            local = (rows + 0.5 - radius) ** 2 + (cols + 0.5 - radius) ** 2 <= radius**2
        else:
            # L: the bounding box without its top-right corner; arms >= 2s thick.
            arm_h, arm_w = max(lo_size, obj_h // 2), max(lo_size, obj_w // 2)
            if arm_h >= obj_h or arm_w >= obj_w:
                continue
            local = np.ones((obj_h, obj_w), dtype=bool)
            local[: obj_h - arm_h, arm_w:] = False
        mask = np.zeros(shape, dtype=bool)
        mask[top:top + obj_h, left:left + obj_w] = local
        if not (mask & blocked).any():
            return mask
    return None


def make_sequence(
    n_frames: int = 8,
    shape_hr: tuple[int, int] = (96, 128),
    scale: int = 4,
    *,
    n_objects: int = 2,
    speed: float = 3.0,
    noise_std: float | None = None,
    color_noise_std: float = 6.0,
    dtype: type | np.dtype = np.uint16,
    seed: int = 0,
) -> list[SyntheticScene]:
    """A sequence from a static camera: a fixed scene and one disc moving across it.

    The background (wall and ``n_objects`` objects) is :func:`make_scene`'s;
    a disc of another :data:`PALETTE` color, nearer than everything (level
    250), moves left to right by ``speed`` color pixels per frame along the
    middle row. Each frame has fresh depth noise and color noise, so a
    method's output changes from frame to frame even where the ground truth
    does not: :func:`depthrefine.bench.metrics.flicker` measures that.

    Parameters
    ----------
    n_frames : int
        Number of frames (>= 1).
    shape_hr, scale, n_objects, noise_std, dtype, seed
        As for :func:`make_scene` (``noise_std`` default: its default).
    speed : float
        Disc motion in color pixels per frame.
    color_noise_std : float
        Gaussian noise on R, G, B (8-bit levels), new in every frame.

    Returns
    -------
    list of SyntheticScene
        One per frame; ``labels_hr`` marks the disc with ``n_objects + 1``.

    Examples
    --------
    >>> frames = make_sequence(3, (64, 96), 4, seed=1)
    >>> len(frames), frames[0].depth_lr.shape, frames[0].depth_lr.dtype.name
    (3, (16, 24), 'uint16')
    >>> bool((frames[0].depth_hr_gt != frames[2].depth_hr_gt).any())
    True
    """
    if isinstance(n_frames, bool) or not isinstance(n_frames, (int, np.integer)) or n_frames < 1:
        raise ValueError(f"n_frames must be an integer >= 1; got {n_frames!r}.")
    base = make_scene(shape_hr, scale, n_objects=n_objects, noise_std=0.0, dtype=dtype, seed=seed)
    dtype = _check_dtype(dtype)
    height, width, s = _check_grid(shape_hr, scale)
    rng = np.random.default_rng([seed, 1])
    used = {tuple(c) for c in base.rgb_hr.reshape(-1, 3)}
    disc_color = next(c for c in PALETTE if tuple(c) not in used)
    wall_colors = base.rgb_hr.astype(np.float64)
    disc_depth = float(_levels_to_units(np.array([250.0]), dtype)[0])
    radius = max(2 * s, min(height, width) // 5)
    rows, cols = np.mgrid[0:height, 0:width]
    noise_std = _DEFAULT_NOISE[dtype] if noise_std is None else float(noise_std)
    frames = []
    for t in range(int(n_frames)):
        cx = radius + s + t * float(speed)
        disc = (rows + 0.5 - height / 2) ** 2 + (cols + 0.5 - cx) ** 2 <= radius ** 2
        labels = np.where(disc, n_objects + 1, base.labels_hr).astype(np.int16)
        depth_hr_gt = np.where(disc, np.float32(disc_depth), base.depth_hr_gt).astype(np.float32)
        rgb = np.where(disc[:, :, None], disc_color[None, None, :].astype(np.float64), wall_colors)
        if color_noise_std > 0:
            rgb = rgb + rng.normal(0.0, color_noise_std, rgb.shape)
        rgb_hr = np.clip(np.floor(rgb + 0.5), 0, 255).astype(np.uint8)
        sampled = depth_hr_gt[s // 2::s, s // 2::s].astype(np.float64)
        measured = sampled + rng.normal(0.0, noise_std, sampled.shape) if noise_std > 0 else sampled
        depth_lr = _to_dtype(measured, np.zeros(sampled.shape, bool), dtype)
        frames.append(SyntheticScene(rgb_hr=rgb_hr, depth_hr_gt=depth_hr_gt, depth_lr=depth_lr, scale=s,
                                     labels_hr=labels, depths=base.depths + (disc_depth,), units=base.units))
    return frames
