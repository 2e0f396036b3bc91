"""Multigrid-preconditioned conjugate gradients (MGPCG) on 7-point stencil systems.

After McAdams, Sifakis & Teran, "A parallel multigrid Poisson solver for fluids simulation on
large grids" (SCA 2010): conjugate gradients preconditioned by one geometric multigrid V-cycle,
its hierarchy built from the assembled fine matrix (:class:`~solver.linalg.pcg.StencilSystem`,
any face weights, ghosts or mass term), so it respects every solid, outflow and cut-cell weight:

- cells are aggregated 2 x 2 (x 2 in 3D) per level down to a few cells a side; a coarse cell is
  an unknown when any of its children is and its diagonal is positive;
- the coarse matrix is the Galerkin product ``P^T A P`` with piecewise-constant ``P`` (7-point,
  symmetric), its zero-row-sum (Laplacian) part scaled by the first of :class:`Multigrid`'s
  ``scales`` (1/2: the same operator rediscretized on cells twice as wide) and its row sums
  (outflow ghosts, a mass, a drag) by the second (1/2 for pressure ghosts, 1 for a mass);
- smoothing: ``PRE_SMOOTH`` red-black Gauss-Seidel sweeps down, as many black-red up (the
  coarsest level ``COARSEST_SWEEPS`` each way): a symmetric positive definite V-cycle for CG.

The hierarchy's arrays are allocated once per grid shape and refilled in place each solve;
:data:`PARALLEL_MIN_CELLS` says which levels run on threads.
"""

from __future__ import annotations

import time
from typing import NamedTuple

import numpy as np
from numba import prange

from solver.compiled.jit import kernel
from solver.compiled.parallel import NEVER, parallel_section, serial_and_parallel, serial_twin
from solver.compiled.timed_choice import TimedChoice
from solver.compiled.unsigned import U0, U1, U2
from solver.linalg.pcg import SolveReport, StencilSystem, apply_stencil, apply_stencil_parallel, dot

PRE_SMOOTH = 2
COARSEST_SWEEPS = 16
COARSEST_CELLS = 4
PRESSURE_SCALES = (0.5, 0.5)
DIFFUSION_SCALES = (0.5, 1.0)
#: The smallest level (cells) that a 3D solve with ``threads`` > 1 runs on numba's threads
#: (:mod:`solver.compiled.parallel`, the same bits); with ``adaptive``, on those or on one,
#: whichever has cost less per iteration lately (:mod:`solver.compiled.timed_choice`). Threads
#: pay on large grids with a free core, not on the painting grid nor beside a busy core, so a
#: simulation asks for them only when its scene sets the threads.
PARALLEL_MIN_CELLS = 32768


