"""Where the local paint grid lies on the canvas, and moving paint between its columns and texels.

The grid's cells are cubes of ``h = k * texel`` (``k`` whole, :func:`cell_texels`); re-centring by
whole cells keeps each column on the same ``k x k`` texel block, and a window that follows the tip
continuously has its corner anywhere: the weights stay a partition of unity at any offset.

Paint in the grid is the *wet* (mobile) part of the canvas paint: a texel with paint ``P_p``
(metres, per pigment) and wetness ``w`` holds ``w P_p`` of mobile paint; the rest is dry and stays
put. Columns and texels trade paint through a quadratic B-spline kernel, the same both ways: a
texel ``(dx, dy)`` texels from a column's centre has weight ``B(dx / k) B(dy / k)`` (``B`` reaches
a cell and a half; its slope is continuous, so no cell lattice prints; a scene may select the
crisper ``tent``, which is also used for ``k = 1``). :meth:`ColumnWindow.gather` gives each column
its weighted mobile paint over its area ``k^2``; :meth:`ColumnWindow.write_back` lays a gain down
with the weights (fresh, fully wet) and takes a loss as the same fraction of the weighted mobile
paint of every texel it reaches. Texels whose change is exactly zero are untouched, texel totals
change by exactly ``k^2`` times the column change (to round-off), and a texel's new wetness is
its mobile share (one wetness for all pigments). Columns not wholly on the canvas are walls; an
edge column's weights are clipped there. Kernels: :mod:`paintapp.paint.columns_kernels`.
"""

from __future__ import annotations

import functools
import math
from typing import Protocol

import numpy as np

from common.errors import InputError
from paintapp.canvas.model import FILM_FLOOR_M as CANVAS_FILM_FLOOR_M
from paintapp.canvas.model import MAX_PAINT_M, Canvas
from paintapp.canvas.regions import Box
from paintapp.paint import columns_kernels as kernels
from paintapp.paint.paint_scene import TransferKernel
from paintapp.paint.share_sweep import sweep_shares

#: Samples per cell of travel that a swept change is averaged over (at most
#: :data:`paintapp.paint.columns_kernels.MAX_SWEEP_SAMPLES`): the columns' change is smooth on
#: the scale of a cell, and the bristle texture's streaks run along the path, so a few a cell lay
#: it as evenly as a sample a texel does; with the sharper fronts of the flux-corrected transport
#: two a cell left a tooth a step beside the strokes, three do not (docs/performance.md, the
#: sweep's samples).
SWEEP_SAMPLES_PER_CELL = 3
#: Longest distance (texels) between two of those samples, for a grid of large cells.
SWEEP_SPACING_TEXELS = 6.0
#: Fewest texels per cell edge at which the write-back lays a step's change along the tip's path.
#: With one texel per cell the change has no detail finer than the tip's own cells, and the teeth
#: left there come from where the tip's faces fall within a cell, which the sweep cannot undo
#: (sweeping deepens them); from two texels per cell the sweep makes them shallower.
SWEEP_MIN_TEXELS = 2
#: Most texels per cell edge at which the sweep moves a step's losses as shares kept
#: (:func:`paintapp.paint.share_sweep.sweep_shares`) rather than as amounts
#: (:func:`paintapp.paint.columns_kernels.sweep_change`). Small cells are where a step's travel
#: is longest in cells (the probe's sub-steps cross three of its two-texel cells), and where the
#: amount sweep's caps printed a tooth a step beside the trough; the share sweep costs
#: exponentials and a logarithm per texel, and a box grows as the square of the cell, so larger
#: cells, whose steps cross fewer cells and print no such teeth, keep the amount sweep
#: (docs/performance.md, the share sweep).
SHARE_SWEEP_MAX_TEXELS = 2

#: Thinnest wet film (m) a changed column may be left with; thinner ones are emptied
#: (:func:`drop_thin_films`): :data:`paintapp.canvas.model.FILM_FLOOR_M`, 0.1 um.
FILM_FLOOR_M = CANVAS_FILM_FLOOR_M
#: Thinnest film (m) a texel at the paint's edge may be left with; thinner ones go to the
#: texel's thickest neighbour (:func:`paintapp.paint.columns_kernels.gather_fringe_films`).
#: Far under anything the eye sees; any of 1e-10 to 1e-8 m closes the holes.
FRINGE_FLOOR_M = 1e-9


