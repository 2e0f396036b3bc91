"""Force and torque on probes from their cut surface (the default ``stress`` model).

Inside each cut cell the probe's surface patch has the area vector (solid outward normal)

    S_c = h^(d-1) * sum_b e_b (w_hi,b - w_lo,b)

from the open fractions of the cell's faces (the divergence theorem over the cell's fluid part),
so the force is the variational projection's own: pressure ``-p_c S_c`` with the cell's pressure,
plus the viscous traction ``mu d(u - u_rigid)/dn |S_c|`` at the surface, the normal derivative of
the velocity relative to the body taken one-sided and second-order from velocities interpolated at
``delta`` and ``2 delta`` along the normal from the surface point (the cell centre moved onto the
zero level of the SDF). Torque: ``(x_s - r_ref) x dF``. Everything varies continuously as a probe
moves, so the force has no grid-crossing spikes. 2D: N/m and N m/m; 3D: N and N m.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from solver.compiled.jit import kernel
from solver.interp import sample, velocity_at
from solver.staircase.faces import rigid_velocity

PROBE_DISTANCE_CELLS = 1.5
PRESSURE_EXTRAPOLATION = 1.0


class SurfacePatches(NamedTuple):
    """What the cut cells' surface patches are formed from (the arrays of
    :class:`~solver.cutcell.geometry.CutGeometry` of those names): the open fraction of every
    face, per component, and the probes' signed distance (m) and nearest probe at the nodes."""

    open_frac: tuple[np.ndarray, ...]
    phi_node: np.ndarray
    owner_node: np.ndarray


@kernel
def _relative_velocity(velocity, dim, point, h, rigid, p, out):
    """Velocity relative to probe ``p``'s rigid motion at ``point`` (x, y, z) into ``out`` (3,)."""
    u, v, w = velocity
    x, y, z = point
    vx, vy, vz = velocity_at(u, v, w, dim, x, y, z, h)
    out[0] = vx - rigid_velocity(rigid, p, x, y, z, 0)
    out[1] = vy - rigid_velocity(rigid, p, x, y, z, 1)
    out[2] = (vz - rigid_velocity(rigid, p, x, y, z, 2)) if dim == 3 else 0.0


@kernel
def _cell_sdf(phi_node, owner_node, dim, i, j, k):
    """Mean SDF of the cell's corners and the owner of its deepest corner."""
    total = 0.0
    best = np.inf
    owner = -1
    nk = 2 if dim == 3 else 1
    for a in range(2):
        for b in range(2):
            for c in range(nk):
                val = phi_node[i + a, j + b, k + c]
                total += val
                if val < best:
                    best = val
                    owner = owner_node[i + a, j + b, k + c]
    return total / (4 * nk), owner


@kernel
def cut_surface_force(patches, window, fields, h, dim, rigid, reference, out):
    """Accumulate per-probe pressure force, viscous force and torque over the cut cells of
    ``window`` (:class:`SurfacePatches` ``patches``, :class:`~solver.bundles.StressFields`
    ``fields``, the probes' :class:`~solver.staircase.faces.RigidMotion`, torque ``reference``
    points (n_probes, 3)) into ``out`` (:class:`~solver.bundles.ForceSums`)."""
    wx, wy, wz = patches.open_frac
    phi_node, owner_node = patches.phi_node, patches.owner_node
    lo, hi = window
    velocity, pressure, mu_cell = fields
    f_pressure, f_viscous, torque = out
    area = h ** (dim - 1)
    nx, ny, nz = pressure.shape
    delta = PROBE_DISTANCE_CELLS * h
    near = np.zeros(3)
    far = np.zeros(3)
    for i in range(lo[0], hi[0]):
        for j in range(lo[1], hi[1]):
            for k in range(lo[2], hi[2]):
                sx = area * (wx[i + 1, j, k] - wx[i, j, k])
                sy = area * (wy[i, j + 1, k] - wy[i, j, k])
                sz = area * (wz[i, j, k + 1] - wz[i, j, k]) if dim == 3 else 0.0
                mag = np.sqrt(sx * sx + sy * sy + sz * sz)
                if mag <= 0.0:
                    continue
                phi_c, p = _cell_sdf(phi_node, owner_node, dim, i, j, k)
                if p < 0:
                    continue
                n0, n1, n2 = sx / mag, sy / mag, sz / mag
                xs = (i + 0.5) * h - phi_c * n0
                ys = (j + 0.5) * h - phi_c * n1
                zs = ((k + 0.5) * h - phi_c * n2) if dim == 3 else 0.5 * h
                near_point = (xs + delta * n0, ys + delta * n1, zs + delta * n2)
                _relative_velocity(velocity, dim, near_point, h, rigid, p, near)
                far_point = (xs + 2 * delta * n0, ys + 2 * delta * n1, zs + 2 * delta * n2)
                _relative_velocity(velocity, dim, far_point, h, rigid, p, far)
                ci = min(max(int((xs + delta * n0) / h), 0), nx - 1)
                cj = min(max(int((ys + delta * n1) / h), 0), ny - 1)
                ck = min(max(int((zs + delta * n2) / h), 0), nz - 1)
                mu = mu_cell[ci, cj, ck]
                p1 = sample(pressure, -1, xs + delta * n0, ys + delta * n1, zs + delta * n2, h)
                p2 = sample(
                    pressure, -1, xs + 2 * delta * n0, ys + 2 * delta * n1, zs + 2 * delta * n2, h
                )
                pc = p1 + PRESSURE_EXTRAPOLATION * (p1 - p2)
                dfp = (-pc * sx, -pc * sy, -pc * sz)
                scale = mu * mag / (2.0 * delta)
                dfv = (
                    scale * (4.0 * near[0] - far[0]),
                    scale * (4.0 * near[1] - far[1]),
                    scale * (4.0 * near[2] - far[2]),
                )
                rx = xs - reference[p, 0]
                ry = ys - reference[p, 1]
                rz = (zs - reference[p, 2]) if dim == 3 else 0.0
                f0 = dfp[0] + dfv[0]
                f1 = dfp[1] + dfv[1]
                f2 = dfp[2] + dfv[2]
                for c in range(3):
                    f_pressure[p, c] += dfp[c]
                    f_viscous[p, c] += dfv[c]
                torque[p, 0] += ry * f2 - rz * f1
                torque[p, 1] += rz * f0 - rx * f2
                torque[p, 2] += rx * f1 - ry * f0
