"""Preconditioned conjugate gradients on 7-point stencil systems (numba kernels).

A system is stored as arrays of one 3D shape: ``diag`` and ``off[b]`` (the coupling between an
entry and its neighbour at +1 along axis b; symmetric), plus ``active`` (entries that are
unknowns). Inactive entries are left untouched. The preconditioner is the modified incomplete
Cholesky factorisation MIC(0) (Bridson, *Fluid Simulation for Computer Graphics*, 2nd ed., ch. 5),
the paper's choice of incomplete Cholesky with the modification that keeps row sums.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

MIC_TAU = 0.97
MIC_SIGMA = 0.25


@dataclass(frozen=True)
class SolveReport:
    """Outcome of one linear solve: iterations used and the final relative residual
    ``||b - A x|| / ||b||`` (0 when ``b`` is 0)."""

    iterations: int
    residual: float
    converged: bool


@njit(cache=True, nogil=True)
def mic0(diag, offx, offy, offz, active, dim, precon):
    """Fill ``precon`` with the MIC(0) factor's inverse diagonal (1/sqrt(e))."""
    nx, ny, nz = diag.shape
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if not active[i, j, k]:
                    precon[i, j, k] = 0.0
                    continue
                e = diag[i, j, k]
                if i > 0 and active[i - 1, j, k]:
                    a = offx[i - 1, j, k] * precon[i - 1, j, k]
                    e -= a * a + MIC_TAU * a * precon[i - 1, j, k] * (
                        offy[i - 1, j, k] + offz[i - 1, j, k]
                    )
                if j > 0 and active[i, j - 1, k]:
                    a = offy[i, j - 1, k] * precon[i, j - 1, k]
                    e -= a * a + MIC_TAU * a * precon[i, j - 1, k] * (
                        offx[i, j - 1, k] + offz[i, j - 1, k]
                    )
                if dim == 3 and k > 0 and active[i, j, k - 1]:
                    a = offz[i, j, k - 1] * precon[i, j, k - 1]
                    e -= a * a + MIC_TAU * a * precon[i, j, k - 1] * (
                        offx[i, j, k - 1] + offy[i, j, k - 1]
                    )
                if e < MIC_SIGMA * diag[i, j, k]:
                    e = diag[i, j, k]
                precon[i, j, k] = 1.0 / np.sqrt(e) if e > 0.0 else 0.0


@njit(cache=True, nogil=True)
def apply_precon(offx, offy, offz, active, dim, precon, r, q, z):
    """z = (L L^T)^{-1} r with the MIC(0) factor; ``q`` is scratch."""
    nx, ny, nz = r.shape
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if not active[i, j, k]:
                    q[i, j, k] = 0.0
                    continue
                t = r[i, j, k]
                if i > 0:
                    t -= offx[i - 1, j, k] * precon[i - 1, j, k] * q[i - 1, j, k]
                if j > 0:
                    t -= offy[i, j - 1, k] * precon[i, j - 1, k] * q[i, j - 1, k]
                if dim == 3 and k > 0:
                    t -= offz[i, j, k - 1] * precon[i, j, k - 1] * q[i, j, k - 1]
                q[i, j, k] = t * precon[i, j, k]
    for i in range(nx - 1, -1, -1):
        for j in range(ny - 1, -1, -1):
            for k in range(nz - 1, -1, -1):
                if not active[i, j, k]:
                    z[i, j, k] = 0.0
                    continue
                t = q[i, j, k]
                p = precon[i, j, k]
                if i + 1 < nx:
                    t -= offx[i, j, k] * p * z[i + 1, j, k]
                if j + 1 < ny:
                    t -= offy[i, j, k] * p * z[i, j + 1, k]
                if dim == 3 and k + 1 < nz:
                    t -= offz[i, j, k] * p * z[i, j, k + 1]
                z[i, j, k] = t * p


