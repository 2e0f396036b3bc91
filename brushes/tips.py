"""Signed-distance geometry of brush tips, in the tip's body frame (metres).

Every shape has ``sdf(points)`` taking points of shape ``(..., d)`` (d = 3 for tips, 2 for the
planar shapes) and returning signed distance of shape ``(...)``: negative inside, zero on the
surface, positive outside; and ``bounding_radius_m``, the largest distance from the body origin to
any point of the shape. 3D tips put the tip apex at the body origin with the handle along +z, and
also give ``support(direction)``, the support function ``max_{x in shape} direction . x`` (for any
non-zero direction, not only unit ones), used to find the tip's lowest point when it is tilted.

Tips:
    :class:`RoundCone`: a round brush, the convex hull of a small tip sphere and a larger belly
        sphere on the axis (a capsule when both radii are equal).
    :class:`RoundedBox`: a flat brush (thin in y, with rounded edges) or, with corner radius 0,
        the paper's square probe as a box.
Planar shapes (2D grids): :class:`Disc`, :class:`Rect` (the paper's 2D square probe), and
:class:`Section`, the cut of a 3D tip by a plane of constant body z.
Deformation: :class:`Splayed` widens a tip laterally (bristles splaying under pressure).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property
from typing import Protocol, runtime_checkable

import numpy as np

from brushes.tips_kernels import (
    ROUND_CONE,
    ROUNDED_BOX,
    round_cone_params,
    rounded_box_params,
    section_sdf,
    tip_sdf,
)

#: A tip's compiled form (:mod:`brushes.tips_kernels`): ``(kind, params, lateral scale)``.
Kernel = tuple[int, np.ndarray, float]


@runtime_checkable
class Shape(Protocol):
    """What the solver needs from a probe shape."""

    @property
    def bounding_radius_m(self) -> float:
        """Largest distance (m) from the body origin to any point of the shape."""
        ...

    def sdf(self, points: np.ndarray) -> np.ndarray:
        """Signed distance (m), shape (...), of body-frame points (..., d)."""
        ...


@runtime_checkable
class TipShape(Shape, Protocol):
    """A 3D brush tip: a :class:`Shape` with a support function."""

    def support(self, direction: np.ndarray) -> float:
        """``max over the shape of direction . x`` (m times |direction|) for direction (3,)."""
        ...


def _points(points: np.ndarray, dim: int) -> np.ndarray:
    p = np.asarray(points, dtype=float)
    if p.ndim == 0 or p.shape[-1] != dim:
        raise ValueError(f"expected points of shape (..., {dim}), got {p.shape}")
    return p


def _compiled_sdf(kernel: Kernel, points: np.ndarray, section_z: float | None = None) -> np.ndarray:
    """A tip's signed distance at ``points`` ((..., 3), or (..., 2) on the plane ``section_z``)
    through its compiled form."""
    p = _points(points, 3 if section_z is None else 2)
    flat = np.ascontiguousarray(p.reshape(-1, p.shape[-1]))
    out = np.empty(flat.shape[0])
    kind, params, scale = kernel
    if section_z is None:
        tip_sdf(kind, params, scale, flat, out)
    else:
        section_sdf(kind, params, scale, float(section_z), flat, out)
    return out.reshape(p.shape[:-1])


@dataclass(frozen=True)
class RoundCone:
    """Convex hull of a tip sphere (radius ``tip_radius_m``) touching the apex at the origin and a
    belly sphere (radius ``belly_radius_m``) whose top touches ``z = length_m``; axis along +z.

    Requires ``length_m > 2 * max(tip_radius_m, belly_radius_m)`` (otherwise one sphere swallows
    the other). Exact signed distance.
    """

    tip_radius_m: float
    belly_radius_m: float
    length_m: float

    def __post_init__(self) -> None:
        r1, r2, length = self.tip_radius_m, self.belly_radius_m, self.length_m
        if min(r1, r2) <= 0.0 or length <= 2.0 * max(r1, r2):
            raise ValueError(
                "round cone needs positive radii and length_m > 2 * the larger radius, "
                f"got tip {r1}, belly {r2}, length {length}"
            )

    @property
    def _centres(self) -> tuple[float, float]:
        return self.tip_radius_m, self.length_m - self.belly_radius_m

    @property
    def bounding_radius_m(self) -> float:
        return self.length_m

    @cached_property
    def kernel(self) -> Kernel:
        """The compiled form (:mod:`brushes.tips_kernels`)."""
        return (
            ROUND_CONE,
            round_cone_params(self.tip_radius_m, self.belly_radius_m, self.length_m),
            1.0,
        )

    def sdf(self, points: np.ndarray) -> np.ndarray:
        return _compiled_sdf(self.kernel, points)

    def sdf_numpy(self, points: np.ndarray) -> np.ndarray:
        """:meth:`sdf` in numpy (the compiled form's reference)."""
        p = _points(points, 3)
        r1, r2 = self.tip_radius_m, self.belly_radius_m
        c1, c2 = self._centres
        h = c2 - c1
        b = (r1 - r2) / h
        a = math.sqrt(1.0 - b * b)
        rho = np.hypot(p[..., 0], p[..., 1])
        qz = p[..., 2] - c1
        k = -b * rho + a * qz
        side = a * rho + b * qz - r1
        low = np.hypot(rho, qz) - r1
        high = np.hypot(rho, qz - h) - r2
        return np.where(k < 0.0, low, np.where(k > a * h, high, side))

    def support(self, direction: np.ndarray) -> float:
        d = np.asarray(direction, dtype=float)
        norm = float(np.linalg.norm(d))
        c1, c2 = self._centres
        return max(d[2] * c1 + self.tip_radius_m * norm, d[2] * c2 + self.belly_radius_m * norm)


@dataclass(frozen=True)
class RoundedBox:
    """Box of full size ``width_m`` (x) by ``thickness_m`` (y) by ``length_m`` (z) whose edges are
    rounded with ``corner_radius_m``; its bottom face is centred on the origin (the apex) and it
    extends to ``z = length_m``. Exact signed distance.
    """

    width_m: float
    thickness_m: float
    length_m: float
    corner_radius_m: float = 0.0

    def __post_init__(self) -> None:
        smallest = min(self.width_m, self.thickness_m, self.length_m)
        if smallest <= 0.0 or not 0.0 <= self.corner_radius_m <= 0.5 * smallest:
            raise ValueError(
                "rounded box needs positive sizes and 0 <= corner_radius_m <= half the smallest "
                f"size, got {self.width_m}, {self.thickness_m}, {self.length_m}, "
                f"corner {self.corner_radius_m}"
            )

    @property
    def _core(self) -> tuple[np.ndarray, np.ndarray]:
        r = self.corner_radius_m
        half = 0.5 * np.array([self.width_m, self.thickness_m, self.length_m]) - r
        return np.array([0.0, 0.0, 0.5 * self.length_m]), half

    @property
    def bounding_radius_m(self) -> float:
        centre, half = self._core
        return float(np.linalg.norm(centre + half)) + self.corner_radius_m

    @cached_property
    def kernel(self) -> Kernel:
        """The compiled form (:mod:`brushes.tips_kernels`)."""
        centre, half = self._core
        return ROUNDED_BOX, rounded_box_params(centre[2], half, self.corner_radius_m), 1.0

    def sdf(self, points: np.ndarray) -> np.ndarray:
        return _compiled_sdf(self.kernel, points)

    def sdf_numpy(self, points: np.ndarray) -> np.ndarray:
        """:meth:`sdf` in numpy (the compiled form's reference)."""
        centre, half = self._core
        q = np.abs(_points(points, 3) - centre) - half
        outside = np.linalg.norm(np.maximum(q, 0.0), axis=-1)
        inside = np.minimum(q.max(axis=-1), 0.0)
        return outside + inside - self.corner_radius_m

    def support(self, direction: np.ndarray) -> float:
        d = np.asarray(direction, dtype=float)
        centre, half = self._core
        core = float(d @ centre + np.abs(d) @ half)
        return core + self.corner_radius_m * float(np.linalg.norm(d))

    def with_min_corner_radius(self, radius_m: float) -> RoundedBox:
        """This box with its edges rounded by at least ``radius_m`` (at most half its smallest
        size): the solver rounds sharp corners at its grid's scale."""
        radius = min(
            max(radius_m, self.corner_radius_m),
            0.5 * min(self.width_m, self.thickness_m, self.length_m),
        )
        return self if radius == self.corner_radius_m else replace(self, corner_radius_m=radius)


@dataclass(frozen=True)
class Disc:
    """Planar disc of radius ``radius_m`` centred on the origin. Exact signed distance."""

    radius_m: float

    @property
    def bounding_radius_m(self) -> float:
        return self.radius_m

    def sdf(self, points: np.ndarray) -> np.ndarray:
        return np.linalg.norm(_points(points, 2), axis=-1) - self.radius_m


@dataclass(frozen=True)
class Rect:
    """Planar rectangle ``width_m`` (x) by ``height_m`` (y) centred on the origin, corners rounded
    with ``corner_radius_m`` (0: the paper's square probe). Exact signed distance.
    """

    width_m: float
    height_m: float
    corner_radius_m: float = 0.0

    def __post_init__(self) -> None:
        smallest = min(self.width_m, self.height_m)
        if smallest <= 0.0 or not 0.0 <= self.corner_radius_m <= 0.5 * smallest:
            raise ValueError(f"bad rectangle {self.width_m} x {self.height_m}")

    @property
    def bounding_radius_m(self) -> float:
        r = self.corner_radius_m
        return math.hypot(0.5 * self.width_m - r, 0.5 * self.height_m - r) + r

    def sdf(self, points: np.ndarray) -> np.ndarray:
        r = self.corner_radius_m
        half = 0.5 * np.array([self.width_m, self.height_m]) - r
        q = np.abs(_points(points, 2)) - half
        outside = np.linalg.norm(np.maximum(q, 0.0), axis=-1)
        return outside + np.minimum(q.max(axis=-1), 0.0) - r


@dataclass(frozen=True)
class Splayed:
    """A 3D tip stretched by ``lateral_scale`` in body x and y (bristles splaying), z unchanged.

    The sign of ``sdf`` is exact; its magnitude is a lower bound on the true distance (scaling the
    base distance by ``min(1, lateral_scale)``), which is all voxelization needs.
    """

    base: TipShape
    lateral_scale: float

    def __post_init__(self) -> None:
        if not self.lateral_scale > 0.0:
            raise ValueError(f"lateral_scale must be positive, got {self.lateral_scale}")

    @property
    def _scale(self) -> np.ndarray:
        return np.array([self.lateral_scale, self.lateral_scale, 1.0])

    @property
    def bounding_radius_m(self) -> float:
        return self.base.bounding_radius_m * max(1.0, self.lateral_scale)

    @property
    def kernel(self) -> Kernel | None:
        """The compiled form (:mod:`brushes.tips_kernels`), or None when the base has none or is
        stretched itself."""
        base = getattr(self.base, "kernel", None)
        if base is None or base[2] != 1.0:
            return None
        return base[0], base[1], self.lateral_scale

    def sdf(self, points: np.ndarray) -> np.ndarray:
        kernel = self.kernel
        if kernel is not None:
            return _compiled_sdf(kernel, points)
        p = _points(points, 3) / self._scale
        return self.base.sdf(p) * min(1.0, self.lateral_scale)

    def support(self, direction: np.ndarray) -> float:
        return self.base.support(np.asarray(direction, dtype=float) * self._scale)


@dataclass(frozen=True)
class Section:
    """The planar cut of a 3D tip by the body plane ``z = z_m``, as a 2D shape in body (x, y).

    The sign of ``sdf`` is exact; outside the cut its magnitude is the 3D distance, a lower bound
    on the in-plane distance. An empty cut (``z_m`` outside the tip) is positive everywhere.
    """

    base: Shape
    z_m: float

    @property
    def bounding_radius_m(self) -> float:
        return self.base.bounding_radius_m

    def sdf(self, points: np.ndarray) -> np.ndarray:
        kernel = getattr(self.base, "kernel", None)
        if kernel is not None:
            return _compiled_sdf(kernel, points, self.z_m)
        p = _points(points, 2)
        z = np.full((*p.shape[:-1], 1), self.z_m)
        return self.base.sdf(np.concatenate([p, z], axis=-1))


def lowest_point_z(shape: TipShape, rotation: np.ndarray) -> float:
    """Height (m) of the tip's lowest point above its apex once rotated by ``rotation`` (3, 3).

    It is ``min over the shape of (R x)_z = -support(R^T (-z))``; zero for an upright tip whose
    apex is its lowest point, negative when a tilt swings part of the tip below the apex.
    """
    down_body = np.asarray(rotation, dtype=float).T @ np.array([0.0, 0.0, -1.0])
    return -shape.support(down_body)
