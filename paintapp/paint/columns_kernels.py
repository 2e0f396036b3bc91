"""Numba kernels of the column/texel transfer (:mod:`paintapp.paint.columns`), one pass each.

Each axis's transfer weights are given per texel as ``first`` (the first column whose weight
reaches the texel) and ``taps`` (that column's weight and the next ``TAPS - 1`` columns',
zero past the last column): the quadratic B-spline reaches three columns, the tent two. The
kernels work on the canvas's own float32 arrays in place, row by row (the canvas's memory order),
with the 2D sums split per axis, so the write-back reads and writes every texel of its box once
instead of the dozen whole-box array passes (and the interpreter lock hand-overs between them) of
the array form; the lock is released throughout.

A texel's *mobile* paint is its paint times its wetness, the wetness read as 1 from
:data:`FULLY_WET` up (float32 round-off of fresh paint is no dry residue).

:func:`sweep_change` then lays a step's change along the path the tip travelled during the step
(a step computes it with the tip at its end pose only, which alone would print one tooth per step
along a fast stroke).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from paintapp.paint.water_filling import capacity, water_fill
from solver import inline_kernel, kernel

#: Columns one texel's weights reach on one axis at most.
TAPS = 3

#: Most samples along the path that a swept change is averaged over: enough for a sample a
#: texel along the demo's fastest sub-steps (6.3 texels); each sample is a pass over the box, so
#: the write-back's cost grows with it. A longer sub-step (a fast stroke, or a stalled session's
#: catch-up) takes more, so that its samples are never more than :data:`MAX_READ_GAP` spacings
#: apart.
MAX_SWEEP_SAMPLES = 8
#: The widest gap between two samples along the path, in the sweep's spacings (three spacings:
#: a cell, for cells of up to 18 texels): eight samples along a sub-step of several cells laid
#: its change as a row of copies.
MAX_READ_GAP = 3.0

#: How far the sweep's moved gains may miss the step's gains, as a share of them, before the
#: box counts as cut short behind the change: the fields are float32 (:func:`_swept_fields`),
#: each value's round-off about 6e-8 of it; the gains are then scaled to their total exactly.
SWEPT_ROUND_OFF = 1e-5

#: What :func:`fill_thin_holes` lifts a hole's paint to, in film floors: clear of the floor
#: once stored as float32.
HOLE_FILL = 1.25

#: The least level, in film floors, that :func:`fill_thin_holes` shares a hole's paint out to
#: with a neighbour too thin to lift it to :data:`HOLE_FILL` (float32 keeps it over the floor).
HOLE_SHARED = 1.001

#: Largest hole (texels) :func:`fill_thin_holes` fills.
MAX_HOLE_TEXELS = 8

#: Wetness at or above which a texel counts as fully wet (float32 round-off of 1).
FULLY_WET = 1.0 - 2.0**-20


class TexelBox(NamedTuple):
    """A box of canvas texels and its transfer weights, as the kernels take them."""

    #: (P, H, W) float32: the canvas's paint per pigment (m), read and written in place.
    paint: np.ndarray
    #: (H, W) float32: the canvas's wetness.
    wetness: np.ndarray
    #: The box's first texel, x and y.
    x0: int
    y0: int
    #: (nx,) int64 and (nx, TAPS): each texel column's first column and taps along x
    #: (:func:`weight_taps`).
    fx: np.ndarray
    tx: np.ndarray
    #: (ny,) and (ny, TAPS): the same along y.
    fy: np.ndarray
    ty: np.ndarray


def axis_taps(weights: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(first, taps) of dense (columns, texels) weights: per texel, the first column with a
    non-zero weight (0 where none) and the weights of it and the next ``TAPS - 1`` columns.
    The reference that :func:`weight_taps`, which the windows use, is tested against."""
    n_col, n_tex = weights.shape
    nonzero = weights != 0.0
    first = np.where(nonzero.any(axis=0), np.argmax(nonzero, axis=0), 0)
    taps = np.zeros((n_tex, TAPS))
    for a in range(TAPS):
        col = first + a
        ok = col < n_col
        taps[ok, a] = weights[col[ok], np.flatnonzero(ok)]
    if np.count_nonzero(taps) != np.count_nonzero(nonzero):
        raise ValueError(f"transfer weights reach more than {TAPS} columns per texel")
    return first.astype(np.int64), taps


@kernel
def weight_taps(origin, k, tent, first, taps, sums):
    """(first, taps) as :func:`axis_taps` gives them for the weights
    :func:`paintapp.paint.columns.transfer_weights` builds (columns ``0..sums.size - 1``, texels
    ``0..first.size - 1``), computed texel by texel with its arithmetic (the same values), and
    each column's total into ``sums``, without the dense (columns, texels) array: a window that
    follows the tip continuously needs new weights every step. Returns False if a texel's weights reach more than
    ``TAPS`` columns."""
    n_col, n_tex = sums.size, first.size
    sums[:] = 0.0
    fits = True
    for x in range(n_tex):
        centre = x + 0.5
        first[x] = 0
        for a in range(TAPS):
            taps[x, a] = 0.0
        found = -1
        for i in range(n_col):
            t = abs(centre - (origin + (i + 0.5) * k)) / k
            if tent:
                w = max(1.0 - t, 0.0)
            elif t <= 0.5:
                w = 0.75 - t * t
            else:
                w = 0.5 * (1.5 - min(t, 1.5)) ** 2
            if w == 0.0:
                continue
            if found < 0:
                found = i
                first[x] = i
            if i - found >= TAPS:
                fits = False
            else:
                taps[x, i - found] = w
            sums[i] += w
    return fits


