"""Variational (cut-cell) pressure projection (Batty, Bertails & Bridson 2007; Ng, Min & Gibou 2009).

With ``phi = p dt / rho`` and ``W_f`` the open fraction of face ``f`` (0 on faces closed by a
static solid or a closed domain side), the system per active cell is

    sum_f W_f (phi_c - phi_nb) = -h * sum_f n_f . (w_f u_f + (1 - w_f) u_solid,f)

summed over the cell's faces (an outflow side is a zero-pressure ghost): the same 7-point
stencil as the staircase Poisson matrix, symmetric and positive (semi-)definite, with the face
weights in place of 0/1. The probe's rigid velocity enters through each face's solid part
``1 - w_f``. Faces with ``W_f > 0`` are then corrected by ``-(phi_hi - phi_lo) / h``. A cell is
active when any of its faces is open; a cell that a probe uncovers takes its first pressure from
its neighbours (:func:`fill_fresh_pressure`), so the incremental scheme sees no jump there.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from solver.boundary import OUTFLOW
from solver.bundles import Velocity, Window
from solver.compiled.jit import inline_kernel, kernel
from solver.compiled.layers import layer_count
from solver.compiled.unsigned import U0, U1
from solver.labels import FLUID
from solver.linalg.pcg import LinearSolve, SolveReport, StencilSystem, solve
from solver.staircase.faces import RigidMotion, rigid_velocity


class CutFaces(NamedTuple):
    """The probes' cut faces as the projection sees them: the open fraction and the owner of the
    solid part of every face, per component (the arrays of
    :class:`~solver.cutcell.geometry.CutGeometry` of those names), and the owners' rigid motion,
    which a face's solid part moves with."""

    open_frac: tuple[np.ndarray, ...]
    owner_face: tuple[np.ndarray, ...]
    rigid: RigidMotion


@inline_kernel
def _neighbour(i, j, k, b, s):
    return i + s * (b == 0), j + s * (b == 1), k + s * (b == 2)


@inline_kernel
def _face_of(i, j, k, b, s):
    """Index of the face of cell (i, j, k) across axis ``b`` on side ``s`` (-1 low, +1 high)."""
    if s > 0:
        return i + (b == 0), j + (b == 1), k + (b == 2)
    return i, j, k


@kernel
def _matrix_weight(static, kinds, wf, i, j, k, b, s, shape):
    """``W`` of the face of cell (i, j, k) across (b, s), and whether it leads to an outflow
    ghost (zero pressure) rather than a neighbouring cell."""
    ii, jj, kk = _neighbour(i, j, k, b, s)
    idx = ii if b == 0 else (jj if b == 1 else kk)
    fi, fj, fk = _face_of(i, j, k, b, s)
    if idx < 0 or idx >= shape[b]:
        if kinds[b, 0 if s < 0 else 1] == OUTFLOW:
            return wf[fi, fj, fk], True
        return 0.0, False
    if static[ii, jj, kk] != FLUID:
        return 0.0, False
    return wf[fi, fj, fk], False


