"""Stylus orientation as a quaternion, and back to tablet-style tilt and twist.

Haptic devices report a quaternion; stroke files and pen tablets use tilt and twist. The
convention is that of :mod:`common.tilt`: the stylus axis (tip toward handle) is
``normalize(tan tilt_x, tan tilt_y, 1)`` in the canvas frame, and the orientation is the
smallest rotation taking +z onto that axis, after a turn by ``twist_rad`` about +z. Quaternions
are (w, x, y, z) with w >= 0.
"""

from __future__ import annotations

import math

import numpy as np

from common.tilt import (
    axis_from_tilt,
    quat_conjugate,
    quat_from_axis_angle,
    quat_multiply,
    quat_to_matrix,
    quat_z_to,
)

_Z = np.array([0.0, 0.0, 1.0])


def quat_from_tilt_twist(tilt_rad: np.ndarray, twist_rad: float) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a stylus with ``tilt_rad`` (2,) and ``twist_rad``."""
    q = quat_multiply(quat_z_to(axis_from_tilt(tilt_rad)), quat_from_axis_angle(_Z, twist_rad))
    return q if q[0] >= 0 else -q


def tilt_twist_from_quat(q: np.ndarray) -> tuple[np.ndarray, float]:
    """Inverse of :func:`quat_from_tilt_twist`: ``(tilt_rad (2,), twist_rad)``.

    Exact while the stylus axis points away from the canvas (tilts below 90 degrees); the twist
    is in (-pi, pi].
    """
    q = np.asarray(q, dtype=np.float64) / np.linalg.norm(q)
    axis = quat_to_matrix(q)[:, 2]
    tilt = np.array([math.atan2(axis[0], axis[2]), math.atan2(axis[1], axis[2])])
    rest = quat_multiply(quat_conjugate(quat_z_to(axis)), q)  # a turn about +z by the twist
    twist = 2.0 * math.atan2(float(rest[3]), float(rest[0]))
    twist = (twist + math.pi) % (2.0 * math.pi) - math.pi
    return tilt, twist