@inline_kernel
def _mobile_share(wet):
    return 1.0 if wet >= FULLY_WET else float(wet)


@kernel
def texels_to_columns(box, texture, textured, active, out_mobile, out_gain):
    """Weighted sums over the texels of ``box`` (a :class:`TexelBox`) into columns:
    ``out_mobile`` (P, ni, nj) gets the mobile paint (times the loss weights when ``textured``)
    of the pigments ``active`` (P,) marks (0 for the rest) and ``out_gain`` (ni, nj) the gain
    weights (when ``textured``); ``texture`` is the (gain, loss) weights, each (ny, nx). Both are
    overwritten.

    Along y first: each texel row, weighed, is added to the texel-wide rows of the (few) rows of
    columns its weights reach (whole rows in order, which the compiler vectorises); then each of
    those rows is summed along x into its columns, a run of texels whose weights start at the
    same column (``k`` of them) summing its three taps in registers."""
    paint, wetness, x0, y0, fx, tx, fy, ty = box
    gain_w, loss_w = texture
    n_p, ni, nj = out_mobile.shape
    nx, ny = fx.shape[0], fy.shape[0]
    out_mobile[:] = 0.0
    out_gain[:] = 0.0
    if nx == 0:
        return
    rows = np.zeros((n_p, nj + TAPS - 1, nx))  # padded: a texel's zero taps may pass the last row
    rows_g = np.zeros((nj + TAPS - 1, nx))
    share = np.empty(nx)
    for y in range(ny):
        wet_row = wetness[y0 + y, x0 : x0 + nx]
        for x in range(nx):
            share[x] = _mobile_share(wet_row[x])
        if textured:
            loss_row = loss_w[y]
            for x in range(nx):
                share[x] *= loss_row[x]
        j0 = fy[y]
        for c in range(TAPS):
            w = ty[y, c]
            if w == 0.0:
                continue
            if textured:
                g_out, g_in = rows_g[j0 + c], gain_w[y]
                for x in range(nx):
                    g_out[x] += w * g_in[x]
            for p in range(n_p):
                if active[p]:
                    out, held = rows[p, j0 + c], paint[p, y0 + y, x0 : x0 + nx]
                    for x in range(nx):
                        out[x] += w * (held[x] * share[x])
    column = np.zeros(ni + TAPS - 1)  # padded: a texel's zero taps may pass the last column
    for j in range(nj):
        for p in range(n_p):
            if active[p]:
                _runs_into(rows[p, j], fx, tx, column)
                for i in range(ni):  # not a slice copy, which compiles a shape check
                    out_mobile[p, i, j] = column[i]
        if textured:
            _runs_into(rows_g[j], fx, tx, column)
            for i in range(ni):
                out_gain[i, j] = column[i]


@inline_kernel
def _runs_into(values, fx, tx, out):
    """``out[fx[x] + a] = sum over x of tx[x, a] * values[x]`` for every texel ``x`` of a row
    (``out`` overwritten), summed in registers over each run of texels with the same first
    column. Written for :data:`TAPS` = 3; ``fx`` must not be empty."""
    out[:] = 0.0
    cur = fx[0]
    a0 = a1 = a2 = 0.0
    for x in range(fx.shape[0]):
        i = fx[x]
        if i != cur:
            out[cur] += a0
            out[cur + 1] += a1
            out[cur + 2] += a2
            cur, a0, a1, a2 = i, 0.0, 0.0, 0.0
        v = values[x]
        a0 += tx[x, 0] * v
        a1 += tx[x, 1] * v
        a2 += tx[x, 2] * v
    out[cur] += a0
    out[cur + 1] += a1
    out[cur + 2] += a2


@kernel
def _spread_along_x(columns, fx, tx, active, out):
    """``out[p, j, x]`` = the column values ``columns`` (P, ni, nj) of column row ``j`` weighed
    along x at texel column ``x`` (``sum_a tx[x, a] columns[p, fx[x] + a, j]``), for the
    pigments ``active`` marks; ``out`` is (P, nj + TAPS - 1, nx), its last rows left as they
    are (zeros: a texel row's zero taps may pass the last row of columns)."""
    n_p, ni, nj = columns.shape
    nx = fx.shape[0]
    for p in range(n_p):
        if not active[p]:
            continue
        for j in range(nj):
            row = out[p, j]
            for x in range(nx):
                i0 = fx[x]
                v = 0.0
                for a in range(TAPS):
                    if i0 + a < ni:
                        v += tx[x, a] * columns[p, i0 + a, j]
                row[x] = v


