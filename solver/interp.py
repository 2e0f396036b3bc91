"""Trilinear interpolation of staggered MAC samples (numba kernels).

A sample array ``q`` of component ``axis`` (or of cell centres, ``axis = -1``) is interpolated at a
point; the point is clamped to the range the samples span, so values beyond the outermost samples
are held constant.
"""

from __future__ import annotations

import numpy as np

from solver.compiled.jit import inline_kernel, kernel


@inline_kernel
def _clamped(s: float, n: int) -> tuple[int, float]:
    """Lower sample index and fraction of sample coordinate ``s``, clamped to [0, n - 1]."""
    if s <= 0.0:
        return 0, 0.0
    if s >= n - 1:
        return max(n - 2, 0), 1.0 if n > 1 else 0.0
    i = int(s)
    return i, s - i


@inline_kernel
def _clamped_index(x: float, offset: float, h: float, n: int) -> tuple[int, float]:
    return _clamped(x / h - offset, n)


@inline_kernel
def lerp(q: np.ndarray, s0: float, s1: float, s2: float) -> float:
    """Trilinear (bilinear when one sample deep) value of ``q`` at sample coordinates
    (s0, s1, s2): index units, clamped to the samples' range (NaN clamps to 0). The kernels'
    inner routine: no division, inlined.

    The lower index along each axis is unsigned (it spares numba's wrap-around test on every
    access), found by branch-free min/max; the upper one is the next sample, or the same one
    along a one-sample axis. Written out, not through helpers: numba inlines a helper by
    compiling it again at each call site, and the kernels inline this one many times."""
    nx, ny, nz = q.shape
    if not s0 > 0.0:  # also NaN
        s0 = 0.0
    if not s1 > 0.0:
        s1 = 0.0
    s0 = min(s0, nx - 1.0)
    s1 = min(s1, ny - 1.0)
    li = min(int(s0), max(nx - 2, 0))
    lj = min(int(s1), max(ny - 2, 0))
    fx = s0 - li
    fy = s1 - lj
    i = np.uint64(li)
    j = np.uint64(lj)
    i1 = i + np.uint64(1) if nx > 1 else i
    j1 = j + np.uint64(1) if ny > 1 else j
    if nz == 1:
        z = np.uint64(0)
        a = q[i, j, z] + fx * (q[i1, j, z] - q[i, j, z])
        b = q[i, j1, z] + fx * (q[i1, j1, z] - q[i, j1, z])
        return a + fy * (b - a)
    if not s2 > 0.0:
        s2 = 0.0
    s2 = min(s2, nz - 1.0)
    lk = min(int(s2), max(nz - 2, 0))
    fz = s2 - lk
    k = np.uint64(lk)
    k1 = k + np.uint64(1)
    c00 = q[i, j, k] + fx * (q[i1, j, k] - q[i, j, k])
    c10 = q[i, j1, k] + fx * (q[i1, j1, k] - q[i, j1, k])
    c01 = q[i, j, k1] + fx * (q[i1, j, k1] - q[i, j, k1])
    c11 = q[i, j1, k1] + fx * (q[i1, j1, k1] - q[i, j1, k1])
    c0 = c00 + fy * (c10 - c00)
    c1 = c01 + fy * (c11 - c01)
    return c0 + fz * (c1 - c0)


@inline_kernel
def velocity_in_cells(
    u: np.ndarray, v: np.ndarray, w: np.ndarray, dim: int, gx: float, gy: float, gz: float
) -> tuple[float, float, float]:
    """Velocity at a point given in cell units (position / h from the origin)."""
    vx = lerp(u, gx, gy - 0.5, gz - 0.5)
    vy = lerp(v, gx - 0.5, gy, gz - 0.5)
    vz = lerp(w, gx - 0.5, gy - 0.5, gz) if dim == 3 else 0.0
    return vx, vy, vz


@kernel
def sample(q: np.ndarray, axis: int, x: float, y: float, z: float, h: float) -> float:
    """Trilinear value of samples ``q`` (component ``axis``, or -1 for cell centres) at (x, y, z).

    Coordinates are relative to the grid origin, metres; ``h`` is the cell size.
    """
    inv = 1.0 / h
    return lerp(
        q,
        x * inv - (0.0 if axis == 0 else 0.5),
        y * inv - (0.0 if axis == 1 else 0.5),
        z * inv - (0.0 if axis == 2 else 0.5),
    )


