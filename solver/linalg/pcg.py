"""Preconditioned conjugate gradients on 7-point stencil systems (numba kernels).

A system is stored as arrays of one 3D shape: ``diag`` and ``off[b]`` (the coupling between an
entry and its neighbour at +1 along axis b; symmetric), plus ``active`` (entries that are
unknowns). Inactive entries are left untouched. The preconditioner is the modified incomplete
Cholesky factorisation MIC(0) (Bridson, *Fluid Simulation for Computer Graphics*, 2nd ed., ch. 5),
the paper's choice of incomplete Cholesky with the modification that keeps row sums.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numba import prange

from solver.compiled.jit import kernel
from solver.compiled.parallel import serial_and_parallel

MIC_TAU = 0.97
MIC_SIGMA = 0.25


@dataclass(frozen=True)
class SolveReport:
    """Outcome of one linear solve: iterations used and the final relative residual
    ``||b - A x|| / ||b||`` (0 when ``b`` is 0)."""

    iterations: int
    residual: float
    converged: bool


@kernel
def mic0(diag, offx, offy, offz, active, strides, precon):
    """Fill ``precon`` with the MIC(0) factor's inverse diagonal (1/sqrt(e)); flat arrays."""
    sx, sy, sz = strides
    for n in range(diag.size):
        if not active[n]:
            precon[n] = 0.0
            continue
        e = diag[n]
        if n >= sx:
            m = n - sx
            a = offx[m] * precon[m]
            e -= a * a + MIC_TAU * a * precon[m] * (offy[m] + offz[m])
        if n >= sy:
            m = n - sy
            a = offy[m] * precon[m]
            e -= a * a + MIC_TAU * a * precon[m] * (offx[m] + offz[m])
        if sz > 0 and n >= sz:
            m = n - sz
            a = offz[m] * precon[m]
            e -= a * a + MIC_TAU * a * precon[m] * (offx[m] + offy[m])
        if e < MIC_SIGMA * diag[n]:
            e = diag[n]
        precon[n] = 1.0 / np.sqrt(e) if e > 0.0 else 0.0


@kernel
def apply_precon(offx, offy, offz, active, strides, precon, r, q, z):
    """z = (L L^T)^{-1} r with the MIC(0) factor; ``q`` is scratch; flat arrays."""
    sx, sy, sz = strides
    size = r.size
    for n in range(size):
        if not active[n]:
            q[n] = 0.0
            continue
        t = r[n]
        if n >= sx:
            t -= offx[n - sx] * precon[n - sx] * q[n - sx]
        if n >= sy:
            t -= offy[n - sy] * precon[n - sy] * q[n - sy]
        if sz > 0 and n >= sz:
            t -= offz[n - sz] * precon[n - sz] * q[n - sz]
        q[n] = t * precon[n]
    for n in range(size - 1, -1, -1):
        if not active[n]:
            z[n] = 0.0
            continue
        t = q[n]
        p = precon[n]
        if n + sx < size:
            t -= offx[n] * p * z[n + sx]
        if n + sy < size:
            t -= offy[n] * p * z[n + sy]
        if sz > 0 and n + sz < size:
            t -= offz[n] * p * z[n + sz]
        z[n] = t * p


def _apply_stencil(diag, offx, offy, offz, active, strides, x, out):
    """out = A x on active entries (0 elsewhere); flat arrays. A stride of 0 is an axis without
    couplings (the z axis in 2D).

    The entries at least the largest stride away from both ends take a loop without bounds
    tests, unsigned-indexed, split among threads in the parallel twin; the rest the tested one,
    which visits only them (not the middle, entry by entry)."""
    sx, sy, sz = strides
    size = x.size
    lo = max(sx, sy, sz)
    hi = size - lo
    if hi <= lo:
        lo = hi = size
    usx, usy, usz = np.uint64(sx), np.uint64(sy), np.uint64(sz)
    for m in prange(lo, hi):
        n = np.uint64(m)
        s = diag[n] * x[n]
        if sx > 0:
            s += offx[n - usx] * x[n - usx]
            s += offx[n] * x[n + usx]
        if sy > 0:
            s += offy[n - usy] * x[n - usy]
            s += offy[n] * x[n + usy]
        if sz > 0:
            s += offz[n - usz] * x[n - usz]
            s += offz[n] * x[n + usz]
        out[n] = s if active[n] else 0.0
    for e in range(lo + size - hi):  # the entries before lo and from hi on, in order
        t = e if e < lo else hi + (e - lo)
        if not active[t]:
            out[t] = 0.0
            continue
        a = diag[t] * x[t]
        if sx > 0:
            if t >= sx:
                a += offx[t - sx] * x[t - sx]
            if t + sx < size:
                a += offx[t] * x[t + sx]
        if sy > 0:
            if t >= sy:
                a += offy[t - sy] * x[t - sy]
            if t + sy < size:
                a += offy[t] * x[t + sy]
        if sz > 0:
            if t >= sz:
                a += offz[t - sz] * x[t - sz]
            if t + sz < size:
                a += offz[t] * x[t + sz]
        out[t] = a