@kernel
def spread_to_texels(box, rates, texture, textured, active, new_mobile, touched, total):
    """New mobile paint (P, ny, nx) into ``new_mobile``, the texels of ``box`` (a
    :class:`TexelBox`) that changed into ``touched`` (ny, nx) and their new paint (dry + new
    mobile, all pigments) into ``total`` (ny, nx), for ``rates`` = (gain, first, rest): column
    gains and loss fractions (P, ni, nj; see :func:`paintapp.paint.columns.column_rates`): a
    texel gains ``g * sum w gain`` and loses ``m (b * sum w first + (1 - b) * sum w rest)``
    (``g``, ``b``: the gain and loss weights ``texture`` when ``textured``, else 1 and 1).
    A pigment ``active`` (P,) does not mark has no rates (all zero): its texels keep their
    mobile paint, the same value its rates would give, without reading them. Reads the canvas
    only. The rates are weighed along x once for each row of columns, then each texel row,
    pigment by pigment, reads three of those rows in order (the compiler vectorises it; a
    pigment that does not change is a plain copy)."""
    paint, wetness, x0, y0, fx, tx, fy, ty = box
    gain_w, loss_w = texture
    n_p, _, nj = rates[0].shape
    nx, ny = fx.shape[0], fy.shape[0]
    # each rate weighed along x first, for every row of columns (their rows are few): a texel
    # row is then three of those rows weighed along y, read in order
    spread = np.zeros((3, n_p, nj + TAPS - 1, nx))
    for k in range(3 if textured else 2):
        _spread_along_x(rates[k], fx, tx, active, spread[k])
    share = np.empty(nx)
    for y in range(ny):
        wet_row, t_row, c_row = wetness[y0 + y, x0 : x0 + nx], total[y], touched[y]
        for x in range(nx):
            share[x] = _mobile_share(wet_row[x])
            t_row[x] = 0.0
            c_row[x] = False
        j0, v0, v1, v2 = fy[y], ty[y, 0], ty[y, 1], ty[y, 2]
        for p in range(n_p):
            held_row, out = paint[p, y0 + y, x0 : x0 + nx], new_mobile[p, y]
            if not active[p]:
                for x in range(nx):
                    held = held_row[x]
                    mobile = held * share[x]
                    out[x] = mobile
                    t_row[x] += held * (1.0 - share[x]) + mobile
                continue
            g0, g1, g2 = spread[0, p, j0], spread[0, p, j0 + 1], spread[0, p, j0 + 2]
            f0, f1, f2 = spread[1, p, j0], spread[1, p, j0 + 1], spread[1, p, j0 + 2]
            r0, r1, r2 = spread[2, p, j0], spread[2, p, j0 + 1], spread[2, p, j0 + 2]
            for x in range(nx):
                held, s = held_row[x], share[x]
                mobile = held * s
                g = gain_w[y, x] if textured else 1.0
                b = loss_w[y, x] if textured else 1.0
                laid = g * (v0 * g0[x] + v1 * g1[x] + v2 * g2[x])
                lost = mobile * b * (v0 * f0[x] + v1 * f1[x] + v2 * f2[x])
                if textured:
                    lost += mobile * (1.0 - b) * (v0 * r0[x] + v1 * r1[x] + v2 * r2[x])
                if lost > 0.0 or laid > 0.0:
                    c_row[x] = True
                m = max(mobile - lost, 0.0) + laid
                out[x] = m
                t_row[x] += held * (1.0 - s) + m


@kernel
def close_pinholes(new_mobile, touched, total, floor):
    """Fill pinholes in place (see :func:`paintapp.paint.columns.ColumnWindow.write_back`): a
    touched texel off the box's edge whose paint ``total`` (dry + wet, all pigments) is at most
    ``floor`` while its eight neighbours' all exceed twice that gets 1/9 of each neighbour's wet
    paint, per pigment (each neighbour gives at most 8/9 of it: conserved, never negative).
    Returns how many were filled; ``total`` is updated."""
    n_p, ny, nx = new_mobile.shape
    if ny < 3 or nx < 3:
        return 0
    pins = []
    for y in range(1, ny - 1):
        for x in range(1, nx - 1):
            if not touched[y, x] or total[y, x] > floor:
                continue
            hole = True
            for dy in range(-1, 2):
                for dx in range(-1, 2):
                    if (dy != 0 or dx != 0) and total[y + dy, x + dx] <= 2.0 * floor:
                        hole = False
            if hole:
                pins.append((y, x))
    if len(pins) == 0:
        return 0
    gains = np.zeros((len(pins), n_p))
    gives = np.zeros((ny, nx))
    for n, (y, x) in enumerate(pins):
        for dy in range(-1, 2):
            for dx in range(-1, 2):
                if dy != 0 or dx != 0:
                    for p in range(n_p):
                        gains[n, p] += new_mobile[p, y + dy, x + dx] / 9.0
                    gives[y + dy, x + dx] += 1.0
    for y in range(ny):
        for x in range(nx):
            if gives[y, x] > 0.0:
                for p in range(n_p):
                    given = new_mobile[p, y, x] * gives[y, x] / 9.0
                    new_mobile[p, y, x] -= given
                    total[y, x] -= given
                touched[y, x] = True
    for n, (y, x) in enumerate(pins):
        for p in range(n_p):
            new_mobile[p, y, x] += gains[n, p]
            total[y, x] += gains[n, p]
    return len(pins)