@njit(cache=True, nogil=True)
def apply_stencil(diag, offx, offy, offz, active, dim, x, out):
    """out = A x on active entries (0 elsewhere)."""
    nx, ny, nz = x.shape
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if not active[i, j, k]:
                    out[i, j, k] = 0.0
                    continue
                s = diag[i, j, k] * x[i, j, k]
                if i > 0:
                    s += offx[i - 1, j, k] * x[i - 1, j, k]
                if i + 1 < nx:
                    s += offx[i, j, k] * x[i + 1, j, k]
                if j > 0:
                    s += offy[i, j - 1, k] * x[i, j - 1, k]
                if j + 1 < ny:
                    s += offy[i, j, k] * x[i, j + 1, k]
                if dim == 3:
                    if k > 0:
                        s += offz[i, j, k - 1] * x[i, j, k - 1]
                    if k + 1 < nz:
                        s += offz[i, j, k] * x[i, j, k + 1]
                out[i, j, k] = s


@njit(cache=True, nogil=True)
def _dot(a, b, active):
    s = 0.0
    for n in range(a.size):
        if active.flat[n]:
            s += a.flat[n] * b.flat[n]
    return s


@njit(cache=True, nogil=True)
def pcg(diag, offx, offy, offz, active, dim, b, x, tol, max_iter):
    """Solve A x = b in place (x holds the warm start). Returns (iterations, relative residual).

    Stops when ``||r|| <= tol * ||b||``. Off-diagonals coupling an active entry to an inactive
    one must be zero.
    """
    precon = np.zeros_like(b)
    mic0(diag, offx, offy, offz, active, dim, precon)
    r = np.zeros_like(b)
    apply_stencil(diag, offx, offy, offz, active, dim, x, r)
    for n in range(b.size):
        r.flat[n] = b.flat[n] - r.flat[n] if active.flat[n] else 0.0
    bnorm = np.sqrt(_dot(b, b, active))
    if bnorm == 0.0:
        for n in range(x.size):
            if active.flat[n]:
                x.flat[n] = 0.0
        return 0, 0.0
    rnorm = np.sqrt(_dot(r, r, active))
    if rnorm <= tol * bnorm:
        return 0, rnorm / bnorm
    q = np.zeros_like(b)
    z = np.zeros_like(b)
    apply_precon(offx, offy, offz, active, dim, precon, r, q, z)
    s = z.copy()
    sigma = _dot(z, r, active)
    it = 0
    while it < max_iter:
        it += 1
        apply_stencil(diag, offx, offy, offz, active, dim, s, z)
        denom = _dot(z, s, active)
        if denom == 0.0:
            break
        alpha = sigma / denom
        for n in range(x.size):
            if active.flat[n]:
                x.flat[n] += alpha * s.flat[n]
                r.flat[n] -= alpha * z.flat[n]
        rnorm = np.sqrt(_dot(r, r, active))
        if rnorm <= tol * bnorm:
            break
        apply_precon(offx, offy, offz, active, dim, precon, r, q, z)
        sigma_new = _dot(z, r, active)
        beta = sigma_new / sigma
        sigma = sigma_new
        for n in range(s.size):
            if active.flat[n]:
                s.flat[n] = z.flat[n] + beta * s.flat[n]
    return it, rnorm / bnorm


def solve(system: StencilSystem, b: np.ndarray, x: np.ndarray, tol: float, max_iter: int) -> SolveReport:
    """Solve ``system`` for right-hand side ``b`` in place in ``x`` (its value is the warm start)."""
    it, res = pcg(
        system.diag, system.off[0], system.off[1], system.off[2], system.active, system.dim,
        b, x, tol, max_iter,
    )
    return SolveReport(iterations=int(it), residual=float(res), converged=bool(res <= tol))


@dataclass
class StencilSystem:
    """A symmetric 7-point stencil matrix over a 3D array of unknowns (see the module docstring)."""

    diag: np.ndarray
    off: tuple[np.ndarray, np.ndarray, np.ndarray]
    active: np.ndarray
    dim: int

    @classmethod
    def empty(cls, shape: tuple[int, int, int], dim: int) -> StencilSystem:
        return cls(
            diag=np.zeros(shape),
            off=(np.zeros(shape), np.zeros(shape), np.zeros(shape)),
            active=np.zeros(shape, dtype=np.bool_),
            dim=dim,
        )
