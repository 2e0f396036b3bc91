"""Flux-corrected transport (Zalesak 1979) of cell-centred scalars: the upwind step of
:mod:`.scalars` plus as much of the Lax-Wendroff flux's correction as keeps every cell within
the range of its neighbourhood.

First-order upwind smears a front over a width that grows with the square root of the distance it
travels (its numerical diffusion is ``|u| h (1 - c) / 2``, ``c`` the Courant number). A
second-order flux keeps the front, but oscillates at it. Flux-corrected transport takes each
sub-step in two parts:

1. the upwind (low-order) update ``q_L`` (:func:`.scalars.gather_substep`'s fluxes);
2. on each face, the *antidiffusive flux* ``A``: the Lax-Wendroff flux less the upwind one, which
   for a face of rate ``r = u dt / h`` between a cell holding ``lo`` (below) and one holding
   ``hi`` (above) is ``A = |r| (1 - |r|) (hi - lo) / 2`` from below to above, whatever the
   flow's direction: exactly the upwind step's numerical diffusion, reversed. ``A`` is set to 0
   where it would run down the slope of ``q_L`` (Zalesak's prelimiting).

Each cell's bounds are the largest and smallest of ``q`` and ``q_L`` over the cell and the
neighbours it shares a flux-carrying face with (never below 0). A cell may take in at most
``R+ = min(1, (max - q_L) / P+)`` of the antidiffusive fluxes entering it (``P+`` their sum) and
give at most ``R- = min(1, (q_L - min) / P-)`` of those leaving it; each face's flux is scaled
by the smaller factor of its two cells (``R+`` of the receiver, ``R-`` of the giver). So:

- every face's flux (upwind and correction) leaves one cell and enters the other: the total is
  conserved to round-off, as upwind's;
- no cell leaves ``[min, max]`` of its neighbourhood: no new extremum, nothing negative (the upwind
  step is non-negative at the sub-steps :func:`.scalars.substeps_needed` takes);
- where the fields are smooth the limiter lets the whole correction through (second order); at a
  front it cuts the correction back to keep the front monotone, which holds the front a cell or
  two wide however far it travels.

Each field is limited on its own (a pigment's bounds are its own). Faces with rate 0 (solid
faces, the domain's sides, a face that carries no flux) carry no correction and add no
neighbour to a cell's bounds.
"""

from __future__ import annotations

import numpy as np

from solver.compiled.jit import inline_kernel, kernel


@inline_kernel
def _upwind(r, lo, hi):
    """The upwind flux through a face of rate ``r`` from the cell holding ``lo`` (below) to the
    one holding ``hi`` (above)."""
    return max(r, 0.0) * lo + min(r, 0.0) * hi


@inline_kernel
def _anti(r, lo, hi):
    """The antidiffusive flux (Lax-Wendroff's less upwind's) through a face of rate ``r``, from
    below to above."""
    a = abs(r)
    return 0.5 * a * (1.0 - a) * (hi - lo)


@inline_kernel
def _prelimit(a, low_lo, low_hi):
    """``a`` where it runs up the slope of the low-order solution (or the slope is flat), else
    0."""
    return a if a * (low_hi - low_lo) >= 0.0 else 0.0


@kernel
def low_order(q, ru, rv, rw, low, ax, ay, az):
    """The upwind update of one field ``q`` (nx, ny, nz) into ``low`` and each face's
    antidiffusive flux into ``ax`` (nx + 1, ny, nz), ``ay`` (nx, ny + 1, nz), ``az`` (nx, ny,
    nz + 1) (the face-rate arrays' shapes; ``ru``, ``rv``, ``rw`` are 0 on faces without flux).
    Each cell sums its six faces in :func:`solver.advection.scalars.gather_substep`'s order."""
    nx, ny, nz = q.shape
    for i in range(nx):
        iw, ie = max(i - 1, 0), min(i + 1, nx - 1)
        for j in range(ny):
            js, jn = max(j - 1, 0), min(j + 1, ny - 1)
            for k in range(nz):
                kb, kt = max(k - 1, 0), min(k + 1, nz - 1)
                c = q[i, j, k]
                xl, xh = ru[i, j, k], ru[i + 1, j, k]
                yl, yh = rv[i, j, k], rv[i, j + 1, k]
                zl, zh = rw[i, j, k], rw[i, j, k + 1]
                t = c + _upwind(xl, q[iw, j, k], c)
                t += _upwind(yl, q[i, js, k], c)
                t += _upwind(zl, q[i, j, kb], c)
                t -= _upwind(zh, c, q[i, j, kt])
                t -= _upwind(yh, c, q[i, jn, k])
                low[i, j, k] = t - _upwind(xh, c, q[ie, j, k])
                ax[i, j, k] = _anti(xl, q[iw, j, k], c)
                ay[i, j, k] = _anti(yl, q[i, js, k], c)
                az[i, j, k] = _anti(zl, q[i, j, kb], c)


