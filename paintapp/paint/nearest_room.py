"""Pushed paint laid in the free room nearest the tip's surface, by distance, not by rings.

The brush exchange pushes the paint the tip overlaps (and the trail's overflow) aside into free
room round the tip, nearest first: that builds the ridges along a stroke. Counted in rings of
cells (:func:`paintapp.paint.cell_kernels.probe_rings`), "nearest" jumps by a whole cell whenever one
of the tip's faces passes a cell centre, and a tip drifting sideways prints that beat as lumps.

Here the distance is the tip's signed distance at each cell centre, in cells (the cut-cell
geometry's, continuous as the tip moves), and the room fills like water rising from the tip's
surface: a cell at distance ``d`` takes its free room times ``clip((L - d) / w, 0, 1)``, the level
``L`` set so that the cells take all the paint (or all their room), ``w`` (:data:`FILL_WIDTH`) the
width of the rising edge. What a cell takes is continuous in the distances, so the pushed paint
follows the tip's faces smoothly. Cells the tip covers in part (``d <= 0``, room left by the cut)
fill first; a cell of unknown distance (beyond the cut geometry's window) takes nothing here, and
the rings place what is left (:func:`paintapp.paint.exchange.place_pushed`).
"""

from __future__ import annotations

import numpy as np

from solver import kernel

#: Width (cells) of the rising edge: the cells between ``L - FILL_WIDTH`` and ``L`` fill in part.
FILL_WIDTH = 1.0
#: The level's bisection stops when its bracket is this narrow (cells), or after
#: :data:`MAX_BISECTIONS` halvings; the last scaling makes the volume exact either way.
LEVEL_TOLERANCE = 1e-9
MAX_BISECTIONS = 64
#: Distances at or above this (cells) are unknown (the cut geometry's far value, over h).
UNKNOWN_DISTANCE = 1e20


def tip_distance(phi_cell: np.ndarray, cell_size_m: float) -> np.ndarray:
    """The tip's signed distance at the cell centres in cells (negative inside), NaN where the
    cut geometry did not compute it (its far value outside the windows round the tips)."""
    d = phi_cell / cell_size_m
    return np.where(d < UNKNOWN_DISTANCE, d, np.nan)


@kernel
def _taken(room, dist, n, level, width):
    """``sum room * clip((level - dist) / width, 0, 1)`` over the first ``n`` candidates."""
    s = 0.0
    for m in range(n):
        s += room[m] * min(max((level - dist[m]) / width, 0.0), 1.0)
    return s


@kernel
def fill_nearest(q, distance, cap, weight, k_max, unit, volume, width):
    """Place paint volumes ``volume`` (P,) m^3 in fields ``q`` (P, nx, ny, nz, cell values in
    units of ``unit`` m^3) by distance from the tip (module docstring): the cells with a known
    ``distance`` (cells; NaN: unknown) up to layer ``k_max``, each with its free room
    ``cap - sum_p q`` times its column's ``weight[i, j]`` (0..1), each pigment in the
    proportions of ``volume``. ``volume`` is reduced in place to what found no room. A cell
    never takes more than its room; nothing goes negative; the volume placed is the volume
    taken from ``volume`` to round-off."""
    n_p, nx, ny, nz = q.shape
    amount = volume / unit
    total = 0.0
    for p in range(n_p):
        total += amount[p]
    if total <= 0.0:
        return
    size = nx * ny * min(nz, k_max + 1)
    room = np.empty(size)
    dist = np.empty(size)
    where = np.empty((size, 3), np.int64)
    n = 0
    lo, hi = np.inf, -np.inf
    for i in range(nx):
        for j in range(ny):
            w = weight[i, j]
            if not w > 0.0:
                continue
            for k in range(min(nz, k_max + 1)):
                d = distance[i, j, k]
                if not np.isfinite(d):
                    continue
                used = 0.0
                for p in range(n_p):
                    used += q[p, i, j, k]
                r = w * (cap[i, j, k] - used)
                if not r > 0.0:
                    continue
                room[n], dist[n] = r, d
                where[n, 0], where[n, 1], where[n, 2] = i, j, k
                n += 1
                lo, hi = min(lo, d), max(hi, d)
    if n == 0:
        return
    hi += width
    everything = _taken(room, dist, n, hi, width)
    take = min(total, (1.0 - 1e-12) * everything)
    for _ in range(MAX_BISECTIONS):  # the level at which the cells take ``take`` (increasing)
        if hi - lo <= LEVEL_TOLERANCE:
            break
        mid = 0.5 * (lo + hi)
        if _taken(room, dist, n, mid, width) < take:
            lo = mid
        else:
            hi = mid
    taken = _taken(room, dist, n, hi, width)  # at least ``take``: each cell within its room
    if not taken > 0.0:
        return
    scale = take / taken
    for m in range(n):
        f = scale * room[m] * min(max((hi - dist[m]) / width, 0.0), 1.0)
        if f <= 0.0:
            continue
        i, j, k = where[m, 0], where[m, 1], where[m, 2]
        for p in range(n_p):
            q[p, i, j, k] += f * (amount[p] / total)
    for p in range(n_p):
        volume[p] = amount[p] * (1.0 - take / total) * unit
