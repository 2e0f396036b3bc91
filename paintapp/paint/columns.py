"""Where the local paint grid lies on the canvas, and moving paint between its columns and texels.

The grid's cells are cubes of ``h = k * texel`` (a whole number ``k`` of canvas texels), and their
columns sit on a lattice of ``k x k`` texel blocks fixed to the canvas (block corners at multiples
of ``k`` texels), so re-centring the grid by whole cells keeps every column on the same texels.
``k`` is chosen so that the grid spans ``span`` brush widths (:func:`cell_texels`).

Paint in the grid is the *wet* (mobile) part of the canvas paint: a texel with paint ``P_p``
(metres, per pigment) and wetness ``w`` holds ``w P_p`` of mobile paint; the rest is dry and stays
put. :meth:`ColumnWindow.gather` averages the mobile paint over each column's block;
:meth:`ColumnWindow.write_back` spreads a column's change over its block: a gain is added evenly
(as fresh, fully wet paint), a loss takes the same fraction of every texel's mobile paint. Each
texel's new wetness is its mobile share of its paint (a texel has one wetness for all its
pigments, so its total of dry paint is kept, not each pigment's). Columns whose change is exactly zero are not
touched, and texel totals change by exactly ``k^2`` times the column change (to float32
round-off), so paint is conserved. Columns not wholly on the canvas hold no paint and are walls.
"""

from __future__ import annotations

import math

import numpy as np

from common.errors import InputError
from paintapp.canvas.model import Canvas


def square_texel_m(canvas: Canvas) -> float:
    """The canvas's texel size (m); :class:`InputError` unless texels are square (0.01 %)."""
    dx, dy = canvas.texel_size_m
    if abs(dx - dy) > 1e-4 * max(dx, dy):
        raise InputError(
            f"painting needs square texels; this canvas has {dx * 1e3:.4g} x {dy * 1e3:.4g} mm "
            "(make size_m / pixels equal on both axes)",
            key="canvas",
        )
    return dx


def cell_texels(width_m: float, texel_m: float, cells_xy: int, span: float) -> int:
    """Texels per cell edge so that ``cells_xy`` cells span ``span`` brush widths (at least 1)."""
    return max(1, round(span * width_m / (cells_xy * texel_m)))


