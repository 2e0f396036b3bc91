"""Implicit viscosity with no-slip at the probes' true surfaces (cut-cell geometry).

The same backward Euler system as :mod:`solver.staircase.viscosity` (per component, the per-cell
dynamic viscosity field, the optional linear drag, symmetric and positive definite), except that a
velocity sample whose neighbour along an axis lies inside a probe is coupled to the probe's
surface itself: the surface sits at the fraction ``theta = phi_f / (phi_f - phi_nb)`` of the way
(from the two samples' signed distances), and the linear ghost value through the surface's rigid
velocity ``u_ghost = u + (u_wall - u) / theta`` (Gibou et al. 2002) adds ``c / theta`` to the
diagonal and ``c u_wall / theta`` to the right-hand side. The matrix stays an M-matrix:
unconditionally stable. ``theta`` is clamped below at ``MIN_THETA``: a sample closer to the
surface is coupled as if it stood that far, so the coupling does not jump as the surface sweeps
across the sample. Samples inside a probe are relaxed towards its rigid velocity with their depth
(:func:`mark_probe_samples`); those of fully closed faces hold it.

Both choices trade the force's noise (a towed disk's drag) against where the no-slip surface sits
(circular Couette's torque), in ``benchmarks/bench_boundary.py``: a larger clamp smooths the
force further but shifts the surface.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from solver.boundary import INFLOW, WALL
from solver.bundles import Sides
from solver.compiled.jit import inline_kernel, kernel
from solver.compiled.layers import layer_count
from solver.labels import BOUNDARY, FREE, INTERIOR
from solver.linalg.pcg import LinearSolve, SolveReport, StencilSystem, solve
from solver.staircase.faces import Component, RigidMotion, rigid_velocity
from solver.staircase.viscosity import (
    Diffusion,
    DiffusionArrays,
    ViscousStep,
    _surface_velocity,
    face_viscosity,
)

MIN_THETA = 0.25
INSIDE_RELAX_CELLS = 0.5


class CutWalls(NamedTuple):
    """The probes as the cut viscosity solve's walls: :class:`solver.staircase.viscosity.Walls`
    (the static labels, the rigid motion, the cell size ``h``, m) and the probes' signed
    distance ``phi`` (m) and nearest probe ``owner`` at one component's samples."""

    label: np.ndarray
    rigid: RigidMotion
    h: float
    phi: np.ndarray
    owner: np.ndarray


@kernel
def mark_probe_samples(comp, walls, open_frac, window, relax):
    """Samples of component ``comp`` inside a probe (``phi <= 0`` of the :class:`CutWalls`
    ``walls``) in ``window`` (``open_frac`` the component's open fractions) are left out of
    the viscosity solve (``BOUNDARY``); those of fully closed faces take the owning probe's rigid
    velocity. Those of partly open faces keep their (advected) value where they have just been
    crossed and are pulled towards the rigid velocity with depth, reaching it
    ``INSIDE_RELAX_CELLS`` deep: a sample's value never jumps as the surface sweeps across it, and
    a sample deep inside does not carry the pressure corrections of many steps. The relaxation is
    once per step (``relax``); a grid shift re-marks the samples without it."""
    q, face_type, axis = comp
    phi, owner, rigid, h = walls.phi, walls.owner, walls.rigid, walls.h
    lo, hi = window
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
                us = rigid_velocity(rigid, o, x, y, z, axis)
                keep = 0.0
                if open_frac[i, j, k] > 0.0:
                    if not relax:
                        continue
                    keep = max(1.0 + phi[i, j, k] / (INSIDE_RELAX_CELLS * h), 0.0)
                q[i, j, k] = us + (q[i, j, k] - us) * keep


@kernel
def _cut_coupling(walls, axis, face, nb, b, s):
    """(1 / theta, wall velocity) for the sample ``face`` (i, j, k) whose neighbour ``nb``
    (ii, jj, kk) along ``b`` (direction ``s``) lies inside a probe (``walls`` a :class:`CutWalls`)."""
    phi, owner, rigid, h = walls.phi, walls.owner, walls.rigid, walls.h
    i, j, k = face
    ii, jj, kk = nb
    pf, pn = phi[i, j, k], phi[ii, jj, kk]
    theta = pf / (pf - pn) if pf - pn > 0.0 else 1.0
    theta = max(theta, MIN_THETA)
    x = (i + (0.0 if axis == 0 else 0.5) + s * theta * (b == 0)) * h
    y = (j + (0.0 if axis == 1 else 0.5) + s * theta * (b == 1)) * h
    z = (k + (0.0 if axis == 2 else 0.5) + s * theta * (b == 2)) * h
    wall = rigid_velocity(rigid, owner[ii, jj, kk], x, y, z, axis)
    return 1.0 / theta, wall


