"""Conservative transport of cell-centred scalars on the MAC grid (finite-volume upwind, numba).

A scalar ``q`` (for example a paint volume fraction, or a pigment's) lives at cell centres. Over a
time step its change is the sum of fluxes through the cell's faces::

    q_i <- q_i - dt / h * sum_faces (u_f n_f) q_upwind(f)

with ``q_upwind`` the value in the cell the face velocity comes from (first-order upwind). Every
face flux leaves one cell and enters the other, so the total ``sum(q) h^dim`` is conserved to
round-off. Fluxes are zero through every face that is not ``FREE`` (a solid's face, a face inside
a solid) and through the domain's sides, open or closed: nothing enters or leaves the grid.

The step is split into ``n`` equal sub-steps so that in every cell the outgoing flux fraction
``dt_sub / h * sum_outgoing |u_f|`` is at most 1: no cell goes negative (an upwind update is a
convex combination). Where the velocity is divergence-free over the faces that carry flux, no
cell exceeds the largest initial value either. Next to a *moving* solid or an open side, whose
faces move fluid but no scalar, the scalar is compressed ahead of a moving probe and thinned
behind it (still conserved and non-negative).
"""

from __future__ import annotations

import math

import numpy as np

from solver.advection.fct import correct_step
from solver.compiled.jit import inline_kernel, kernel
from solver.compiled.threads import run_components
from solver.compiled.unsigned import U1
from solver.labels import FREE

#: The transport schemes (:func:`transport`'s ``scheme``).
SCHEMES = ("upwind", "fct")

#: Hard cap on sub-steps per call (a velocity this violent means something upstream is wrong).
MAX_SUBSTEPS = 1000


@kernel
def outflow_fraction(u, v, w, tu, tv, tw, dim, rate):
    """Largest ``rate * sum of outgoing face speeds`` over the cells (``rate = dt / h``).

    Only interior ``FREE`` faces count (the others carry no flux). ``tu``/``tv``/``tw`` are the
    face types of the three components.
    """
    nx, ny, nz = u.shape[0] - 1, v.shape[1] - 1, w.shape[2] - 1 if dim == 3 else 1
    worst = 0.0
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                out = 0.0
                if i > 0 and tu[i, j, k] == FREE and u[i, j, k] < 0.0:
                    out -= u[i, j, k]
                if i < nx - 1 and tu[i + 1, j, k] == FREE and u[i + 1, j, k] > 0.0:
                    out += u[i + 1, j, k]
                if j > 0 and tv[i, j, k] == FREE and v[i, j, k] < 0.0:
                    out -= v[i, j, k]
                if j < ny - 1 and tv[i, j + 1, k] == FREE and v[i, j + 1, k] > 0.0:
                    out += v[i, j + 1, k]
                if dim == 3:
                    if k > 0 and tw[i, j, k] == FREE and w[i, j, k] < 0.0:
                        out -= w[i, j, k]
                    if k < nz - 1 and tw[i, j, k + 1] == FREE and w[i, j, k + 1] > 0.0:
                        out += w[i, j, k + 1]
                out *= rate
                if out > worst:
                    worst = out
    return worst


@kernel
def upwind_substep(q, u, v, w, tu, tv, tw, dim, rate, out):
    """One explicit upwind update of fields ``q`` (n, nx, ny, nz) into ``out`` (same shape).

    ``rate`` is ``dt / h`` for this sub-step; ``out`` must not alias ``q``. Each face moves
    ``rate * vel * q_upwind`` from the cell on its low side to the one on its high side (vel > 0)
    or back; the upwind choice is a max/min, not a branch, and each field runs its own pass over
    contiguous cells (unsigned-indexed), each cell's sums in the same order as a face-by-face,
    field-by-field pass. :func:`transport` takes :func:`gather_substep` instead, which gives
    these values bit for bit (the reference it is tested against)."""
    n, nx, ny, nz = q.shape
    out[:] = q
    three = dim == 3
    for p in range(n):
        qp = q[p]
        op = out[p]
        for i in range(nx):
            ui = np.uint64(i)
            for j in range(ny):
                uj = np.uint64(j)
                for k in range(nz):
                    uk = np.uint64(k)
                    here = qp[ui, uj, uk]
                    if i > 0 and tu[ui, uj, uk] == FREE:
                        vel = rate * u[ui, uj, uk]
                        f = max(vel, 0.0) * qp[ui - U1, uj, uk] + min(vel, 0.0) * here
                        op[ui - U1, uj, uk] -= f
                        op[ui, uj, uk] += f
                    if j > 0 and tv[ui, uj, uk] == FREE:
                        vel = rate * v[ui, uj, uk]
                        f = max(vel, 0.0) * qp[ui, uj - U1, uk] + min(vel, 0.0) * here
                        op[ui, uj - U1, uk] -= f
                        op[ui, uj, uk] += f
                    if three and k > 0 and tw[ui, uj, uk] == FREE:
                        vel = rate * w[ui, uj, uk]
                        f = max(vel, 0.0) * qp[ui, uj, uk - U1] + min(vel, 0.0) * here
                        op[ui, uj, uk - U1] -= f
                        op[ui, uj, uk] += f