class ColumnWindow:
    """The lateral placement of an (nx, ny) grid of ``k x k``-texel columns on a canvas.

    Args:
        canvas: the canvas (square texels).
        cells_xy: (nx, ny) columns.
        texels_per_cell: ``k``.
    """

    def __init__(self, canvas: Canvas, cells_xy: tuple[int, int], texels_per_cell: int) -> None:
        self.texel_m = square_texel_m(canvas)
        self.k = int(texels_per_cell)
        self.cells = (int(cells_xy[0]), int(cells_xy[1]))
        self.pixels = canvas.pixels
        self.origin_texel = (0, 0)

    @property
    def cell_size_m(self) -> float:
        """Cell edge h (m)."""
        return self.k * self.texel_m

    @property
    def origin_m(self) -> tuple[float, float]:
        """Canvas position (m) of the grid's lower-left corner."""
        return (self.origin_texel[0] * self.texel_m, self.origin_texel[1] * self.texel_m)

    def place(self, x_m: float, y_m: float) -> None:
        """Centre the window on (x, y) metres, snapped to the block lattice."""
        k = self.k
        ox = k * round(x_m / self.texel_m / k - 0.5 * self.cells[0])
        oy = k * round(y_m / self.texel_m / k - 0.5 * self.cells[1])
        self.origin_texel = (ox, oy)

    def recentre_offset(self, x_m: float, y_m: float, margin: int) -> tuple[int, int]:
        """Whole-cell shift (di, dj) that re-centres on (x, y), or (0, 0) while it is farther
        than ``margin`` cells from every side."""
        out = []
        for a, pos in enumerate((x_m, y_m)):
            n = self.cells[a]
            c = (pos - self.origin_m[a]) / self.cell_size_m
            out.append(0 if margin <= c <= n - margin else round(c - 0.5 * n))
        return out[0], out[1]

    def shift(self, di: int, dj: int) -> None:
        """Move the window by whole cells."""
        self.origin_texel = (self.origin_texel[0] + di * self.k, self.origin_texel[1] + dj * self.k)

    def on_canvas_range(self) -> tuple[int, int, int, int] | None:
        """Columns wholly on the canvas: (i0, i1, j0, j1), half-open, or None."""
        bounds = []
        for a in range(2):
            o, n, size = self.origin_texel[a], self.cells[a], self.pixels[a]
            lo = max(0, math.ceil(-o / self.k))
            hi = min(n, (size - o) // self.k)
            if hi <= lo:
                return None
            bounds += [lo, hi]
        return bounds[0], bounds[1], bounds[2], bounds[3]

    def on_canvas(self) -> np.ndarray:
        """(nx, ny) bool: columns wholly on the canvas."""
        mask = np.zeros(self.cells, dtype=bool)
        r = self.on_canvas_range()
        if r is not None:
            mask[r[0] : r[1], r[2] : r[3]] = True
        return mask

    def _texel_block(self, r: tuple[int, int, int, int]) -> tuple[int, int, int, int]:
        i0, i1, j0, j1 = r
        ox, oy = self.origin_texel
        return ox + i0 * self.k, oy + j0 * self.k, ox + i1 * self.k, oy + j1 * self.k

    def _mobile(self, canvas: Canvas, r: tuple[int, int, int, int]):
        x0, y0, x1, y1 = self._texel_block(r)
        paint = canvas.paint_m[:, y0:y1, x0:x1].astype(np.float64)
        wet = canvas.wetness[y0:y1, x0:x1].astype(np.float64)
        return paint, wet, paint * wet

    def _column_means(self, texels: np.ndarray) -> np.ndarray:
        """(P, ny_t, nx_t) texel values -> (P, ni, nj) column means (grid order: x first)."""
        p, ht, wt = texels.shape
        k = self.k
        blocks = texels.reshape(p, ht // k, k, wt // k, k).mean(axis=(2, 4))
        return blocks.transpose(0, 2, 1)

    def gather(self, canvas: Canvas) -> np.ndarray:
        """Mobile paint per column and pigment, (P, nx, ny) float64, metres (0 off the canvas)."""
        out = np.zeros((len(canvas.pigment_names), *self.cells))
        r = self.on_canvas_range()
        if r is None or not canvas.pigment_names:
            return out
        _, _, mobile = self._mobile(canvas, r)
        out[:, r[0] : r[1], r[2] : r[3]] = self._column_means(mobile)
        return out

    def write_back(self, canvas: Canvas, delta_m: np.ndarray) -> None:
        """Apply a change of mobile paint per column, (P, nx, ny) metres, to the texels."""
        r = self.on_canvas_range()
        if r is None or not canvas.pigment_names:
            return
        delta = delta_m[:, r[0] : r[1], r[2] : r[3]]
        changed = np.any(delta != 0.0, axis=0)
        if not changed.any():
            return
        ci, cj = np.nonzero(changed)
        sub = (r[0] + ci.min(), r[0] + ci.max() + 1, r[2] + cj.min(), r[2] + cj.max() + 1)
        delta = delta_m[:, sub[0] : sub[1], sub[2] : sub[3]]
        paint, wet, mobile = self._mobile(canvas, sub)
        new_mobile = _spread_change(mobile, self._column_means(mobile), delta, self.k)
        new_paint = paint * (1.0 - wet) + new_mobile  # dry part + new wet part
        total = new_paint.sum(axis=0)
        with np.errstate(invalid="ignore", divide="ignore"):
            new_wet = np.where(total > 0.0, new_mobile.sum(axis=0) / total, 0.0)
        keep = ~np.repeat(np.repeat(np.any(delta != 0.0, axis=0).T, self.k, 0), self.k, 1)
        new_paint[:, keep] = paint[:, keep]
        new_wet[keep] = wet[keep]
        x0, y0, _, _ = self._texel_block(sub)
        canvas.write_region(x0, y0, new_paint, np.clip(new_wet, 0.0, 1.0))


def _spread_change(mobile: np.ndarray, column: np.ndarray, delta: np.ndarray, k: int) -> np.ndarray:
    """New mobile paint per texel (P, ny_t, nx_t) after column changes ``delta`` (P, ni, nj):
    gains added evenly, losses taken as a common fraction of each texel's mobile paint."""

    def texels(per_column: np.ndarray) -> np.ndarray:
        return np.repeat(np.repeat(per_column.transpose(0, 2, 1), k, 1), k, 2)

    with np.errstate(invalid="ignore", divide="ignore"):
        factor = np.where(column > 0.0, np.maximum(column + delta, 0.0) / column, 1.0)
    gain = np.maximum(delta, 0.0)
    factor = np.where(delta >= 0.0, 1.0, factor)
    return mobile * texels(factor) + texels(gain)
