"""Rigid canvas contact: a stiff spring-damper that holds the tip above the canvas plane.

The fluid gives the feel of the paint; the canvas under it must feel solid. When the tip goes
below the canvas plane (height ``height_m`` along +z in the device frame) by a depth ``d``, the
servo loop adds ``F_z = k d - b v_z`` (never pulling: ``F_z >= 0``). The gains are fractions of
the device's own ``max_stiffness_n_per_m`` and ``max_damping_ns_per_m``, the largest values it
renders without going unstable, so the wall is as stiff as the device allows.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from common.errors import InputError
from paintapp.haptics.device import DeviceInfo


@dataclass(frozen=True)
class ContactConfig:
    """Canvas plane and wall gains.

    Attributes:
        height_m: canvas plane height (z) in the device frame, m.
        stiffness_fraction: wall stiffness as a fraction of the device's maximum.
        damping_fraction: wall damping as a fraction of the device's maximum.
        pressure_depth_m: depth below the canvas at which a haptic device reports full pressure.
    """

    height_m: float = 0.0
    stiffness_fraction: float = 0.5
    damping_fraction: float = 0.5
    pressure_depth_m: float = 0.004

    def __post_init__(self) -> None:
        if not math.isfinite(self.height_m):
            raise InputError("canvas height must be finite", key="height_m")
        for name in ("stiffness_fraction", "damping_fraction"):
            value = getattr(self, name)
            if not (math.isfinite(value) and 0.0 <= value <= 1.0):
                raise InputError(f"must be in [0, 1], got {value}", key=name)
        if not self.pressure_depth_m > 0:
            raise InputError("pressure depth must be positive", key="pressure_depth_m")


class CanvasContact:
    """Spring-damper force of the canvas plane on the tip.

    Args:
        info: the device; its stiffness and damping limits set the gains.
        config: plane height and gain fractions.
    """

    def __init__(self, info: DeviceInfo, config: ContactConfig | None = None) -> None:
        self.config = config or ContactConfig()
        self.stiffness_n_per_m = self.config.stiffness_fraction * info.max_stiffness_n_per_m
        self.damping_ns_per_m = self.config.damping_fraction * info.max_damping_ns_per_m

    def depth_m(self, position_m: np.ndarray) -> float:
        """How far the tip is below the canvas plane, m (negative above it)."""
        return self.config.height_m - float(position_m[2])

    def force(self, position_m: np.ndarray, velocity_m_per_s: np.ndarray) -> np.ndarray:
        """Contact force on the tip, N, shape (3,); zero above the canvas."""
        depth = self.depth_m(position_m)
        out = np.zeros(3)
        if depth > 0.0:
            fz = self.stiffness_n_per_m * depth - self.damping_ns_per_m * float(velocity_m_per_s[2])
            out[2] = max(fz, 0.0)
        return out

    def pressure(self, position_m: np.ndarray) -> float:
        """Pressure in [0, 1] a force device reports: depth over ``pressure_depth_m``, clipped."""
        return min(max(self.depth_m(position_m) / self.config.pressure_depth_m, 0.0), 1.0)
