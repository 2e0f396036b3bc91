"""Force and torque on probes: the discrete stress-tensor boundary integral (paper eqs. 9-18).

For every face between a probe cell and a fluid cell, with outward normal ``n`` (from the probe
into the fluid), the traction is ``P = sigma . n`` with
``sigma = -p I + mu (grad u + grad u^T)``:

* normal part: ``-p n + 2 mu (du_n/dx_n) n``, with ``p`` and ``du_n/dx_n`` taken in the fluid cell
  (paper eq. 16);
* tangential part: ``mu (du_t/dx_n + du_n/dx_t)``, with ``du_t/dx_n`` the one-sided difference
  between the fluid cell's velocity and the probe's surface velocity over ``h/2``, and
  ``du_n/dx_t`` the surface's own (rigid) velocity gradient.

``F = sum P dA`` and ``tau = sum r x P dA`` with ``r`` from the reference point to the face centre.
In 2D ``dA = h`` (per unit depth): N/m and N m/m; in 3D ``dA = h^2``: N and N m. The dynamic
viscosity is a field over the cells: each face's traction takes the viscosity of the fluid cell
next to it, so a probe in thick paint feels more than one in thin air.
"""

from __future__ import annotations

import numpy as np

from solver.compiled.jit import inline_kernel, kernel
from solver.labels import FLUID
from solver.staircase.faces import rigid_velocity


@inline_kernel
def _cell_value(q, b, i, j, k):
    """Cell-centred value of component ``b`` (mean of the cell's two b-faces)."""
    return 0.5 * (q[i, j, k] + q[i + (b == 0), j + (b == 1), k + (b == 2)])


@kernel
def _tangential_derivative(q, b, t, i, j, k, h):
    """d(u_b)/d(x_t) at the centre of cell (i, j, k) by central differences of cell-centred
    values (one-sided at the domain edge). Solid neighbours hold their rigid velocity, so the
    derivative sees the body's motion, and on a staircase it sees the flow turning round the
    steps, which the face-normal difference alone misses."""
    n = (q.shape[0] - (b == 0), q.shape[1] - (b == 1), q.shape[2] - (b == 2))
    idx = i if t == 0 else (j if t == 1 else k)
    lo = idx - 1 if idx > 0 else idx
    hi = idx + 1 if idx + 1 < n[t] else idx
    if hi == lo:
        return 0.0
    vlo = _cell_value(
        q, b, i + (lo - idx) * (t == 0), j + (lo - idx) * (t == 1), k + (lo - idx) * (t == 2)
    )
    vhi = _cell_value(
        q, b, i + (hi - idx) * (t == 0), j + (hi - idx) * (t == 1), k + (hi - idx) * (t == 2)
    )
    return (vhi - vlo) / ((hi - lo) * h)


@kernel
def _face_traction(fields, p, face, point, dim, h, rigid, out):
    """Traction (N/m^2) on probe ``p`` (``rigid`` a :class:`~solver.staircase.faces.RigidMotion`)
    at its face ``face`` (gi, gj, gk, b, s: into fluid cell (gi, gj, gk) across axis ``b``,
    direction ``s``), centred at ``point`` (x, y, z), with that cell's viscosity, into ``out``
    (3,); returns the pressure part's component along ``b``."""
    u, v, w = fields.velocity
    comps = (u, v, w)
    pressure = fields.pressure
    gi, gj, gk, b, s = face
    xf, yf, zf = point
    mu = fields.mu_cell[gi, gj, gk]
    qb = comps[b]
    dndn = (qb[gi + (b == 0), gj + (b == 1), gk + (b == 2)] - qb[gi, gj, gk]) / h
    out[:] = 0.0
    out[b] = 2.0 * mu * dndn * s
    for t in range(dim):
        if t == b:
            continue
        qt = comps[t]
        ut = 0.5 * (qt[gi, gj, gk] + qt[gi + (t == 0), gj + (t == 1), gk + (t == 2)])
        wall = rigid_velocity(rigid, p, xf, yf, zf, t)
        out[t] = mu * (2.0 * (ut - wall) / h + s * _tangential_derivative(qb, b, t, gi, gj, gk, h))
    return -pressure[gi, gj, gk] * s


@kernel
def stress_integral(label, fields, h, dim, rigid, reference, out):
    """Accumulate per-probe pressure force, viscous force and torque.

    Args:
        label: cell labels (probe index >= 0, ``FLUID``, ``STATIC_SOLID``).
        fields: the :class:`~solver.bundles.StressFields` (velocity, pressure, viscosity).
        h: cell size (m); dim: 2 or 3.
        rigid: the probes' :class:`~solver.staircase.faces.RigidMotion`.
        reference: torque reference points (n_probes, 3), relative to the grid origin.
        out: the :class:`~solver.bundles.ForceSums`, (n_probes, 3) each: N and N m in 3D, per
            unit depth in 2D.
    """
    f_pressure, f_viscous, torque = out
    nx, ny, nz = label.shape
    shape = (nx, ny, nz)
    area = h ** (dim - 1)
    f_pressure[:] = 0.0
    f_viscous[:] = 0.0
    torque[:] = 0.0
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
                        face = (gi, gj, gk, b, s)
                        pn = _face_traction(fields, p, face, (xf, yf, zf), dim, h, rigid, traction)
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