class TexelWeights(Protocol):
    """Per-texel weights shaping a column change (see :func:`column_rates`)."""

    def weights(self, box: Box) -> tuple[np.ndarray, np.ndarray] | None:
        """(gain, loss) weights (ny, nx) over ``box``: gains > 0, losses in (0, 1]; or None
        (even weights)."""


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
        kernel: ``"bspline"`` or ``"tent"`` (:func:`transfer_weights`).
        continuous: the window follows a point exactly, keeping it at the centre of its
            middle cell (its corner anywhere, to a fraction of a texel: :meth:`place` and
            :meth:`recentre_offset`), not by whole cells.
    """

    def __init__(
        self,
        canvas: Canvas,
        cells_xy: tuple[int, int],
        texels_per_cell: int,
        kernel: TransferKernel = "bspline",
        continuous: bool = False,
    ) -> None:
        self.kernel = kernel
        self.continuous = continuous
        self.texel_m = square_texel_m(canvas)
        self.k = int(texels_per_cell)
        self.cells = (int(cells_xy[0]), int(cells_xy[1]))
        self.pixels = canvas.pixels
        #: The grid's lower-left corner in texels (whole cells' worth of texels, or anywhere
        #: when ``continuous``).
        self.origin_texel: tuple[float, float] = (0, 0)

    @property
    def cell_size_m(self) -> float:
        """Cell edge h (m)."""
        return self.k * self.texel_m

    @property
    def origin_m(self) -> tuple[float, float]:
        """Canvas position (m) of the grid's lower-left corner."""
        return (self.origin_texel[0] * self.texel_m, self.origin_texel[1] * self.texel_m)

    def whole_origin(self) -> tuple[int, int]:
        """The corner in whole texels, for a window that follows by whole cells."""
        if self.continuous:
            raise ValueError("a window that follows continuously has no whole-texel corner")
        return int(self.origin_texel[0]), int(self.origin_texel[1])

    def place(self, x_m: float, y_m: float) -> None:
        """Centre the window on (x, y) metres (snapped to the block lattice unless
        ``continuous``)."""
        k = self.k
        if self.continuous:
            ox = x_m / self.texel_m / k - self._centre_cell(0)
            oy = y_m / self.texel_m / k - self._centre_cell(1)
            self.origin_texel = (k * ox, k * oy)
        else:
            ox = x_m / self.texel_m / k - 0.5 * self.cells[0]
            oy = y_m / self.texel_m / k - 0.5 * self.cells[1]
            self.origin_texel = (k * round(ox), k * round(oy))

    def _centre_cell(self, axis: int) -> float:
        """Where a window that follows continuously keeps the point it follows, in cells from
        its corner: the centre of its middle cell (a point between two cells would put a tip
        thinner than a cell across both, and half of each would never be its)."""
        return self.cells[axis] // 2 + 0.5

    def recentre_offset(self, x_m: float, y_m: float, margin: int) -> tuple[float, float]:
        """The shift (di, dj), in cells, that re-centres on (x, y): whole cells, or (0, 0) while
        it is farther than ``margin`` cells from every side; when ``continuous``, the exact
        shift that puts (x, y) at the centre of the middle cell, every time."""
        out: list[float] = []
        for a, pos in enumerate((x_m, y_m)):
            n = self.cells[a]
            c = (pos - self.origin_m[a]) / self.cell_size_m
            if self.continuous:
                out.append(c - self._centre_cell(a))
            else:
                out.append(0 if margin <= c <= n - margin else round(c - 0.5 * n))
        return out[0], out[1]

    def shift(self, di: float, dj: float) -> None:
        """Move the window by (di, dj) cells (whole cells unless ``continuous``)."""
        k = self.k
        self.origin_texel = (self.origin_texel[0] + di * k, self.origin_texel[1] + dj * k)

    def on_canvas_range(self) -> tuple[int, int, int, int] | None:
        """Columns wholly on the canvas: (i0, i1, j0, j1), half-open, or None."""
        bounds = []
        for a in range(2):
            o, n, size = self.origin_texel[a], self.cells[a], self.pixels[a]
            lo = max(0, math.ceil(-o / self.k - EDGE_TOLERANCE))
            hi = min(n, math.floor((size - o) / self.k + EDGE_TOLERANCE))
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

    def _texel_block(
        self, r: tuple[int, int, int, int], behind: tuple[float, float] = (0.0, 0.0)
    ) -> tuple[int, int, int, int]:
        """Texels (x0, y0, x1, y1), half-open and clipped to the canvas, that the weights of
        columns ``r`` = (i0, i1, j0, j1) reach (their blocks and :func:`reach_cells` around),
        and as far again as ``behind`` (texels, x and y) back the way the tip came."""
        i0, i1, j0, j1 = r
        ox, oy = self.origin_texel
        k, (w, h) = self.k, self.pixels
        m = reach_cells(k, self.kernel)
        bx, by = (math.ceil(abs(v)) + 1 if abs(v) >= 0.5 else 0 for v in behind)
        x0 = max(0, _floor(ox + (i0 - m) * k) - (bx if behind[0] > 0 else 0))
        x1 = min(w, _ceil(ox + (i1 + m) * k) + (bx if behind[0] < 0 else 0))
        y0 = max(0, _floor(oy + (j0 - m) * k) - (by if behind[1] > 0 else 0))
        y1 = min(h, _ceil(oy + (j1 + m) * k) + (by if behind[1] < 0 else 0))
        return x0, y0, x1, y1

    def _weights(
        self, r: tuple[int, int, int, int], box: tuple[int, int, int, int]
    ) -> tuple[AxisWeights, AxisWeights]:
        """Weights of columns ``r`` over the texels of ``box``: x (ni, nx_t), y (nj, ny_t)."""
        ox, oy = self.origin_texel
        k, kernel = self.k, self.kernel
        return (
            axis_weights(ox + r[0] * k - box[0], k, r[1] - r[0], box[2] - box[0], kernel),
            axis_weights(oy + r[2] * k - box[1], k, r[3] - r[2], box[3] - box[1], kernel),
        )

    def gather(self, canvas: Canvas) -> np.ndarray:
        """Mobile paint per column and pigment, (P, nx, ny) float64, metres (0 off the canvas):
        the weighted sum of the texels' mobile paint over the column's area ``k^2``."""
        out = np.zeros((len(canvas.pigment_names), *self.cells))
        r = self.on_canvas_range()
        if r is None or not canvas.pigment_names:
            return out
        box = self._texel_block(r)
        wx, wy = self._weights(r, box)
        sums = np.empty((out.shape[0], r[1] - r[0], r[3] - r[2]))
        unused = np.empty((0, 0))
        block = (canvas.paint_m, canvas.wetness, box[0], box[1])
        texels = kernels.TexelBox(*block, wx.first, wx.taps, wy.first, wy.taps)
        every = np.ones(out.shape[0], np.bool_)
        kernels.texels_to_columns(
            texels, (unused, unused), False, every, sums, np.empty(sums.shape[1:])
        )
        out[:, r[0] : r[1], r[2] : r[3]] = sums / self.k**2
        return out

    def write_back(
        self,
        canvas: Canvas,
        delta_m: np.ndarray,
        texture: TexelWeights | None = None,
        gathered: np.ndarray | None = None,
        sweep_texels: tuple[float, float] | None = None,
    ) -> None:
        """Apply a change of mobile paint per column, (P, nx, ny) metres, to the texels.

        ``texture`` (a brush's bristle texture, :mod:`paintapp.paint.bristles`) gives per-texel
        gain and loss weights that shape where within its support a column's change lands.
        ``gathered`` is what :meth:`gather` returned for this canvas, unchanged since (a step
        passes it on; otherwise it is gathered again): thin films are dropped column by column
        first, so only the texels of columns whose change survives are read and written (the
        transport's thin tails reach the whole grid). ``sweep_texels``, the tip's travel during
        the step (texels, x and y), lays the change along that path
        (:func:`paintapp.paint.columns_kernels.sweep_change`, or
        :func:`paintapp.paint.share_sweep.sweep_shares` for cells of at most
        :data:`SHARE_SWEEP_MAX_TEXELS` texels); a texture with a canvas tooth's own gain weights
        (a ``weights_and_gains(box)`` method, :class:`paintapp.paint.tooth.ToothTexture`) has
        the amount sweep lay the gains where the tooth takes them. The texels are read and written by
        :mod:`paintapp.paint.columns_kernels`'s kernels; only the texels that changed are written
        and marked dirty."""
        r = self.on_canvas_range()
        if r is None or not canvas.pigment_names:
            return
        delta = delta_m[:, r[0] : r[1], r[2] : r[3]]
        if not np.any(delta != 0.0):
            return
        columns = self.gather(canvas) if gathered is None else gathered
        k2 = self.k**2
        held = columns[:, r[0] : r[1], r[2] : r[3]] * k2
        change = drop_thin_films(held, delta * k2, FILM_FLOOR_M * k2)
        changed = np.any(change != 0.0, axis=0)
        if not changed.any():
            return
        ci, cj = np.nonzero(changed)
        a0, a1, b0, b1 = ci.min(), ci.max() + 1, cj.min(), cj.max() + 1
        sub = (r[0] + a0, r[0] + a1, r[2] + b0, r[2] + b1)
        change, owned = change[:, a0:a1, b0:b1], held[:, a0:a1, b0:b1]
        # the pigments that change: the texel passes skip the others (their texels keep
        # their paint, as zero rates would leave it)
        active = np.any(change != 0.0, axis=(1, 2))
        if self.k < SWEEP_MIN_TEXELS:
            sweep_texels = None
        box = self._texel_block(sub, sweep_texels or (0.0, 0.0))
        wx, wy = self._weights(sub, box)
        shape: tuple[np.ndarray, np.ndarray] | None = None
        tooth: np.ndarray | None = None  # a canvas tooth's own gain weights, for the sweep
        split = getattr(texture, "weights_and_gains", None)
        if split is not None:
            gain_w, loss_w, tooth = split(box)
            shape = (gain_w, loss_w)
        elif texture is not None:
            shape = texture.weights(box)
        block = (canvas.paint_m, canvas.wetness, box[0], box[1])
        texels = kernels.TexelBox(*block, wx.first, wx.taps, wy.first, wy.taps)
        if shape is None:
            unused = np.empty((0, 0))
            texture_w = (unused, unused)
            rates = column_rates(owned, change, np.outer(wx.sums, wy.sums)[None], owned)
        else:
            texture_w = shape
            first = np.empty_like(owned)
            support = np.empty(owned.shape[1:])
            kernels.texels_to_columns(texels, texture_w, True, active, first, support)
            rates = column_rates(owned, change, support[None], first)
        ny, nx = box[3] - box[1], box[2] - box[0]
        new_mobile = np.empty((owned.shape[0], ny, nx))
        touched = np.empty((ny, nx), dtype=np.bool_)
        total = np.empty((ny, nx))
        kernels.spread_to_texels(
            texels, rates, texture_w, shape is not None, active, new_mobile, touched, total
        )
        if sweep_texels is not None:
            spacing = min(self.k / SWEEP_SAMPLES_PER_CELL, SWEEP_SPACING_TEXELS)
            travel = (float(sweep_texels[0]), float(sweep_texels[1]))
            args = (*block, new_mobile, touched, total, *travel, spacing, active)
            if self.k <= SHARE_SWEEP_MAX_TEXELS:
                sweep_shares(*args)
            elif tooth is None:
                kernels.sweep_change(*args)
            else:
                kernels.sweep_change(*args, tooth)
        kernels.close_pinholes(new_mobile, touched, total, FILM_FLOOR_M)
        kernels.fill_thin_holes(new_mobile, touched, total, FILM_FLOOR_M)
        kernels.gather_fringe_films(new_mobile, touched, total, FRINGE_FLOOR_M)
        bounds = np.zeros(4, np.int64)
        kernels.store_texels(*block, new_mobile, touched, MAX_PAINT_M, bounds)
        if bounds[2] > bounds[0]:
            canvas.mark_dirty(*(int(v) for v in bounds))