@kernel
def fill_thin_holes(new_mobile, touched, total, floor):
    """Fill in place the holes that :func:`close_pinholes` leaves: texels whose paint ``total``
    (dry + wet, all pigments) is at most ``floor`` and that painted texels enclose within the
    box (no path through four-neighbours at most ``floor`` to the box's edge; changed or not:
    their neighbours' change may have closed round them). Each takes from its thickest
    neighbour of eight the wet paint (in that neighbour's pigment shares) that lifts it to
    ``HOLE_FILL`` times ``floor``, where the neighbour keeps more than that itself, else the
    two share their paint evenly where that is over ``HOLE_SHARED`` times ``floor`` (a film
    barely over the floor round a texel barely under it); those beside paint first, then those
    beside the filled ones. (Films of about 0.1 um at a stroke's fringe, a texel or two among
    thicker ones.) A larger unpainted region that paint encloses
    (over ``MAX_HOLE_TEXELS``: the inside of a loop the brush drew) is left as it is. Conserved,
    never negative; ``total`` updated. Returns how many were filled."""
    n_p, ny, nx = new_mobile.shape
    open_ = np.zeros((ny, nx), dtype=np.bool_)
    stack = []
    for y in range(ny):
        for x in range(nx):
            if (y == 0 or x == 0 or y == ny - 1 or x == nx - 1) and total[y, x] <= floor:
                open_[y, x] = True
                stack.append((y, x))
    while len(stack) > 0:
        y, x = stack.pop()
        for dy, dx in ((-1, 0), (1, 0), (0, -1), (0, 1)):
            yy, xx = y + dy, x + dx
            if 0 <= yy < ny and 0 <= xx < nx and not open_[yy, xx] and total[yy, xx] <= floor:
                open_[yy, xx] = True
                stack.append((yy, xx))
    holes = []
    for y in range(1, ny - 1):
        for x in range(1, nx - 1):
            if total[y, x] > floor or open_[y, x]:
                continue
            part = [(y, x)]  # this hole's texels, four-connected
            open_[y, x] = True  # seen
            n = 0
            while n < len(part):
                py, px = part[n]
                n += 1
                for dy, dx in ((-1, 0), (1, 0), (0, -1), (0, 1)):
                    yy, xx = py + dy, px + dx
                    if not open_[yy, xx] and total[yy, xx] <= floor:
                        open_[yy, xx] = True
                        part.append((yy, xx))
            if len(part) <= MAX_HOLE_TEXELS:
                holes.extend(part)
    target = HOLE_FILL * floor
    filled = 0
    progress = True
    while progress:
        progress = False
        for n in range(len(holes)):
            y, x = holes[n]
            t = total[y, x]
            if t > floor:
                continue
            best, by, bx = 0.0, -1, -1
            for dy in range(-1, 2):
                for dx in range(-1, 2):
                    if (dy != 0 or dx != 0) and total[y + dy, x + dx] > best:
                        best, by, bx = total[y + dy, x + dx], y + dy, x + dx
            if by < 0:
                continue
            need = target - t
            if best - need <= target:  # too thin to lift it so far: share evenly
                need = 0.5 * (best - t)
                if t + need <= HOLE_SHARED * floor:
                    continue
            wet = 0.0
            for p in range(n_p):
                wet += new_mobile[p, by, bx]
            if wet < need:
                continue
            for p in range(n_p):
                m = new_mobile[p, by, bx] * (need / wet)
                new_mobile[p, by, bx] -= m
                new_mobile[p, y, x] += m
            total[by, bx] -= need
            total[y, x] += need
            touched[by, bx] = True
            touched[y, x] = True
            filled += 1
            progress = True
    return filled