@kernel
def face_rates(u, v, w, tu, tv, tw, dim, rate, ru, rv, rw):
    """``rate`` times each face velocity where the face carries flux (an interior ``FREE``
    face), else 0, into ``ru``, ``rv``, ``rw`` (the components' shapes; ``rw`` is left alone in
    2D): what every field and sub-step of :func:`gather_substep` reads, formed once."""
    for q, t, out, axis in ((u, tu, ru, 0), (v, tv, rv, 1), (w, tw, rw, 2)):
        if axis == 2 and dim != 3:
            continue
        nx, ny, nz = q.shape
        last = (nx, ny, nz)[axis] - 1
        for i in range(nx):
            for j in range(ny):
                for k in range(nz):
                    at = i if axis == 0 else (j if axis == 1 else k)
                    flows = 0 < at < last and t[i, j, k] == FREE
                    out[i, j, k] = rate * q[i, j, k] if flows else 0.0


@inline_kernel
def _flux(r, lo, hi):
    """The upwind flux through a face of rate ``r`` (``rate * velocity``) from the cell below,
    holding ``lo``, to the one above, holding ``hi``: :func:`upwind_substep`'s expression."""
    return max(r, 0.0) * lo + min(r, 0.0) * hi


@kernel
def gather_substep(q, ru, rv, rw, dim, out):
    """:func:`upwind_substep` with the face rates of :func:`face_rates`, each cell summing its
    own faces: the same values, bit for bit. A cell's change in :func:`upwind_substep` comes in
    the order its loop makes it: the cell's own low x, y and z faces (added), then its high z,
    y and x faces (subtracted); here it is summed in that order, a row along the last axis at a
    time (along y on one layer), with no branch, so the rows vectorize. A face that carries no
    flux has rate 0 and adds 0; the rows' neighbours beyond the grid's sides are read as the
    cell itself, through faces of rate 0 (clamping the rows' ends inside the row loop would keep
    it from vectorizing)."""
    n, nx, ny, nz = q.shape
    for p in range(n):
        qp, op = q[p], out[p]
        for i in range(nx):
            iw, ie = max(i - 1, 0), min(i + 1, nx - 1)
            if dim != 3:  # one layer: a row along y
                q0, qw, qe = qp[i, :, 0], qp[iw, :, 0], qp[ie, :, 0]
                xl, xh, yr = ru[i, :, 0], ru[i + 1, :, 0], rv[i, :, 0]
                o = op[i, :, 0]
                for j in range(1, ny - 1):
                    c = q0[j]
                    t = c + _flux(xl[j], qw[j], c)
                    t += _flux(yr[j], q0[j - 1], c)
                    t -= _flux(yr[j + 1], c, q0[j + 1])
                    o[j] = t - _flux(xh[j], c, qe[j])
                for j in range(0, ny, max(ny - 1, 1)):  # the row's ends
                    js, jn = max(j - 1, 0), min(j + 1, ny - 1)
                    c = q0[j]
                    t = c + _flux(xl[j], qw[j], c)
                    t += _flux(yr[j], q0[js], c)
                    t -= _flux(yr[j + 1], c, q0[jn])
                    o[j] = t - _flux(xh[j], c, qe[j])
                continue
            for j in range(ny):
                js, jn = max(j - 1, 0), min(j + 1, ny - 1)
                q0, qw, qe, qs, qn = qp[i, j], qp[iw, j], qp[ie, j], qp[i, js], qp[i, jn]
                xl, xh, yl, yh, zr = ru[i, j], ru[i + 1, j], rv[i, j], rv[i, j + 1], rw[i, j]
                o = op[i, j]
                for k in range(1, nz - 1):  # no clamped index: it vectorizes
                    c = q0[k]
                    t = c + _flux(xl[k], qw[k], c)
                    t += _flux(yl[k], qs[k], c)
                    t += _flux(zr[k], q0[k - 1], c)
                    t -= _flux(zr[k + 1], c, q0[k + 1])
                    t -= _flux(yh[k], c, qn[k])
                    o[k] = t - _flux(xh[k], c, qe[k])
                for k in range(0, nz, max(nz - 1, 1)):  # the row's ends
                    kb, kt = max(k - 1, 0), min(k + 1, nz - 1)
                    c = q0[k]
                    t = c + _flux(xl[k], qw[k], c)
                    t += _flux(yl[k], qs[k], c)
                    t += _flux(zr[k], q0[kb], c)
                    t -= _flux(zr[k + 1], c, q0[kt])
                    t -= _flux(yh[k], c, qn[k])
                    o[k] = t - _flux(xh[k], c, qe[k])


