"""Probes: rigid bodies moving through the fluid, voxelized into the grid.

A probe has a shape (see :mod:`solver.shapes`), a pose (centre and orientation) and a rigid
motion (linear velocity, angular velocity). It moves either at its set velocities or along a
keyframed path, interpolated linearly (orientations by slerp in 3D) or by a cubic spline
(``path_interpolation = "cubic"``: positions and 2D angles by a not-a-knot cubic spline, 3D
orientations by scipy's ``RotationSpline``), whose velocity is continuous: a linear path's velocity
jumps at every keyframe, and the fluid answers each jump with an added-mass impulse. Within a step
its velocities are the average over the step, so that the voxelized body moves by exactly the
displacement its boundary velocities describe.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Literal, get_args

import numpy as np

from common import quaternion as rotation
from solver.grid import Grid
from solver.shapes import Shape

PathInterpolation = Literal["linear", "cubic"]
PATH_INTERPOLATIONS: tuple[PathInterpolation, ...] = get_args(PathInterpolation)
Pose = tuple[np.ndarray, np.ndarray | float]


def cubic_path(path: np.ndarray, dim: int) -> Callable[[float], Pose]:
    """Pose at time t (inside the keyframes' span) on a cubic spline through ``path``."""
    from scipy.interpolate import CubicSpline
    from scipy.spatial.transform import Rotation, RotationSpline

    times = path[:, 0]
    kind = "not-a-knot" if len(times) > 3 else "natural"
    if dim == 2:
        spline = CubicSpline(times, path[:, 1:4], axis=0, bc_type=kind)

        def pose2(t_s: float) -> Pose:
            row = spline(t_s)
            return np.asarray(row[:2], dtype=float), float(row[2])

        return pose2
    centres = CubicSpline(times, path[:, 1:4], axis=0, bc_type=kind)
    quats = np.array([rotation.normalise(q) for q in path[:, 4:8]])
    spin = RotationSpline(times, Rotation.from_quat(quats[:, [1, 2, 3, 0]]))  # scipy: x, y, z, w

    def pose3(t_s: float) -> Pose:
        x, y, z, w = spin(t_s).as_quat()
        return np.asarray(centres(t_s), dtype=float), rotation.normalise(np.array([w, x, y, z]))

    return pose3


@dataclass
class Probe:
    """A rigid probe.

    Attributes:
        name: identifier used in results.
        shape: body-frame signed distance shape.
        dim: 2 or 3.
        centre_m: position of the body origin, world frame, shape (dim,).
        orientation: 2D angle (radians) or 3D unit quaternion [w, x, y, z].
        velocity_m_s: linear velocity, shape (dim,).
        angular_velocity_rad_s: 2D scalar, 3D vector (3,).
        path: optional keyframes, shape (n, 1 + dim + (1 or 4)): t, position, angle/quaternion.
        path_interpolation: ``"linear"`` or ``"cubic"`` (see the module docstring).
        reference_m: torque reference point in the body frame, shape (dim,) (default: origin).
    """

    name: str
    shape: Shape
    dim: int
    centre_m: np.ndarray
    orientation: np.ndarray | float = 0.0
    velocity_m_s: np.ndarray = field(default_factory=lambda: np.zeros(3))
    angular_velocity_rad_s: np.ndarray | float = 0.0
    path: np.ndarray | None = None
    reference_m: np.ndarray | None = None
    path_interpolation: PathInterpolation = "linear"
    _spline: Callable[[float], Pose] | None = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        d = self.dim
        self.centre_m = np.asarray(self.centre_m, dtype=float).reshape(d).copy()
        self.velocity_m_s = np.asarray(self.velocity_m_s, dtype=float).reshape(-1)[:d].copy()
        if d == 3:
            q = self.orientation if np.ndim(self.orientation) else [1.0, 0.0, 0.0, 0.0]
            self.orientation = rotation.normalise(np.asarray(q, dtype=float))
            self.angular_velocity_rad_s = np.asarray(
                self.angular_velocity_rad_s if np.ndim(self.angular_velocity_rad_s) else [0, 0, 0],
                dtype=float,
            ).copy()
        else:
            self.orientation = float(self.orientation)
            self.angular_velocity_rad_s = float(self.angular_velocity_rad_s)
        if self.reference_m is None:
            self.reference_m = np.zeros(d)
        if self.path_interpolation not in PATH_INTERPOLATIONS:
            raise ValueError(
                f"path_interpolation must be one of {PATH_INTERPOLATIONS}, "
                f"got {self.path_interpolation!r}"
            )
        if self.path is not None:
            self.path = np.asarray(self.path, dtype=float)
            if self.path_interpolation == "cubic" and len(self.path) > 1:
                self._spline = cubic_path(self.path, d)
            self.centre_m, self.orientation = self.pose_at(float(self.path[0, 0]))

    # -- pose -------------------------------------------------------------------------------
    def pose_at(self, t_s: float) -> tuple[np.ndarray, np.ndarray | float]:
        """Centre and orientation on the keyframed path at time ``t_s`` (held outside it)."""
        assert self.path is not None
        times = self.path[:, 0]
        d = self.dim
        if t_s <= times[0] or len(times) == 1:
            row = self.path[0]
            return row[1 : 1 + d].copy(), self._orientation_of(row)
        if t_s >= times[-1]:
            row = self.path[-1]
            return row[1 : 1 + d].copy(), self._orientation_of(row)
        if self._spline is not None:
            return self._spline(t_s)
        n = int(np.searchsorted(times, t_s, side="right")) - 1
        t0, t1 = times[n], times[n + 1]
        f = 0.0 if t1 <= t0 else (t_s - t0) / (t1 - t0)
        a, b = self.path[n], self.path[n + 1]
        centre = (1 - f) * a[1 : 1 + d] + f * b[1 : 1 + d]
        if d == 2:
            return centre, float((1 - f) * a[1 + d] + f * b[1 + d])
        return centre, rotation.slerp(a[1 + d :], b[1 + d :], f)

    def _orientation_of(self, row: np.ndarray) -> np.ndarray | float:
        return (
            float(row[1 + self.dim]) if self.dim == 2 else rotation.normalise(row[1 + self.dim :])
        )

    def advance(self, t_s: float, dt_s: float) -> None:
        """Move from time ``t_s`` to ``t_s + dt_s``; velocities become the step's average."""
        if self.path is None:
            self.centre_m = self.centre_m + self.velocity_m_s * dt_s
            if self.dim == 2:
                self.orientation = float(self.orientation) + self.angular_velocity_rad_s * dt_s
            else:
                dq = rotation.from_rotation_vector(np.asarray(self.angular_velocity_rad_s) * dt_s)
                self.orientation = rotation.normalise(
                    rotation.multiply(dq, np.asarray(self.orientation))
                )
            return
        c0, o0 = self.pose_at(t_s)
        c1, o1 = self.pose_at(t_s + dt_s)
        self.centre_m, self.orientation = c1, o1
        if dt_s <= 0:
            return
        self.velocity_m_s = (c1 - c0) / dt_s
        if self.dim == 2:
            self.angular_velocity_rad_s = (float(o1) - float(o0)) / dt_s
        else:
            rel = rotation.multiply(np.asarray(o1), rotation.conjugate(np.asarray(o0)))
            self.angular_velocity_rad_s = rotation.to_rotation_vector(rel) / dt_s

    def drive_to(self, centre_m: np.ndarray, orientation: np.ndarray | float, dt_s: float) -> None:
        """Set the velocities that carry the probe to the given pose in one step of ``dt_s``.

        For probes driven from outside (a stylus): call before each :meth:`Simulation.step`.
        Clears any keyframed path.
        """
        self.path = None
        self._spline = None
        centre = np.asarray(centre_m, dtype=float).reshape(self.dim)
        self.velocity_m_s = (centre - self.centre_m) / dt_s
        if self.dim == 2:
            self.angular_velocity_rad_s = (float(orientation) - float(self.orientation)) / dt_s
        else:
            target = rotation.normalise(np.asarray(orientation, dtype=float))
            rel = rotation.multiply(target, rotation.conjugate(np.asarray(self.orientation)))
            self.angular_velocity_rad_s = rotation.to_rotation_vector(rel) / dt_s

    # -- geometry ---------------------------------------------------------------------------
    def rotation_matrix(self) -> np.ndarray:
        return rotation.rotation_matrix(self.dim, self.orientation)

    def world_box(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper corners (dim,) of a world box holding the probe, metres: from the
        shape's support function ``support(direction)`` (``max over the shape of direction . x``,
        body frame) where it has one, the tight box in any pose; else the bounding sphere's. A
        brush tip's bounding sphere is its whole length wide: on the painting grid the tight box
        (plus the cut geometry's margin) holds about a third of the sphere's cells."""
        support = getattr(self.shape, "support", None)
        if support is None:
            r = self.shape.bounding_radius_m
            return self.centre_m - r, self.centre_m + r
        rot = self.rotation_matrix()
        half_extents = getattr(self.shape, "half_extents", None)
        if half_extents is not None:  # a centrally symmetric shape: the box is centred
            reach = np.array(half_extents(rot))
            return self.centre_m - reach, self.centre_m + reach
        upper = np.array([float(support(rot[a])) for a in range(self.dim)])
        lower = np.array([-float(support(-rot[a])) for a in range(self.dim)])
        return self.centre_m + lower, self.centre_m + upper

    def reference_point(self) -> np.ndarray:
        """Torque reference point in the world frame, shape (dim,)."""
        return self.centre_m + self.rotation_matrix() @ np.asarray(self.reference_m)

    def omega3(self) -> np.ndarray:
        """Angular velocity as a 3-vector (2D: about z)."""
        if self.dim == 2:
            return np.array([0.0, 0.0, float(self.angular_velocity_rad_s)])
        return np.asarray(self.angular_velocity_rad_s, dtype=float)

    def voxelize(self, grid: Grid) -> tuple[tuple[slice, ...], np.ndarray]:
        """Cells whose centre lies inside the probe: a window of the grid and a mask over it."""
        h = grid.cell_size_m
        d = self.dim
        reach = self.shape.bounding_radius_m
        lo_idx, hi_idx = [], []
        for a in range(3):
            if a >= d:
                lo_idx.append(0)
                hi_idx.append(grid.cells[a])
                continue
            rel = float(self.centre_m[a]) - grid.origin_m[a]
            lo = math.floor((rel - reach) / h - 1.0)
            hi = math.ceil((rel + reach) / h + 1.0)
            lo_idx.append(min(max(lo, 0), grid.cells[a]))
            hi_idx.append(min(max(hi, 0), grid.cells[a]))
        window = tuple(slice(lo_idx[a], hi_idx[a]) for a in range(3))
        axes = [grid.origin_m[a] + (np.arange(lo_idx[a], hi_idx[a]) + 0.5) * h for a in range(d)]
        if any(len(ax) == 0 for ax in axes):
            return window, np.zeros([hi_idx[a] - lo_idx[a] for a in range(3)], dtype=bool)
        pts = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
        body = (pts - self.centre_m) @ self.rotation_matrix()
        inside = self.shape.sdf(body) <= 0.0
        if d == 2:
            inside = inside[:, :, None]
            if grid.cells[2] > 1:
                inside = np.repeat(inside, grid.cells[2], axis=2)
        return window, inside