@kernel
def _ascending(keys):
    """The indices that order ``keys`` (1D) ascending, equal keys by index (a stable order), by
    heapsort: numba's ``np.argsort`` compiles its quicksort's generic parts (about 1 s on a
    first run) for this one use."""
    n = keys.size
    order = np.empty(n, np.int64)
    for i in range(n):
        order[i] = i
    for start in range(n // 2 - 1, -1, -1):
        _sift_down(keys, order, start, n)
    for end in range(n - 1, 0, -1):
        order[0], order[end] = order[end], order[0]
        _sift_down(keys, order, 0, end)
    return order


@inline_kernel
def _before(keys, a, b):
    """Whether index ``a`` comes before ``b``: its key is less, or equal with a lower index."""
    return keys[a] < keys[b] or (keys[a] == keys[b] and a < b)


@inline_kernel
def _sift_down(keys, order, root, end):
    """Heapsort's step: the heap over ``order[:end]`` (each parent after its children in
    :func:`_before`'s order) restored below ``root``."""
    while 2 * root + 1 < end:
        child = 2 * root + 1
        if child + 1 < end and _before(keys, order[child], order[child + 1]):
            child += 1
        if not _before(keys, order[root], order[child]):
            return
        order[root], order[child] = order[child], order[root]
        root = child


@kernel
def gather_fringe_films(new_mobile, touched, total, floor):
    """Take the thinnest films off the paint's edge, in place: a touched texel whose paint
    ``total`` (dry + wet, all pigments) is above 0 but under ``floor``, with an unpainted texel
    beside it (one of its four edge neighbours at 0), gives its wet paint, per pigment, to its
    thickest neighbour of eight, if that one is thicker; thinnest first, each move updating
    ``total``, and again while a pass moved any (an emptied texel puts the next at the edge).
    A column emptied under the grid's film floor while its neighbours' transfer tails still
    reach round it left rings of films of 1e-13 to 1e-9 m round an empty block: holes inside
    the paint. Only a texel beside an unpainted one gives, so an emptied texel joins a region
    already unpainted and opens no new hole. Conserved, never negative. Returns the moves."""
    n_p, ny, nx = new_mobile.shape
    gave = 0
    where = np.empty(ny * nx, np.int64)
    thin = np.empty(ny * nx)
    while True:
        count = 0
        for y in range(ny):
            for x in range(nx):
                if touched[y, x] and 0.0 < total[y, x] < floor:
                    where[count] = y * nx + x
                    thin[count] = total[y, x]
                    count += 1
        if count == 0:
            return gave
        moves = 0
        for n in _ascending(thin[:count]):
            y, x = where[n] // nx, where[n] % nx
            t = total[y, x]
            if not 0.0 < t < floor:
                continue
            edge = (
                (y > 0 and total[y - 1, x] <= 0.0)
                or (y < ny - 1 and total[y + 1, x] <= 0.0)
                or (x > 0 and total[y, x - 1] <= 0.0)
                or (x < nx - 1 and total[y, x + 1] <= 0.0)
            )
            if not edge:
                continue
            best, by, bx = t, -1, -1
            for dy in range(-1, 2):
                for dx in range(-1, 2):
                    yy, xx = y + dy, x + dx
                    if (dy != 0 or dx != 0) and 0 <= yy < ny and 0 <= xx < nx:
                        if total[yy, xx] > best:
                            best, by, bx = total[yy, xx], yy, xx
            if by < 0:
                continue
            moved = 0.0
            for p in range(n_p):
                m = new_mobile[p, y, x]
                new_mobile[p, by, bx] += m
                new_mobile[p, y, x] = 0.0
                moved += m
            if moved <= 0.0:
                continue
            total[by, bx] += moved
            rest = t - moved  # its dry paint, or round-off of nothing
            total[y, x] = rest if rest > 1e-9 * t else 0.0
            touched[by, bx] = True
            moves += 1
        if moves == 0:
            return gave
        gave += moves


@kernel
def store_texels(paint, wetness, x0, y0, new_mobile, touched, max_paint, bounds):
    """Write the touched texels: paint = dry part + ``new_mobile``, wetness = the mobile share
    of the total (0 where the stored float32 paint is 0), as float32; non-finite values become
    0, paint is clamped to [0, ``max_paint``] and wetness to [0, 1]. ``bounds`` (4,) gets the touched texels'
    box (x0, y0, x1, y1) in canvas texels (x1 <= x0 when none). Returns the non-finite count."""
    n_p, ny, nx = new_mobile.shape
    bad = 0
    bx0, by0, bx1, by1 = nx, ny, -1, -1
    dry_share, total, wet = np.empty(nx), np.empty(nx), np.empty(nx)
    stored = np.empty(nx, np.bool_)
    for y in range(ny):
        t_row = touched[y]
        for x in range(nx):
            if t_row[x]:
                bx0, bx1 = min(bx0, x), max(bx1, x)
                by0, by1 = min(by0, y), max(by1, y)
        if by1 < y:
            continue  # no texel of this row is touched
        wet_row = wetness[y0 + y, x0 : x0 + nx]
        for x in range(nx):
            dry_share[x] = 1.0 - _mobile_share(wet_row[x])
            total[x], wet[x], stored[x] = 0.0, 0.0, False
        for p in range(n_p):
            held, new_row = paint[p, y0 + y, x0 : x0 + nx], new_mobile[p, y]
            for x in range(nx):
                v = held[x] * dry_share[x] + new_row[x]
                total[x] += v
                wet[x] += new_row[x]
                f = np.float32(v)
                if not np.isfinite(f):
                    bad += 1 if t_row[x] else 0
                    f = np.float32(0.0)
                f = min(max(f, np.float32(0.0)), np.float32(max_paint))
                if t_row[x]:
                    held[x] = f
                stored[x] = stored[x] or f > 0.0
        for x in range(nx):
            if not t_row[x]:
                continue
            # no wetness where no paint is left once stored (a total below float32's range)
            t = total[x]
            share = np.float32(wet[x] / t) if t > 0.0 and stored[x] else np.float32(0.0)
            if not np.isfinite(share):
                bad += 1
                share = np.float32(0.0)
            wet_row[x] = min(max(share, np.float32(0.0)), np.float32(1.0))
    bounds[0], bounds[1] = x0 + bx0, y0 + by0
    bounds[2], bounds[3] = x0 + bx1 + 1, y0 + by1 + 1
    return bad


@kernel
def _sum(a):
    """Sum of the 1D array ``a`` in eight interleaved partial sums: a single running sum waits
    on each addition's latency (as :func:`solver.linalg.pcg.dot`)."""
    size = a.size
    s0 = s1 = s2 = s3 = s4 = s5 = s6 = s7 = 0.0
    end = size - size % 8
    for m in range(0, end, 8):
        s0 += a[m]
        s1 += a[m + 1]
        s2 += a[m + 2]
        s3 += a[m + 3]
        s4 += a[m + 4]
        s5 += a[m + 5]
        s6 += a[m + 6]
        s7 += a[m + 7]
    for m in range(end, size):
        s0 += a[m]
    return ((s0 + s1) + (s2 + s3)) + ((s4 + s5) + (s6 + s7))


@inline_kernel
def _bilinear(field, x, y):
    """``field`` (ny, nx) at texel coordinates (x, y) (texel centres at whole numbers), linear in
    between and 0 beyond the edge texels' neighbours."""
    ny, nx = field.shape
    i0, j0 = int(np.floor(x)), int(np.floor(y))
    fx, fy = x - i0, y - j0
    v = 0.0
    for dj in range(2):
        j = j0 + dj
        if j < 0 or j >= ny:
            continue
        wy = fy if dj else 1.0 - fy
        for di in range(2):
            i = i0 + di
            if 0 <= i < nx:
                v += wy * (fx if di else 1.0 - fx) * field[j, i]
    return v


@kernel
def _path_samples(dx, dy, samples):
    """The sweep's sample points along the path (dx, dy), ``(k + 1/2) / samples`` of the way:
    each one's whole-texel offsets ``(offs_i, offs_j)`` and its four bilinear weights ``w``
    (samples, 4): lower-left, lower-right, upper-left, upper-right."""
    offs_i = np.empty(samples, np.int64)
    offs_j = np.empty(samples, np.int64)
    w = np.empty((samples, 4))
    for k in range(samples):
        s = (k + 0.5) / samples
        ox, oy = s * dx, s * dy
        i0, j0 = int(np.floor(ox)), int(np.floor(oy))
        fx, fy = ox - i0, oy - j0
        offs_i[k] = i0
        offs_j[k] = j0
        w[k, 0], w[k, 1] = (1 - fx) * (1 - fy), fx * (1 - fy)
        w[k, 2], w[k, 3] = (1 - fx) * fy, fx * fy
    return offs_i, offs_j, w


@inline_kernel
def _gain_loss(w, a0, a1, b0, b1):
    """The bilinear read, with the float32 weights ``w`` (four scalars: scalars, not an array, so
    that the loop calling it stays vectorised), of the gains ``max(c, 0)`` and of the losses
    ``max(-c, 0)`` of the float32 changes ``c`` at four texels (``a0``, ``a1`` on the first row,
    ``b0``, ``b1`` on the next), in float32."""
    w0, w1, w2, w3 = w
    zero = np.float32(0.0)
    g = w0 * max(a0, zero) + w1 * max(a1, zero) + w2 * max(b0, zero) + w3 * max(b1, zero)
    lo = w0 * max(-a0, zero) + w1 * max(-a1, zero) + w2 * max(-b0, zero) + w3 * max(-b1, zero)
    return g, lo


@kernel
def _swept_fields(fields, path, gain_s, loss_s, cap):
    """The step's fields moved back along the path, in one pass over the rows: ``fields`` =
    (change, frac), each (ny, nx) float32 padded with ``pad_y`` rows and ``pad_x`` columns of
    zeros on every side (at least ``|d| + 1``), ``path`` = (pad_x, pad_y, dx, dy, samples). Each
    is read at ``(k + 1/2) / samples`` of the way along (dx, dy) ahead, bilinearly: ``gain_s``
    and ``loss_s`` (ny, nx) float32 get the means of the gains (the positive changes) and of the
    losses (the negative ones, as amounts), ``cap`` (float32) the largest ``frac`` read. Row by
    row, every sample's reads summed into the row in turn (the rows stay in the first-level
    cache), unsigned indices, in float32 (twice the values a vector instruction takes, half the
    memory; float64 throughout took 1.6-1.9 times as long); returns the sum of ``gain_s`` in
    float64, row by row (:func:`_sum`)."""
    change, frac = fields
    pad_x, pad_y, dx, dy, samples = path
    ny, nx = gain_s.shape
    total = 0.0
    offs_i, offs_j, w = _path_samples(dx, dy, samples)
    mean = np.float32(1.0 / samples)
    for y in range(ny):
        g_out, l_out, c_out = gain_s[y], loss_s[y], cap[y]
        for k in range(samples):
            ya = np.uint64(y + pad_y + offs_j[k])
            yb = ya + np.uint64(1)
            ca, cb, fa, fb = change[ya], change[yb], frac[ya], frac[yb]
            w00, w10 = np.float32(w[k, 0]), np.float32(w[k, 1])
            w01, w11 = np.float32(w[k, 2]), np.float32(w[k, 3])
            wk = (w00, w10, w01, w11)
            xo = pad_x + offs_i[k]
            if k == 0:
                for x in range(nx):
                    xa = np.uint64(x + xo)
                    xb = xa + np.uint64(1)
                    g_out[x], l_out[x] = _gain_loss(wk, ca[xa], ca[xb], cb[xa], cb[xb])
                    c_out[x] = w00 * fa[xa] + w10 * fa[xb] + w01 * fb[xa] + w11 * fb[xb]
            else:
                for x in range(nx):
                    xa = np.uint64(x + xo)
                    xb = xa + np.uint64(1)
                    g, lo = _gain_loss(wk, ca[xa], ca[xb], cb[xa], cb[xb])
                    g_out[x] += g
                    l_out[x] += lo
                    c_out[x] = max(
                        c_out[x], w00 * fa[xa] + w10 * fa[xb] + w01 * fb[xa] + w11 * fb[xb]
                    )
        for x in range(nx):
            g_out[x] *= mean
            l_out[x] *= mean
        total += _sum(g_out)
    return total


@kernel
def sweep_change(
    paint, wetness, x0, y0, new_mobile, touched, total, dx, dy, spacing, active, laid_w=None
):
    """Lay a step's change of mobile paint along the path the tip swept, in place.

    The step changed each texel's mobile paint ``m`` to ``new_mobile`` with the tip at its end
    pose; during the step it came from ``(dx, dy)`` texels back. Per pigment, the gains
    ``g = max(new - m, 0)`` are laid as their mean along that path,
    ``g_s(x) = mean over s in (0, 1) of g(x + s d)`` (bilinear, a sample every ``spacing`` texels
    or closer, as :func:`sweep_reads` counts them; every value
    moves whole, so the total is kept when the box reaches ``|d|`` behind the change). The losses
    ``l = max(m - new, 0)`` go the same way, each texel's take capped at ``c = f_max m`` (its own
    paint times the largest *fraction* ``f = l / m`` lost along its path) and scaled, water-filling
    against the caps (:mod:`paintapp.paint.water_filling`), so the total loss is kept: a texel
    never loses more than it holds, nor a larger share than a texel on its path lost. (The mean
    fraction times the texel's paint is not linear in the change and left a step's teeth;
    uncapped amounts emptied texels, leaving holes.) The moved fields are float32 (the canvas's
    precision; each texel's swept change to about 1e-7 of it), their totals float64: the swept
    gains are scaled to the step's gains, so both totals are kept to float64 round-off. A
    pigment whose swept gains miss by more than :data:`SWEPT_ROUND_OFF` of them (the box cut
    short at the canvas's edge), or whose caps cannot take its loss, keeps its unswept change.
    ``touched`` and ``total`` (as :func:`spread_to_texels` fills them) are updated; a pigment
    ``active`` (P,) does not mark is left as it is (it has no change to lay). Returns whether
    anything was swept.

    ``laid_w`` (ny, nx), positive, when given: where the box's texels take gains more or less
    readily (the canvas tooth's gain weights, :meth:`paintapp.paint.tooth.ToothTexture.weights_and_gains`).
    The step's gains hold that pattern at the texels the step laid them on; moved whole along
    the path they would land off it. So the gains are divided by it before they are moved and
    multiplied by it where they land, ``g_s(x) = w(x) mean over s of g(x + s d) / w(x + s d)``,
    then scaled to the step's gains as before."""
    n_p, ny, nx = new_mobile.shape
    samples, pad_x, pad_y = sweep_reads(dx, dy, spacing)
    if samples == 0:
        return False
    padded = (ny + 2 * pad_y, nx + 2 * pad_x)  # zero-padded for :func:`_swept_fields`
    change, frac = np.zeros(padded, np.float32), np.zeros(padded, np.float32)
    gain_row, loss_row = np.empty(nx), np.empty(nx)  # a row's gains and losses, to be summed
    gain_s = np.empty((ny, nx), np.float32)
    loss_s = np.empty((ny, nx), np.float32)
    cap = np.empty((ny, nx), np.float32)  # the largest fraction lost along the path
    ratio_n = np.empty(ny * nx)
    cap_n = np.empty(ny * nx)
    mobile = np.empty((ny, nx))
    share = mobile_shares(wetness, x0, y0, ny, nx)
    done = False
    for p in range(n_p):
        if not active[p]:
            continue
        gained, lost, moved = 0.0, 0.0, 0.0  # moved: the gains as moved (divided by laid_w)
        for y in range(ny):
            row = paint[p, y0 + y, x0 : x0 + nx]
            change_row = change[pad_y + y, pad_x : pad_x + nx]
            frac_row = frac[pad_y + y, pad_x : pad_x + nx]
            share_row, mobile_row, new_row = share[y], mobile[y], new_mobile[p, y]
            for x in range(nx):
                m = row[x] * share_row[x]
                mobile_row[x] = m
                c = new_row[x] - m
                change_row[x] = c
                gain_row[x] = max(c, 0.0)
                loss_row[x] = max(-c, 0.0)
                frac_row[x] = min(-c / m, 1.0) if c < 0.0 and m > 0.0 else 0.0
            gained += _sum(gain_row)
            lost += _sum(loss_row)
            if laid_w is not None:
                w_row = laid_w[y]
                for x in range(nx):
                    if gain_row[x] > 0.0:
                        gain_row[x] /= w_row[x]
                        change_row[x] = gain_row[x]
                moved += _sum(gain_row)
        if gained == 0.0 and lost == 0.0:
            continue
        if laid_w is None:
            moved = gained
        path = (pad_x, pad_y, dx, dy, samples)
        swept = _swept_fields((change, frac), path, gain_s, loss_s, cap)
        if abs(swept - moved) > SWEPT_ROUND_OFF * moved:
            continue  # the box was cut short behind the change (the canvas's edge)
        if laid_w is not None and gained > 0.0:
            swept = 0.0  # the gains as laid: weighed again where they land
            for y in range(ny):
                g_row, w_row = gain_s[y], laid_w[y]
                for x in range(nx):
                    g_row[x] *= w_row[x]
                swept += _sum(g_row)
        spread = gained / swept if gained > 0.0 else 0.0  # the gains' total kept exactly
        n = 0  # the texels that lose paint, gathered for the water-filling's passes
        for y in range(ny):
            c_row, l_row, m_row = cap[y], loss_s[y], mobile[y]
            for x in range(nx):
                c = min(c_row[x], 1.0) * m_row[x]  # a share read in float32 may pass 1
                if l_row[x] > 0.0 and c > 0.0:
                    ratio_n[n], cap_n[n] = l_row[x] / c, c  # the swept loss over the cap
                    n += 1
        # The first pass of the water-filling (scale 1) also finds the largest ratio (when the
        # scaled ratios stay within 1, no texel reaches its cap and the scale is exact) and all
        # that the caps hold (when that is less than the loss, no scale takes it).
        taken, _, top, room = capacity(ratio_n[:n], cap_n[:n])
        if room < lost * (1.0 - 1e-9):
            continue  # the caps meet too little paint: keep the unswept change
        scale = 1.0
        if taken > 0.0 and abs(taken - lost) > 1e-12 * lost:
            scale = lost / taken
            if scale * top > 1.0:  # some texels reach their caps: solve taken(scale) = lost
                scale, taken = water_fill(ratio_n[:n], cap_n[:n], scale, lost)
            else:
                taken = lost
        if lost > 0.0 and abs(taken - lost) > 1e-9 * lost:
            continue  # the caps meet too little paint: keep the unswept change
        for y in range(ny):
            l_row, m_row, g_row, c_row = loss_s[y], mobile[y], gain_s[y], cap[y]
            t_row, new_row = touched[y], new_mobile[p, y]
            for x in range(nx):
                m = m_row[x]
                take = min(scale * l_row[x], min(c_row[x], 1.0) * m)  # min(scale ratio, 1) cap
                new = max(m - take, 0.0) + spread * g_row[x]
                if new != m:
                    t_row[x] = True
                new_row[x] = new
        done = True
    if done:
        texel_totals(paint, (x0, y0, share), new_mobile, total)
    return done


@kernel
def sweep_reads(dx, dy, spacing):
    """``(samples, pad_x, pad_y)`` of a sweep along (``dx``, ``dy``) texels read every
    ``spacing`` texels or closer (at most :data:`MAX_SWEEP_SAMPLES` reads, or more where those
    would lie more than :data:`MAX_READ_GAP` spacings apart), and the columns and
    rows of zeros its fields are padded with on every side (``|d| + 2``); no reads (0, 0, 0)
    for a travel under half a texel, which is not swept."""
    travel = max(abs(dx), abs(dy))
    if travel < 0.5:
        return 0, 0, 0
    most = max(MAX_SWEEP_SAMPLES, int(np.ceil(travel / (MAX_READ_GAP * spacing))))
    samples = min(max(1, int(np.ceil(travel / spacing))), most)
    return samples, int(np.ceil(abs(dx))) + 2, int(np.ceil(abs(dy))) + 2


@kernel
def mobile_shares(wetness, x0, y0, ny, nx):
    """(ny, nx): the mobile share of each texel of the box at (``x0``, ``y0``), its wetness
    read as 1 from :data:`FULLY_WET` up."""
    share = np.empty((ny, nx))
    for y in range(ny):
        for x in range(nx):
            share[y, x] = _mobile_share(wetness[y0 + y, x0 + x])
    return share


@kernel
def texel_totals(paint, box, new_mobile, total):
    """Each texel's new paint, its dry part and ``new_mobile`` (P, ny, nx) summed over the
    pigments, into ``total`` (ny, nx): ``box`` = (x0, y0, share), the box's first texel and its
    texels' mobile shares; pigment by pigment along the rows."""
    x0, y0, share = box
    n_p, ny, nx = new_mobile.shape
    for y in range(ny):
        t_row, share_row = total[y], share[y]
        for x in range(nx):
            t_row[x] = 0.0
        for p in range(n_p):
            held, new_row = paint[p, y0 + y, x0 : x0 + nx], new_mobile[p, y]
            for x in range(nx):
                t_row[x] += held[x] * (1.0 - share_row[x]) + new_row[x]
