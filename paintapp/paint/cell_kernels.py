"""Numba kernels of the paint grid: filling cells from columns, and brush exchange on cells.

Paint fields are arrays ``q`` of shape (P, nx, ny, nz), one per pigment. In the 3D grid a value is
the volume fraction of a cell that pigment's paint fills (so ``sum_p q <= 1``, the capacity); in
the depth-averaged grid it is the paint thickness in metres (capacity ``max_height_m``). A cell's
paint volume is ``q * unit`` with ``unit`` the cell volume (3D) or the cell area (2D).
"""

from __future__ import annotations

import numpy as np

from solver import FREE, STATIC_SOLID, kernel

FLUID = -1


@kernel
def fill_columns(column_m, h, out):
    """Fill cells bottom-up from column paint (P, nx, ny) metres into fractions (P, nx, ny, nz).

    A column of total height H fills cell k by ``clamp(H / h - k, 0, 1)`` (a fractional top cell),
    shared among the pigments in the column's proportions. Paint above the grid's top is left out.
    """
    n_p, nx, ny, nz = out.shape
    for i in range(nx):
        for j in range(ny):
            total = 0.0
            for p in range(n_p):
                total += column_m[p, i, j]
            for k in range(nz):
                frac = min(max(total / h - k, 0.0), 1.0)
                for p in range(n_p):
                    out[p, i, j, k] = frac * column_m[p, i, j] / total if total > 0.0 else 0.0


@kernel
def sweep_overlap(q, cap, full, unit, swept):
    """Take the paint that overlaps the tip out of every cell into ``swept`` (P,) volumes.

    A cell the tip covers in whole or in part (``cap`` below the full capacity ``full``: its
    fluid share of it, 0 inside the tip) keeps at most ``cap``; of a cell holding more, each
    pigment gives up its share of the excess. Cells the tip does not reach are left alone.
    """
    n_p, nx, ny, nz = q.shape
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if cap[i, j, k] >= full:
                    continue
                total = 0.0
                for p in range(n_p):
                    total += q[p, i, j, k]
                excess = total - cap[i, j, k]
                if excess <= 0.0 or total <= 0.0:
                    continue
                keep = cap[i, j, k] / total if cap[i, j, k] > 0.0 else 0.0
                for p in range(n_p):
                    swept[p] += q[p, i, j, k] * (1.0 - keep) * unit
                    q[p, i, j, k] *= keep


@kernel
def probe_rings(label, max_ring, dist):
    """Graph distance of fluid cells from the probe (6-neighbours through fluid cells).

    ``dist`` gets 0 on probe cells, r in 1..max_ring on fluid cells r steps away, -1 elsewhere.
    A breadth-first search from the probe's cells, which visits only the cells within
    ``max_ring`` of it, not the whole grid per ring."""
    nx, ny, nz = label.shape
    flat_label, flat = label.reshape(-1), dist.reshape(-1)
    queue = np.empty(flat.size, dtype=np.int64)
    tail = 0
    for c in range(flat.size):
        if flat_label[c] >= 0:
            flat[c] = 0
            queue[tail] = c
            tail += 1
        else:
            flat[c] = -1
    sx, sy = ny * nz, nz
    head = 0
    while head < tail:
        c = queue[head]
        head += 1
        r = flat[c] + 1
        if r > max_ring:
            break  # the queue holds its cells in order of distance
        i, rest = divmod(c, sx)
        j, k = divmod(rest, sy)
        for b in range(6):
            if b == 0:
                n, ok = c - sx, i > 0
            elif b == 1:
                n, ok = c + sx, i < nx - 1
            elif b == 2:
                n, ok = c - sy, j > 0
            elif b == 3:
                n, ok = c + sy, j < ny - 1
            elif b == 4:
                n, ok = c - 1, k > 0
            else:
                n, ok = c + 1, k < nz - 1
            if ok and flat[n] == -1 and flat_label[n] == FLUID:
                flat[n] = r
                queue[tail] = n
                tail += 1


@kernel
def _ring_room(q, dist, ring, k_max, cap, weight):
    """Free room (``cap`` less the paint) of ``ring``'s cells up to layer ``k_max``, each
    column's times ``weight[i, j]``."""
    n_p, nx, ny, nz = q.shape
    room = 0.0
    for i in range(nx):
        for j in range(ny):
            if weight[i, j] <= 0.0:
                continue
            for k in range(min(nz, k_max + 1)):
                if dist[i, j, k] != ring:
                    continue
                used = 0.0
                for p in range(n_p):
                    used += q[p, i, j, k]
                room += weight[i, j] * max(cap[i, j, k] - used, 0.0)
    return room