@inline_kernel
def _side(wall, own, d, r, velocity):
    """A neighbour beyond the domain's side: a wall or inflow side's ghost adds ``2 own`` to the
    diagonal and ``2 own`` times its velocity to the right-hand side."""
    if wall:
        d += 2.0 * own
        r += 2.0 * own * velocity
    return d, r


@kernel
def _short_rows_3d(comp, coeffs, sides, out):
    """The short path of :func:`build_cut_system` on a 3D grid, a row at a time along z: each
    sample's sums are formed as if it and its neighbours within the domain were unknowns, and
    written with ``active`` saying whether they are (the general path then overwrites every
    sample that is not). A row's samples away from the sides take a loop without a branch,
    which vectorizes; its two ends, and every sample of a row along a side, take the sides'
    ghosts as the general path does, in its order."""
    q, face_type, axis = comp
    mu_face, scale, drag_face = coeffs
    kinds, side_vel = sides
    diag, offx, offy, offz, active, rhs = out
    nx, ny, nz = q.shape
    walls = (kinds == WALL) | (kinds == INFLOW)
    vel = side_vel[:, :, axis]
    for i in range(nx):
        w_out, e_out = i == 0, i == nx - 1
        iw, ie = max(i - 1, 0), min(i + 1, nx - 1)
        for j in range(ny):
            s_out, n_out = j == 0, j == ny - 1
            js, jn = max(j - 1, 0), min(j + 1, ny - 1)
            f0, fw, fe = face_type[i, j], face_type[iw, j], face_type[ie, j]
            fs, fn = face_type[i, js], face_type[i, jn]
            m0, mw, me = mu_face[i, j], mu_face[iw, j], mu_face[ie, j]
            ms, mn = mu_face[i, js], mu_face[i, jn]
            dr, qr = drag_face[i, j], q[i, j]
            dg, ox, oy, oz = diag[i, j], offx[i, j], offy[i, j], offz[i, j]
            ac, rh = active[i, j], rhs[i, j]
            side_row = w_out or e_out or s_out or n_out
            if not side_row:
                for k in range(1, nz - 1):
                    ac[k] = (
                        (f0[k] == FREE)
                        & (fw[k] == FREE)
                        & (fe[k] == FREE)
                        & (fs[k] == FREE)
                        & (fn[k] == FREE)
                        & (f0[k - 1] == FREE)
                        & (f0[k + 1] == FREE)
                    )
                    own = scale * m0[k]
                    d = 1.0 + dr[k]
                    d += 0.5 * (own + scale * mw[k])
                    c = 0.5 * (own + scale * me[k])
                    d += c
                    ox[k] = -c
                    d += 0.5 * (own + scale * ms[k])
                    c = 0.5 * (own + scale * mn[k])
                    d += c
                    oy[k] = -c
                    d += 0.5 * (own + scale * m0[k - 1])
                    c = 0.5 * (own + scale * m0[k + 1])
                    d += c
                    oz[k] = -c
                    dg[k] = d
                    rh[k] = qr[k]
            # the row's ends, or all of a row along a side
            step = 1 if side_row else max(nz - 1, 1)
            k = 0
            while k < nz:
                b_out, t_out = k == 0, k == nz - 1
                kb, kt = max(k - 1, 0), min(k + 1, nz - 1)
                ac[k] = (
                    (f0[k] == FREE)
                    & (w_out | (fw[k] == FREE))
                    & (e_out | (fe[k] == FREE))
                    & (s_out | (fs[k] == FREE))
                    & (n_out | (fn[k] == FREE))
                    & (b_out | (f0[kb] == FREE))
                    & (t_out | (f0[kt] == FREE))
                )
                own = scale * m0[k]
                d = 1.0 + dr[k]
                r = qr[k]
                if w_out:
                    d, r = _side(walls[0, 0], own, d, r, vel[0, 0])
                else:
                    d += 0.5 * (own + scale * mw[k])
                c = 0.0
                if e_out:
                    d, r = _side(walls[0, 1], own, d, r, vel[0, 1])
                else:
                    c = 0.5 * (own + scale * me[k])
                    d += c
                ox[k] = -c
                if s_out:
                    d, r = _side(walls[1, 0], own, d, r, vel[1, 0])
                else:
                    d += 0.5 * (own + scale * ms[k])
                c = 0.0
                if n_out:
                    d, r = _side(walls[1, 1], own, d, r, vel[1, 1])
                else:
                    c = 0.5 * (own + scale * mn[k])
                    d += c
                oy[k] = -c
                if b_out:
                    d, r = _side(walls[2, 0], own, d, r, vel[2, 0])
                else:
                    d += 0.5 * (own + scale * m0[kb])
                c = 0.0
                if t_out:
                    d, r = _side(walls[2, 1], own, d, r, vel[2, 1])
                else:
                    c = 0.5 * (own + scale * m0[kt])
                    d += c
                oz[k] = -c
                dg[k] = d
                rh[k] = r
                k += step


