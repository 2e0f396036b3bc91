"""Orientations: 2D angles and 3D unit quaternions ``[w, x, y, z]``."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np


def rotation_matrix(dim: int, orientation: np.ndarray | float) -> np.ndarray:
    """Body-to-world rotation matrix (dim x dim) for an angle (2D, radians) or a quaternion (3D)."""
    if dim == 2:
        c, s = np.cos(float(orientation)), np.sin(float(orientation))
        return np.array([[c, -s], [s, c]])
    w, x, y, z = normalise(np.asarray(orientation, dtype=float))
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def normalise(q: np.ndarray) -> np.ndarray:
    n = float(np.linalg.norm(q))
    if not np.isfinite(n) or n == 0.0:
        raise ValueError("quaternion must be finite and non-zero")
    return q / n


def multiply(a: np.ndarray | Sequence[float], b: np.ndarray | Sequence[float]) -> np.ndarray:
    """Hamilton product a * b of quaternions [w, x, y, z] (arrays, or sequences of floats, whose
    scalar arithmetic is the cheaper where it runs every servo tick)."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return np.array(
        [
            aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
        ]
    )


def from_rotation_vector(v: np.ndarray) -> np.ndarray:
    """Quaternion of a rotation by |v| radians about v."""
    angle = float(np.linalg.norm(v))
    if angle < 1e-15:
        return np.array([1.0, 0.5 * v[0], 0.5 * v[1], 0.5 * v[2]])
    axis = v / angle
    return np.concatenate([[np.cos(0.5 * angle)], np.sin(0.5 * angle) * axis])


def to_rotation_vector(q: np.ndarray) -> np.ndarray:
    """Rotation vector (axis times angle, radians) of a unit quaternion, angle in [0, pi]."""
    q = normalise(q)
    if q[0] < 0:
        q = -q
    s = float(np.linalg.norm(q[1:]))
    if s < 1e-15:
        return 2.0 * q[1:]
    return 2.0 * np.arctan2(s, q[0]) * q[1:] / s


def slerp(a: np.ndarray, b: np.ndarray, f: float) -> np.ndarray:
    """Spherical interpolation from a (f = 0) to b (f = 1) along the shorter arc."""
    a = normalise(a)
    b = normalise(b)
    if float(np.dot(a, b)) < 0.0:
        b = -b
    rel = multiply(b, conjugate(a))
    return normalise(multiply(from_rotation_vector(f * to_rotation_vector(rel)), a))


def conjugate(q: np.ndarray) -> np.ndarray:
    return np.array([q[0], -q[1], -q[2], -q[3]])
