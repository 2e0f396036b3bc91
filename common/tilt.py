"""Unit quaternions ``[w, x, y, z]`` for brush orientation, and the stylus tilt/twist convention.

A quaternion ``q`` maps body-frame vectors to the canvas (world) frame: ``v_world = R(q) v_body``.
All functions take and return plain numpy arrays of float64; the basic quaternion algebra is the
solver's (:mod:`common.quaternion`), re-exported here under brush-side names.

Tilt convention (canvas frame: x right, y up the canvas, z out of the canvas toward the painter):
the stylus axis points from the tip to the handle; ``tilt_x`` is the angle of that axis from the
canvas normal in the x-z plane (positive: the handle leans toward +x), ``tilt_y`` likewise toward
+y. So the axis direction is ``normalize(tan(tilt_x), tan(tilt_y), 1)``. Twist turns the tip
about its own axis (right-handed about the axis, i.e. counter-clockwise seen from the handle).
"""

from __future__ import annotations

import math

import numpy as np

from common import quaternion as _rot
from common.quaternion import conjugate as quat_conjugate
from common.quaternion import multiply as quat_multiply
from common.quaternion import normalise as normalize_quat
from common.quaternion import to_rotation_vector as rotation_vector

IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])
__all__ = [
    "IDENTITY",
    "angular_velocity",
    "axis_from_tilt",
    "normalize_quat",
    "quat_conjugate",
    "quat_from_axis_angle",
    "quat_multiply",
    "quat_to_matrix",
    "quat_z_to",
    "rotation_vector",
    "yaw_angle",
]


def quat_to_matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrix (3, 3) of the unit quaternion ``q``: ``v_world = M @ v_body``."""
    return _rot.rotation_matrix(3, np.asarray(q, dtype=float))


def quat_from_axis_angle(axis: np.ndarray, angle_rad: float) -> np.ndarray:
    """Quaternion of a right-handed rotation by ``angle_rad`` about ``axis`` (3,, any length)."""
    axis = np.asarray(axis, dtype=float)
    norm = float(np.linalg.norm(axis))
    if norm == 0.0 or angle_rad == 0.0:
        return IDENTITY.copy()
    half = 0.5 * angle_rad
    return np.concatenate([[math.cos(half)], math.sin(half) * axis / norm])


def angular_velocity(q0: np.ndarray, q1: np.ndarray, dt_s: float) -> np.ndarray:
    """World-frame angular velocity (rad/s, (3,)) turning ``q0`` into ``q1`` in ``dt_s`` seconds.

    Uses the shortest rotation between the two orientations; ``dt_s`` must be positive.
    """
    rel = quat_multiply(q1, quat_conjugate(q0))
    return rotation_vector(rel) / dt_s


def axis_from_tilt(tilt_rad: np.ndarray) -> np.ndarray:
    """Unit stylus axis (3,) (tip toward handle) in the canvas frame from ``[tilt_x, tilt_y]``."""
    tx, ty = (float(v) for v in tilt_rad)
    axis = np.array([math.tan(tx), math.tan(ty), 1.0])
    return axis / np.linalg.norm(axis)


def quat_z_to(direction: np.ndarray) -> np.ndarray:
    """The smallest rotation taking the body +z axis onto the unit ``direction`` (3,).

    ``direction`` must not point along -z (a brush axis never points into the canvas).
    """
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    cross = np.array([-d[1], d[0], 0.0])  # z x d
    angle = math.atan2(float(np.linalg.norm(cross)), float(d[2]))
    return quat_from_axis_angle(cross, angle)


def yaw_angle(q: np.ndarray) -> float:
    """Angle (rad) of the body x axis projected onto the canvas plane, measured from canvas +x.

    This is the 2D orientation of a tip seen from above (used for depth-averaged 2D grids).
    """
    m = quat_to_matrix(q)
    return math.atan2(float(m[1, 0]), float(m[0, 0]))
