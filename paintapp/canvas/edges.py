"""How wide a painting's edges are: the texels of its ramps over the length of its outline.

The measure, on the total paint thickness of each texel (the sum over pigments, metres):

- ``T90``: the 90th percentile of the thickness over the painted texels (thickness above
  ``FILM_FLOOR_M`` = 1e-7 m; numpy's default, linear, percentile);
- ramp texels: the texels whose thickness lies in ``[0.05, 0.5] x T90`` (both ends included);
- contour texels: the length, in texels, of the 50 % contour: the texels with a thickness of at
  least ``0.5 T90`` that have a 4-neighbour (inside the canvas) below ``0.5 T90``;
- edge width = ramp texels / contour texels, in texels.

A hard edge (full thickness next to bare canvas) has no ramp texels: width 0. An edge whose
thickness falls linearly from ``T90`` to 0 over ``N`` texels, straight along a texel axis, has
``0.45 N`` ramp texels per contour texel: width ``0.45 N``. Along a slanted edge the contour
counts ``max(|cos a|, |sin a|)`` texels per texel of length (``a``: the edge's angle to an
axis), so round shapes measure a little wider: a disc's contour counts ``4 sqrt(2) r`` texels
against its circumference ``2 pi r``, 0.90 of it, and a ramped disc measures about ``0.50 N``.

A canvas with no painted texel, or whose paint has no 50 % contour (the same thickness
everywhere), has no edge to measure: its width is NaN (not 0, which would read as a perfectly
sharp edge), with ``contour_texels`` 0 (:attr:`EdgeWidth.has_edge` is False).

**The local measure** (:func:`local_edge_width`) takes the scale per texel instead: ``T90``
of the painted texels within :data:`LOCAL_TILES` x :data:`LOCAL_TILES` tiles of
:data:`TILE_TEXELS` texels around it (about 10 mm at 0.1 mm texels), interpolated between the
tiles' centres. On a canvas whose strokes are of different thicknesses, the global ``T90`` is set
by the thickest, and the whole body of a thinner stroke (under half of it) counts as ramp; the
local scale follows each stroke's own thickness, so what it counts is the ramps at the strokes'
edges. Both read the same on strokes of one thickness.

``python -m paintapp.canvas.edges DIR`` prints both edge widths of ``DIR/canvas.exr`` (as
``paintapp demo --out DIR`` writes it), one line each.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.ndimage import binary_dilation

from paintapp.canvas.model import FILM_FLOOR_M

#: The ramp's thickness band and the contour's level, fractions of T90.
RAMP_LOW, RAMP_HIGH = 0.05, 0.5
CONTOUR_LEVEL = 0.5
#: The percentile of the painted texels' thickness that sets the scale.
SCALE_PERCENTILE = 90.0
#: The local measure's tiles: texels a side, and tiles a side of the block around each tile
#: whose painted texels set its scale.
TILE_TEXELS = 32
LOCAL_TILES = 3


@dataclass(frozen=True)
class EdgeWidth:
    """The edge width of a painting (module docstring).

    Attributes:
        width_texels: ramp texels over contour texels; NaN without an edge.
        t90_m: the 90th percentile of the painted texels' thickness, metres (0 without paint).
        ramp_texels: texels with a thickness in ``[0.05, 0.5] x T90``.
        contour_texels: texels of at least ``0.5 T90`` with a 4-neighbour below it.
        local: measured against the local ``T90`` (:func:`local_edge_width`; ``t90_m`` is still
            the global one).
    """

    width_texels: float
    t90_m: float
    ramp_texels: int
    contour_texels: int
    local: bool = False

    @property
    def has_edge(self) -> bool:
        """Whether there was a 50 % contour to measure against."""
        return self.contour_texels > 0

    def describe(self, texel_m: float | None = None) -> str:
        """One line: the width (and in mm with ``texel_m``, the texel's size in metres)."""
        if not self.has_edge:
            return (
                f"edge width: none (no 50 % contour; T90 {1e3 * self.t90_m:.4g} mm, "
                f"{self.ramp_texels} ramp texels)"
            )
        mm = f" ({1e3 * self.width_texels * texel_m:.3g} mm)" if texel_m else ""
        band = f"{100 * RAMP_LOW:g}-{100 * RAMP_HIGH:g} %"
        if self.local:
            return (
                f"local edge width {self.width_texels:.3g} texels{mm}: {self.ramp_texels} texels "
                f"at {band} of the local T90, {self.contour_texels} on its "
                f"{100 * CONTOUR_LEVEL:g} % contour"
            )
        return (
            f"edge width {self.width_texels:.3g} texels{mm}: {self.ramp_texels} texels at "
            f"{band} of T90 = {1e3 * self.t90_m:.4g} mm, "
            f"{self.contour_texels} on the {100 * CONTOUR_LEVEL:g} % contour"
        )


def contour_mask(thickness_m: np.ndarray, level_m: float) -> np.ndarray:
    """(H, W) bool: texels of at least ``level_m`` with a 4-neighbour inside the array below it."""
    return outline(np.asarray(thickness_m) >= level_m)


def outline(above: np.ndarray) -> np.ndarray:
    """(H, W) bool: the texels of the mask ``above`` with a 4-neighbour inside the array not in
    it."""
    below = ~above
    edge = np.zeros_like(above)
    edge[1:, :] |= below[:-1, :]
    edge[:-1, :] |= below[1:, :]
    edge[:, 1:] |= below[:, :-1]
    edge[:, :-1] |= below[:, 1:]
    return above & edge


def edge_width(thickness_m: np.ndarray) -> EdgeWidth:
    """The edge width (module docstring) of an (H, W) map of total paint thickness, metres."""
    thickness = np.asarray(thickness_m, dtype=np.float64)
    if thickness.ndim != 2:
        raise ValueError(f"expected an (H, W) thickness map, got shape {thickness.shape}")
    painted = thickness[thickness > FILM_FLOOR_M]
    if painted.size == 0:
        return EdgeWidth(math.nan, 0.0, 0, 0)
    t90 = float(np.percentile(painted, SCALE_PERCENTILE))
    ramp = int(np.count_nonzero((thickness >= RAMP_LOW * t90) & (thickness <= RAMP_HIGH * t90)))
    contour = int(np.count_nonzero(contour_mask(thickness, CONTOUR_LEVEL * t90)))
    width = ramp / contour if contour else math.nan
    return EdgeWidth(width, t90, ramp, contour)


def local_scale(thickness_m: np.ndarray) -> np.ndarray:
    """(H, W) float64: the local ``T90`` of the module docstring at every texel (0 where no
    tile block near it holds paint)."""
    thickness = np.asarray(thickness_m, dtype=np.float64)
    h, w = thickness.shape
    t, half = TILE_TEXELS, LOCAL_TILES // 2
    ty, tx = -(-h // t), -(-w // t)
    painted = np.zeros((ty * t, tx * t), dtype=bool)
    painted[:h, :w] = thickness > FILM_FLOOR_M
    any_paint = np.asarray(painted.reshape(ty, t, tx, t).any(axis=(1, 3)), dtype=bool)
    tiles = np.zeros((ty, tx))
    near = binary_dilation(any_paint, np.ones((LOCAL_TILES, LOCAL_TILES), dtype=bool))
    for j, i in zip(*np.nonzero(near), strict=True):
        y0, y1 = max(0, (j - half) * t), min(h, (j + half + 1) * t)
        x0, x1 = max(0, (i - half) * t), min(w, (i + half + 1) * t)
        block = thickness[y0:y1, x0:x1]
        values = block[block > FILM_FLOOR_M]
        if values.size:
            tiles[j, i] = np.percentile(values, SCALE_PERCENTILE)
    # linear between the tiles' centres, constant beyond the outer ones
    rows = np.interp(np.arange(h) + 0.5, (np.arange(ty) + 0.5) * t, np.arange(ty))
    cols = np.interp(np.arange(w) + 0.5, (np.arange(tx) + 0.5) * t, np.arange(tx))
    r0 = np.minimum(rows.astype(int), max(ty - 2, 0))
    c0 = np.minimum(cols.astype(int), max(tx - 2, 0))
    r1, c1 = np.minimum(r0 + 1, ty - 1), np.minimum(c0 + 1, tx - 1)
    fr, fc = (rows - r0)[:, None], (cols - c0)[None, :]
    top = tiles[r0][:, c0] * (1 - fc) + tiles[r0][:, c1] * fc
    bottom = tiles[r1][:, c0] * (1 - fc) + tiles[r1][:, c1] * fc
    return top * (1 - fr) + bottom * fr


def _painted_tiles(thickness: np.ndarray) -> tuple[slice, slice]:
    """The rows and columns of the whole tiles round the painted texels, with a margin of tiles
    whose scale is 0: the local measure reads the same on them as on the whole map."""
    rows = np.flatnonzero((thickness > FILM_FLOOR_M).any(axis=1))
    cols = np.flatnonzero((thickness > FILM_FLOOR_M).any(axis=0))
    t, margin = TILE_TEXELS, (LOCAL_TILES // 2 + 1) * TILE_TEXELS
    r0, c0 = max(0, (rows[0] // t) * t - margin), max(0, (cols[0] // t) * t - margin)
    r1, c1 = (rows[-1] // t + 1) * t + margin, (cols[-1] // t + 1) * t + margin
    return slice(r0, r1), slice(c0, c1)


def local_edge_width(thickness_m: np.ndarray) -> EdgeWidth:
    """The local edge width (module docstring) of an (H, W) map of total paint thickness,
    metres; its ``t90_m`` is the global ``T90`` (for reference)."""
    thickness = np.asarray(thickness_m, dtype=np.float64)
    if thickness.ndim != 2:
        raise ValueError(f"expected an (H, W) thickness map, got shape {thickness.shape}")
    painted = thickness[thickness > FILM_FLOOR_M]
    if painted.size == 0:
        return EdgeWidth(math.nan, 0.0, 0, 0, local=True)
    t90 = float(np.percentile(painted, SCALE_PERCENTILE))
    thickness = thickness[_painted_tiles(thickness)]
    scale = local_scale(thickness)
    inside = scale > 0.0
    ramp = inside & (thickness >= RAMP_LOW * scale) & (thickness <= RAMP_HIGH * scale)
    contour = int(np.count_nonzero(outline(inside & (thickness >= CONTOUR_LEVEL * scale))))
    count = int(np.count_nonzero(ramp))
    return EdgeWidth(count / contour if contour else math.nan, t90, count, contour, local=True)


def paint_edge_width(paint_m: np.ndarray) -> EdgeWidth:
    """The edge width of a canvas's paint, (P, H, W) metres per pigment (summed over P)."""
    return edge_width(np.asarray(paint_m).sum(axis=0, dtype=np.float64))


def paint_edge_widths(paint_m: np.ndarray) -> tuple[EdgeWidth, EdgeWidth]:
    """The global and the local edge width of a canvas's paint, (P, H, W) metres per pigment
    (summed over P once for both)."""
    thickness = np.asarray(paint_m).sum(axis=0, dtype=np.float64)
    return edge_width(thickness), local_edge_width(thickness)


def main(argv: list[str]) -> int:
    """Print the edge width of a demo output folder's ``canvas.exr``."""
    from common.errors import InputError
    from paintapp.canvas.exr import read_canvas_exr

    folder = Path(argv[0]) if argv else Path("paintapp-demo")
    try:
        canvas = read_canvas_exr(folder / "canvas.exr")
    except (OSError, InputError) as err:
        print(f"edges: error: {err} (expected a paintapp demo folder)", file=sys.stderr)
        return 2
    texel = canvas.texel_size_m[0]
    for width in paint_edge_widths(canvas.paint_m):
        print(width.describe(texel))
    return 0


if __name__ == "__main__":
    from common.pipes import run_tool

    run_tool(main, sys.argv[1:])