@kernel
def build_cut_pressure_system(static, dim, kinds, open_frac, sys_out, window, layers):
    """Assemble the face-weighted Poisson matrix (the one place it is built; a preconditioner
    may be built on ``diag``/``off*``/``active``), in the cells of ``window`` (clipped to the
    grid; the rest of the outputs is left as it is).

    Args:
        static: cell labels without the probes (``FLUID`` or ``STATIC_SOLID``).
        kinds: domain side kinds (3, 2).
        open_frac: (wx, wy, wz), open face fractions of the probes.
        sys_out: outputs (diag, offx, offy, offz, active), cells' shape.
        window: the :class:`~solver.bundles.Window` of cells to assemble.
        layers: as :func:`solver.compiled.layers.layer_count` gives it.
    """
    wx, wy, wz = open_frac
    diag, offx, offy, offz, active = sys_out
    lo, hi = window
    nx, ny, nz = static.shape
    shape = (nx, ny, nz)
    ws = (wx, wy, wz)
    three = dim == 3
    k0 = (
        0 if layers is None else max(lo[2], 0)
    )  # constants on a 2D grid (see solver.compiled.layers)
    k1 = 1 if layers is None else min(hi[2], nz)
    for i in range(max(lo[0], 0), min(hi[0], nx)):
        ui = np.uint64(i)
        inner_i = 0 < i < nx - 1
        for j in range(max(lo[1], 0), min(hi[1], ny)):
            uj = np.uint64(j)
            inner_ij = inner_i and 0 < j < ny - 1
            for k in range(k0, k1):
                uk = np.uint64(k)
                if (  # a fluid cell among fluid cells: the same sums on a short unsigned path
                    inner_ij
                    and (not three or 0 < k < nz - 1)
                    and static[ui, uj, uk] == FLUID
                    and static[ui - U1, uj, uk] == FLUID
                    and static[ui + U1, uj, uk] == FLUID
                    and static[ui, uj - U1, uk] == FLUID
                    and static[ui, uj + U1, uk] == FLUID
                    and (
                        not three
                        or (static[ui, uj, uk - U1] == FLUID and static[ui, uj, uk + U1] == FLUID)
                    )
                ):
                    d = 0.0
                    d += wx[ui, uj, uk]
                    w = wx[ui + U1, uj, uk]
                    d += w
                    offx[ui, uj, uk] = -w if w > 0.0 else 0.0
                    d += wy[ui, uj, uk]
                    w = wy[ui, uj + U1, uk]
                    d += w
                    offy[ui, uj, uk] = -w if w > 0.0 else 0.0
                    if three:
                        d += wz[ui, uj, uk]
                        w = wz[ui, uj, uk + U1]
                        d += w
                        offz[ui, uj, uk] = -w if w > 0.0 else 0.0
                    else:
                        offz[ui, uj, uk] = 0.0
                    active[ui, uj, uk] = d > 0.0
                    diag[ui, uj, uk] = d
                    continue
                offx[i, j, k] = 0.0
                offy[i, j, k] = 0.0
                offz[i, j, k] = 0.0
                d = 0.0
                if static[i, j, k] == FLUID:
                    for b in range(dim):
                        for s in (-1, 1):
                            wgt, ghost = _matrix_weight(static, kinds, ws[b], i, j, k, b, s, shape)
                            d += wgt
                            if s > 0 and wgt > 0.0 and not ghost:
                                if b == 0:
                                    offx[i, j, k] = -wgt
                                elif b == 1:
                                    offy[i, j, k] = -wgt
                                else:
                                    offz[i, j, k] = -wgt
                active[i, j, k] = d > 0.0
                diag[i, j, k] = d


@kernel
def cut_flux(velocity, faces, active, dim, h, out, layers):
    """Net outward flux per active cell through the fluid and solid parts of its faces (m/s).

    A face on the domain's side carries its prescribed (side) velocity on its fluid part and, where
    a probe reaches through the side, the probe's velocity on its solid part: the probe's volume
    in a cell by the side then stays balanced (what leaves through an inner face's solid part came
    in through the side), instead of the fluid being drawn in through the cell's open sliver at the
    solid's speed over the sliver's fraction (a box entering the domain at 3 m/s: 15.7 m/s through
    a face 16 % open). In a closed domain the probe's entry is then a net inflow, which the
    projection spreads over all cells (it removes the mean). ``velocity``: the
    :class:`~solver.bundles.Velocity`; ``faces``: the :class:`CutFaces`; ``layers``: as
    :func:`solver.compiled.layers.layer_count` gives it."""
    u, v, w = velocity
    wx, wy, wz = faces.open_frac
    ox, oy, oz = faces.owner_face
    rigid = faces.rigid
    nx, ny, nz = out.shape
    nl = 1 if layers is None else nz  # a constant on a 2D grid (see solver.compiled.layers)
    comps = (u, v, w)
    ws = (wx, wy, wz)
    owners = (ox, oy, oz)
    three = dim == 3
    for i in range(nx):
        ui = np.uint64(i)
        for j in range(ny):
            uj = np.uint64(j)
            for k in range(nl):
                uk = np.uint64(k)
                if not active[ui, uj, uk]:
                    out[ui, uj, uk] = 0.0
                    continue
                if (  # no face with a solid part: the plain sum, unsigned-indexed
                    ox[ui, uj, uk] < 0
                    and ox[ui + U1, uj, uk] < 0
                    and oy[ui, uj, uk] < 0
                    and oy[ui, uj + U1, uk] < 0
                    and (not three or (oz[ui, uj, uk] < 0 and oz[ui, uj, uk + U1] < 0))
                ):
                    total = 0.0
                    total += -u[ui, uj, uk]
                    total += u[ui + U1, uj, uk]
                    total += -v[ui, uj, uk]
                    total += v[ui, uj + U1, uk]
                    if three:
                        total += -w[ui, uj, uk]
                        total += w[ui, uj, uk + U1]
                    out[ui, uj, uk] = total
                    continue
                total = 0.0
                for b in range(dim):
                    for s in (-1, 1):
                        fi, fj, fk = _face_of(i, j, k, b, s)
                        f = ws[b][fi, fj, fk]
                        q = comps[b][fi, fj, fk]
                        o = owners[b][fi, fj, fk]
                        if f < 1.0 and o >= 0:
                            x = (fi + (0.0 if b == 0 else 0.5)) * h
                            y = (fj + (0.0 if b == 1 else 0.5)) * h
                            z = (fk + (0.0 if b == 2 else 0.5)) * h
                            us = rigid_velocity(rigid, o, x, y, z, b)
                            q = f * q + (1.0 - f) * us
                        total += s * q
                out[i, j, k] = total


