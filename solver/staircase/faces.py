"""Classifying velocity faces against solids, and the rigid no-slip values (numba kernels).

The cell labels and face kinds it writes are defined in :mod:`solver.labels`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from solver.compiled.jit import inline_kernel, kernel
from solver.compiled.unsigned import U0, U1
from solver.labels import BOUNDARY, FLUID, FREE, INTERIOR, STATIC_SOLID


class RigidMotion(NamedTuple):
    """Per-probe rigid motion, each (n_probes, 3): centre (m, relative to the grid origin),
    velocity (m/s) and angular velocity (rad/s)."""

    centre: np.ndarray
    vel: np.ndarray
    omega: np.ndarray


class Component(NamedTuple):
    """One velocity component: its samples ``q`` (m/s), their face kinds (int8, the same shape)
    and its axis (0, 1, 2)."""

    q: np.ndarray
    face_type: np.ndarray
    axis: int


@inline_kernel
def rigid_velocity(rigid, p, x, y, z, axis):
    """Component ``axis`` of the rigid velocity V + omega x (x - c) of probe ``p`` at (x, y, z)
    (``rigid`` a :class:`RigidMotion`)."""
    centre, vel, omega = rigid.centre, rigid.vel, rigid.omega
    rx = x - centre[p, 0]
    ry = y - centre[p, 1]
    rz = z - centre[p, 2]
    if axis == 0:
        return vel[p, 0] + omega[p, 1] * rz - omega[p, 2] * ry
    if axis == 1:
        return vel[p, 1] + omega[p, 2] * rx - omega[p, 0] * rz
    return vel[p, 2] + omega[p, 0] * ry - omega[p, 1] * rx


@kernel
def classify_faces(label, comp, open_ends, rigid, h, window):
    """Classify the faces of component ``comp`` and set solid faces to the solid's velocity, in
    the faces of ``window`` (clipped to the array; the rest is left as it is).

    Args:
        label: cell labels, shape (nx, ny, nz).
        comp: the :class:`Component`: its ``face_type`` is written, its solid faces' ``q`` set.
        open_ends: (low, high), whether the domain side at that end of the axis is an outflow.
        rigid: the probes' :class:`RigidMotion`.
        h: cell size, metres.
        window: the :class:`~solver.bundles.Window` of faces to classify.
    """
    values, face_type, axis = comp
    open_lo, open_hi = open_ends
    lo, hi = window
    nx, ny, nz = face_type.shape
    n_axis = label.shape[axis]
    di = U1 if axis == 0 else U0
    dj = U1 if axis == 1 else U0
    dk = U1 if axis == 2 else U0
    for i in range(max(lo[0], 0), min(hi[0], nx)):
        ui = np.uint64(i)
        for j in range(max(lo[1], 0), min(hi[1], ny)):
            uj = np.uint64(j)
            for k in range(max(lo[2], 0), min(hi[2], nz)):
                uk = np.uint64(k)
                idx = i if axis == 0 else (j if axis == 1 else k)
                if (  # between two fluid cells (most faces): unsigned, no side tests
                    0 < idx < n_axis
                    and label[ui, uj, uk] == FLUID
                    and label[ui - di, uj - dj, uk - dk] == FLUID
                ):
                    face_type[ui, uj, uk] = FREE
                    continue
                lo_in = idx > 0
                hi_in = idx < n_axis
                lo_lab = FLUID
                hi_lab = FLUID
                if lo_in:
                    lo_lab = label[i - (axis == 0), j - (axis == 1), k - (axis == 2)]
                if hi_in:
                    hi_lab = label[i, j, k]
                lo_solid = lo_in and lo_lab != FLUID
                hi_solid = hi_in and hi_lab != FLUID
                lo_closed = lo_solid or (not lo_in and not open_lo)
                hi_closed = hi_solid or (not hi_in and not open_hi)
                if not lo_solid and not hi_solid:
                    face_type[i, j, k] = BOUNDARY if (lo_closed or hi_closed) else FREE
                    continue
                face_type[i, j, k] = INTERIOR if (lo_closed and hi_closed) else BOUNDARY
                owner = lo_lab if lo_solid else hi_lab
                if lo_solid and hi_solid and lo_lab < 0:
                    owner = hi_lab
                if owner >= 0:
                    x = (i + (0.0 if axis == 0 else 0.5)) * h
                    y = (j + (0.0 if axis == 1 else 0.5)) * h
                    z = (k + (0.0 if axis == 2 else 0.5)) * h
                    values[i, j, k] = rigid_velocity(rigid, owner, x, y, z, axis)
                else:
                    values[i, j, k] = 0.0


@kernel
def label_cells(label, static_label, static_solid, owner_cell, use_owner):
    """Cell labels for a step: ``STATIC_SOLID`` where ``static_solid``, else ``FLUID``, into both
    ``label`` and ``static_label``; then, with ``use_owner``, a fluid cell whose centre a probe
    covers (``owner_cell >= 0``, the cut geometry's) takes that probe's index in ``label``. One
    pass, for the several whole-grid masks it replaces."""
    lab = label.reshape(-1)
    stat = static_label.reshape(-1)
    solid = static_solid.reshape(-1)
    owner = owner_cell.reshape(-1)
    for n in range(lab.size):
        value = STATIC_SOLID if solid[n] else FLUID
        stat[n] = value
        if use_owner and value == FLUID and owner[n] >= 0:
            value = owner[n]
        lab[n] = value


def solid_adjacent_faces(label: np.ndarray, axis: int, shape: tuple[int, ...]) -> np.ndarray:
    """Flat indices of the faces of component ``axis`` (array ``shape``) next to a cell that is
    not fluid: those whose value :func:`classify_faces` sets."""
    solid = label != FLUID
    touch = np.zeros(shape, dtype=bool)
    upper = [slice(None)] * 3
    lower = [slice(None)] * 3
    upper[axis] = slice(0, shape[axis] - 1)  # face i's upper cell is cell i
    lower[axis] = slice(1, shape[axis])  # face i's lower cell is cell i - 1
    touch[tuple(upper)] |= solid
    touch[tuple(lower)] |= solid
    return np.flatnonzero(touch)
