"""Implicit viscosity: backward Euler ``(I - nu dt lap) u = u*`` per velocity component.

Unconditionally stable for any ``nu >= 0`` and ``dt``. Tangential no-slip conditions reflect a
ghost value across the wall (``u_ghost = 2 u_wall - u``, paper eq. 15), free-slip and outflow
sides reflect the value itself (zero gradient).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from solver.boundary import INFLOW, WALL
from solver.faces import FREE, INTERIOR, rigid_velocity
from solver.pcg import SolveReport, StencilSystem, solve


@njit(cache=True, nogil=True)
def _surface_velocity(label, rigid, axis, i, j, k, ii, jj, kk, b, s, h):
    """Component ``axis`` of the solid's velocity on the surface between face (i, j, k) and its
    solid neighbour (ii, jj, kk) across axis ``b`` (direction ``s``)."""
    owner = label[
        min(ii, label.shape[0] - 1), min(jj, label.shape[1] - 1), min(kk, label.shape[2] - 1)
    ]
    if owner < 0:
        li, lj, lk = ii - (axis == 0), jj - (axis == 1), kk - (axis == 2)
        if li >= 0 and lj >= 0 and lk >= 0:
            owner = label[li, lj, lk]
    if owner < 0:
        return 0.0
    x = (i + (0.0 if axis == 0 else 0.5) + 0.5 * s * (b == 0)) * h
    y = (j + (0.0 if axis == 1 else 0.5) + 0.5 * s * (b == 1)) * h
    z = (k + (0.0 if axis == 2 else 0.5) + 0.5 * s * (b == 2)) * h
    return rigid_velocity(rigid[0], rigid[1], rigid[2], owner, x, y, z, axis)


@njit(cache=True, nogil=True)
def build_viscosity_system(
    q,
    face_type,
    axis,
    dim,
    coeff,
    kinds,
    side_vel,
    label,
    rigid,
    h,
    diag,
    offx,
    offy,
    offz,
    active,
    rhs,
):
    """Assemble the backward-Euler diffusion system for component ``axis``.

    ``coeff`` is ``nu dt / h^2``. ``q`` holds the advected values at free faces and the prescribed
    values elsewhere; ``rhs`` receives the right-hand side. ``rigid`` stacks the probes' centre,
    velocity and angular velocity (3, n_probes, 3) so that a ghost across a probe's surface
    reflects about the surface velocity at the surface itself.
    """
    nx, ny, nz = q.shape
    shape = (nx, ny, nz)
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                offx[i, j, k] = 0.0
                offy[i, j, k] = 0.0
                offz[i, j, k] = 0.0
                free = face_type[i, j, k] == FREE
                active[i, j, k] = free
                if not free:
                    diag[i, j, k] = 1.0
                    rhs[i, j, k] = 0.0
                    continue
                d = 1.0
                r = q[i, j, k]
                for b in range(dim):
                    for s in (-1, 1):
                        ii = i + s * (b == 0)
                        jj = j + s * (b == 1)
                        kk = k + s * (b == 2)
                        idx = ii if b == 0 else (jj if b == 1 else kk)
                        if idx < 0 or idx >= shape[b]:
                            kind = kinds[b, 0 if s < 0 else 1]
                            if kind == WALL or kind == INFLOW:
                                d += 2.0 * coeff
                                r += 2.0 * coeff * side_vel[b, 0 if s < 0 else 1, axis]
                            continue
                        t = face_type[ii, jj, kk]
                        if t == FREE:
                            d += coeff
                            if s > 0:
                                if b == 0:
                                    offx[i, j, k] = -coeff
                                elif b == 1:
                                    offy[i, j, k] = -coeff
                                else:
                                    offz[i, j, k] = -coeff
                        elif t == INTERIOR and b != axis:
                            d += 2.0 * coeff
                            r += (
                                2.0
                                * coeff
                                * _surface_velocity(
                                    label, rigid, axis, i, j, k, ii, jj, kk, b, s, h
                                )
                            )
                        else:
                            d += coeff
                            r += coeff * q[ii, jj, kk]
                diag[i, j, k] = d
                rhs[i, j, k] = r


def diffuse(
    q: np.ndarray,
    face_type: np.ndarray,
    axis: int,
    dim: int,
    coeff: float,
    kinds: np.ndarray,
    side_vel: np.ndarray,
    label: np.ndarray,
    rigid: np.ndarray,
    h: float,
    tol: float,
    max_iter: int,
) -> SolveReport:
    """Apply implicit viscosity to component ``axis`` in place; returns the solve report."""
    system = StencilSystem.empty(q.shape, dim)
    rhs = np.empty_like(q)
    build_viscosity_system(
        q,
        face_type,
        axis,
        dim,
        coeff,
        kinds,
        side_vel,
        label,
        rigid,
        h,
        system.diag,
        system.off[0],
        system.off[1],
        system.off[2],
        system.active,
        rhs,
    )
    return solve(system, rhs, q, tol, max_iter)
