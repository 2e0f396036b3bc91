"""Force and torque that a stored flow exerts on a rigid probe placed in it (one-way: the probe
does not change the flow).

The stress ``sigma = -p I + mu (G + G^T)`` of a :class:`~solver.sampled.flow.SampledFlow` is
integrated over the probe's exact surface with a :class:`~solver.sampled.quadrature.SurfaceRule`:
``F = sum_k w_k sigma(x_k) n_k``, ``tau = sum_k w_k (x_k - c) x sigma(x_k) n_k`` about the probe's
centre ``c`` -- the paper's eqs. 9-18 on a smooth surface instead of a staircase. In 2D the force
is per unit depth (N/m) and the torque a scalar (N m/m); in 3D N and N m. By the divergence
theorem the force equals the volume integral of ``div sigma`` over the probe, so a uniform flow
gives none and a pressure gradient ``g`` gives ``-g V`` (the buoyancy-like integral), exactly
for a linear field.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from solver.sampled.flow import SampledFlow
from solver.sampled.quadrature import SurfaceRule


@dataclass(frozen=True)
class FieldForce:
    """Force (dim,), torque (float in 2D, (3,) in 3D), the pressure and viscous parts of the
    force, and the fraction of the surface that lay outside the data set's grid."""

    force: np.ndarray
    torque: np.ndarray | float
    pressure_force: np.ndarray
    viscous_force: np.ndarray
    outside_fraction: float


def surface_force(
    flow: SampledFlow,
    rule: SurfaceRule,
    centre_m: np.ndarray,
    rotation: np.ndarray,
    t_s: float,
) -> FieldForce:
    """The stored flow's force on the surface ``rule`` (body frame) placed at ``centre_m`` with
    body-to-world ``rotation`` (dim x dim), at time ``t_s``."""
    centre = np.asarray(centre_m, dtype=np.float64)
    arm = rule.points @ rotation.T
    normals = rule.normals @ rotation.T
    p, grad, outside = flow.sample(t_s, centre + arm)
    strain = grad + np.swapaxes(grad, 1, 2)
    pressure_t = -p[:, None] * normals
    viscous_t = flow.viscosity_pa_s * np.einsum("kij,kj->ki", strain, normals)
    w = rule.weights[:, None]
    pressure_force = (w * pressure_t).sum(axis=0)
    viscous_force = (w * viscous_t).sum(axis=0)
    traction = pressure_t + viscous_t
    if flow.dim == 2:
        torque: np.ndarray | float = float(
            np.sum(rule.weights * (arm[:, 0] * traction[:, 1] - arm[:, 1] * traction[:, 0]))
        )
    else:
        torque = (w * np.cross(arm, traction)).sum(axis=0)
    return FieldForce(
        force=pressure_force + viscous_force,
        torque=torque,
        pressure_force=pressure_force,
        viscous_force=viscous_force,
        outside_fraction=outside / max(len(rule.weights), 1),
    )
