"""Rigid probe shapes as signed distance functions in their own body frame.

Any object with ``sdf(points) -> distances`` (points shape (..., d) in metres, body frame,
negative inside) and a ``bounding_radius_m`` attribute can be a probe shape; the brushes layer
provides its own tips through the same protocol. A shape may also give ``support(direction)``,
``max over the shape of direction . x`` (body frame): the cut geometry then samples only the
probe's tight world box, not its bounding sphere's. A centrally symmetric shape may also give
``half_extents(rot)``, that box's half extents turned by ``rot`` (``support`` of each row) in
one call.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from solver.compiled.jit import kernel


def _sum_of_squares(points: np.ndarray) -> np.ndarray:
    """``sum_i points[..., i]^2``, written per component (numpy's reductions over a last axis of
    length 2 or 3 cost several times the arithmetic)."""
    total = points[..., 0] * points[..., 0]
    for a in range(1, points.shape[-1]):
        total = total + points[..., a] * points[..., a]
    return total


@kernel
def _ball_sdf(points, radius, out):
    """:meth:`Ball.sdf` point by point (``points`` (n, d)), in the numpy version's order."""
    n, d = points.shape
    for m in range(n):
        total = points[m, 0] * points[m, 0]
        for a in range(1, d):
            total = total + points[m, a] * points[m, a]
        out[m] = np.sqrt(total) - radius


@kernel
def _box_sdf(points, half, out):
    """:meth:`Box.sdf` point by point (``points`` (n, d)), in the numpy version's order: the
    same maxima and minima (numpy's ``maximum``/``minimum`` keep the first of equal values, as
    these comparisons do), the same sums."""
    n, d = points.shape
    for m in range(n):
        q = abs(points[m, 0]) - half[0]
        out_q = q if q >= 0.0 else 0.0
        total = out_q * out_q
        inside = q
        for a in range(1, d):
            q = abs(points[m, a]) - half[a]
            out_q = q if q >= 0.0 else 0.0
            total = total + out_q * out_q
            inside = inside if inside >= q else q
        out[m] = np.sqrt(total) + (inside if inside <= 0.0 else 0.0)


def _compiled(kernel, points: np.ndarray, param) -> np.ndarray:  # type: ignore[no-untyped-def]
    """``kernel`` over ``points`` (..., d) flattened, shaped back."""
    p = np.asarray(points, dtype=float)
    flat = np.ascontiguousarray(p.reshape(-1, p.shape[-1]))
    out = np.empty(flat.shape[0])
    kernel(flat, param, out)
    return out.reshape(p.shape[:-1])


@runtime_checkable
class Shape(Protocol):
    """A solid described by its signed distance (metres, negative inside) in its body frame."""

    @property
    def bounding_radius_m(self) -> float: ...

    def sdf(self, points: np.ndarray) -> np.ndarray: ...


@dataclass(frozen=True)
class Ball:
    """A circle (2D) or sphere (3D) of ``radius_m`` centred on the body origin."""

    radius_m: float

    @property
    def bounding_radius_m(self) -> float:
        return self.radius_m

    def sdf(self, points: np.ndarray) -> np.ndarray:
        return _compiled(_ball_sdf, points, float(self.radius_m))

    def sdf_numpy(self, points: np.ndarray) -> np.ndarray:
        """:meth:`sdf` as numpy expressions (the reference of the compiled form)."""
        return np.sqrt(_sum_of_squares(points)) - self.radius_m

    def cross_section_m(self, dim: int) -> float:
        """Projected frontal extent (2D: length per unit depth) or area (3D)."""
        return 2.0 * self.radius_m if dim == 2 else np.pi * self.radius_m**2


@dataclass(frozen=True)
class Box:
    """An axis-aligned (in the body frame) box with full extents ``size_m``."""

    size_m: tuple[float, ...]

    @property
    def bounding_radius_m(self) -> float:
        return 0.5 * float(np.linalg.norm(self.size_m))

    def sdf(self, points: np.ndarray) -> np.ndarray:
        half = 0.5 * np.asarray(self.size_m, dtype=float)
        return _compiled(_box_sdf, points, half)

    def sdf_numpy(self, points: np.ndarray) -> np.ndarray:
        """:meth:`sdf` as numpy expressions (the reference of the compiled form)."""
        half = 0.5 * np.asarray(self.size_m, dtype=float)
        q = np.abs(points) - half
        outside = np.sqrt(_sum_of_squares(np.maximum(q, 0.0)))
        inside = q[..., 0]
        for a in range(1, q.shape[-1]):
            inside = np.maximum(inside, q[..., a])
        return outside + np.minimum(inside, 0.0)

    def support(self, direction: np.ndarray) -> float:
        """``max over the box of direction . x``."""
        return 0.5 * float(np.abs(np.asarray(direction, dtype=float)) @ np.asarray(self.size_m))

    def half_extents(self, rot: np.ndarray) -> list[float]:
        """Half the world extents of the box turned by ``rot``: :meth:`support` of each row
        (the same values, in one call)."""
        size, rows = np.asarray(self.size_m, dtype=float), np.abs(rot)
        return [0.5 * float(rows[a] @ size) for a in range(rows.shape[0])]

    def cross_section_m(self, dim: int) -> float:
        """Frontal extent across x (2D: height) or frontal area across x (3D)."""
        return float(self.size_m[1]) if dim == 2 else float(self.size_m[1] * self.size_m[2])


@dataclass(frozen=True)
class FilletedBox:
    """A :class:`Box` of full extents ``size_m`` whose edges and corners are rounded with
    ``radius_m`` (the rounding stays inside the box's extents; ``radius_m`` at most half the
    smallest extent)."""

    size_m: tuple[float, ...]
    radius_m: float

    @property
    def bounding_radius_m(self) -> float:
        return 0.5 * float(np.linalg.norm(self.size_m))

    def sdf(self, points: np.ndarray) -> np.ndarray:
        return self._core().sdf(points) - self.radius_m

    def support(self, direction: np.ndarray) -> float:
        """``max over the shape of direction . x``."""
        d = np.asarray(direction, dtype=float)
        return self._core().support(d) + self.radius_m * float(np.linalg.norm(d))

    def half_extents(self, rot: np.ndarray) -> list[float]:
        """As :meth:`Box.half_extents`."""
        core = self._core().half_extents(rot)
        return [c + self.radius_m * float(np.linalg.norm(rot[a])) for a, c in enumerate(core)]

    def _core(self) -> Box:
        return Box(tuple(float(s) - 2.0 * self.radius_m for s in self.size_m))

    def cross_section_m(self, dim: int) -> float:
        return Box(self.size_m).cross_section_m(dim)


def with_rounded_corners(shape: Shape, radius_m: float) -> Shape:
    """``shape`` with its sharp corners rounded by at least ``radius_m``: a :class:`Box` becomes a
    :class:`FilletedBox` (the radius clamped to half its smallest extent); a shape with a
    ``with_min_corner_radius(radius_m)`` method (a brush's box tip) answers for itself; smooth
    shapes come back unchanged."""
    if radius_m <= 0.0:
        return shape
    if isinstance(shape, Box):
        radius = min(radius_m, 0.5 * min(float(s) for s in shape.size_m))
        return FilletedBox(tuple(float(s) for s in shape.size_m), radius)
    rounded = getattr(shape, "with_min_corner_radius", None)
    return rounded(radius_m) if callable(rounded) else shape
