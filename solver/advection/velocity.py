"""Semi-Lagrangian advection of the staggered velocity (numba kernels).

Each face sample is traced back through the velocity field with a second-order (midpoint)
Runge-Kutta step and the field is interpolated there. ``maccormack`` adds the bounded
second-order correction of Selle et al. (2008): forward, then backward advection estimates the
error, and the corrected value is clamped to the range of the interpolation stencil at the
departure point, so the scheme cannot create new extrema. (Falling back to the first-order value
there instead, Selle's other limiter, damps the vortices behind a cylinder more: Schaefer-Turek
2D-2 at D/h 20, c_L max 0.921 against 0.926 clamped, c_D max 3.287 against 3.258.)
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numba import njit

from solver.bundles import Velocity
from solver.compiled.jit import inline_kernel, kernel
from solver.compiled.threads import run_components, run_shared
from solver.interp import lerp, range_at, velocity_in_cells

LINEAR = 0
MACCORMACK = 1
SCHEMES = {"linear": LINEAR, "maccormack": MACCORMACK}
#: Slabs per component when the advection shares its threads with other work
#: (:func:`advect_velocity`'s ``lead``): fine enough that the threads end together.
SHARED_SLABS = 4
#: The kernels' floating-point license: each blend ``a + f * (b - a)`` may become one fused
#: multiply-add (a rounding fewer; no other reordering, NaN and infinity kept as IEEE has them),
#: which speeds up the 3D kernel.
FUSED = {"contract"}


@inline_kernel
def _trace(u, v, w, dim, gx, gy, gz, c):
    """Departure point (cell units) of the point (gx, gy, gz) over a step of ``c = dt / h``."""
    ax, ay, az = velocity_in_cells(u, v, w, dim, gx, gy, gz)
    mx = gx - 0.5 * c * ax
    my = gy - 0.5 * c * ay
    mz = gz - 0.5 * c * az
    bx, by, bz = velocity_in_cells(u, v, w, dim, mx, my, mz)
    return gx - c * bx, gy - c * by, gz - c * bz


@njit(cache=True, nogil=True, fastmath=FUSED)
def advect_component(
    q: np.ndarray,
    axis: int,
    velocity: Velocity,
    dim: int,
    h: float,
    dt: float,
    out: np.ndarray,
    bounds: tuple[np.ndarray, np.ndarray],
    want_range: bool,
) -> None:
    """Advect samples ``q`` of component ``axis`` (-1: cell centres) by ``velocity`` (a
    :class:`~solver.bundles.Velocity` of a ``dim``-D grid) over ``dt`` into ``out``.

    With ``want_range``, ``bounds`` = (lo, hi) receive the extrema of the interpolation stencil
    at each departure point (for MacCormack limiting). Positions are traced in cell units (no
    division per sample).
    """
    u, v, w = velocity
    lo, hi = bounds
    nx, ny, nz = q.shape
    ox = 0.0 if axis == 0 else 0.5
    oy = 0.0 if axis == 1 else 0.5
    oz = 0.0 if axis == 2 else 0.5
    c = dt / h
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                bx, by, bz = _trace(u, v, w, dim, i + ox, j + oy, k + oz, c)
                sx, sy, sz = bx - ox, by - oy, bz - oz
                out[i, j, k] = lerp(q, sx, sy, sz)
                if want_range:
                    a, b = range_at(q, sx, sy, sz)
                    lo[i, j, k] = a
                    hi[i, j, k] = b


@inline_kernel
def _half(a: float, b: float) -> float:
    """``lerp``'s blend at fraction 0.5, in its operation order."""
    return a + 0.5 * (b - a)


@inline_kernel
def _unclamped(axis: int, along: int, cells: int) -> tuple[int, int, float]:
    """For face samples of component ``axis``, along grid axis ``along`` of ``cells`` cells: the
    indices ``[lo, hi)`` whose first trace stage clamps no interpolation fraction, and the
    samples' offset from the cell corner (0 along their own axis, else 1/2)."""
    if axis == along:
        return 1, cells, 0.0
    return 0, cells - 1, 0.5