#: Texels' worth of round-off under which a window's edge counts as on a texel boundary.
EDGE_TOLERANCE = 1e-9


def _floor(v: float) -> int:
    return math.floor(v + EDGE_TOLERANCE)


def _ceil(v: float) -> int:
    return math.ceil(v - EDGE_TOLERANCE)


def reach_cells(k: int, kernel: str = "bspline") -> float:
    """Cells beyond its own block that a column's weights reach: the B-spline (``k > 1``)
    reaches a cell and a half from the column's centre, one beyond its block; the tent a cell,
    half of one beyond. A texel farther has no weight, and every pass of the write-back would
    read it."""
    return 1.0 if kernel == "bspline" and k > 1 else 0.5


def transfer_weights(
    origin: float, k: int, i0: int, i1: int, t0: int, t1: int, kernel: str = "bspline"
) -> np.ndarray:
    """(i1 - i0, t1 - t0) weights ``B(|x_t - c_i| / k)`` (module docstring; the tent
    ``max(0, 1 - |t|)`` for ``kernel = "tent"`` or ``k = 1``) of texels ``t0..t1-1`` (centres
    ``x_t = t + 1/2``) for columns ``i0..i1-1`` (centres ``c_i = origin + (i + 1/2) k``), texel
    units. Inside the window's columns they sum to 1 over the columns at every texel (a partition
    of unity), and to ``k`` over the texels of a column."""
    centres = origin + (np.arange(i0, i1) + 0.5) * k
    texels = np.arange(t0, t1) + 0.5
    t = np.abs(texels[None, :] - centres[:, None]) / k
    if kernel == "tent" or k == 1:
        return np.maximum(1.0 - t, 0.0)
    outer = 0.5 * (1.5 - np.minimum(t, 1.5)) ** 2
    return np.where(t <= 0.5, 0.75 - t * t, outer)