apply_stencil, apply_stencil_parallel = serial_and_parallel(_apply_stencil)


@kernel
def dot(a, b):
    """Sum of ``a * b`` over the first ``b.size`` entries, in eight interleaved partial sums: a
    single running sum waits on each addition's latency."""
    size = b.size
    s0 = s1 = s2 = s3 = s4 = s5 = s6 = s7 = 0.0
    end = size - size % 8
    for m in range(0, end, 8):
        s0 += a[m] * b[m]
        s1 += a[m + 1] * b[m + 1]
        s2 += a[m + 2] * b[m + 2]
        s3 += a[m + 3] * b[m + 3]
        s4 += a[m + 4] * b[m + 4]
        s5 += a[m + 5] * b[m + 5]
        s6 += a[m + 6] * b[m + 6]
        s7 += a[m + 7] * b[m + 7]
    for m in range(end, size):
        s0 += a[m] * b[m]
    return ((s0 + s1) + (s2 + s3)) + ((s4 + s5) + (s6 + s7))


@kernel
def scaled_dot(w, a):
    """:func:`dot` of ``w * a`` with ``a`` (the products rounded as that of a stored ``w * a``
    would be), in its eight interleaved partial sums."""
    size = a.size
    s0 = s1 = s2 = s3 = s4 = s5 = s6 = s7 = 0.0
    end = size - size % 8
    for m in range(0, end, 8):
        s0 += (w[m] * a[m]) * a[m]
        s1 += (w[m + 1] * a[m + 1]) * a[m + 1]
        s2 += (w[m + 2] * a[m + 2]) * a[m + 2]
        s3 += (w[m + 3] * a[m + 3]) * a[m + 3]
        s4 += (w[m + 4] * a[m + 4]) * a[m + 4]
        s5 += (w[m + 5] * a[m + 5]) * a[m + 5]
        s6 += (w[m + 6] * a[m + 6]) * a[m + 6]
        s7 += (w[m + 7] * a[m + 7]) * a[m + 7]
    for m in range(end, size):
        s0 += (w[m] * a[m]) * a[m]
    return ((s0 + s1) + (s2 + s3)) + ((s4 + s5) + (s6 + s7))


@kernel
def pcg_flat(diag, offx, offy, offz, active, strides, b, x, tol, max_iter):
    """PCG on flat arrays; see :func:`pcg`. Entries of ``b`` off ``active`` must be 0."""
    size = b.size
    precon = np.zeros(size)
    mic0(diag, offx, offy, offz, active, strides, precon)
    r = np.zeros(size)
    apply_stencil(diag, offx, offy, offz, active, strides, x, r)
    for n in range(size):
        r[n] = b[n] - r[n] if active[n] else 0.0
    bnorm = np.sqrt(dot(b, b))
    if bnorm == 0.0:
        for n in range(size):
            if active[n]:
                x[n] = 0.0
        return 0, 0.0
    rnorm = np.sqrt(dot(r, r))
    if rnorm <= tol * bnorm:
        return 0, rnorm / bnorm
    q = np.zeros(size)
    z = np.zeros(size)
    apply_precon(offx, offy, offz, active, strides, precon, r, q, z)
    s = z.copy()
    sigma = dot(z, r)
    it = 0
    while it < max_iter:
        it += 1
        apply_stencil(diag, offx, offy, offz, active, strides, s, z)
        denom = dot(z, s)
        if denom == 0.0:
            break
        alpha = sigma / denom
        for n in range(size):
            x[n] += alpha * s[n]
            r[n] -= alpha * z[n]
        rnorm = np.sqrt(dot(r, r))
        if rnorm <= tol * bnorm:
            break
        apply_precon(offx, offy, offz, active, strides, precon, r, q, z)
        sigma_new = dot(z, r)
        beta = sigma_new / sigma
        sigma = sigma_new
        for n in range(size):
            s[n] = z[n] + beta * s[n]
    return it, rnorm / bnorm