@inline_kernel
def _face_velocity(u, v, w, axis, i, j, k):
    """Velocity (cell units per unit time) at face sample ``(i, j, k)`` of component ``axis``
    of a 3D grid, a sample away from the walls (as :func:`advect_face_3d` picks them), as
    :func:`~solver.interp.velocity_in_cells` gives it there: the face's own component is its
    sample, each other one a blend of the four samples around it at fraction 0.5."""
    if axis == 0:
        ay = _half(_half(v[i - 1, j, k], v[i, j, k]), _half(v[i - 1, j + 1, k], v[i, j + 1, k]))
        az = _half(_half(w[i - 1, j, k], w[i, j, k]), _half(w[i - 1, j, k + 1], w[i, j, k + 1]))
        return u[i, j, k], ay, az
    if axis == 1:
        ax = _half(_half(u[i, j - 1, k], u[i + 1, j - 1, k]), _half(u[i, j, k], u[i + 1, j, k]))
        az = _half(_half(w[i, j - 1, k], w[i, j, k]), _half(w[i, j - 1, k + 1], w[i, j, k + 1]))
        return ax, v[i, j, k], az
    ax = _half(_half(u[i, j, k - 1], u[i + 1, j, k - 1]), _half(u[i, j, k], u[i + 1, j, k]))
    ay = _half(_half(v[i, j, k - 1], v[i, j + 1, k - 1]), _half(v[i, j, k], v[i, j + 1, k]))
    return ax, ay, w[i, j, k]


@njit(cache=True, nogil=True, fastmath=FUSED)
def advect_face_3d(
    q: np.ndarray,
    axis: int,
    u: np.ndarray,
    v: np.ndarray,
    w: np.ndarray,
    h: float,
    dt: float,
    out: np.ndarray,
    i0: int,
    i1: int,
) -> None:
    """:func:`advect_component` for face samples of a 3D grid (``axis`` 0-2), linear scheme,
    with the same values and less work: the trace's first stage starts on a face sample, where
    the velocity's interpolation weights are 0, 1/2 or 1. Away from the walls (where no
    fraction is clamped) :func:`_face_velocity` reads 9 samples instead of interpolating 24
    (the blends at weight 0 and 1 give exactly the sample, so nothing changes); at the walls
    the general interpolation runs. Only the rows ``i0 <= i < i1`` of ``out`` are written (a
    slab; two threads can fill one component)."""
    nx, ny, nz = q.shape
    cx, cy, cz = w.shape[0], u.shape[1], v.shape[2]  # the grid's cells
    lo_i, hi_i, ox = _unclamped(axis, 0, cx)
    lo_j, hi_j, oy = _unclamped(axis, 1, cy)
    lo_k, hi_k, oz = _unclamped(axis, 2, cz)
    c = dt / h
    for i in range(max(i0, 0), min(i1, nx)):
        inner_i = lo_i <= i < hi_i
        for j in range(ny):
            inner = inner_i and lo_j <= j < hi_j
            for k in range(nz):
                gx, gy, gz = i + ox, j + oy, k + oz
                if inner and lo_k <= k < hi_k:
                    ax, ay, az = _face_velocity(u, v, w, axis, i, j, k)
                else:
                    ax, ay, az = velocity_in_cells(u, v, w, 3, gx, gy, gz)
                mx = gx - 0.5 * c * ax
                my = gy - 0.5 * c * ay
                mz = gz - 0.5 * c * az
                bx, by, bz = velocity_in_cells(u, v, w, 3, mx, my, mz)
                out[i, j, k] = lerp(q, gx - c * bx - ox, gy - c * by - oy, gz - c * bz - oz)


@njit(cache=True, nogil=True, fastmath=FUSED)
def advect_face_2d(
    q: np.ndarray,
    axis: int,
    u: np.ndarray,
    v: np.ndarray,
    h: float,
    dt: float,
    out: np.ndarray,
    i0: int,
    i1: int,
) -> None:
    """:func:`advect_face_3d` on a 2D grid (one cell deep, ``axis`` 0 or 1): the face's own
    component is its sample, the other the blend of the four around it; rows ``i0 <= i < i1``."""
    nx, ny, _ = q.shape
    cx, cy = v.shape[0], u.shape[1]  # the grid's cells
    lo_i, hi_i, ox = _unclamped(axis, 0, cx)
    lo_j, hi_j, oy = _unclamped(axis, 1, cy)
    w = u  # never read in 2D
    c = dt / h
    for i in range(max(i0, 0), min(i1, nx)):
        inner_i = lo_i <= i < hi_i
        for j in range(ny):
            gx, gy = i + ox, j + oy
            if inner_i and lo_j <= j < hi_j:
                if axis == 0:
                    ax = u[i, j, 0]
                    ay = _half(
                        _half(v[i - 1, j, 0], v[i, j, 0]), _half(v[i - 1, j + 1, 0], v[i, j + 1, 0])
                    )
                else:
                    ax = _half(
                        _half(u[i, j - 1, 0], u[i + 1, j - 1, 0]), _half(u[i, j, 0], u[i + 1, j, 0])
                    )
                    ay = v[i, j, 0]
            else:
                ax, ay, _ = velocity_in_cells(u, v, w, 2, gx, gy, 0.5)
            bx, by, _ = velocity_in_cells(u, v, w, 2, gx - 0.5 * c * ax, gy - 0.5 * c * ay, 0.5)
            out[i, j, 0] = lerp(q, gx - c * bx - ox, gy - c * by - oy, 0.0)


