"""Chorin projection: solve the pressure Poisson equation and subtract the pressure gradient.

With ``phi = p dt / rho`` the discrete system per fluid cell is
``sum_nb (phi_c - phi_nb) = -h * sum_faces n . u*``, summed over non-solid neighbours; an outflow
side is a zero-pressure ghost cell. Faces between two fluid cells are then corrected by
``-(phi_hi - phi_lo) / h``; solid faces keep their prescribed velocity.
"""

from __future__ import annotations

import numpy as np

from solver.boundary import OUTFLOW
from solver.compiled.jit import kernel
from solver.labels import FLUID, FREE
from solver.linalg.pcg import LinearSolve, SolveReport, StencilSystem, solve


@kernel
def divergence_sum(u, v, w, label, dim, out):
    """Net outward flux per cell, ``sum_faces n . u`` (m/s; divide by h for the divergence)."""
    nx, ny, nz = label.shape
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if label[i, j, k] != FLUID:
                    out[i, j, k] = 0.0
                    continue
                d = u[i + 1, j, k] - u[i, j, k] + v[i, j + 1, k] - v[i, j, k]
                if dim == 3:
                    d += w[i, j, k + 1] - w[i, j, k]
                out[i, j, k] = d


@kernel
def build_pressure_system(label, dim, kinds, diag, offx, offy, offz, active):
    """Assemble the Poisson matrix over fluid cells."""
    nx, ny, nz = label.shape
    shape = (nx, ny, nz)
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                offx[i, j, k] = 0.0
                offy[i, j, k] = 0.0
                offz[i, j, k] = 0.0
                fluid = label[i, j, k] == FLUID
                active[i, j, k] = fluid
                if not fluid:
                    diag[i, j, k] = 0.0
                    continue
                d = 0.0
                for b in range(dim):
                    for s in (-1, 1):
                        ii = i + s * (b == 0)
                        jj = j + s * (b == 1)
                        kk = k + s * (b == 2)
                        idx = ii if b == 0 else (jj if b == 1 else kk)
                        if idx < 0 or idx >= shape[b]:
                            if kinds[b, 0 if s < 0 else 1] == OUTFLOW:
                                d += 1.0
                            continue
                        if label[ii, jj, kk] == FLUID:
                            d += 1.0
                            if s > 0:
                                if b == 0:
                                    offx[i, j, k] = -1.0
                                elif b == 1:
                                    offy[i, j, k] = -1.0
                                else:
                                    offz[i, j, k] = -1.0
                diag[i, j, k] = d


@kernel
def subtract_gradient(q, face_type, axis, phi, h):
    """Correct the free faces of component ``axis`` by ``-(phi_hi - phi_lo) / h``."""
    nx, ny, nz = q.shape
    n_axis = phi.shape[axis]
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if face_type[i, j, k] != FREE:
                    continue
                idx = i if axis == 0 else (j if axis == 1 else k)
                hi = phi[i, j, k] if idx < n_axis else 0.0
                lo = 0.0
                if idx > 0:
                    lo = phi[i - (axis == 0), j - (axis == 1), k - (axis == 2)]
                q[i, j, k] -= (hi - lo) / h


def project(
    comps: list[np.ndarray],
    face_types: list[np.ndarray],
    label: np.ndarray,
    dim: int,
    h: float,
    kinds: np.ndarray,
    phi: np.ndarray,
    tol: float,
    max_iter: int,
    linear_solve: LinearSolve = solve,
) -> SolveReport:
    """Make the velocity divergence-free in place; ``phi`` (= p dt / rho) is warm start and result.
    ``linear_solve`` solves the Poisson system (MIC(0)-PCG unless given)."""
    u, v, w = comps
    system = StencilSystem.empty(label.shape, dim)
    build_pressure_system(
        label, dim, kinds, system.diag, system.off[0], system.off[1], system.off[2], system.active
    )
    flux = np.empty(label.shape)
    divergence_sum(u, v, w, label, dim, flux)
    rhs = -h * flux
    if not np.any(kinds[:dim] == OUTFLOW):
        fluid = system.active
        n = int(fluid.sum())
        if n:
            rhs[fluid] -= rhs[fluid].sum() / n
    phi[~system.active] = 0.0
    report = linear_solve(system, rhs, phi, tol, max_iter)
    for a in range(dim):
        subtract_gradient(comps[a], face_types[a], a, phi, h)
    return report
