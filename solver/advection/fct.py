"""Flux-corrected transport of cell-centred scalars (Boris and Book 1973, with Zalesak's 1979
limiter): a step of the upwind transport of :mod:`.scalars`, then as much of its numerical
diffusion taken back as keeps every cell within the range of its neighbourhood.

First-order upwind smears a front over a width that grows as the root of the distance it
travels: a sub-step of face rate ``r = u dt / h`` (the Courant number) diffuses with the
coefficient ``|r| (1 - |r|) / 2`` (cells squared). After a step of ``n`` upwind sub-steps
(:func:`.scalars.transport`) with the upwind result ``q_L``, each face carries an
*antidiffusive flux*, the step's summed diffusion times the difference across the face::

    A = n |r| (1 - |r|) / 2 (q_L[above] - q_L[below])     (from below to above)

which moves paint from the thinner cell to the thicker: upwind's diffusion run backwards, on
the step's own result (Boris and Book's order: transport and diffuse, then correct). Left as it
is it would steepen every slope into oscillations; the limiter keeps it monotone:

- each cell's bounds are the largest and smallest ``q_L`` over itself and the neighbours it
  shares a face of nonzero rate with (the lower bound never below 0);
- a cell may take in at most ``R+ = min(1, (max - q_L) / P+)`` of the antidiffusive fluxes
  entering it (``P+`` their sum) and give at most ``R- = min(1, (q_L - min) / P-)`` of those
  leaving it (``P-``);
- each face's flux is scaled by the smaller of ``R+`` of the cell it enters and ``R-`` of the
  cell it leaves.

So every flux leaves one cell and enters the other (the total conserved to round-off, as
upwind's), and no cell leaves its neighbourhood's range (no new extremum; nothing negative).
Where the field is smooth the whole correction goes through; at a front it is cut back just
enough to keep the front monotone, which holds the front a few cells wide however far it
travels. Each field is limited on its own (a pigment's bounds are its own). Faces of rate 0
(solid faces, the domain's sides, faces without flux) carry no correction and add no neighbour
to a cell's bounds.

Two passes over the cells per field and step, whatever the number of sub-steps: the factors
(:func:`limits`), then the corrected fields (:func:`corrected`), each face's flux formed again
from ``q_L`` where it is needed. Both run a row along the last axis at a time over a copy of
``q_L`` padded by a layer below and above, so that no index is clamped in a row and the rows
vectorize.
"""

from __future__ import annotations

import numpy as np

from solver.compiled.jit import inline_kernel, kernel


@inline_kernel
def _anti(r, n, lo, hi):
    """The antidiffusive flux through a face of rate ``r`` after ``n`` sub-steps, from the cell
    holding ``lo`` (below) to the one holding ``hi`` (above)."""
    a = abs(r)
    return 0.5 * n * a * (1.0 - a) * (hi - lo)


@inline_kernel
def _top(r, here, there):
    """``there`` where the face between (rate ``r``) carries flux, else ``here``."""
    return there if r != 0.0 else here


@inline_kernel
def _factors(n, c, w, e, s, nn, b, t, xl, xh, yl, yh, zl, zh):
    """A cell's ``(R+, R-)``: its ``q_L`` ``c``, its neighbours' ``w``, ``e`` (x), ``s``,
    ``nn`` (y), ``b``, ``t`` (z), and the rates of its low and high faces on each axis."""
    top = max(
        max(max(c, _top(xl, c, w)), max(_top(xh, c, e), _top(yl, c, s))),
        max(max(_top(yh, c, nn), _top(zl, c, b)), _top(zh, c, t)),
    )
    bottom = min(
        min(min(c, _top(xl, c, w)), min(_top(xh, c, e), _top(yl, c, s))),
        min(min(_top(yh, c, nn), _top(zl, c, b)), _top(zh, c, t)),
    )
    f1 = _anti(xl, n, w, c)  # into the cell through its low faces...
    f2 = _anti(yl, n, s, c)
    f3 = _anti(zl, n, b, c)
    f4 = _anti(xh, n, e, c)  # ...and through its high ones
    f5 = _anti(yh, n, nn, c)
    f6 = _anti(zh, n, t, c)
    gain = max(f1, 0.0) + max(f2, 0.0) + max(f3, 0.0) + max(f4, 0.0) + max(f5, 0.0)
    gain += max(f6, 0.0)
    loss = max(-f1, 0.0) + max(-f2, 0.0) + max(-f3, 0.0) + max(-f4, 0.0) + max(-f5, 0.0)
    loss += max(-f6, 0.0)
    room = max(top - c, 0.0)
    spare = max(c - max(bottom, 0.0), 0.0)
    up = min(1.0, room / gain) if gain > 0.0 else 0.0
    down = min(1.0, spare / loss) if loss > 0.0 else 0.0
    return up, down