@functools.lru_cache(maxsize=64)
def axis_weights(offset: float, k: int, columns: int, texels: int, kernel: str) -> AxisWeights:
    """:class:`AxisWeights` of ``columns`` columns over ``texels`` texels, the first column's
    block starting ``offset`` texels after the first texel (a fraction of a texel for a window
    that follows continuously): the weights depend on nothing else, and a window that moves by
    whole cells meets the same few again and again (kept, not built anew with their sparse
    matrices each time). Read only."""
    return AxisWeights(offset, k, columns, texels, kernel)


class AxisWeights:
    """One axis's transfer weights (:func:`transfer_weights`, columns by texels), per texel:
    ``first``, the first column its weights reach, and ``taps``, the weights of it and the next
    columns (as :func:`paintapp.paint.columns_kernels.axis_taps` takes them from the dense
    weights); ``sums``, each column's total. Built by
    :func:`paintapp.paint.columns_kernels.weight_taps`."""

    def __init__(self, offset: float, k: int, columns: int, texels: int, kernel: str) -> None:
        self.shape = (columns, texels)
        self.first = np.empty(texels, np.int64)
        self.taps = np.empty((texels, kernels.TAPS))
        self.sums = np.empty(columns)
        tent = kernel == "tent" or k == 1
        if not kernels.weight_taps(float(offset), k, tent, self.first, self.taps, self.sums):
            raise ValueError(f"transfer weights reach more than {kernels.TAPS} columns per texel")


