"""Trilinear interpolation of staggered MAC samples (numba kernels).

A sample array ``q`` of component ``axis`` (or of cell centres, ``axis = -1``) is interpolated at a
point; the point is clamped to the range the samples span, so values beyond the outermost samples
are held constant.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, nogil=True, inline="always")
def _clamped_index(x: float, offset: float, h: float, n: int) -> tuple[int, float]:
    s = x / h - offset
    if s <= 0.0:
        return 0, 0.0
    if s >= n - 1:
        return max(n - 2, 0), 1.0 if n > 1 else 0.0
    i = int(s)
    return i, s - i


@njit(cache=True, nogil=True)
def sample(q: np.ndarray, axis: int, x: float, y: float, z: float, h: float) -> float:
    """Trilinear value of samples ``q`` (component ``axis``, or -1 for cell centres) at (x, y, z).

    Coordinates are relative to the grid origin, metres; ``h`` is the cell size.
    """
    nx, ny, nz = q.shape
    i, fx = _clamped_index(x, 0.0 if axis == 0 else 0.5, h, nx)
    j, fy = _clamped_index(y, 0.0 if axis == 1 else 0.5, h, ny)
    k, fz = _clamped_index(z, 0.0 if axis == 2 else 0.5, h, nz)
    i1 = min(i + 1, nx - 1)
    j1 = min(j + 1, ny - 1)
    if nz == 1:
        a = q[i, j, 0] * (1.0 - fx) + q[i1, j, 0] * fx
        b = q[i, j1, 0] * (1.0 - fx) + q[i1, j1, 0] * fx
        return a * (1.0 - fy) + b * fy
    k1 = min(k + 1, nz - 1)
    c00 = q[i, j, k] * (1.0 - fx) + q[i1, j, k] * fx
    c10 = q[i, j1, k] * (1.0 - fx) + q[i1, j1, k] * fx
    c01 = q[i, j, k1] * (1.0 - fx) + q[i1, j, k1] * fx
    c11 = q[i, j1, k1] * (1.0 - fx) + q[i1, j1, k1] * fx
    c0 = c00 * (1.0 - fy) + c10 * fy
    c1 = c01 * (1.0 - fy) + c11 * fy
    return c0 * (1.0 - fz) + c1 * fz


@njit(cache=True, nogil=True)
def sample_range(
    q: np.ndarray, axis: int, x: float, y: float, z: float, h: float
) -> tuple[float, float]:
    """Minimum and maximum of the samples that :func:`sample` blends at (x, y, z)."""
    nx, ny, nz = q.shape
    i, _ = _clamped_index(x, 0.0 if axis == 0 else 0.5, h, nx)
    j, _ = _clamped_index(y, 0.0 if axis == 1 else 0.5, h, ny)
    k, _ = _clamped_index(z, 0.0 if axis == 2 else 0.5, h, nz)
    lo = np.inf
    hi = -np.inf
    for a in range(i, min(i + 2, nx)):
        for b in range(j, min(j + 2, ny)):
            for c in range(k, min(k + 2, nz)):
                v = q[a, b, c]
                lo = min(lo, v)
                hi = max(hi, v)
    return lo, hi


@njit(cache=True, nogil=True)
def velocity_at(
    u: np.ndarray, v: np.ndarray, w: np.ndarray, dim: int, x: float, y: float, z: float, h: float
) -> tuple[float, float, float]:
    """Velocity vector at a point from the three staggered components (w is 0 in 2D)."""
    vx = sample(u, 0, x, y, z, h)
    vy = sample(v, 1, x, y, z, h)
    vz = sample(w, 2, x, y, z, h) if dim == 3 else 0.0
    return vx, vy, vz


@njit(cache=True)
def sample_many(q: np.ndarray, axis: int, points: np.ndarray, h: float) -> np.ndarray:
    """:func:`sample` at each row of ``points`` (shape (n, 3), relative to the origin)."""
    out = np.empty(points.shape[0])
    for n in range(points.shape[0]):
        out[n] = sample(q, axis, points[n, 0], points[n, 1], points[n, 2], h)
    return out


@njit(cache=True)
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