@kernel
def limits(low, ru, rv, rw, n, up, down):
    """Each cell's factors ``R+`` (into ``up``) and ``R-`` (into ``down``) of the module
    docstring, for ``low``, the upwind result of ``n`` sub-steps at the face rates ``ru`` (nx +
    1, ny, nz), ``rv`` (nx, ny + 1, nz), ``rw`` (nx, ny, nz + 1). ``low``, ``up`` and ``down``
    are (nx, ny, nz + 2): the cells with a layer of padding below and above (cell ``k`` at
    ``k + 1``), so that every cell has both z neighbours and the rows carry no clamped index
    (they vectorize); the padding's factors are left alone."""
    nx, ny, nz = ru.shape[0] - 1, ru.shape[1], ru.shape[2]
    for i in range(nx):
        iw, ie = max(i - 1, 0), min(i + 1, nx - 1)
        for j in range(ny):
            js, jn = max(j - 1, 0), min(j + 1, ny - 1)
            l0, lw, le, ls, ln = low[i, j], low[iw, j], low[ie, j], low[i, js], low[i, jn]
            xl, xh, yl, yh, zr = ru[i, j], ru[i + 1, j], rv[i, j], rv[i, j + 1], rw[i, j]
            u0, d0 = up[i, j], down[i, j]
            for k in range(nz):
                c = k + 1
                u0[c], d0[c] = _factors(n, l0[c], lw[c], le[c], ls[c], ln[c], l0[c - 1],
                                        l0[c + 1], xl[k], xh[k], yl[k], yh[k], zr[k],
                                        zr[k + 1])  # fmt: skip


@inline_kernel
def _limited(r, n, lo, hi, up_lo, down_lo, up_hi, down_hi):
    """The limited antidiffusive flux from below to above: the flux times ``R+`` of the cell it
    enters and ``R-`` of the cell it leaves, the smaller."""
    f = _anti(r, n, lo, hi)
    return f * (min(up_hi, down_lo) if f >= 0.0 else min(up_lo, down_hi))


@inline_kernel
def _corrected_cell(n, c, w, e, s, nn, b, t, rates, u, d):
    """A cell's corrected value: ``c`` plus the limited fluxes through its six faces
    (``rates``: its low and high faces' on x, y, z; ``u``, ``d``: the factors of the cell, then
    of its neighbours in ``w, e, s, nn, b, t``'s order)."""
    xl, xh, yl, yh, zl, zh = rates
    v = c + _limited(xl, n, w, c, u[1], d[1], u[0], d[0])
    v += _limited(yl, n, s, c, u[3], d[3], u[0], d[0])
    v += _limited(zl, n, b, c, u[5], d[5], u[0], d[0])
    v -= _limited(zh, n, c, t, u[0], d[0], u[6], d[6])
    v -= _limited(yh, n, c, nn, u[0], d[0], u[4], d[4])
    v -= _limited(xh, n, c, e, u[0], d[0], u[2], d[2])
    return max(v, 0.0)  # round-off below 0 (the limiter allows down to 0)


@kernel
def corrected(low, ru, rv, rw, n, up, down, out):
    """``out`` (nx, ny, nz) = ``low`` plus the limited antidiffusive fluxes through each cell's
    faces (``low``, ``up``, ``down`` padded as in :func:`limits`, the padding's factors 0)."""
    nx, ny, nz = out.shape
    for i in range(nx):
        iw, ie = max(i - 1, 0), min(i + 1, nx - 1)
        for j in range(ny):
            js, jn = max(j - 1, 0), min(j + 1, ny - 1)
            l0, lw, le, ls, ln = low[i, j], low[iw, j], low[ie, j], low[i, js], low[i, jn]
            xl, xh, yl, yh, zr = ru[i, j], ru[i + 1, j], rv[i, j], rv[i, j + 1], rw[i, j]
            u0, uw, ue, us, un = up[i, j], up[iw, j], up[ie, j], up[i, js], up[i, jn]
            d0, dw, de, ds, dn = down[i, j], down[iw, j], down[ie, j], down[i, js], down[i, jn]
            o = out[i, j]
            for k in range(nz):
                c = k + 1
                o[k] = _corrected_cell(
                    n, l0[c], lw[c], le[c], ls[c], ln[c], l0[c - 1], l0[c + 1],
                    (xl[k], xh[k], yl[k], yh[k], zr[k], zr[k + 1]),
                    (u0[c], uw[c], ue[c], us[c], un[c], u0[c - 1], u0[c + 1]),
                    (d0[c], dw[c], de[c], ds[c], dn[c], d0[c - 1], d0[c + 1]),
                )  # fmt: skip


@kernel
def fields_correct(fields, ru, rv, rw, n, low, up, down):
    """:func:`correct_step`'s work as one kernel: each field copied into the padded ``low``,
    its factors, then its corrected values written back into it."""
    _, nx, ny, nz = fields.shape
    for p in range(fields.shape[0]):
        field = fields[p]
        for i in range(nx):  # loops, not a slice copy: numba compiles these far faster
            for j in range(ny):
                for k in range(nz):
                    low[i, j, k + 1] = field[i, j, k]
        limits(low, ru, rv, rw, n, up, down)
        corrected(low, ru, rv, rw, n, up, down, field)


def correct_step(
    fields: np.ndarray, rates: tuple[np.ndarray, np.ndarray, np.ndarray], substeps: int
) -> None:
    """Correct ``fields`` (n, nx, ny, nz), the result of ``substeps`` upwind sub-steps at the
    face rates of :func:`solver.advection.scalars.face_rates`, in place (the module docstring).
    In 2D, a single layer: ``rates[2]`` all 0 with shape (nx, ny, 2)."""
    nx, ny, nz = fields.shape[1:]
    low = np.zeros((nx, ny, nz + 2))  # the padding: no flux through the z ends reads it
    up, down = np.zeros((nx, ny, nz + 2)), np.zeros((nx, ny, nz + 2))
    fields_correct(fields, *rates, float(substeps), low, up, down)