@kernel
def subtract_cut_gradient(q, static, kinds, wf, axis, active, phi, h):
    """Correct the faces of component ``axis`` with ``W > 0`` by ``-(phi_hi - phi_lo) / h``.

    Faces between two cells take an unsigned-indexed loop without side tests; the two planes
    of faces on the domain's sides the general one (an outflow side is a zero-pressure
    ghost). A 2D grid (one layer) skips the loop over its single layer: an innermost loop of
    one pass costs several times the work itself."""
    nx, ny, nz = q.shape
    n_axis = static.shape[axis]
    di = U1 if axis == 0 else U0
    dj = U1 if axis == 1 else U0
    if nz == 1 and axis != 2:  # 2D: no loop over a single layer
        for i in range(1 if axis == 0 else 0, nx - 1 if axis == 0 else nx):
            ui = np.uint64(i)
            for j in range(1 if axis == 1 else 0, ny - 1 if axis == 1 else ny):
                uj = np.uint64(j)
                if wf[ui, uj, U0] > 0.0 and active[ui, uj, U0] and active[ui - di, uj - dj, U0]:
                    q[ui, uj, U0] -= (phi[ui, uj, U0] - phi[ui - di, uj - dj, U0]) / h
    else:  # a row at a time along z, the correction selected, not branched on: it vectorizes
        ii, jj = (1, 0) if axis == 0 else ((0, 1) if axis == 1 else (0, 0))
        for i in range(ii, nx - 1 if axis == 0 else nx):
            for j in range(jj, ny - 1 if axis == 1 else ny):
                qr, wr, ar, pr = q[i, j], wf[i, j], active[i, j], phi[i, j]
                if axis == 2:
                    for k in range(1, nz - 1):
                        fix = (wr[k] > 0.0) & ar[k] & ar[k - 1]
                        value = qr[k] - (pr[k] - pr[k - 1]) / h
                        qr[k] = value if fix else qr[k]
                else:
                    al, pl = active[i - ii, j - jj], phi[i - ii, j - jj]
                    for k in range(nz):
                        fix = (wr[k] > 0.0) & ar[k] & al[k]
                        value = qr[k] - (pr[k] - pl[k]) / h
                        qr[k] = value if fix else qr[k]
    for side in (0, n_axis):
        for i in range(side, side + 1) if axis == 0 else range(nx):
            for j in range(side, side + 1) if axis == 1 else range(ny):
                for k in range(side, side + 1) if axis == 2 else range(nz):
                    if wf[i, j, k] <= 0.0:
                        continue
                    li, lj, lk = i - (axis == 0), j - (axis == 1), k - (axis == 2)
                    lo_in, hi_in = side > 0, side < n_axis
                    lo_ok = active[li, lj, lk] if lo_in else kinds[axis, 0] == OUTFLOW
                    hi_ok = active[i, j, k] if hi_in else kinds[axis, 1] == OUTFLOW
                    if not (lo_ok and hi_ok):
                        continue
                    hi = phi[i, j, k] if hi_in else 0.0
                    lo = phi[li, lj, lk] if lo_in else 0.0
                    q[i, j, k] -= (hi - lo) / h


@kernel
def _fresh_pressure(p, was_active, i, j, k, dim):
    """The mean pressure of the previously active neighbours of cell (i, j, k) (0 when none)."""
    nx, ny, nz = p.shape
    shape = (nx, ny, nz)
    total = 0.0
    n = 0
    for b in range(dim):
        for s in (-1, 1):
            ii, jj, kk = _neighbour(i, j, k, b, s)
            idx = ii if b == 0 else (jj if b == 1 else kk)
            if 0 <= idx < shape[b] and was_active[ii, jj, kk]:
                total += p[ii, jj, kk]
                n += 1
    return total / n if n else 0.0