@inline_kernel
def _widen(r, ql, q_nb, low_nb, top, bottom):
    """``(top, bottom)`` widened by a neighbour's ``q`` and ``q_L`` where the face to it (rate
    ``r``) carries flux (else by the cell's own ``q_L``, ``ql``: no change)."""
    flows = r != 0.0
    top = max(top, max(q_nb, low_nb) if flows else ql)
    bottom = min(bottom, min(q_nb, low_nb) if flows else ql)
    return top, bottom


@kernel
def limits(q, low, ru, rv, rw, ax, ay, az, up, down):
    """Each cell's factors ``R+`` (into ``up``) and ``R-`` (into ``down``) of the module
    docstring, from its bounds and its prelimited antidiffusive fluxes."""
    nx, ny, nz = q.shape
    for i in range(nx):
        iw, ie = max(i - 1, 0), min(i + 1, nx - 1)
        for j in range(ny):
            js, jn = max(j - 1, 0), min(j + 1, ny - 1)
            for k in range(nz):
                kb, kt = max(k - 1, 0), min(k + 1, nz - 1)
                ql = low[i, j, k]
                top, bottom = max(q[i, j, k], ql), min(q[i, j, k], ql)
                top, bottom = _widen(ru[i, j, k], ql, q[iw, j, k], low[iw, j, k], top, bottom)
                top, bottom = _widen(ru[i + 1, j, k], ql, q[ie, j, k], low[ie, j, k], top, bottom)
                top, bottom = _widen(rv[i, j, k], ql, q[i, js, k], low[i, js, k], top, bottom)
                top, bottom = _widen(rv[i, j + 1, k], ql, q[i, jn, k], low[i, jn, k], top, bottom)
                top, bottom = _widen(rw[i, j, k], ql, q[i, j, kb], low[i, j, kb], top, bottom)
                top, bottom = _widen(rw[i, j, k + 1], ql, q[i, j, kt], low[i, j, kt], top, bottom)
                # what enters through the low faces (flux from below) and the high ones (against)
                f1 = _prelimit(ax[i, j, k], low[iw, j, k], ql)
                f2 = _prelimit(ay[i, j, k], low[i, js, k], ql)
                f3 = _prelimit(az[i, j, k], low[i, j, kb], ql)
                f4 = _prelimit(ax[i + 1, j, k], ql, low[ie, j, k])
                f5 = _prelimit(ay[i, j + 1, k], ql, low[i, jn, k])
                f6 = _prelimit(az[i, j, k + 1], ql, low[i, j, kt])
                gain = max(f1, 0.0) + max(f2, 0.0) + max(f3, 0.0)
                gain += max(-f4, 0.0) + max(-f5, 0.0) + max(-f6, 0.0)
                loss = max(-f1, 0.0) + max(-f2, 0.0) + max(-f3, 0.0)
                loss += max(f4, 0.0) + max(f5, 0.0) + max(f6, 0.0)
                room = top - ql
                spare = ql - max(bottom, 0.0)
                up[i, j, k] = min(1.0, room / gain) if gain > 0.0 and room > 0.0 else 0.0
                down[i, j, k] = min(1.0, spare / loss) if loss > 0.0 and spare > 0.0 else 0.0


@inline_kernel
def _corrected(a, low_lo, low_hi, up_lo, down_lo, up_hi, down_hi):
    """The limited antidiffusive flux from below to above: the prelimited flux times ``R+`` of
    the cell it enters and ``R-`` of the cell it leaves."""
    f = _prelimit(a, low_lo, low_hi)
    scale = min(up_hi, down_lo) if f >= 0.0 else min(up_lo, down_hi)
    return scale * f


