"""Quadrature rules on the exact surface of a probe shape, in its body frame.

A rule is points on the surface, their outward unit normals and weights (the length or area each
point stands for), so that ``sum(w * f(x))`` approximates the surface integral of ``f``. Circles
use the midpoint rule in angle (spectrally accurate for smooth periodic integrands), spheres a
Fibonacci lattice of equal-area points, boxes the midpoint rule on every side. The weights sum to
the exact perimeter or area.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from solver.shapes import Ball, Box


@dataclass(frozen=True)
class SurfaceRule:
    """Points (n, dim), outward unit normals (n, dim) and weights (n,) (m in 2D, m^2 in 3D)."""

    points: np.ndarray
    normals: np.ndarray
    weights: np.ndarray


def surface_rule(shape: object, dim: int, spacing_m: float) -> SurfaceRule:
    """A rule on ``shape``'s surface with points about ``spacing_m`` apart (at least 16 in 2D,
    64 in 3D). ``shape`` is a :class:`~solver.shapes.Ball` or :class:`~solver.shapes.Box`."""
    if dim not in (2, 3):
        raise ValueError(f"dim must be 2 or 3, got {dim}")
    if not (spacing_m > 0 and np.isfinite(spacing_m)):
        raise ValueError(f"spacing must be finite and > 0, got {spacing_m}")
    if isinstance(shape, Ball):
        return (
            _circle(shape.radius_m, spacing_m) if dim == 2 else _sphere(shape.radius_m, spacing_m)
        )
    if isinstance(shape, Box):
        size = np.asarray(shape.size_m, dtype=float)
        if size.shape != (dim,):
            raise ValueError(f"a {dim}D box needs {dim} sizes, got {shape.size_m}")
        return _box(size, spacing_m)
    raise ValueError(f"no surface rule for {type(shape).__name__}; expected a Ball or a Box")


def _circle(radius: float, spacing: float) -> SurfaceRule:
    n = max(16, int(np.ceil(2.0 * np.pi * radius / spacing)))
    theta = (np.arange(n) + 0.5) * (2.0 * np.pi / n)
    normals = np.column_stack([np.cos(theta), np.sin(theta)])
    return SurfaceRule(radius * normals, normals, np.full(n, 2.0 * np.pi * radius / n))


def _sphere(radius: float, spacing: float) -> SurfaceRule:
    area = 4.0 * np.pi * radius**2
    n = max(64, int(np.ceil(area / spacing**2)))
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    r = np.sqrt(1.0 - z * z)
    phi = np.pi * (3.0 - np.sqrt(5.0)) * i
    normals = np.column_stack([r * np.cos(phi), r * np.sin(phi), z])
    return SurfaceRule(radius * normals, normals, np.full(n, area / n))


def _box(size: np.ndarray, spacing: float) -> SurfaceRule:
    dim = len(size)
    half = 0.5 * size
    points, normals, weights = [], [], []
    for axis in range(dim):
        others = [a for a in range(dim) if a != axis]
        counts = [max(4, int(np.ceil(size[a] / spacing))) for a in others]
        axes_1d = [
            (np.arange(c) + 0.5) / c * size[a] - half[a]
            for a, c in zip(others, counts, strict=True)
        ]
        mesh = np.meshgrid(*axes_1d, indexing="ij")
        cell = float(np.prod([size[a] / c for a, c in zip(others, counts, strict=True)]))
        for sign in (-1.0, 1.0):
            p = np.zeros((mesh[0].size, dim))
            for a, m in zip(others, mesh, strict=True):
                p[:, a] = m.ravel()
            p[:, axis] = sign * half[axis]
            nrm = np.zeros_like(p)
            nrm[:, axis] = sign
            points.append(p)
            normals.append(nrm)
            weights.append(np.full(len(p), cell))
    return SurfaceRule(np.concatenate(points), np.concatenate(normals), np.concatenate(weights))