@kernel
def fill_fresh_pressure(p, was_active, active, dim):
    """Cells active now but not before take the mean pressure of their previously active
    neighbours (0 when none); cells no longer active are zeroed."""
    nx, ny, nz = p.shape
    if nz == 1:  # 2D: no loop over a single layer (see subtract_cut_gradient)
        for i in range(nx):
            for j in range(ny):
                if active[i, j, 0] and not was_active[i, j, 0]:
                    p[i, j, 0] = _fresh_pressure(p, was_active, i, j, 0, dim)
    else:
        for i in range(nx):
            for j in range(ny):
                for k in range(nz):
                    if active[i, j, k] and not was_active[i, j, k]:
                        p[i, j, k] = _fresh_pressure(p, was_active, i, j, k, dim)
    if nz == 1:  # 2D: no loop over a single layer (see subtract_cut_gradient)
        for i in range(nx):
            ui = np.uint64(i)
            for j in range(ny):
                uj = np.uint64(j)
                if not active[ui, uj, U0]:
                    p[ui, uj, U0] = 0.0
        return
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if not active[i, j, k]:
                    p[i, j, k] = 0.0


@kernel
def pressure_rhs(flux, active, h, closed, phi):
    """In place, flat arrays: the flux through each cell's faces times ``-h`` (the Poisson
    right-hand side), less its mean over ``active`` where the domain is ``closed``
    (:func:`remove_mean`); ``phi`` (the warm start, or empty) is zeroed off ``active``."""
    for idx in range(flux.size):
        flux[idx] *= -h
    if closed:
        remove_mean(flux, active)
    for idx in range(phi.size):
        if not active[idx]:
            phi[idx] = 0.0


@kernel
def remove_mean(rhs, active):
    """Subtract the mean over ``active`` entries from those entries, flat arrays (a closed
    domain's Poisson problem is solvable only for a right-hand side of zero sum)."""
    total = 0.0
    n = 0
    for idx in range(rhs.size):
        if active[idx]:
            total += rhs[idx]
            n += 1
    if n == 0:
        return
    mean = total / n
    for idx in range(rhs.size):
        if active[idx]:
            rhs[idx] -= mean


def pressure_system(
    static: np.ndarray,
    dim: int,
    kinds: np.ndarray,
    open_frac: Sequence[np.ndarray],
    out: StencilSystem | None = None,
    boxes: list[tuple[np.ndarray, np.ndarray]] | None = None,
) -> StencilSystem:
    """The face-weighted Poisson matrix on the grid of ``static``, in ``out`` when given (of
    ``static``'s shape; every entry is rewritten, or with ``boxes`` (cell boxes ``lo <= idx <
    hi``, clipped to the grid) only the entries in them: the rest must already hold this
    matrix)."""
    system = out if out is not None else StencilSystem.empty(static.shape, dim)  # type: ignore[arg-type]
    ox, oy, oz = system.off
    sys_out = (system.diag, ox, oy, oz, system.active)
    if boxes is None or out is None:
        boxes = [(np.zeros(3, dtype=np.int64), np.array(static.shape, dtype=np.int64))]
    weights = tuple(open_frac)
    for lo, hi in boxes:
        window = Window(lo, hi)
        build_cut_pressure_system(
            static, dim, kinds, weights, sys_out, window, layer_count(static.shape)
        )
    return system


def project_cut(
    comps: list[np.ndarray],
    system: StencilSystem,
    static: np.ndarray,
    faces: CutFaces,
    h: float,
    kinds: np.ndarray,
    phi: np.ndarray,
    tol: float,
    max_iter: int,
    linear_solve: LinearSolve = solve,
) -> SolveReport:
    """Make the velocity discretely divergence-free on the cut geometry (``static`` labels, the
    probes' cut ``faces``, side ``kinds``), in place; ``phi`` is the warm start and the result
    (``p dt / rho`` or its increment); ``linear_solve`` as in
    :func:`solver.staircase.projection.project`."""
    dim = system.dim
    flux = np.empty(static.shape)
    velocity = Velocity(comps[0], comps[1], comps[2])
    cut_flux(velocity, faces, system.active, dim, h, flux, layer_count(flux.shape))
    closed = not (kinds[:dim] == OUTFLOW).any()
    if phi.flags.c_contiguous:
        pressure_rhs(flux.reshape(-1), system.active.reshape(-1), h, closed, phi.reshape(-1))
    else:
        pressure_rhs(flux.reshape(-1), system.active.reshape(-1), h, closed, np.empty(0))
        phi[~system.active] = 0.0
    report = linear_solve(system, flux, phi, tol, max_iter)
    for a in range(dim):
        subtract_cut_gradient(comps[a], static, kinds, faces.open_frac[a], a, system.active, phi, h)
    return report