@inline_kernel
def range_at(q: np.ndarray, s0: float, s1: float, s2: float) -> tuple[float, float]:
    """Minimum and maximum of the samples that :func:`lerp` blends at (s0, s1, s2) (its lower
    indices, written out as there)."""
    nx, ny, nz = q.shape
    if not s0 > 0.0:  # also NaN
        s0 = 0.0
    if not s1 > 0.0:
        s1 = 0.0
    if not s2 > 0.0:
        s2 = 0.0
    i = np.uint64(min(int(min(s0, nx - 1.0)), max(nx - 2, 0)))
    j = np.uint64(min(int(min(s1, ny - 1.0)), max(ny - 2, 0)))
    k = np.uint64(min(int(min(s2, nz - 1.0)), max(nz - 2, 0)))
    ii = (i, i + np.uint64(1) if nx > 1 else i)
    jj = (j, j + np.uint64(1) if ny > 1 else j)
    kk = (k, k + np.uint64(1) if nz > 1 else k)
    lo = np.inf
    hi = -np.inf
    for a in ii:
        for b in jj:
            for c in kk:
                v = q[a, b, c]
                lo = min(lo, v)
                hi = max(hi, v)
    return lo, hi


@kernel
def sample_range(
    q: np.ndarray, axis: int, x: float, y: float, z: float, h: float
) -> tuple[float, float]:
    """Minimum and maximum of the samples that :func:`sample` blends at (x, y, z)."""
    inv = 1.0 / h
    return range_at(
        q,
        x * inv - (0.0 if axis == 0 else 0.5),
        y * inv - (0.0 if axis == 1 else 0.5),
        z * inv - (0.0 if axis == 2 else 0.5),
    )


@kernel
def velocity_at(
    u: np.ndarray, v: np.ndarray, w: np.ndarray, dim: int, x: float, y: float, z: float, h: float
) -> tuple[float, float, float]:
    """Velocity vector at a point from the three staggered components (w is 0 in 2D)."""
    inv = 1.0 / h
    return velocity_in_cells(u, v, w, dim, x * inv, y * inv, z * inv)


@kernel
def sample_many(q: np.ndarray, axis: int, points: np.ndarray, h: float) -> np.ndarray:
    """:func:`sample` at each row of ``points`` (shape (n, 3), relative to the origin)."""
    out = np.empty(points.shape[0])
    for n in range(points.shape[0]):
        out[n] = sample(q, axis, points[n, 0], points[n, 1], points[n, 2], h)
    return out


@kernel
def sample_cells_fluid(
    q: np.ndarray, label: np.ndarray, points: np.ndarray, h: float
) -> np.ndarray:
    """Trilinear value of a cell-centred field at each point, from fluid cells only.

    Solid cells (``label >= 0`` or ``-2``) are left out and the weights of the fluid cells are
    renormalised, so that pressure sampled on a body's surface is the fluid's, not a blend with
    the (meaningless) value inside the body. NaN where no fluid cell is near.
    """
    nx, ny, nz = q.shape
    out = np.empty(points.shape[0])
    for n in range(points.shape[0]):
        i, fx = _clamped_index(points[n, 0], 0.5, h, nx)
        j, fy = _clamped_index(points[n, 1], 0.5, h, ny)
        k, fz = _clamped_index(points[n, 2], 0.5, h, nz)
        total = 0.0
        weight = 0.0
        for a in range(2):
            for b in range(2):
                for c in range(2):
                    ii, jj, kk = min(i + a, nx - 1), min(j + b, ny - 1), min(k + c, nz - 1)
                    if label[ii, jj, kk] != -1:
                        continue
                    wgt = (
                        (fx if a else 1.0 - fx) * (fy if b else 1.0 - fy) * (fz if c else 1.0 - fz)
                    )
                    total += wgt * q[ii, jj, kk]
                    weight += wgt
        out[n] = total / weight if weight > 1e-12 else np.nan
    return out
