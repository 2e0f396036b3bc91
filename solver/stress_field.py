"""Force and torque on probes with a viscosity that varies from cell to cell (numba kernel).

The same discrete stress-tensor boundary integral as :mod:`solver.stress` (paper eqs. 9-18), with
the dynamic viscosity in each face's traction taken from the fluid cell next to that face. Where a
probe touches a thin fluid (air) the viscous traction is small; where it touches a thick one
(paint) it is large: the force follows the fluid the probe is actually in.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from solver.faces import FLUID, rigid_velocity
from solver.stress import _tangential_derivative


@njit(cache=True, nogil=True)
def _face_traction(comps, pressure, mu, p, gi, gj, gk, b, s, xf, yf, zf, dim, h, rigid, out):
    """Traction (N/m^2) on probe ``p`` at its face across axis ``b`` (direction ``s``) into fluid
    cell (gi, gj, gk) into ``out`` (3,); returns the pressure part's component along ``b``."""
    centre, vel, omega = rigid
    qb = comps[b]
    dndn = (qb[gi + (b == 0), gj + (b == 1), gk + (b == 2)] - qb[gi, gj, gk]) / h
    out[:] = 0.0
    out[b] = 2.0 * mu * dndn * s
    for t in range(dim):
        if t == b:
            continue
        qt = comps[t]
        ut = 0.5 * (qt[gi, gj, gk] + qt[gi + (t == 0), gj + (t == 1), gk + (t == 2)])
        wall = rigid_velocity(centre, vel, omega, p, xf, yf, zf, t)
        out[t] = mu * (2.0 * (ut - wall) / h + s * _tangential_derivative(qb, b, t, gi, gj, gk, h))
    return -pressure[gi, gj, gk] * s


@njit(cache=True, nogil=True)
def stress_integral_field(
    label, u, v, w, pressure, mu_cell, h, dim, rigid, reference, f_pressure, f_viscous, torque
):
    """Accumulate per-probe pressure force, viscous force and torque (arrays (n_probes, 3)).

    Args:
        label: cell labels (probe index >= 0, ``FLUID``, ``STATIC_SOLID``).
        u, v, w: velocity components (m/s); pressure (Pa) at cells.
        mu_cell: dynamic viscosity (Pa s) per cell.
        h: cell size (m); dim: 2 or 3.
        rigid: (centre, velocity, angular velocity), each (n_probes, 3), relative to the origin.
        reference: torque reference points (n_probes, 3), relative to the grid origin.
        f_pressure, f_viscous, torque: outputs (n_probes, 3): N and N m in 3D, per unit depth in 2D.
    """
    nx, ny, nz = label.shape
    shape = (nx, ny, nz)
    area = h ** (dim - 1)
    f_pressure[:] = 0.0
    f_viscous[:] = 0.0
    torque[:] = 0.0
    comps = (u, v, w)
    traction = np.zeros(3)
    force = np.zeros(3)
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                p = label[i, j, k]
                if p < 0:
                    continue
                for b in range(dim):
                    for s in (-1, 1):
                        gi = i + s * (b == 0)
                        gj = j + s * (b == 1)
                        gk = k + s * (b == 2)
                        idx = gi if b == 0 else (gj if b == 1 else gk)
                        if idx < 0 or idx >= shape[b] or label[gi, gj, gk] != FLUID:
                            continue
                        xf = (i + 0.5 + 0.5 * s * (b == 0)) * h
                        yf = (j + 0.5 + 0.5 * s * (b == 1)) * h
                        zf = (k + 0.5 + 0.5 * s * (b == 2)) * h
                        mu = mu_cell[gi, gj, gk]
                        pn = _face_traction(
                            comps,
                            pressure,
                            mu,
                            p,
                            gi,
                            gj,
                            gk,
                            b,
                            s,
                            xf,
                            yf,
                            zf,
                            dim,
                            h,
                            rigid,
                            traction,
                        )
                        f_pressure[p, b] += pn * area
                        for c in range(3):
                            f_viscous[p, c] += traction[c] * area
                            force[c] = traction[c] * area
                        force[b] += pn * area
                        rx = xf - reference[p, 0]
                        ry = yf - reference[p, 1]
                        rz = (zf - reference[p, 2]) if dim == 3 else 0.0
                        torque[p, 0] += ry * force[2] - rz * force[1]
                        torque[p, 1] += rz * force[0] - rx * force[2]
                        torque[p, 2] += rx * force[1] - ry * force[0]
