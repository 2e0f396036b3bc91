"""Kernels of the wet paint's transport on the canvas texels: a limited flux-form upwind scheme.

Fields are (P, ny, nx) paint volumes per area (metres), one per pigment, on square texels of unit
width; velocities are in texels per second on the texel faces: ``ux`` (ny, nx + 1) on the faces
between texels ``x - 1`` and ``x`` (index ``x``), ``vy`` (ny + 1, nx) likewise along y. The
outermost faces are walls (their velocity is ignored), so nothing enters or leaves the box.

One sub-step of ``dt`` moves, through every interior face, ``|c| q_f`` from the upwind texel ``a``
to the downwind one ``b`` (``c = u dt`` the face's Courant number). ``q_f`` is the upwind value
with a van Leer limited slope, ``q_f = q_a + (1 - |c|) s d / (s + d)`` where ``d = q_b - q_a``,
``s = q_a - q_up`` and ``s d > 0`` (else ``q_f = q_a``): second order where the paint is smooth,
first order at a steep edge, which stays a few texels sharp; never negative.

Every flux leaves one texel and enters its neighbour: each pigment's total is conserved to
round-off. With sub-steps such that every texel's outgoing Courant numbers sum to at most 1
(:func:`substeps_needed`), a limited face value can still exceed its donor's paint where two
faces draw on it; each texel's outgoing fluxes are then scaled down together to at most what it
holds (still conservative: a flux has a single donor), so no texel goes negative.
"""

from __future__ import annotations

import numpy as np

from solver import inline_kernel, kernel, substeps_for

#: Hard cap on sub-steps per call (faster paint means something upstream is wrong).


@kernel
def outflow_courant(ux, vy):
    """Largest sum of outgoing face speeds (texels/s) over the texels (walls excluded)."""
    ny, nx = vy.shape[0] - 1, ux.shape[1] - 1
    worst = 0.0
    for y in range(ny):
        for x in range(nx):
            out = 0.0
            if x > 0 and ux[y, x] < 0.0:
                out -= ux[y, x]
            if x < nx - 1 and ux[y, x + 1] > 0.0:
                out += ux[y, x + 1]
            if y > 0 and vy[y, x] < 0.0:
                out -= vy[y, x]
            if y < ny - 1 and vy[y + 1, x] > 0.0:
                out += vy[y + 1, x]
            worst = max(worst, out)
    return worst


@inline_kernel
def _face_value(q_up, q_a, q_b, courant):
    """Limited upwind face value (module docstring); ``courant`` = |c| in [0, 1]."""
    d = q_b - q_a
    s = q_a - q_up
    if s * d <= 0.0:
        return q_a
    return q_a + (1.0 - courant) * s * d / (s + d)


@kernel
def face_fluxes(q, ux, vy, dt, fx, fy):
    """Signed fluxes (amounts moved in +x, +y) of one sub-step into ``fx`` (P, ny, nx + 1) and
    ``fy`` (P, ny + 1, nx); wall faces get 0."""
    n_p, ny, nx = q.shape
    fx[:] = 0.0
    fy[:] = 0.0
    for p in range(n_p):
        for y in range(ny):
            for x in range(1, nx):
                c = ux[y, x] * dt
                if c > 0.0:
                    up = x - 2 if x >= 2 else x - 1
                    fx[p, y, x] = c * _face_value(q[p, y, up], q[p, y, x - 1], q[p, y, x], c)
                elif c < 0.0:
                    up = x + 1 if x + 1 < nx else x
                    fx[p, y, x] = c * _face_value(q[p, y, up], q[p, y, x], q[p, y, x - 1], -c)
        for y in range(1, ny):
            for x in range(nx):
                c = vy[y, x] * dt
                if c > 0.0:
                    up = y - 2 if y >= 2 else y - 1
                    fy[p, y, x] = c * _face_value(q[p, up, x], q[p, y - 1, x], q[p, y, x], c)
                elif c < 0.0:
                    up = y + 1 if y + 1 < ny else y
                    fy[p, y, x] = c * _face_value(q[p, up, x], q[p, y, x], q[p, y - 1, x], -c)


@kernel
def limit_outflow(q, fx, fy, scale):
    """Scale each texel's outgoing fluxes so that they sum to at most its paint (in place)."""
    n_p, ny, nx = q.shape
    for p in range(n_p):
        for y in range(ny):
            for x in range(nx):
                out = max(-fx[p, y, x], 0.0) + max(fx[p, y, x + 1], 0.0)
                out += max(-fy[p, y, x], 0.0) + max(fy[p, y + 1, x], 0.0)
                scale[y, x] = q[p, y, x] / out if out > q[p, y, x] else 1.0
        for y in range(ny):
            for x in range(1, nx):
                f = fx[p, y, x]
                fx[p, y, x] = f * (scale[y, x - 1] if f > 0.0 else scale[y, x])
        for y in range(1, ny):
            for x in range(nx):
                f = fy[p, y, x]
                fy[p, y, x] = f * (scale[y - 1, x] if f > 0.0 else scale[y, x])


@kernel
def apply_fluxes(q, fx, fy):
    """``q`` minus the divergence of the fluxes (in place), clamped at 0 against round-off."""
    n_p, ny, nx = q.shape
    for p in range(n_p):
        for y in range(ny):
            for x in range(nx):
                net = fx[p, y, x] - fx[p, y, x + 1] + fy[p, y, x] - fy[p, y + 1, x]
                if net != 0.0:
                    q[p, y, x] = max(q[p, y, x] + net, 0.0)


@kernel
def advance(q, ux, vy, dt, substeps):
    """Move fields ``q`` (P, ny, nx) by ``substeps`` equal sub-steps over ``dt`` s (in place)."""
    n_p, ny, nx = q.shape
    fx = np.empty((n_p, ny, nx + 1))
    fy = np.empty((n_p, ny + 1, nx))
    scale = np.empty((ny, nx))
    h = dt / substeps
    for _ in range(substeps):
        face_fluxes(q, ux, vy, h, fx, fy)
        limit_outflow(q, fx, fy, scale)
        apply_fluxes(q, fx, fy)


def substeps_needed(ux: np.ndarray, vy: np.ndarray, dt_s: float) -> int:
    """Sub-steps that keep every texel's outgoing Courant numbers summing to at most 1."""
    return substeps_for(outflow_courant(ux, vy) * dt_s, "the texel transport")