@kernel
def maccormack_correct(
    q: np.ndarray, fwd: np.ndarray, back: np.ndarray, lo: np.ndarray, hi: np.ndarray
) -> None:
    """Overwrite ``fwd`` with the MacCormack value ``fwd + (q - back) / 2`` clamped to
    ``[lo, hi]``."""
    for idx in range(q.size):
        value = fwd.flat[idx] + 0.5 * (q.flat[idx] - back.flat[idx])
        fwd.flat[idx] = min(max(value, lo.flat[idx]), hi.flat[idx])


def advect(
    q: np.ndarray,
    axis: int,
    velocity: tuple[np.ndarray, np.ndarray, np.ndarray],
    dim: int,
    h: float,
    dt: float,
    scheme: int = LINEAR,
) -> np.ndarray:
    """Return ``q`` (component ``axis``, -1 for cell centres) advected by ``velocity`` over ``dt``."""
    u, v, w = velocity
    out = np.empty_like(q)
    if scheme == LINEAR:
        if dim == 3 and axis >= 0:
            advect_face_3d(q, axis, u, v, w, h, dt, out, 0, q.shape[0])
        elif dim == 2 and axis >= 0:
            advect_face_2d(q, axis, u, v, h, dt, out, 0, q.shape[0])
        else:
            advect_component(q, axis, Velocity(u, v, w), dim, h, dt, out, (out, out), False)
        return out
    mac = Velocity(u, v, w)
    lo = np.empty_like(q)
    hi = np.empty_like(q)
    advect_component(q, axis, mac, dim, h, dt, out, (lo, hi), True)
    back = np.empty_like(q)
    advect_component(out, axis, mac, dim, h, -dt, back, (back, back), False)
    maccormack_correct(q, out, back, lo, hi)
    return out


def advect_velocity(
    velocity: tuple[np.ndarray, np.ndarray, np.ndarray],
    dim: int,
    h: float,
    dt: float,
    scheme: int,
    threads: int,
    lead: Callable[[], object] | None = None,
) -> list[np.ndarray]:
    """The ``dim`` velocity components, each advected by ``velocity`` over ``dt``, on
    ``threads`` threads (:mod:`solver.compiled.threads`): under the linear scheme each
    component is cut into ``threads`` slabs of rows, so two threads share three components
    evenly; otherwise whole components. The same values as :func:`advect`, one by one.

    ``lead``: other work that reads and writes nothing the advection does (a step's geometry),
    run first on a pool thread while this one advects; the components, cut finer
    (:data:`SHARED_SLABS` slabs each under the linear scheme), are then taken by whichever
    thread is free (:func:`~solver.compiled.threads.run_shared`). With one thread, ``lead``
    runs first."""
    linear = scheme == LINEAR and threads > 1
    parts = (SHARED_SLABS if lead is not None else threads) if linear else 1
    u, v, w = velocity
    outs: list[np.ndarray] = [np.empty(0)] * dim

    def slab(index: int) -> None:
        a, part = divmod(index, parts)
        if not linear:
            outs[a] = advect(velocity[a], a, velocity, dim, h, dt, scheme)
            return
        rows = velocity[a].shape[0]
        i0, i1 = rows * part // parts, rows * (part + 1) // parts
        if dim == 3:
            advect_face_3d(velocity[a], a, u, v, w, h, dt, outs[a], i0, i1)
        else:
            advect_face_2d(velocity[a], a, u, v, h, dt, outs[a], i0, i1)

    if linear:  # every output exists before any thread writes a slab of it
        for a in range(dim):
            outs[a] = np.empty_like(velocity[a])
    if lead is not None:
        run_shared(slab, dim * parts, threads, lead)
    else:
        run_components(slab, dim * parts, threads)
    return outs
