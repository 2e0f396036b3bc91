"""Force and torque on a probe from a momentum balance over a control volume around it.

The staircase boundary makes the surface stress integral (:mod:`solver.staircase.stress`) biased
and noisy (the paper's Figs. 4-5): its shear is taken on faces that do not follow the true
surface. The momentum balance over a box of fluid around the probe,

    F = sum_box_faces (sigma . n - rho u (u . n)) dA - d/dt sum_fluid_in_box rho u dV,

moves the evaluation a few cells away from the body, where the flow is smooth (a closer drag
than the staircase integral's on Schaefer-Turek 2D-1). The torque is the same balance of angular
momentum about the reference point. The box must lie inside the domain and enclose the probe
with a margin; otherwise the caller falls back to the surface integral.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from solver.bundles import Window
from solver.compiled.jit import inline_kernel, kernel
from solver.labels import FLUID


class ControlVolume(NamedTuple):
    """The box a momentum balance is taken over: its cells (a :class:`~solver.bundles.Window`),
    the grid's dimension (2 or 3) and cell size ``h`` (m), the fluid's density ``rho`` (kg/m^3)
    and the torque reference ``ref`` (3,), relative to the grid origin."""

    window: Window
    dim: int
    h: float
    rho: float
    ref: np.ndarray


@inline_kernel
def _cc(q, a, i, j, k):
    """Cell-centred value of component ``a`` at cell (i, j, k)."""
    return 0.5 * (q[i, j, k] + q[i + (a == 0), j + (a == 1), k + (a == 2)])


@kernel
def box_surface_flux(fields, label, cv, out):
    """Sum of ``(sigma . n - rho u (u . n)) dA`` over the faces of the :class:`ControlVolume`
    ``cv``.

    ``fields``: the :class:`~solver.bundles.StressFields` (velocity, pressure, the dynamic
    viscosity per cell). ``out`` receives (force(3), torque(3)) about the reference point.
    Faces next to a solid cell make the box invalid: returns False.
    """
    lo, hi = cv.window
    dim, h = cv.dim, cv.h
    area = h ** (dim - 1)
    out[:] = 0.0
    for b in range(dim):
        for side in range(2):
            s = -1.0 if side == 0 else 1.0
            plane = lo[b] if side == 0 else hi[b]
            a1 = (b + 1) % 3
            a2 = (b + 2) % 3
            n1 = hi[a1] - lo[a1] if a1 < dim else 1
            n2 = hi[a2] - lo[a2] if a2 < dim else 1
            for c1 in range(n1):
                for c2 in range(n2):
                    idx = [0, 0, 0]
                    idx[b] = plane
                    idx[a1] = (lo[a1] + c1) if a1 < dim else 0
                    idx[a2] = (lo[a2] + c2) if a2 < dim else 0
                    fi, fj, fk = idx[0], idx[1], idx[2]
                    li, lj, lk = fi - (b == 0), fj - (b == 1), fk - (b == 2)
                    if label[li, lj, lk] != FLUID or label[fi, fj, fk] != FLUID:
                        return False
                    if not _face_flux(fields, cv, b, s, (fi, fj, fk), (li, lj, lk), area, out):
                        return False
    return True


@kernel
def _face_flux(fields, cv, b, s, face, lower, area, out):
    """Add the face ``face`` (fi, fj, fk) of axis ``b`` between cells ``lower`` and ``face``
    (direction ``s`` out of the box ``cv``, area ``area``) to ``out``."""
    dim, h, rho, ref = cv.dim, cv.h, cv.rho, cv.ref
    u, v, w = fields.velocity
    comps = (u, v, w)
    pressure, mu_cell = fields.pressure, fields.mu_cell
    fi, fj, fk = face
    li, lj, lk = lower
    qb = comps[b]
    ub = qb[fi, fj, fk]
    p = 0.5 * (pressure[li, lj, lk] + pressure[fi, fj, fk])
    mu = 0.5 * (mu_cell[li, lj, lk] + mu_cell[fi, fj, fk])
    div_lo = (qb[li + (b == 0), lj + (b == 1), lk + (b == 2)] - qb[li, lj, lk]) / h
    div_hi = (qb[fi + (b == 0), fj + (b == 1), fk + (b == 2)] - ub) / h
    contrib = np.zeros(3)
    for i in range(dim):
        if i == b:
            sigma = -p + mu * (div_lo + div_hi)
            ui = ub
        else:
            qi = comps[i]
            c_lo = _cc(qi, i, li, lj, lk)
            c_hi = _cc(qi, i, fi, fj, fk)
            ui = 0.5 * (c_lo + c_hi)
            idx = (fi, fj, fk)
            n_i = qb.shape[i]
            up = min(idx[i] + 1, n_i - 1)
            dn = max(idx[i] - 1, 0)
            q_up = qb[up if i == 0 else fi, up if i == 1 else fj, up if i == 2 else fk]
            q_dn = qb[dn if i == 0 else fi, dn if i == 1 else fj, dn if i == 2 else fk]
            dub_dxi = (q_up - q_dn) / ((up - dn) * h) if up > dn else 0.0
            sigma = mu * ((c_hi - c_lo) / h + dub_dxi)
        contrib[i] = (sigma * s - rho * ui * ub * s) * area
    x = (fi + (0.0 if b == 0 else 0.5)) * h - ref[0]
    y = (fj + (0.0 if b == 1 else 0.5)) * h - ref[1]
    z = ((fk + (0.0 if b == 2 else 0.5)) * h - ref[2]) if dim == 3 else 0.0
    out[0] += contrib[0]
    out[1] += contrib[1]
    out[2] += contrib[2]
    out[3] += y * contrib[2] - z * contrib[1]
    out[4] += z * contrib[0] - x * contrib[2]
    out[5] += x * contrib[1] - y * contrib[0]
    return True


@kernel
def box_momentum(velocity, label, cv, out):
    """Linear (3) and angular (3, about the reference point) momentum of the fluid cells of the
    :class:`ControlVolume` ``cv`` (``velocity`` a :class:`~solver.bundles.Velocity`)."""
    u, v, w = velocity
    lo, hi = cv.window
    dim, h, rho, ref = cv.dim, cv.h, cv.rho, cv.ref
    out[:] = 0.0
    vol = h**dim
    for i in range(lo[0], hi[0]):
        for j in range(lo[1], hi[1]):
            for k in range(lo[2], hi[2]):
                if label[i, j, k] != FLUID:
                    continue
                m = rho * vol
                px = m * _cc(u, 0, i, j, k)
                py = m * _cc(v, 1, i, j, k)
                pz = m * _cc(w, 2, i, j, k) if dim == 3 else 0.0
                x = (i + 0.5) * h - ref[0]
                y = (j + 0.5) * h - ref[1]
                z = ((k + 0.5) * h - ref[2]) if dim == 3 else 0.0
                out[0] += px
                out[1] += py
                out[2] += pz
                out[3] += y * pz - z * py
                out[4] += z * px - x * pz
                out[5] += x * py - y * px


def probe_box(
    mask_window: tuple[slice, ...],
    mask: np.ndarray,
    cells: tuple[int, int, int],
    dim: int,
    margin: int,
) -> tuple[np.ndarray, np.ndarray] | None:
    """The cell box [lo, hi) enclosing a probe's solid cells with ``margin`` cells of fluid,
    or None when it would not fit strictly inside the domain."""
    if not mask.any():
        return None
    lo = np.zeros(3, dtype=np.int64)
    hi = np.array(cells, dtype=np.int64)
    for a in range(dim):
        other = tuple(x for x in range(3) if x != a)
        occupied = np.flatnonzero(mask.any(axis=other))
        lo[a] = mask_window[a].start + occupied[0] - margin
        hi[a] = mask_window[a].start + occupied[-1] + 1 + margin
        if lo[a] < 1 or hi[a] > cells[a] - 1:
            return None
    return lo, hi
