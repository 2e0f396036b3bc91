"""Implicit viscosity: backward Euler ``u - dt / rho * div(mu grad u) = u*`` per velocity component.

Unconditionally stable for any viscosity and time step. The dynamic viscosity ``mu`` is a field
over the cells (uniform for a plain fluid; paint and air in the painting grid): each face sample
carries ``mu_face``, the mean of the two cells it separates (one cell at a domain side), and a
pair of samples is coupled by the mean of their two ``mu_face`` values, so the matrix stays
symmetric (PCG with MIC(0) applies). The ``grad u^T`` part of the stress, which vanishes for
uniform viscosity, is left out (the usual simplification for variable-viscosity stable fluids).

Tangential no-slip conditions reflect a ghost value across the wall (``u_ghost = 2 u_wall - u``,
paper eq. 15) about the wall's own velocity at the wall; free-slip and outflow sides reflect the
value itself (zero gradient).

An optional linear drag toward rest, ``du/dt = -k u`` with a rate ``k`` (1/s) per cell, enters the
same solve implicitly as ``k dt`` on the diagonal: for a depth-averaged thin layer this is the
friction of the no-slip surface beneath it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from solver.boundary import INFLOW, WALL
from solver.bundles import Sides
from solver.compiled.jit import kernel
from solver.labels import FREE, INTERIOR
from solver.linalg.pcg import LinearSolve, SolveReport, StencilSystem, solve
from solver.staircase.faces import Component, RigidMotion, rigid_velocity


class Walls(NamedTuple):
    """The probes as the viscosity solve's walls: the cell labels (a probe's index where it
    covers the cell), the probes' rigid motion and the cell size ``h`` (m)."""

    label: np.ndarray
    rigid: RigidMotion
    h: float


class Diffusion(NamedTuple):
    """One component's diffusion coefficients: the viscosity at its samples (Pa s), ``scale`` =
    ``dt / (rho h^2)`` (a pair's coefficient is ``scale * mu_pair``) and the linear drag's
    ``k dt`` at its samples."""

    mu_face: np.ndarray
    scale: float
    drag_face: np.ndarray


class DiffusionArrays(NamedTuple):
    """What a component's assembly fills, each of the component's shape: the diagonal, the
    couplings to the next sample along x, y and z, the unknowns' mask and the right-hand side."""

    diag: np.ndarray
    offx: np.ndarray
    offy: np.ndarray
    offz: np.ndarray
    active: np.ndarray
    rhs: np.ndarray

    @classmethod
    def of(cls, system: StencilSystem, rhs: np.ndarray) -> DiffusionArrays:
        """The arrays of ``system`` and ``rhs``."""
        return cls(system.diag, system.off[0], system.off[1], system.off[2], system.active, rhs)


@dataclass(frozen=True)
class ViscousStep:
    """What one step's viscosity solves share across the components.

    Attributes:
        dim: 2 or 3.
        mu_cell: dynamic viscosity per cell (Pa s, cells' shape).
        dt_s: the time step, s.
        density_kg_m3: the fluid's density.
        sides: the domain's sides (kinds and velocities).
        drag_cell: the linear drag rate per cell (1/s, cells' shape), or None for none.
    """

    dim: int
    mu_cell: np.ndarray
    dt_s: float
    density_kg_m3: float
    sides: Sides
    drag_cell: np.ndarray | None = None


@kernel
def _surface_velocity(walls, axis, face, nb, b, s):
    """Component ``axis`` of the solid's velocity on the surface between face ``face`` (i, j, k)
    and its solid neighbour ``nb`` (ii, jj, kk) across axis ``b`` (direction ``s``)."""
    label, rigid, h = walls.label, walls.rigid, walls.h
    i, j, k = face
    ii, jj, kk = nb
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
    return rigid_velocity(rigid, owner, x, y, z, axis)