@kernel
def _short_rows_2d(comp, coeffs, sides, out):
    """:func:`_short_rows_3d` on one layer: the rows run along y."""
    q, face_type, axis = comp
    mu_face, scale, drag_face = coeffs
    kinds, side_vel = sides
    diag, offx, offy, offz, active, rhs = out
    nx, ny, _ = q.shape
    walls = (kinds == WALL) | (kinds == INFLOW)
    vel = side_vel[:, :, axis]
    for i in range(nx):
        w_out, e_out = i == 0, i == nx - 1
        iw, ie = max(i - 1, 0), min(i + 1, nx - 1)
        f0, fw, fe = face_type[i, :, 0], face_type[iw, :, 0], face_type[ie, :, 0]
        m0, mw, me = mu_face[i, :, 0], mu_face[iw, :, 0], mu_face[ie, :, 0]
        dr, qr = drag_face[i, :, 0], q[i, :, 0]
        dg, ox, oy, oz = diag[i, :, 0], offx[i, :, 0], offy[i, :, 0], offz[i, :, 0]
        ac, rh = active[i, :, 0], rhs[i, :, 0]
        side_row = w_out or e_out
        if not side_row:
            for j in range(1, ny - 1):
                ac[j] = (
                    (f0[j] == FREE)
                    & (fw[j] == FREE)
                    & (fe[j] == FREE)
                    & (f0[j - 1] == FREE)
                    & (f0[j + 1] == FREE)
                )
                own = scale * m0[j]
                d = 1.0 + dr[j]
                d += 0.5 * (own + scale * mw[j])
                c = 0.5 * (own + scale * me[j])
                d += c
                ox[j] = -c
                d += 0.5 * (own + scale * m0[j - 1])
                c = 0.5 * (own + scale * m0[j + 1])
                d += c
                oy[j] = -c
                oz[j] = 0.0
                dg[j] = d
                rh[j] = qr[j]
        step = 1 if side_row else max(ny - 1, 1)
        j = 0
        while j < ny:
            s_out, n_out = j == 0, j == ny - 1
            js, jn = max(j - 1, 0), min(j + 1, ny - 1)
            ac[j] = (
                (f0[j] == FREE)
                & (w_out | (fw[j] == FREE))
                & (e_out | (fe[j] == FREE))
                & (s_out | (f0[js] == FREE))
                & (n_out | (f0[jn] == FREE))
            )
            own = scale * m0[j]
            d = 1.0 + dr[j]
            r = qr[j]
            if w_out:
                d, r = _side(walls[0, 0], own, d, r, vel[0, 0])
            else:
                d += 0.5 * (own + scale * mw[j])
            c = 0.0
            if e_out:
                d, r = _side(walls[0, 1], own, d, r, vel[0, 1])
            else:
                c = 0.5 * (own + scale * me[j])
                d += c
            ox[j] = -c
            if s_out:
                d, r = _side(walls[1, 0], own, d, r, vel[1, 0])
            else:
                d += 0.5 * (own + scale * m0[js])
            c = 0.0
            if n_out:
                d, r = _side(walls[1, 1], own, d, r, vel[1, 1])
            else:
                c = 0.5 * (own + scale * m0[jn])
                d += c
            oy[j] = -c
            oz[j] = 0.0
            dg[j] = d
            rh[j] = r
            j += step


