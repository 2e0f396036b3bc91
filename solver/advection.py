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

import numpy as np
from numba import njit

from solver.interp import lerp, range_at, velocity_in_cells

LINEAR = 0
MACCORMACK = 1
SCHEMES = {"linear": LINEAR, "maccormack": MACCORMACK}
#: What ``SolverSettings.advection`` may name: a scheme, or ``none`` (Stokes flow: the velocity's
#: self-advection is left out, for flows whose Reynolds number is far below 1).
ADVECTION_CHOICES = (*SCHEMES, "none")


@njit(cache=True, nogil=True, inline="always")
def _trace(u, v, w, dim, gx, gy, gz, c):
    """Departure point (cell units) of the point (gx, gy, gz) over a step of ``c = dt / h``."""
    ax, ay, az = velocity_in_cells(u, v, w, dim, gx, gy, gz)
    mx = gx - 0.5 * c * ax
    my = gy - 0.5 * c * ay
    mz = gz - 0.5 * c * az
    bx, by, bz = velocity_in_cells(u, v, w, dim, mx, my, mz)
    return gx - c * bx, gy - c * by, gz - c * bz


@njit(cache=True, nogil=True)
def advect_component(
    q: np.ndarray,
    axis: int,
    u: np.ndarray,
    v: np.ndarray,
    w: np.ndarray,
    dim: int,
    h: float,
    dt: float,
    out: np.ndarray,
    lo: np.ndarray,
    hi: np.ndarray,
    want_range: bool,
) -> None:
    """Advect samples ``q`` of component ``axis`` (-1: cell centres) by ``dt`` into ``out``.

    With ``want_range``, ``lo``/``hi`` receive the extrema of the interpolation stencil at each
    departure point (for MacCormack limiting). Positions are traced in cell units (no division
    per sample).
    """
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


@njit(cache=True, nogil=True)
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
        advect_component(q, axis, u, v, w, dim, h, dt, out, out, out, False)
        return out
    lo = np.empty_like(q)
    hi = np.empty_like(q)
    advect_component(q, axis, u, v, w, dim, h, dt, out, lo, hi, True)
    back = np.empty_like(q)
    advect_component(out, axis, u, v, w, dim, h, -dt, back, back, back, False)
    maccormack_correct(q, out, back, lo, hi)
    return out
