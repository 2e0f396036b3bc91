"""The brush tip as a moving solver probe: its placement and motion, and a pure-numpy voxelizer.

:class:`ProbeMotion` holds what the solver's probe constructor takes (name, shape, centre,
orientation, velocity, angular velocity); :meth:`ProbeMotion.to_probe` builds the solver's probe.
:func:`voxelize` applies the solver's rule (a cell is solid when the shape's signed distance at the
cell centre, taken into the body frame, is <= 0) without the solver's grid.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from brushes.pose import TipPose
from brushes.presets import BrushPreset
from brushes.tips import Section, Shape
from common import quaternion as _rot
from common.tilt import yaw_angle
from solver import Probe


@dataclass(frozen=True)
class ProbeMotion:
    """A probe placement and rigid motion, in 3D or 2D.

    Attributes:
        name: probe name.
        shape: body-frame shape (``sdf``, ``bounding_radius_m``).
        center: (d,) where the body origin sits in the grid's frame (m).
        orientation: 3D: (4,) unit quaternion [w, x, y, z]; 2D: a float angle (rad).
        velocity: (d,) linear velocity of the body origin (m/s).
        angular_velocity: 3D: (3,) (rad/s); 2D: a float, about the axis out of the plane.
    """

    name: str
    shape: Shape
    center: np.ndarray
    orientation: np.ndarray | float
    velocity: np.ndarray
    angular_velocity: np.ndarray | float

    @property
    def dim(self) -> int:
        """2 or 3."""
        return int(np.asarray(self.center).shape[0])

    def rotation(self) -> np.ndarray:
        """(d, d) rotation matrix body -> grid frame."""
        return rotation_matrix(self.orientation, self.dim)

    def solid_velocity(self, points: np.ndarray) -> np.ndarray:
        """Rigid-body velocity (m/s) at grid-frame points (..., d): ``v + omega x (x - c)``."""
        r = np.asarray(points, dtype=float) - self.center
        if self.dim == 2:
            w = float(self.angular_velocity)
            return self.velocity + w * np.stack([-r[..., 1], r[..., 0]], axis=-1)
        return self.velocity + np.cross(self.angular_velocity, r)

    def to_probe(self) -> Probe:
        """The solver's probe at this placement and motion (torque about the body origin)."""
        return Probe(
            name=self.name,
            shape=self.shape,
            dim=self.dim,
            centre_m=np.array(self.center, dtype=float),
            orientation=self.orientation,
            velocity_m_s=np.array(self.velocity, dtype=float),
            angular_velocity_rad_s=self.angular_velocity,
        )

    def voxelize(
        self,
        grid_origin: Sequence[float],
        cell_size_m: float | Sequence[float],
        cells: Sequence[int],
    ) -> np.ndarray:
        """Boolean solid mask of this probe on a grid; see :func:`voxelize`."""
        return voxelize(self.shape, self.center, self.orientation, grid_origin, cell_size_m, cells)


def rotation_matrix(orientation: np.ndarray | float, dim: int) -> np.ndarray:
    """(d, d) rotation body -> grid frame of a 2D angle (rad) or a 3D quaternion [w, x, y, z]."""
    return _rot.rotation_matrix(dim, orientation)


def probe_motion(pose: TipPose, preset: BrushPreset, name: str = "brush") -> ProbeMotion:
    """The 3D probe for a tip pose: the preset's tip splayed as the pose says, at the apex.

    Its torque reference point is the apex (the body origin).
    """
    return ProbeMotion(
        name=name,
        shape=preset.tip(pose.splay),
        center=np.array(pose.position_m, dtype=float),
        orientation=np.array(pose.orientation, dtype=float),
        velocity=np.array(pose.velocity_m_s, dtype=float),
        angular_velocity=np.array(pose.angular_velocity_rad_s, dtype=float),
    )


def probe_motion_2d(
    pose: TipPose,
    preset: BrushPreset,
    section_z_m: float | None = None,
    name: str = "brush",
) -> ProbeMotion:
    """The 2D probe for a depth-averaged grid in the canvas plane.

    The shape is the cut of the (splayed) tip by the body plane ``z = section_z_m`` (default: half
    the press depth above the apex, the middle of the pressed part); the 2D angle is the tip's yaw
    (:func:`common.tilt.yaw_angle`) and the angular velocity its z component. Tilt is not
    represented in 2D.
    """
    z = 0.5 * pose.press_depth_m if section_z_m is None else section_z_m
    return ProbeMotion(
        name=name,
        shape=Section(preset.tip(pose.splay), z),
        center=np.array(pose.position_m[:2], dtype=float),
        orientation=yaw_angle(pose.orientation),
        velocity=np.array(pose.velocity_m_s[:2], dtype=float),
        angular_velocity=float(pose.angular_velocity_rad_s[2]),
    )


def voxelize(
    shape: Shape,
    center: Sequence[float] | np.ndarray,
    orientation: np.ndarray | float,
    grid_origin: Sequence[float] | np.ndarray,
    cell_size_m: float | Sequence[float],
    cells: Sequence[int],
) -> np.ndarray:
    """Solid mask (bool, shape ``cells``) of ``shape`` placed at ``center`` with ``orientation``.

    Cell ``i`` (a d-tuple) has its centre at ``grid_origin + (i + 0.5) * cell_size_m``; it is solid
    when ``shape.sdf(R^T (centre - center)) <= 0``. Only cells within the shape's bounding sphere
    are evaluated. ``orientation`` is an angle (rad) in 2D, a quaternion [w, x, y, z] in 3D.
    """
    cells = tuple(int(n) for n in cells)
    dim = len(cells)
    if dim not in (2, 3) or min(cells) <= 0:
        raise ValueError(f"cells must be 2 or 3 positive counts, got {cells}")
    origin = np.asarray(grid_origin, dtype=float).reshape(dim)
    h = np.broadcast_to(np.asarray(cell_size_m, dtype=float), (dim,))
    c = np.asarray(center, dtype=float).reshape(dim)
    if np.any(h <= 0.0) or not (np.all(np.isfinite(c)) and np.all(np.isfinite(origin))):
        raise ValueError("cell sizes must be positive and positions finite")
    mask = np.zeros(cells, dtype=bool)
    radius = float(shape.bounding_radius_m)
    lo = np.maximum(np.floor((c - radius - origin) / h - 0.5).astype(int), 0)
    hi = np.minimum(np.ceil((c + radius - origin) / h - 0.5).astype(int) + 1, cells)
    if np.any(hi <= lo):
        return mask
    axes = [origin[k] + (np.arange(lo[k], hi[k]) + 0.5) * h[k] for k in range(dim)]
    centres = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    body = (centres - c) @ rotation_matrix(orientation, dim)  # rows: R^T (x - c)
    mask[tuple(slice(lo[k], hi[k]) for k in range(dim))] = shape.sdf(body) <= 0.0
    return mask