def drop_thin_films(owned: np.ndarray, change: np.ndarray, floor: float) -> np.ndarray:
    """Column changes (P, ni, nj) with no column left holding a wet film thinner than ``floor``.

    The grid's transport is upwind, so every step smears an exponentially thin tail of paint
    over the whole grid (1e-19 m and less); written to the canvas it would put paint everywhere.
    A changed column whose wet paint (``owned + change``, all pigments) ends below ``floor`` is
    emptied instead, and what it would have held goes, per pigment, to the columns gaining that
    pigment (in proportion to their gains), else to those losing it (their losses shrink), else
    to the column holding most of it: paint stays conserved and nothing turns negative."""
    after = np.maximum(owned + change, 0.0)
    total = after.sum(axis=0)
    thin = (total < floor) & np.any(change != 0.0, axis=0)
    if not thin.any() or thin.sum() == thin.size:
        return change
    out = change.copy()
    out[:, thin] = -owned[:, thin]
    freed = after[:, thin].sum(axis=1)
    keep = ~thin & np.any(change != 0.0, axis=0)
    for p in np.flatnonzero(freed > 0.0):
        gains = np.where(keep & (change[p] > 0.0), change[p], 0.0)
        if not gains.any():
            gains = np.where(keep & (change[p] < 0.0), -change[p], 0.0)
        if gains.any():
            out[p] += freed[p] * gains / gains.sum()
        else:
            held = np.where(~thin, after[p], 0.0)
            out[p].flat[int(np.argmax(held))] += freed[p]
    return out


def column_rates(
    owned: np.ndarray, change: np.ndarray, support: np.ndarray, first: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per column (P, ni, nj): the gain per unit of gain weight, and the loss fractions of the
    loss-weighted paint and of the rest, for column changes ``change`` (texel volumes: metres
    times texels; ``owned``: the columns' weighted mobile paint in the same units).

    A gain is laid down with the column's weights times the texels' gain weights ``g``,
    normalised by their sum ``support``; a loss is taken first as a fraction ``f`` of the
    loss-weighted paint ``first`` (the columns' weighted sums of ``b`` times the mobile paint,
    ``b`` in (0, 1]), any rest as a fraction ``r`` of the ``(1 - b)``-weighted paint: a texel
    with mobile paint ``m`` loses ``m (b F + (1 - b) R)`` with ``F``, ``R`` the weighted sums of
    the columns' fractions, both at most 1, so with the weights' partition of unity no texel
    loses more than it holds, and each column loses exactly its loss. Without a texture
    (``g = b = 1``: ``first`` is ``owned`` and ``support`` the weights' sums) ``r`` is 0."""
    loss = np.maximum(-change, 0.0)
    rest = np.maximum(owned - first, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        gain = np.where(support > 0.0, np.maximum(change, 0.0) / support, 0.0)
        f = np.where((loss > 0.0) & (first > 0.0), np.minimum(loss / first, 1.0), 0.0)
        left = np.maximum(loss - f * first, 0.0)
        r = np.where((left > 0.0) & (rest > 0.0), np.minimum(left / rest, 1.0), 0.0)
    return gain, f, r