@kernel
def _fill_ring(q, dist, ring, k_max, cap, weight, amount, share):
    """Add ``share * amount[p] * weight * room_cell`` to every cell of ``ring``."""
    n_p, nx, ny, nz = q.shape
    for i in range(nx):
        for j in range(ny):
            if weight[i, j] <= 0.0:
                continue
            for k in range(min(nz, k_max + 1)):
                if dist[i, j, k] != ring:
                    continue
                used = 0.0
                for p in range(n_p):
                    used += q[p, i, j, k]
                room = weight[i, j] * max(cap[i, j, k] - used, 0.0)
                for p in range(n_p):
                    q[p, i, j, k] += share * amount[p] * room


@kernel
def spread_into_rings(q, dist, first, last, k_max, cap, weight, unit, volume):
    """Place paint volumes ``volume`` (P,) in the free room of rings ``first..last``, nearest first.

    Within a ring each cell (with layer index <= ``k_max``) takes a share proportional to its free
    room ``cap - sum_p q`` (``cap`` per cell: its fluid share of the capacity) times its column's
    ``weight[i, j]`` (>= 0, at most 1; a column of
    weight 0 takes nothing), each pigment in the proportions of ``volume``; a ring is filled
    before the next one gets anything. ``volume`` is reduced in place to what did not fit.
    """
    n_p = q.shape[0]
    amount = volume / unit
    for ring in range(first, last + 1):
        total = 0.0
        for p in range(n_p):
            total += amount[p]
        if total <= 0.0:
            break
        room = _ring_room(q, dist, ring, k_max, cap, weight)
        if room <= 0.0:
            continue
        take = min(total, room)
        _fill_ring(q, dist, ring, k_max, cap, weight, amount, take / (total * room))
        for p in range(n_p):
            amount[p] *= 1.0 - take / total
    for p in range(n_p):
        volume[p] = amount[p] * unit


@kernel
def add_to_ring(q, dist, ring, unit, volume):
    """Add volumes ``volume`` (P,) evenly to the cells of ``ring`` (no capacity limit)."""
    n_p, nx, ny, nz = q.shape
    count = 0
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if dist[i, j, k] == ring:
                    count += 1
    if count == 0:
        return False
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if dist[i, j, k] == ring:
                    for p in range(n_p):
                        q[p, i, j, k] += volume[p] / (unit * count)
    return True


@kernel
def paint_face_axis(u, frac, label, fluid_frac, min_fluid, axis, vel, types):
    """The paint's velocity ``vel`` and face types ``types`` on the faces of ``axis`` (see
    :func:`paintapp.paint.trail.paint_faces`): ``u`` times the open fraction ``frac``, where an
    interior face beside a tip cell (label >= 0) is open in full, one beside a static solid
    closed, and an interior face's fraction is divided by its upwind cell's fluid share (1 in a
    tip cell, at least ``min_fluid``; with an empty ``fluid_frac``, no division). ``types``
    comes in filled with ``BOUNDARY``; interior faces that pass paint become ``FREE``."""
    ni, nj, nk = u.shape
    cells = label.shape[axis]
    di = 1 if axis == 0 else 0
    dj = 1 if axis == 1 else 0
    dk = 1 if axis == 2 else 0
    divide = fluid_frac.size > 0
    for i in range(ni):
        for j in range(nj):
            for k in range(nk):
                f = frac[i, j, k]
                m = i if axis == 0 else (j if axis == 1 else k)
                if cells > 1 and 0 < m < cells:
                    a = label[i - di, j - dj, k - dk]
                    b = label[i, j, k]
                    solid = a == STATIC_SOLID or b == STATIC_SOLID
                    if not solid and (a >= 0 or b >= 0):
                        f = 1.0
                    if not solid and f > 0.0:
                        types[i, j, k] = FREE
                    if divide:
                        if u[i, j, k] > 0.0:  # the upwind cell: below the face, or above
                            tip, fluid = a >= 0, fluid_frac[i - di, j - dj, k - dk]
                        else:
                            tip, fluid = b >= 0, fluid_frac[i, j, k]
                        f /= 1.0 if tip else max(fluid, min_fluid)
                vel[i, j, k] = u[i, j, k] * f