def build_cut_system(
    comp: Component,
    dim: int,
    coeffs: Diffusion,
    sides: Sides,
    walls: CutWalls,
    out: DiffusionArrays,
    layers: int | None,
    short: bool = True,
) -> None:
    """Assemble the diffusion system of component ``comp`` into ``out`` (see
    :func:`solver.staircase.viscosity.build_variable_system`), with ``walls`` a :class:`CutWalls`;
    ``layers`` as :func:`solver.compiled.layers.layer_count` gives it.

    An unknown whose neighbours within the domain are all unknowns (most of them) takes a short
    path (:func:`_short_rows_3d`, :func:`_short_rows_2d`), with the same sums in the same order
    as the general path (:func:`_general_rows`), which then visits the rest; with ``short``
    False it visits every sample (the reference the short path is tested against). The short
    path for the grid's dimension is chosen here, not in a kernel, so that a run compiles only
    the one it takes."""
    if short:
        (_short_rows_3d if dim == 3 else _short_rows_2d)(comp, coeffs, sides, out)
    _general_rows(comp, dim, coeffs, sides, walls, out, layers, short)


@kernel
def _general_rows(comp, dim, coeffs, sides, walls, out, layers, short):
    """:func:`build_cut_system`'s general path: every sample, or with ``short`` every sample
    the short path left inactive. It stays inline here: as a function of its own, called per
    sample or per neighbour, it is several times slower."""
    q, face_type, axis = comp
    mu_face, scale, drag_face = coeffs
    kinds, side_vel = sides
    phi, owner = walls.phi, walls.owner
    diag, offx, offy, offz, active, rhs = out
    nx, ny, nz = q.shape
    shape = (nx, ny, nz)
    nl = 1 if layers is None else nz  # a constant on a 2D grid (see solver.compiled.layers)
    for i in range(nx):
        for j in range(ny):
            for k in range(nl):
                if short and active[i, j, k]:
                    continue  # the short path's
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
                            inv, wall = _cut_coupling(walls, axis, (i, j, k), (ii, jj, kk), b, s)
                            d += c * inv
                            r += c * inv * wall
                        elif t == INTERIOR and b != axis:
                            wall = _surface_velocity(walls, axis, (i, j, k), (ii, jj, kk), b, s)
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
        return cls(
            np.empty(shape), np.empty(shape), StencilSystem.empty(shape, dim), np.empty(shape)
        )


def assemble_cut(
    comp: Component, step: ViscousStep, walls: CutWalls, work: ViscosityWork | None = None
) -> ViscosityWork:
    """The implicit viscosity system of component ``comp`` (the ``step``'s viscosity and drag,
    no-slip at the probes' surfaces: ``walls``) and its right-hand side, in ``work`` (of the
    component's shape) when given, else in fresh arrays; returns the arrays that hold them."""
    q, axis = comp.q, comp.axis
    dim, mu_cell, dt_s, drag_cell = step.dim, step.mu_cell, step.dt_s, step.drag_cell
    h = walls.h
    if work is None or work.rhs.shape != q.shape:
        work = ViscosityWork.for_shape(q.shape, dim)
    mu_face, drag_face, system, rhs = work.mu_face, work.drag_face, work.system, work.rhs
    face_viscosity(mu_cell, axis, mu_face)
    if drag_cell is not None:
        face_viscosity(drag_cell, axis, drag_face)
        drag_face *= dt_s
    else:
        drag_face.fill(0.0)
    scale = dt_s / (step.density_kg_m3 * h * h)
    coeffs = Diffusion(mu_face, scale, drag_face)
    out = DiffusionArrays.of(system, rhs)
    build_cut_system(comp, dim, coeffs, step.sides, walls, out, layer_count(q.shape))
    return work


def diffuse_cut(
    comp: Component,
    step: ViscousStep,
    walls: CutWalls,
    tol: float,
    max_iter: int,
    linear_solve: LinearSolve = solve,
    work: ViscosityWork | None = None,
) -> SolveReport:
    """Implicit viscosity of component ``comp`` in place, no-slip at the probes' surfaces;
    ``work`` (of the component's shape), when given, holds the system instead of fresh arrays
    (:func:`assemble_cut`, then ``linear_solve`` to ``tol`` in ``max_iter`` iterations)."""
    work = assemble_cut(comp, step, walls, work)
    return linear_solve(work.system, work.rhs, comp.q, tol, max_iter)