def _third(
    comps: list[np.ndarray], face_types: list[np.ndarray], dim: int
) -> tuple[np.ndarray, np.ndarray]:
    """The z component and its face types, or 2-entry placeholders in 2D (never read there)."""
    if dim == 3:
        return comps[2], face_types[2]
    return np.zeros((1, 1, 2)), np.zeros((1, 1, 2), dtype=np.int8)


def substeps_needed(
    comps: list[np.ndarray], face_types: list[np.ndarray], dim: int, h: float, dt: float
) -> int:
    """Sub-steps that keep every cell's outgoing flux fraction <= 1 over a step of ``dt`` s."""
    w, tw = _third(comps, face_types, dim)
    worst = outflow_fraction(comps[0], comps[1], w, face_types[0], face_types[1], tw, dim, dt / h)
    return substeps_for(worst, "scalar transport")


def substeps_for(worst: float, what: str) -> int:
    """Sub-steps that bring the largest outgoing flux fraction ``worst`` of one step to <= 1,
    at most ``MAX_SUBSTEPS``; ``what`` names the transport in the error otherwise."""
    if not math.isfinite(worst):
        raise FloatingPointError(f"non-finite velocity in {what}")
    n = max(1, math.ceil(worst - 1e-12))
    if n > MAX_SUBSTEPS:
        raise FloatingPointError(f"{what} would need {n} sub-steps (velocity too large)")
    return n


def transport(
    fields: np.ndarray,
    comps: list[np.ndarray],
    face_types: list[np.ndarray],
    dim: int,
    h: float,
    dt: float,
    threads: int = 1,
    scheme: str = "upwind",
) -> int:
    """Advance cell-centred ``fields`` (n, nx, ny, nz) by ``dt`` seconds in place.

    Args:
        fields: float64 array of ``n`` scalars per cell (any units; each is conserved).
        comps: the three velocity component arrays of the MAC grid, m/s (w unused in 2D).
        face_types: the face types of each component (:mod:`solver.staircase.faces`); only ``FREE``
            interior faces carry flux.
        dim: 2 or 3.
        h: cell size, metres.
        dt: time step, seconds (>= 0).
        threads: with 2 or more and at least two fields, the fields are cut into that many
            groups (at most one per field), each taken through every sub-step on a thread of
            its own (:mod:`solver.compiled.threads`): the fields are independent, so the
            same values, bit for bit.
        scheme: ``"upwind"`` (first order, the module docstring) or ``"fct"``
            (flux-corrected transport, :mod:`solver.advection.fct`: the same sub-steps, then
            fronts kept a few cells wide however far they travel, conserved and within each
            neighbourhood's range).

    Returns:
        The number of sub-steps taken.
    """
    if scheme not in SCHEMES:
        raise ValueError(f"unknown transport scheme {scheme!r}: expected one of {SCHEMES}")
    if fields.ndim != 4 or fields.dtype != np.float64:
        raise ValueError("fields must be a float64 array of shape (n, nx, ny, nz)")
    if dt <= 0.0 or fields.shape[0] == 0:
        return 0
    n = substeps_needed(comps, face_types, dim, h, dt)
    rate = dt / (n * h)
    w, tw = _third(comps, face_types, dim)
    ru, rv, rw = np.empty(comps[0].shape), np.empty(comps[1].shape), np.empty(w.shape)
    face_rates(comps[0], comps[1], w, face_types[0], face_types[1], tw, dim, rate, ru, rv, rw)
    if scheme == "fct" and dim != 3:  # one layer: its z faces carry nothing
        rw = np.zeros((*fields.shape[1:3], 2))
    groups = max(1, min(int(threads), fields.shape[0]))
    cuts = [fields.shape[0] * g // groups for g in range(groups + 1)]

    def group(g: int) -> None:
        part = fields[cuts[g] : cuts[g + 1]]
        src, dst = part, np.empty_like(part)
        for _ in range(n):
            gather_substep(src, ru, rv, rw, dim, dst)
            src, dst = dst, src
        if scheme == "fct":
            correct_step(src, (ru, rv, rw), n)
        if src is not part:
            part[:] = src

    run_components(group, groups, groups)
    return n