def level_shapes(shape: tuple[int, int, int]) -> list[tuple[int, int, int]]:
    """The shapes of the hierarchy, finest first: every axis longer than one cell halved
    (rounded up) until none exceeds ``COARSEST_CELLS`` cells."""
    shapes = [tuple(int(c) for c in shape)]
    while max(shapes[-1]) > COARSEST_CELLS:
        shapes.append(tuple((c + 1) // 2 for c in shapes[-1]))
    return shapes  # type: ignore[return-value]


class Hierarchy(NamedTuple):
    """The packed arrays of a multigrid hierarchy: every level's entries concatenated, finest
    first, each flat in the kernels' axis order (see :class:`Multigrid`)."""

    #: Diagonal of each level's matrix.
    diag: np.ndarray
    #: Coupling of each entry to its successor along the first, second and third axis.
    offx: np.ndarray
    offy: np.ndarray
    offz: np.ndarray
    #: Whether an entry is an unknown (bool).
    active: np.ndarray
    #: Inverse diagonal (0 where no unknown).
    inv: np.ndarray
    #: (L, 3) int64: each level's shape.
    shapes: np.ndarray
    #: (L,) int64: each level's first entry in the packed arrays.
    starts: np.ndarray


@kernel
def coarsen(h, level, scale_l, scale_m):
    """Fill level ``level + 1`` of the packed hierarchy ``h`` from level ``level``, and the
    inverse diagonal ``inv`` of level ``level``."""
    diag, offx, offy, offz, active, inv, shapes, starts = h
    nx, ny, nz = shapes[level, 0], shapes[level, 1], shapes[level, 2]
    cx, cy, cz = shapes[level + 1, 0], shapes[level + 1, 1], shapes[level + 1, 2]
    fo, co = starts[level], starts[level + 1]
    fx = 2 if cx < nx else 1
    fy = 2 if cy < ny else 1
    fz = 2 if cz < nz else 1
    csize = cx * cy * cz
    # scratch in the coarse level's slots: diag holds the Laplacian part, inv the row sums,
    # active the "any child" flag; offx/offy/offz accumulate the couplings between aggregates
    for c in range(co, co + csize):
        diag[c] = 0.0
        inv[c] = 0.0
        offx[c] = 0.0
        offy[c] = 0.0
        offz[c] = 0.0
        active[c] = False
    unx, uny, unz = np.uint64(nx), np.uint64(ny), np.uint64(nz)
    ucy, ucz = np.uint64(cy), np.uint64(cz)
    ufo, uco = np.uint64(fo), np.uint64(co)
    hz = U1 if fz == 2 else U0
    sx, sy = uny * unz, unz
    for ii in range(nx):
        i = np.uint64(ii)
        ci = np.uint64(ii // fx)
        inner_x = fx == 2 and (ii & 1) == 0 and ii + 1 < nx
        outer_x = (fx == 1 or (ii & 1) == 1) and ii + 1 < nx
        for jj in range(ny):
            j = np.uint64(jj)
            cj = np.uint64(jj // fy)
            inner_y = fy == 2 and (jj & 1) == 0 and jj + 1 < ny
            outer_y = (fy == 1 or (jj & 1) == 1) and jj + 1 < ny
            base = ufo + (i * uny + j) * unz
            cbase = uco + (ci * ucy + cj) * ucz
            for kk in range(nz):
                k = np.uint64(kk)
                n = base + k
                if not active[n]:
                    inv[n] = 0.0
                    continue
                d = diag[n]
                inv[n] = 1.0 / d if d > 0.0 else 0.0  # an entry cut off from every neighbour
                c = cbase + (k >> hz)
                m = d
                if i > U0:
                    m += offx[n - sx]
                if i + U1 < unx:
                    m += offx[n]
                if j > U0:
                    m += offy[n - sy]
                if j + U1 < uny:
                    m += offy[n]
                if k > U0:
                    m += offz[n - U1]
                if k + U1 < unz:
                    m += offz[n]
                lap = d - m
                if inner_x:
                    lap += 2.0 * offx[n]
                if inner_y:
                    lap += 2.0 * offy[n]
                if fz == 2 and (kk & 1) == 0 and kk + 1 < nz:
                    lap += 2.0 * offz[n]
                if outer_x:
                    offx[c] += offx[n]
                if outer_y:
                    offy[c] += offy[n]
                if (fz == 1 or (kk & 1) == 1) and kk + 1 < nz:
                    offz[c] += offz[n]
                diag[c] += lap
                inv[c] += m
                active[c] = True
    for c in range(co, co + csize):
        d = scale_l * diag[c] + scale_m * inv[c]
        ref = scale_l * diag[c] + abs(scale_m * inv[c])
        ok = active[c] and d > 1e-12 * ref
        active[c] = ok
        diag[c] = d if ok else 0.0
        inv[c] = 1.0 / d if ok else 0.0
        offx[c] *= scale_l
        offy[c] *= scale_l
        offz[c] *= scale_l
    # a coupling to an inactive coarse cell must vanish (the stencil's contract), as must one
    # beyond the end of an axis
    csx, csy = cy * cz, cz
    for ci in range(cx):
        for cj in range(cy):
            for ck in range(cz):
                c = co + (ci * cy + cj) * cz + ck
                if ci == cx - 1:
                    offx[c] = 0.0
                if cj == cy - 1:
                    offy[c] = 0.0
                if ck == cz - 1:
                    offz[c] = 0.0
                if not active[c]:
                    offx[c] = 0.0
                    offy[c] = 0.0
                    offz[c] = 0.0
                    if ci > 0:
                        offx[c - csx] = 0.0
                    if cj > 0:
                        offy[c - csy] = 0.0
                    if ck > 0:
                        offz[c - 1] = 0.0


# The kernels below index with unsigned integers (solver.compiled.unsigned). The neighbour sum is written
# out in each kernel: as an inlined helper it runs far slower. Each is compiled serial and parallel
# (solver.compiled.parallel): their outer loop runs over the planes of a level, or over the
# coarse planes, whose iterations write disjoint entries, so both give the same bits; the small
# dispatchers after them pick one per level. The outer loop runs along the first axis of the
# kernels' order (a 3D grid's x; a 2D grid's single plane, which runs on one thread).


def _sweep_rows(h, o, shape, b, x, colour):
    """One Gauss-Seidel pass over the cells of one colour (``(i + j + k) % 2``) of the level at
    offset ``o`` with ``shape`` of the hierarchy ``h``. An entry that is no unknown has
    ``inv = 0`` and no couplings, so it stays 0 without a test. A cell of one colour reads only
    the other's, so the planes are independent."""
    inv, offx, offy, offz = h.inv, h.offx, h.offy, h.offz
    nx, ny, nz = np.uint64(shape[0]), np.uint64(shape[1]), np.uint64(shape[2])
    sx, sy = ny * nz, nz
    uo = np.uint64(o)
    for ii in prange(shape[0]):
        i = np.uint64(ii)
        for jj in range(shape[1]):
            j = np.uint64(jj)
            base = uo + (i * ny + j) * nz
            k = np.uint64((ii + jj + colour) & 1)
            while k < nz:
                n = base + k
                s = b[n]
                if i > U0:
                    s -= offx[n - sx] * x[n - sx]
                if i + U1 < nx:
                    s -= offx[n] * x[n + sx]
                if j > U0:
                    s -= offy[n - sy] * x[n - sy]
                if j + U1 < ny:
                    s -= offy[n] * x[n + sy]
                if k > U0:
                    s -= offz[n - U1] * x[n - U1]
                if k + U1 < nz:
                    s -= offz[n] * x[n + U1]
                x[n] = s * inv[n]
                k += U2


def _residual_restrict_rows(h, level, b, x, colour):
    """Restrict ``b - A x`` of ``level`` of the hierarchy ``h`` into ``b`` of ``level + 1`` (sum
    over the children that are unknowns), from the cells of ``colour`` (``(i + j + k) % 2``) only.

    Right after a Gauss-Seidel half-sweep over the other colour, the residual of every cell of
    that colour is zero (to round-off: each was just solved for its neighbours, none of which
    has changed since), so half the cells need no residual at all. Each coarse plane (along the
    first axis) sums its own children's planes, in the order of the fine grid's rows."""
    diag, offx, offy, offz, active = h.diag, h.offx, h.offy, h.offz, h.active
    shapes, starts = h.shapes, h.starts
    nx, ny, nz = (
        np.uint64(shapes[level, 0]),
        np.uint64(shapes[level, 1]),
        np.uint64(shapes[level, 2]),
    )
    cx, cy, cz = (
        np.uint64(shapes[level + 1, 0]),
        np.uint64(shapes[level + 1, 1]),
        np.uint64(shapes[level + 1, 2]),
    )
    o, co = np.uint64(starts[level]), np.uint64(starts[level + 1])
    # children per coarse plane, and halving shifts (1 where an axis is coarsened): no integer
    # division in the loops
    fx = 2 if cx < nx else 1
    hy = U1 if cy < ny else U0
    hz = U1 if cz < nz else U0
    sx, sy = ny * nz, nz
    plane = cy * cz
    for ci in prange(shapes[level + 1, 0]):
        cplane = co + np.uint64(ci) * plane
        for c in range(plane):
            b[cplane + np.uint64(c)] = 0.0
        for ii in range(ci * fx, min(ci * fx + fx, shapes[level, 0])):
            i = np.uint64(ii)
            for jj in range(shapes[level, 1]):
                j = np.uint64(jj)
                base = o + (i * ny + j) * nz
                cbase = cplane + (j >> hy) * cz
                k = np.uint64((ii + jj + colour) & 1)
                while k < nz:
                    n = base + k
                    if active[n]:
                        r = b[n] - diag[n] * x[n]
                        if i > U0:
                            r -= offx[n - sx] * x[n - sx]
                        if i + U1 < nx:
                            r -= offx[n] * x[n + sx]
                        if j > U0:
                            r -= offy[n - sy] * x[n - sy]
                        if j + U1 < ny:
                            r -= offy[n] * x[n + sy]
                        if k > U0:
                            r -= offz[n - U1] * x[n - U1]
                        if k + U1 < nz:
                            r -= offz[n] * x[n + U1]
                        b[cbase + (k >> hz)] += r
                    k += U2


def _prolong_add_rows(shapes, starts, level, x):
    """Add the correction of ``level + 1`` to every entry of ``level`` (constant per child; an
    entry that is no unknown is overwritten with 0 by the next sweep)."""
    ny, nz = np.uint64(shapes[level, 1]), np.uint64(shapes[level, 2])
    cx, cy, cz = (
        np.uint64(shapes[level + 1, 0]),
        np.uint64(shapes[level + 1, 1]),
        np.uint64(shapes[level + 1, 2]),
    )
    nx = np.uint64(shapes[level, 0])
    o, co = np.uint64(starts[level]), np.uint64(starts[level + 1])
    hx = U1 if cx < nx else U0
    hy = U1 if cy < ny else U0
    hz = U1 if cz < nz else U0
    for ii in prange(shapes[level, 0]):
        i = np.uint64(ii)
        for jj in range(shapes[level, 1]):
            j = np.uint64(jj)
            base = o + (i * ny + j) * nz
            cbase = co + ((i >> hx) * cy + (j >> hy)) * cz
            for kk in range(shapes[level, 2]):
                k = np.uint64(kk)
                x[base + k] += x[cbase + (k >> hz)]


def _scale_into(src, scale, dst, lo, hi):
    """``dst[n] = src[n] * scale[n]`` for ``lo <= n < hi``.

    The loop runs over views of the range from index 0: an index the compiler can see is never
    negative needs no wraparound test, and the loop vectorizes."""
    s, f, d = src[lo:hi], scale[lo:hi], dst[lo:hi]
    for n in prange(s.size):
        d[n] = s[n] * f[n]


def _copy_into(src, dst, size):
    """``dst[n] = src[n]`` for the first ``size`` entries."""
    for n in prange(size):
        dst[n] = src[n]


def _masked_copy(src, active, dst, size):
    """``dst[n] = src[n]`` where ``active``, else 0, for the first ``size`` entries."""
    for n in prange(size):
        dst[n] = src[n] if active[n] else 0.0


def _cg_step(x, r, s, q, alpha, size):
    """``x += alpha s`` and ``r -= alpha q`` on the first ``size`` entries."""
    for n in prange(size):
        x[n] += alpha * s[n]
        r[n] -= alpha * q[n]


def _cg_direction(s, z, beta, size):
    """``s = z + beta s`` on the first ``size`` entries."""
    for n in prange(size):
        s[n] = z[n] + beta * s[n]


_sweep_s, _sweep_p = serial_and_parallel(_sweep_rows)
_restrict_s, _restrict_p = serial_and_parallel(_residual_restrict_rows)
_prolong_s, _prolong_p = serial_and_parallel(_prolong_add_rows)
_scale_s, _scale_p = serial_and_parallel(_scale_into)
_copy_s, _copy_p = serial_and_parallel(_copy_into)
_masked_s, _masked_p = serial_and_parallel(_masked_copy)
_cg_step_s, _cg_step_p = serial_and_parallel(_cg_step)
_direction_s, _direction_p = serial_and_parallel(_cg_direction)


@kernel
def _sweep(par, h, o, shape, b, x, colour):
    if par:
        _sweep_p(h, o, shape, b, x, colour)
    else:
        _sweep_s(h, o, shape, b, x, colour)


@kernel
def _residual_restrict(par, h, level, b, x, colour):
    if par:
        _restrict_p(h, level, b, x, colour)
    else:
        _restrict_s(h, level, b, x, colour)


@kernel
def _prolong_add(par, shapes, starts, level, x):
    if par:
        _prolong_p(shapes, starts, level, x)
    else:
        _prolong_s(shapes, starts, level, x)


@kernel
def _scale(par, src, scale, dst, lo, hi):
    if par:
        _scale_p(src, scale, dst, lo, hi)
    else:
        _scale_s(src, scale, dst, lo, hi)


@kernel
def v_cycle(h, r, z, b, x, par_cells=NEVER):
    """z = M^{-1} r, one symmetric V-cycle of the hierarchy ``h`` from a zero guess (``b``,
    ``x``: packed scratch; ``PRE_SMOOTH`` and ``COARSEST_SWEEPS`` are at least 1); levels of at
    least ``par_cells`` cells run the parallel kernels."""
    active, inv, shapes, starts = h.active, h.inv, h.shapes, h.starts
    levels = shapes.shape[0]
    size0 = r.size
    # the colours as int64, not literals: the sweeps compile once, not once per colour
    even, odd = np.int64(0), np.int64(1)
    par0 = size0 >= par_cells
    if par0:
        _copy_p(r, b, size0)
    else:
        _copy_s(r, b, size0)
    for lev in range(levels):
        o, shape = starts[lev], shapes[lev]
        cells = shape[0] * shape[1] * shape[2]
        par = cells >= par_cells
        # The first half-sweep (colour 0) starts from x = 0 and so reads no neighbour: it is
        # x = b / diag. Written over the whole level, it also fills colour 1, which the next
        # half-sweep overwrites without reading. (The same values as sweeping from zeros.)
        _scale(par, b, inv, x, o, o + cells)
        _sweep(par, h, o, shape, b, x, odd)
        for _ in range((PRE_SMOOTH if lev < levels - 1 else COARSEST_SWEEPS) - 1):
            _sweep(par, h, o, shape, b, x, even)
            _sweep(par, h, o, shape, b, x, odd)
        if lev < levels - 1:
            # the last half-sweep was colour 1: only colour 0 has a residual left
            _residual_restrict(par, h, lev, b, x, 0)
    for _ in range(COARSEST_SWEEPS):
        _sweep(par, h, o, shape, b, x, odd)
        _sweep(par, h, o, shape, b, x, even)
    for lev in range(levels - 2, -1, -1):
        o, shape = starts[lev], shapes[lev]
        par = shape[0] * shape[1] * shape[2] >= par_cells
        _prolong_add(par, shapes, starts, lev, x)
        for _ in range(PRE_SMOOTH):
            _sweep(par, h, o, shape, b, x, odd)
            _sweep(par, h, o, shape, b, x, even)
    if par0:
        _masked_p(x, active, z, size0)
    else:
        _masked_s(x, active, z, size0)


@kernel
def build_levels(h, scales):
    """Fill every coarse level of the hierarchy ``h`` (and every level's inverse diagonal) from
    the finest."""
    diag, active, inv, shapes = h.diag, h.active, h.inv, h.shapes
    levels = shapes.shape[0]
    for lev in range(levels - 1):
        coarsen(h, lev, scales[0], scales[1])
    if levels == 1:
        for n in range(shapes[0, 0] * shapes[0, 1] * shapes[0, 2]):
            inv[n] = 1.0 / diag[n] if active[n] and diag[n] > 0.0 else 0.0


@kernel
def _stencil(par, diag, offx, offy, offz, active, strides, x, out):
    if par:
        apply_stencil_parallel(diag, offx, offy, offz, active, strides, x, out)
    else:
        apply_stencil(diag, offx, offy, offz, active, strides, x, out)


@kernel
def mgpcg_flat(h, bvec, x, tol, max_iter, work, par_cells=NEVER):
    """CG preconditioned by :func:`v_cycle` on the finest level of a built hierarchy ``h`` (its
    matrix occupies the first ``bvec.size`` entries of the packed arrays); ``work`` is (6, packed
    size) scratch; levels of at least ``par_cells`` cells run the parallel kernels (the inner
    products stay serial, so the result is the same either way). Returns (iterations, relative
    residual)."""
    diag, offx, offy, offz, active, shapes = h.diag, h.offx, h.offy, h.offz, h.active, h.shapes
    size = bvec.size
    par = size >= par_cells
    r, s, q, z, vb, vx = work[0], work[1], work[2], work[3], work[4], work[5]
    nx, ny, nz = shapes[0, 0], shapes[0, 1], shapes[0, 2]
    strides = (ny * nz if nx > 1 else 0, nz if ny > 1 else 0, 1 if nz > 1 else 0)
    bnorm = np.sqrt(dot(bvec, bvec))
    if bnorm == 0.0:
        for n in range(size):
            if active[n]:
                x[n] = 0.0
        return 0, 0.0
    _stencil(par, diag, offx, offy, offz, active, strides, x, q[:size])
    for n in range(size):
        r[n] = bvec[n] - q[n] if active[n] else 0.0
    rnorm = np.sqrt(dot(r[:size], r[:size]))
    if rnorm <= tol * bnorm:
        return 0, rnorm / bnorm
    v_cycle(h, r[:size], z, vb, vx, par_cells)
    for n in range(size):
        s[n] = z[n]
    sigma = dot(z, r[:size])
    it = 0
    while it < max_iter:
        it += 1
        _stencil(par, diag, offx, offy, offz, active, strides, s[:size], q)
        denom = dot(q, s[:size])
        if denom <= 0.0:
            break
        alpha = sigma / denom
        if par:
            _cg_step_p(x, r, s, q, alpha, size)
        else:
            _cg_step_s(x, r, s, q, alpha, size)
        rnorm = np.sqrt(dot(r, r[:size]))
        if rnorm <= tol * bnorm:
            break
        v_cycle(h, r[:size], z, vb, vx, par_cells)
        sigma_new = dot(z, r[:size])
        if sigma_new <= 0.0:
            break
        beta = sigma_new / sigma
        sigma = sigma_new
        if par:
            _direction_p(s, z, beta, size)
        else:
            _direction_s(s, z, beta, size)
    return it, rnorm / bnorm


# mgpcg_flat and every driver below it with each parallel kernel replaced by its serial self: a
# solve that never runs on threads compiles no parallel kernel (solver.compiled.parallel).
_SERIAL = {
    "_sweep_p": _sweep_s,
    "_restrict_p": _restrict_s,
    "_prolong_p": _prolong_s,
    "_scale_p": _scale_s,
    "_copy_p": _copy_s,
    "_masked_p": _masked_s,
    "_cg_step_p": _cg_step_s,
    "_direction_p": _direction_s,
    "apply_stencil_parallel": apply_stencil,
}
for _driver in (_sweep, _residual_restrict, _prolong_add, _scale, _stencil, v_cycle, mgpcg_flat):
    _SERIAL[_driver.py_func.__name__] = serial_twin(_driver, _SERIAL)
mgpcg_flat_serial = _SERIAL["mgpcg_flat"]


class Multigrid:
    """MGPCG for systems of one grid shape; arrays are allocated once and reused every solve.

    ``scales`` = (Laplacian part, row-sum part) of the coarse operators: ``PRESSURE_SCALES`` for
    the Poisson matrix, ``DIFFUSION_SCALES`` for an implicit viscosity solve (its identity term
    is a mass, which aggregation sums exactly). ``threads`` and ``adaptive``: see the module
    docstring."""

    def __init__(
        self,
        shape: tuple[int, int, int],
        dim: int,
        scales: tuple[float, float] = PRESSURE_SCALES,
        threads: int = 1,
        adaptive: bool = False,
    ) -> None:
        self.shape = tuple(int(c) for c in shape)
        self.dim = dim
        if threads < 1:
            raise ValueError(f"threads must be >= 1, got {threads}")
        #: Threads for the 3D levels of at least ``PARALLEL_MIN_CELLS`` cells (1: all serial).
        self.threads = int(threads)
        #: Whether each solve picks threads or one by their recent cost (when :attr:`parallel`).
        self.adaptive = bool(adaptive)
        #: The choice between one thread (0) and ``threads`` (1), for adaptive solves.
        self.choice = TimedChoice(2)
        # A grid one cell deep (2D) is seen as (1, nx, ny), so that the kernels' innermost loop
        # runs along a long axis. A 3D grid keeps its own order, with no copies into another
        # (the copies cost more than a reordering gains on flat grids).
        self.perm = (
            tuple(int(a) for a in np.argsort(self.shape, kind="stable"))
            if self.shape[2] == 1
            else (0, 1, 2)
        )
        self.unperm = tuple(int(a) for a in np.argsort(self.perm))
        inner = tuple(self.shape[a] for a in self.perm)
        self._inner_shape = inner
        self._size0 = int(np.prod(inner))
        # whether the grid's own C order already is the kernels' order (a 2D grid's is: its
        # moved axis is one cell long)
        self._same_order = bool(np.empty(self.shape).transpose(self.perm).flags.c_contiguous)
        shapes = level_shapes(inner)  # type: ignore[arg-type]
        sizes = [int(np.prod(s)) for s in shapes]
        self.shapes = np.array(shapes, dtype=np.int64)
        self.starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
        total = int(sum(sizes))
        self.diag = np.zeros(total)
        self.off = (np.zeros(total), np.zeros(total), np.zeros(total))
        self.inv = np.zeros(total)
        self.active = np.zeros(total, dtype=np.bool_)
        self.work = np.zeros((6, total))
        #: The arrays above, as the kernels take them.
        self.hierarchy = Hierarchy(
            self.diag, *self.off, self.active, self.inv, self.shapes, self.starts
        )
        # the right-hand side and solution in the kernels' order, when that is not the grid's
        self._b = np.zeros(sizes[0])
        self._x = np.zeros(sizes[0])
        self.scales = np.array(scales, dtype=np.float64)
        #: Whether the last solve ran on threads.
        self.last_on_threads = False

    @property
    def levels(self) -> int:
        return int(self.shapes.shape[0])

    @property
    def parallel(self) -> bool:
        """Whether solves run their largest levels on ``threads`` threads (adaptive: may run
        them there): in 3D, with a finest level of at least ``PARALLEL_MIN_CELLS`` cells (2D
        levels are one plane: their outer loops have nothing to split)."""
        return (
            self.threads > 1 and self.dim == 3 and int(self.shapes[0].prod()) >= PARALLEL_MIN_CELLS
        )

    def load(self, system: StencilSystem) -> None:
        """Take ``system`` as the finest level and build the coarse ones from it."""
        if tuple(system.diag.shape) != self.shape or system.dim != self.dim:
            raise ValueError(f"system shape {system.diag.shape} does not match {self.shape}")
        perm = self.perm
        # each array copied once, straight into the packed level (a transposed view is read
        # with its strides)
        np.copyto(self._finest(self.diag), system.diag.transpose(perm))
        for a in range(3):
            np.copyto(self._finest(self.off[a]), system.off[perm[a]].transpose(perm))
        # an entry cut off from every neighbour (a fluid cell walled in by solid) has a zero row:
        # it is no unknown
        np.logical_and(
            system.active.transpose(perm),
            self._finest(self.diag) > 0.0,
            out=self._finest(self.active),
        )
        build_levels(self.hierarchy, self.scales)

    def solve(
        self, system: StencilSystem, b: np.ndarray, x: np.ndarray, tol: float, max_iter: int
    ) -> SolveReport:
        """Solve ``system`` x = ``b`` in place in ``x`` (warm start), as :func:`solver.linalg.pcg.solve`;
        active entries with a zero row are left as they are and out of the residual."""
        self.load(system)
        return self.solve_loaded(b, x, tol, max_iter)

    def solve_loaded(self, b: np.ndarray, x: np.ndarray, tol: float, max_iter: int) -> SolveReport:
        """:meth:`solve` for the system last given to :meth:`load` (which may have run on another
        thread while this one did other work)."""
        if tuple(b.shape) != self.shape or tuple(x.shape) != self.shape:
            raise ValueError(f"b and x must have the shape {self.shape}, got {b.shape}, {x.shape}")
        # the kernels work on x itself where it is contiguous in their order
        in_place = self._same_order and x.transpose(self.perm).flags.c_contiguous
        if self._same_order:
            flat_x = np.ascontiguousarray(x.transpose(self.perm)).reshape(-1)
            flat_b = np.ascontiguousarray(b.transpose(self.perm)).reshape(-1)
        else:
            flat_x, flat_b = self._x[: x.size], self._b[: b.size]
            np.copyto(self._finest(flat_x), x.transpose(self.perm))
            np.copyto(self._finest(flat_b), b.transpose(self.perm))
        args = (self.hierarchy, flat_b, flat_x, tol, max_iter, self.work)
        on_threads = self.parallel and (not self.adaptive or self.choice.pick() == 1)
        start = time.perf_counter()
        if on_threads:
            with parallel_section(self.threads):
                it, res = mgpcg_flat(*args, PARALLEL_MIN_CELLS)
        elif self.parallel:  # the same compiled kernel as on threads
            it, res = mgpcg_flat(*args, NEVER)
        else:
            it, res = mgpcg_flat_serial(*args)
        if self.parallel and self.adaptive:
            self.choice.record(int(on_threads), (time.perf_counter() - start) / max(int(it), 1))
        self.last_on_threads = on_threads
        if not in_place:
            x[...] = self._finest(flat_x).transpose(self.unperm)
        return SolveReport(iterations=int(it), residual=float(res), converged=bool(res <= tol))

    def _finest(self, flat: np.ndarray) -> np.ndarray:
        """The finest level's entries of a packed (or finest-sized) array, as a view shaped like
        the grid in the kernels' axis order."""
        return flat[: self._size0].reshape(self._inner_shape)
