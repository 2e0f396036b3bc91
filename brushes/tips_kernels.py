"""Compiled signed distances of the brush tips (numba kernels), for :mod:`brushes.tips`.

A tip's ``sdf`` runs on every paint step over thousands of points: the paint grid's cut
geometry samples it at the lattice nodes around the tip, and the bristle texture over the
texels of its footprint. As numpy expressions each call made a dozen temporary arrays; here
each point is one pass. A tip is described by ``(kind, params, scale)``: its base shape
(:data:`ROUND_CONE` or :data:`ROUNDED_BOX`), that shape's numbers (:func:`round_cone_params`,
:func:`rounded_box_params`) and the lateral stretch of :class:`brushes.tips.Splayed` (1 for
none). Each kernel does the numpy version's arithmetic in its order, so both give the same
values (checked in the tests).
"""

from __future__ import annotations

import math

import numpy as np

from solver import kernel

ROUND_CONE = 0
ROUNDED_BOX = 1


def round_cone_params(tip_radius_m: float, belly_radius_m: float, length_m: float) -> np.ndarray:
    """``(r1, r2, c1, h, a, b)`` of a round cone: radii, tip sphere centre height, distance
    between the centres, and the cosine and sine of the side's slope."""
    r1, r2 = tip_radius_m, belly_radius_m
    c1, c2 = r1, length_m - r2
    h = c2 - c1
    b = (r1 - r2) / h
    return np.array([r1, r2, c1, h, math.sqrt(1.0 - b * b), b])


def rounded_box_params(centre_z_m: float, half: np.ndarray, corner_radius_m: float) -> np.ndarray:
    """``(cz, hx, hy, hz, r)`` of a rounded box: its centre height, the half sizes of its core
    (the box less the rounding) and the corner radius."""
    return np.array([centre_z_m, half[0], half[1], half[2], corner_radius_m])


@kernel
def _round_cone(x, y, z, p):
    r1, r2, c1, h, a, b = p[0], p[1], p[2], p[3], p[4], p[5]
    rho = math.hypot(x, y)
    qz = z - c1
    k = -b * rho + a * qz
    if k < 0.0:
        return math.hypot(rho, qz) - r1
    if k > a * h:
        return math.hypot(rho, qz - h) - r2
    return a * rho + b * qz - r1


@kernel
def _rounded_box(x, y, z, p):
    qx = abs(x - 0.0) - p[1]
    qy = abs(y - 0.0) - p[2]
    qz = abs(z - p[0]) - p[3]
    mx, my, mz = max(qx, 0.0), max(qy, 0.0), max(qz, 0.0)
    outside = math.sqrt(mx * mx + my * my + mz * mz)
    inside = min(max(qx, qy, qz), 0.0)
    return outside + inside - p[4]


@kernel
def tip_distance(kind, p, scale, x, y, z):
    """The tip's signed distance at body-frame point (x, y, z), its compiled form ``(kind, p,
    scale)``: what :func:`tip_sdf` and :func:`section_sdf` give at each point."""
    if scale != 1.0:  # Splayed: stretched laterally, the distance scaled down to a lower bound
        x, y, z = x / scale, y / scale, z / 1.0
    d = _round_cone(x, y, z, p) if kind == ROUND_CONE else _rounded_box(x, y, z, p)
    return d * min(1.0, scale) if scale != 1.0 else d


@kernel
def tip_sdf(kind, params, scale, points, out):
    """``out[n]`` = the tip's signed distance at body-frame point ``points[n]`` ((n, 3))."""
    for n in range(points.shape[0]):
        out[n] = tip_distance(kind, params, scale, points[n, 0], points[n, 1], points[n, 2])


@kernel
def section_sdf(kind, params, scale, z, points, out):
    """``out[n]`` = the tip's signed distance at ``(points[n, 0], points[n, 1], z)`` ((n, 2))."""
    for n in range(points.shape[0]):
        out[n] = tip_distance(kind, params, scale, points[n, 0], points[n, 1], z)