@kernel
def jacobi_pcg_flat(diag, offx, offy, offz, active, strides, b, x, tol, max_iter, work):
    """CG preconditioned by the diagonal (flat arrays; see :func:`pcg`): no sequential sweep,
    so every pass streams; the cheapest solve of a strongly diagonally dominant system (an
    implicit viscosity step with ``nu dt / h^2`` of order 0.1). ``work`` is (4, ``b.size``)
    scratch, overwritten."""
    size = b.size
    inv, r, s, z = work[0], work[1], work[2], work[3]
    for n in range(size):
        inv[n] = 1.0 / diag[n] if active[n] and diag[n] > 0.0 else 0.0
    apply_stencil(diag, offx, offy, offz, active, strides, x, r)
    for n in range(size):
        r[n] = b[n] - r[n] if active[n] else 0.0
    bnorm = np.sqrt(dot(b, b))
    if bnorm == 0.0:
        for n in range(size):
            if active[n]:
                x[n] = 0.0
        return 0, 0.0
    rnorm = np.sqrt(dot(r, r))
    if rnorm <= tol * bnorm:
        return 0, rnorm / bnorm
    for n in range(size):
        s[n] = inv[n] * r[n]
    sigma = dot(s, r)
    it = 0
    while it < max_iter:
        it += 1
        apply_stencil(diag, offx, offy, offz, active, strides, s, z)
        denom = dot(z, s)
        if denom <= 0.0:
            break
        alpha = sigma / denom
        for n in range(size):
            x[n] += alpha * s[n]
            r[n] -= alpha * z[n]
        rnorm = np.sqrt(dot(r, r))
        if rnorm <= tol * bnorm:
            break
        # the preconditioned residual inv * r is formed where it is used, not stored: one pass
        # less, the same products in the same order
        sigma_new = scaled_dot(inv, r)
        beta = sigma_new / sigma
        sigma = sigma_new
        for n in range(size):
            s[n] = inv[n] * r[n] + beta * s[n]
    return it, rnorm / bnorm


@kernel
def pcg(diag, offx, offy, offz, active, dim, b, x, tol, max_iter):
    """Solve A x = b in place (x holds the warm start; 3D arrays, C order). Returns
    (iterations, relative residual ``||b - A x|| / ||b||``), stopping at ``tol``.

    Off-diagonals coupling an active entry to an inactive one, or to beyond the array's end along
    their axis, must be zero; ``b`` must be zero off ``active``.
    """
    _nx, ny, nz = b.shape
    strides = (ny * nz, nz, 1 if dim == 3 else 0)
    xf = x.reshape(-1)
    it, res = pcg_flat(
        diag.reshape(-1),
        offx.reshape(-1),
        offy.reshape(-1),
        offz.reshape(-1),
        active.reshape(-1),
        strides,
        b.reshape(-1),
        xf,
        tol,
        max_iter,
    )
    return it, res


class JacobiPCG:
    """:func:`jacobi_pcg_flat` for systems of one grid shape, its scratch kept from solve to
    solve: each fresh array's first touch faults in its pages, a large share of a short solve's
    time on a large grid."""

    def __init__(self, shape: tuple[int, int, int]) -> None:
        self.shape = tuple(int(c) for c in shape)
        self.work = np.zeros((4, int(np.prod(self.shape))))

    def solve(
        self, system: StencilSystem, b: np.ndarray, x: np.ndarray, tol: float, max_iter: int
    ) -> SolveReport:
        """As :func:`solve`, preconditioned by the diagonal."""
        if tuple(b.shape) != self.shape:
            raise ValueError(f"b must have the shape {self.shape}, got {b.shape}")
        _nx, ny, nz = b.shape
        strides = (ny * nz, nz, 1 if system.dim == 3 else 0)
        ox, oy, oz = (o.reshape(-1) for o in system.off)
        diag, active = system.diag.reshape(-1), system.active.reshape(-1)
        xf = x.reshape(-1)
        it, res = jacobi_pcg_flat(
            diag, ox, oy, oz, active, strides, b.reshape(-1), xf, tol, max_iter, self.work
        )
        if not x.flags.c_contiguous:  # its flat form was a copy
            x[...] = xf.reshape(x.shape)
        return SolveReport(iterations=int(it), residual=float(res), converged=bool(res <= tol))


def solve_jacobi(
    system: StencilSystem, b: np.ndarray, x: np.ndarray, tol: float, max_iter: int
) -> SolveReport:
    """As :func:`solve`, preconditioned by the diagonal (:class:`JacobiPCG`, its scratch for this
    solve only)."""
    return JacobiPCG(b.shape).solve(system, b, x, tol, max_iter)


def solve(
    system: StencilSystem, b: np.ndarray, x: np.ndarray, tol: float, max_iter: int
) -> SolveReport:
    """Solve ``system`` for right-hand side ``b`` in place in ``x`` (its value is the warm start)."""
    it, res = pcg(
        system.diag,
        system.off[0],
        system.off[1],
        system.off[2],
        system.active,
        system.dim,
        b,
        x,
        tol,
        max_iter,
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


LinearSolve = Callable[[StencilSystem, np.ndarray, np.ndarray, float, int], SolveReport]
"""A solver for a :class:`StencilSystem`: ``(system, b, x, tol, max_iter) -> SolveReport``,
solving in place in ``x`` (its value is the warm start); :func:`solve` (MIC(0)-PCG) or
:meth:`solver.linalg.multigrid.Multigrid.solve`."""