@kernel
def corrected(low, ax, ay, az, up, down, out):
    """``out`` = ``low`` plus the limited antidiffusive fluxes through each cell's faces."""
    nx, ny, nz = low.shape
    for i in range(nx):
        iw, ie = max(i - 1, 0), min(i + 1, nx - 1)
        for j in range(ny):
            js, jn = max(j - 1, 0), min(j + 1, ny - 1)
            for k in range(nz):
                kb, kt = max(k - 1, 0), min(k + 1, nz - 1)
                ql, u0, d0 = low[i, j, k], up[i, j, k], down[i, j, k]
                t = ql + _corrected(
                    ax[i, j, k], low[iw, j, k], ql, up[iw, j, k], down[iw, j, k], u0, d0
                )
                t += _corrected(
                    ay[i, j, k], low[i, js, k], ql, up[i, js, k], down[i, js, k], u0, d0
                )
                t += _corrected(
                    az[i, j, k], low[i, j, kb], ql, up[i, j, kb], down[i, j, kb], u0, d0
                )
                t -= _corrected(
                    az[i, j, k + 1], ql, low[i, j, kt], u0, d0, up[i, j, kt], down[i, j, kt]
                )
                t -= _corrected(
                    ay[i, j + 1, k], ql, low[i, jn, k], u0, d0, up[i, jn, k], down[i, jn, k]
                )
                t -= _corrected(
                    ax[i + 1, j, k], ql, low[ie, j, k], u0, d0, up[ie, j, k], down[ie, j, k]
                )
                out[i, j, k] = max(t, 0.0)  # round-off below 0 (the limiter allows down to 0)


class FctScratch:
    """The work arrays of :func:`correct_step` for cells of shape (nx, ny, nz), made once a
    transport call."""

    def __init__(self, shape: tuple[int, int, int]) -> None:
        nx, ny, nz = shape
        self.up = np.empty(shape)
        self.down = np.empty(shape)
        self.out = np.empty(shape)
        self.ax = np.zeros((nx + 1, ny, nz))
        self.ay = np.zeros((nx, ny + 1, nz))
        self.az = np.zeros((nx, ny, nz + 1))


@kernel
def step_antidiffusion(low, ru, rv, rw, substeps, ax, ay, az):
    """Each face's antidiffusive flux for a whole step of ``substeps`` upwind sub-steps at the
    face rates ``ru``, ``rv``, ``rw``: the sub-steps' summed numerical diffusion
    ``substeps |r| (1 - |r|) / 2`` times the difference of ``low`` (the step's upwind result)
    across the face, from below to above."""
    nx, ny, nz = low.shape
    for i in range(nx):
        iw = max(i - 1, 0)
        for j in range(ny):
            js = max(j - 1, 0)
            for k in range(nz):
                kb = max(k - 1, 0)
                c = low[i, j, k]
                ax[i, j, k] = substeps * _anti(ru[i, j, k], low[iw, j, k], c)
                ay[i, j, k] = substeps * _anti(rv[i, j, k], low[i, js, k], c)
                az[i, j, k] = substeps * _anti(rw[i, j, k], low[i, j, kb], c)


@kernel
def fields_correct(fields, ru, rv, rw, substeps, ax, ay, az, up, down, out):
    """:func:`correct_step` as one kernel, field by field, in place."""
    for p in range(fields.shape[0]):
        low = fields[p]
        step_antidiffusion(low, ru, rv, rw, substeps, ax, ay, az)
        limits(low, low, ru, rv, rw, ax, ay, az, up, down)
        corrected(low, ax, ay, az, up, down, out)
        low[:] = out


def correct_step(
    fields: np.ndarray,
    rates: tuple[np.ndarray, np.ndarray, np.ndarray],
    substeps: int,
    scratch: FctScratch,
) -> None:
    """Correct ``fields`` (n, nx, ny, nz), the result of ``substeps`` upwind sub-steps at the
    face rates of :func:`solver.advection.scalars.face_rates`, in place (in 2D a single layer,
    ``rw`` all 0 with shape (nx, ny, 2))."""
    s = scratch
    fields_correct(fields, *rates, float(substeps), s.ax, s.ay, s.az, s.up, s.down, s.out)
