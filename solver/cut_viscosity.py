"""Implicit viscosity with no-slip at the probes' true surfaces (cut-cell geometry).

The same backward Euler system as :mod:`solver.viscosity` (per component, the per-cell dynamic
viscosity field, the optional linear drag, symmetric and positive definite), except that a velocity
sample whose neighbour along an axis lies inside a probe is coupled to the probe's surface
itself: the surface sits at the fraction ``theta = phi_f / (phi_f - phi_nb)`` of the way (from the
two samples' signed distances), and the linear ghost value through the surface's rigid velocity
``u_ghost = u + (u_wall - u) / theta`` (Gibou et al. 2002) adds ``c / theta`` to the diagonal and
``c u_wall / theta`` to the right-hand side. The matrix stays an M-matrix: unconditionally stable.
``theta`` is clamped below at ``MIN_THETA``: a sample closer to the surface than that is coupled as
if it stood that far, which keeps the coupling from jumping as the surface sweeps across the sample.
Samples inside a probe are relaxed towards its rigid velocity with their depth (see
:func:`mark_probe_samples`); those of fully closed faces hold it.

Both constants were chosen by measurement (``benchmarks/bench_boundary.py``, a towed disk at D/h
5.8, 7.7 and 12.8 and circular Couette at 64²): with ``MIN_THETA`` 0.1 and samples inside keeping
their advected value, the towed disk's drag noise was 2.2 / 3.5 / 2.0 % (HF RMS of the mean drag);
with 0.25 and the relaxation over half a cell it is 1.7 / 2.9 / 1.0 %. A larger clamp smooths the
force further (0.5: 0.43 % at D/h 12.8) but shifts the no-slip surface: the Couette torque error
goes from +0.6 % (0.25) to +2.4 % (0.35) and +6.3 % (0.5).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from solver.boundary import INFLOW, WALL
from solver.faces import BOUNDARY, FREE, INTERIOR, rigid_velocity
from solver.layers import layer_count
from solver.pcg import LinearSolve, SolveReport, StencilSystem, solve
from solver.unsigned import U1
from solver.viscosity import _surface_velocity, face_viscosity

MIN_THETA = 0.25
INSIDE_RELAX_CELLS = 0.5


@njit(cache=True, nogil=True)
def mark_probe_samples(face_type, q, phi, owner, open_frac, axis, lo, hi, rigid, h, relax):
    """Samples of component ``axis`` inside a probe (``phi <= 0``) in the window are left out of
    the viscosity solve (``BOUNDARY``); those of fully closed faces take the owning probe's rigid
    velocity. Those of partly open faces keep their (advected) value where they have just been
    crossed and are pulled towards the rigid velocity with depth, reaching it
    ``INSIDE_RELAX_CELLS`` deep: a sample's value never jumps as the surface sweeps across it, and
    a sample deep inside does not carry the pressure corrections of many steps. The relaxation is
    once per step (``relax``); a grid shift re-marks the samples without it."""
    for i in range(lo[0], hi[0]):
        for j in range(lo[1], hi[1]):
            for k in range(lo[2], hi[2]):
                o = owner[i, j, k]
                if phi[i, j, k] > 0.0 or o < 0:
                    continue
                if face_type[i, j, k] == FREE:
                    face_type[i, j, k] = BOUNDARY
                x = (i + (0.0 if axis == 0 else 0.5)) * h
                y = (j + (0.0 if axis == 1 else 0.5)) * h
                z = (k + (0.0 if axis == 2 else 0.5)) * h
                us = rigid_velocity(rigid[0], rigid[1], rigid[2], o, x, y, z, axis)
                keep = 0.0
                if open_frac[i, j, k] > 0.0:
                    if not relax:
                        continue
                    keep = max(1.0 + phi[i, j, k] / (INSIDE_RELAX_CELLS * h), 0.0)
                q[i, j, k] = us + (q[i, j, k] - us) * keep


@njit(cache=True, nogil=True)
def _cut_coupling(phi, owner, rigid, axis, i, j, k, ii, jj, kk, b, s, h):
    """(1 / theta, wall velocity) for the sample (i, j, k) whose neighbour (ii, jj, kk) along
    ``b`` (direction ``s``) lies inside a probe."""
    pf, pn = phi[i, j, k], phi[ii, jj, kk]
    theta = pf / (pf - pn) if pf - pn > 0.0 else 1.0
    theta = max(theta, MIN_THETA)
    x = (i + (0.0 if axis == 0 else 0.5) + s * theta * (b == 0)) * h
    y = (j + (0.0 if axis == 1 else 0.5) + s * theta * (b == 1)) * h
    z = (k + (0.0 if axis == 2 else 0.5) + s * theta * (b == 2)) * h
    wall = rigid_velocity(rigid[0], rigid[1], rigid[2], owner[ii, jj, kk], x, y, z, axis)
    return 1.0 / theta, wall


@njit(cache=True, nogil=True)
def build_cut_system(
    q, face_type, axis, dim, mu_face, scale, drag_face, kinds, side_vel, label, rigid, h, phi,
    owner, sys_out, rhs, layers,
):  # fmt: skip
    """Assemble the diffusion system of component ``axis`` (see :mod:`solver.viscosity`), with
    ``phi``/``owner`` the probes' signed distance and nearest probe at this component's samples;
    ``layers`` as :func:`solver.layers.layer_count` gives it.

    An unknown away from the domain's sides whose neighbours are all unknowns (most of them)
    takes a short path, unsigned-indexed, with the same sums in the same order as the general
    path below it (2.3x faster at 32³: a general path in a function of its own, called per
    sample, ran 4-10x slower)."""
    diag, offx, offy, offz, active = sys_out
    nx, ny, nz = q.shape
    shape = (nx, ny, nz)
    three = dim == 3
    nl = 1 if layers is None else nz  # a constant on a 2D grid (see solver.layers)
    for i in range(nx):
        ui = np.uint64(i)
        inner_i = 0 < i < nx - 1
        for j in range(ny):
            uj = np.uint64(j)
            inner_ij = inner_i and 0 < j < ny - 1
            for k in range(nl):
                uk = np.uint64(k)
                if (
                    inner_ij
                    and (not three or 0 < k < nz - 1)
                    and face_type[ui, uj, uk] == FREE
                    and face_type[ui - U1, uj, uk] == FREE
                    and face_type[ui + U1, uj, uk] == FREE
                    and face_type[ui, uj - U1, uk] == FREE
                    and face_type[ui, uj + U1, uk] == FREE
                    and (
                        not three
                        or (
                            face_type[ui, uj, uk - U1] == FREE
                            and face_type[ui, uj, uk + U1] == FREE
                        )
                    )
                ):
                    own = scale * mu_face[ui, uj, uk]
                    d = 1.0 + drag_face[ui, uj, uk]
                    d += 0.5 * (own + scale * mu_face[ui - U1, uj, uk])
                    c = 0.5 * (own + scale * mu_face[ui + U1, uj, uk])
                    d += c
                    offx[ui, uj, uk] = -c
                    d += 0.5 * (own + scale * mu_face[ui, uj - U1, uk])
                    c = 0.5 * (own + scale * mu_face[ui, uj + U1, uk])
                    d += c
                    offy[ui, uj, uk] = -c
                    if three:
                        d += 0.5 * (own + scale * mu_face[ui, uj, uk - U1])
                        c = 0.5 * (own + scale * mu_face[ui, uj, uk + U1])
                        d += c
                        offz[ui, uj, uk] = -c
                    else:
                        offz[ui, uj, uk] = 0.0
                    active[ui, uj, uk] = True
                    diag[ui, uj, uk] = d
                    rhs[ui, uj, uk] = q[ui, uj, uk]
                    continue
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
                        if t == FREE:  # never inside a probe: those are marked BOUNDARY
                            d += c
                            if s > 0:
                                if b == 0:
                                    offx[i, j, k] = -c
                                elif b == 1:
                                    offy[i, j, k] = -c
                                else:
                                    offz[i, j, k] = -c
                        elif phi[ii, jj, kk] <= 0.0 and owner[ii, jj, kk] >= 0:
                            inv, wall = _cut_coupling(
                                phi, owner, rigid, axis, i, j, k, ii, jj, kk, b, s, h
                            )
                            d += c * inv
                            r += c * inv * wall
                        elif t == INTERIOR and b != axis:
                            wall = _surface_velocity(
                                label, rigid, axis, i, j, k, ii, jj, kk, b, s, h
                            )
                            d += 2.0 * own
                            r += 2.0 * own * wall
                        else:
                            d += c
                            r += c * q[ii, jj, kk]
                diag[i, j, k] = d
                rhs[i, j, k] = r


@dataclass
class ViscosityWork:
    """The arrays one component's viscosity step fills, kept from step to step (a fresh
    allocation of each, every step, costs its page faults on grids of 32³ and more)."""

    mu_face: np.ndarray
    drag_face: np.ndarray
    system: StencilSystem
    rhs: np.ndarray

    @classmethod
    def for_shape(cls, shape: tuple[int, int, int], dim: int) -> ViscosityWork:
        return cls(np.empty(shape), np.empty(shape), StencilSystem.empty(shape, dim),
                   np.empty(shape))  # fmt: skip


def diffuse_cut(
    q: np.ndarray,
    face_type: np.ndarray,
    axis: int,
    dim: int,
    mu_cell: np.ndarray,
    dt_s: float,
    density_kg_m3: float,
    kinds: np.ndarray,
    side_vel: np.ndarray,
    label: np.ndarray,
    rigid: np.ndarray,
    h: float,
    phi: np.ndarray,
    owner: np.ndarray,
    tol: float,
    max_iter: int,
    drag_cell: np.ndarray | None = None,
    linear_solve: LinearSolve = solve,
    work: ViscosityWork | None = None,
) -> SolveReport:
    """Implicit viscosity of component ``axis`` in place, no-slip at the probes' surfaces;
    ``work`` (of ``q``'s shape), when given, holds the system instead of fresh arrays."""
    if work is None or work.rhs.shape != q.shape:
        work = ViscosityWork.for_shape(q.shape, dim)
    mu_face, drag_face, system, rhs = work.mu_face, work.drag_face, work.system, work.rhs
    face_viscosity(mu_cell, axis, mu_face)
    if drag_cell is not None:
        face_viscosity(drag_cell, axis, drag_face)
        drag_face *= dt_s
    else:
        drag_face.fill(0.0)
    arrays = (system.diag, system.off[0], system.off[1], system.off[2], system.active)
    scale = dt_s / (density_kg_m3 * h * h)
    build_cut_system(
        q, face_type, axis, dim, mu_face, scale, drag_face, kinds, side_vel, label, rigid, h, phi,
        owner, arrays, rhs, layer_count(q.shape),
    )  # fmt: skip
    return linear_solve(system, rhs, q, tol, max_iter)