@kernel
def face_viscosity(mu_cell, axis, out):
    """Viscosity at the faces normal to ``axis``: mean of the two cells (edge faces: one cell).
    A 2D grid's single layer is no innermost loop."""
    nx, ny, nz = out.shape
    n_axis = mu_cell.shape[axis]
    if nz == 1 and axis != 2:  # 2D: no loop over a single layer
        for i in range(nx):
            for j in range(ny):
                idx = i if axis == 0 else j
                lo = idx - 1 if idx > 0 else idx
                hi = idx if idx < n_axis else n_axis - 1
                if axis == 0:
                    out[i, j, 0] = 0.5 * (mu_cell[lo, j, 0] + mu_cell[hi, j, 0])
                else:
                    out[i, j, 0] = 0.5 * (mu_cell[i, lo, 0] + mu_cell[i, hi, 0])
        return
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                idx = i if axis == 0 else (j if axis == 1 else k)
                lo = idx - 1 if idx > 0 else idx
                hi = idx if idx < n_axis else n_axis - 1
                if axis == 0:
                    out[i, j, k] = 0.5 * (mu_cell[lo, j, k] + mu_cell[hi, j, k])
                elif axis == 1:
                    out[i, j, k] = 0.5 * (mu_cell[i, lo, k] + mu_cell[i, hi, k])
                else:
                    out[i, j, k] = 0.5 * (mu_cell[i, j, lo] + mu_cell[i, j, hi])


@kernel
def build_variable_system(comp, dim, coeffs, sides, walls, out):
    """Assemble the diffusion system of component ``comp`` (:class:`Diffusion` ``coeffs``, the
    domain's ``sides``, the probes as ``walls``) into ``out`` (:class:`DiffusionArrays`)."""
    q, face_type, axis = comp
    mu_face, scale, drag_face = coeffs
    kinds, side_vel = sides
    diag, offx, offy, offz, active, rhs = out
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
                own = scale * mu_face[i, j, k]
                d = 1.0 + drag_face[i, j, k]
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
                                d += 2.0 * own
                                r += 2.0 * own * side_vel[b, 0 if s < 0 else 1, axis]
                            continue
                        c = 0.5 * (own + scale * mu_face[ii, jj, kk])
                        t = face_type[ii, jj, kk]
                        if t == FREE:
                            d += c
                            if s > 0:
                                if b == 0:
                                    offx[i, j, k] = -c
                                elif b == 1:
                                    offy[i, j, k] = -c
                                else:
                                    offz[i, j, k] = -c
                        elif t == INTERIOR and b != axis:
                            wall = _surface_velocity(walls, axis, (i, j, k), (ii, jj, kk), b, s)
                            d += 2.0 * own
                            r += 2.0 * own * wall
                        else:
                            d += c
                            r += c * q[ii, jj, kk]
                diag[i, j, k] = d
                rhs[i, j, k] = r


def diffuse(
    comp: Component,
    step: ViscousStep,
    walls: Walls,
    tol: float,
    max_iter: int,
    linear_solve: LinearSolve = solve,
) -> SolveReport:
    """Apply implicit viscosity to component ``comp`` in place, with the ``step``'s viscosity
    and drag, the probes as ``walls``; ``linear_solve`` to ``tol`` in ``max_iter`` iterations."""
    q, axis = comp.q, comp.axis
    dim, mu_cell, dt_s, drag_cell = step.dim, step.mu_cell, step.dt_s, step.drag_cell
    h = walls.h
    mu_face = np.empty_like(q)
    face_viscosity(mu_cell, axis, mu_face)
    drag_face = np.zeros_like(q)
    if drag_cell is not None:
        face_viscosity(drag_cell, axis, drag_face)
        drag_face *= dt_s
    system = StencilSystem.empty(q.shape, dim)
    rhs = np.empty_like(q)
    scale = dt_s / (step.density_kg_m3 * h * h)
    coeffs = Diffusion(mu_face, scale, drag_face)
    build_variable_system(comp, dim, coeffs, step.sides, walls, DiffusionArrays.of(system, rhs))
    return linear_solve(system, rhs, q, tol, max_iter)
