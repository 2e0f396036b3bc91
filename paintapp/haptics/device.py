"""The haptic device interface: what a device is (:class:`DeviceInfo`), what it senses
(:class:`DeviceState`), and the four calls every driver implements (:class:`HapticDevice`).

Frames and units: positions in metres in the device's own frame, z up, the canvas plane at a
height the servo loop is told; forces in newtons and torques in newton-metres in the same frame.
Devices report only what they sense; velocity is estimated in shared code
(:mod:`paintapp.haptics.velocity`), never by a driver.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

import numpy as np

from common.errors import InputError


class DeviceError(RuntimeError):
    """A device failed while running: a read or write error, or it was unplugged."""


class DeviceNotFoundError(InputError):
    """The requested device is not attached (or cannot be opened); carries a user-facing message."""


def _limit(value: float, name: str) -> float:
    value = float(value)
    if not math.isfinite(value) or value < 0:
        raise InputError(f"device limit must be finite and >= 0, got {value}", key=name)
    return value


@dataclass(frozen=True)
class DeviceInfo:
    """What a device can sense and do. Limits are the device's safe maxima.

    Attributes:
        name: human-readable name.
        kind: driver family: "simulated", "replay", "hid-stylus", "hid-pid", ...
        dof_sensed: degrees of freedom sensed (2: planar axes, 3: position, 6: position and
            orientation).
        dof_actuated: degrees of freedom actuated (0: input only such as a pen tablet, 2: a
            force-feedback joystick, 3: force, 6: force and torque).
        max_force_n: largest force magnitude the device may output, N.
        max_torque_nm: largest torque magnitude, N m (0 without torque output).
        max_stiffness_n_per_m: stiffest virtual spring the device renders stably, N/m.
        max_damping_ns_per_m: largest virtual damping it renders stably, N s/m.
        workspace_m: full extent of the workspace along x, y, z, m.
    """

    name: str
    kind: str
    dof_sensed: int
    dof_actuated: int
    max_force_n: float = 0.0
    max_torque_nm: float = 0.0
    max_stiffness_n_per_m: float = 0.0
    max_damping_ns_per_m: float = 0.0
    workspace_m: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        if self.dof_sensed not in (2, 3, 6) or self.dof_actuated not in (0, 2, 3, 6):
            raise InputError(
                f"unsupported degrees of freedom: sensed {self.dof_sensed}, "
                f"actuated {self.dof_actuated}",
                key="dof",
            )
        for name in ("max_force_n", "max_torque_nm", "max_stiffness_n_per_m"):
            object.__setattr__(self, name, _limit(getattr(self, name), name))
        damping = _limit(self.max_damping_ns_per_m, "max_damping_ns_per_m")
        object.__setattr__(self, "max_damping_ns_per_m", damping)
        workspace = tuple(_limit(v, "workspace_m") for v in self.workspace_m)
        if len(workspace) != 3:
            raise InputError("workspace needs three extents (x, y, z)", key="workspace_m")
        object.__setattr__(self, "workspace_m", workspace)

    @property
    def has_force(self) -> bool:
        """Whether the device outputs force at all."""
        return self.dof_actuated > 0 and self.max_force_n > 0

    @property
    def has_torque(self) -> bool:
        """Whether the device outputs torque."""
        return self.dof_actuated >= 6 and self.max_torque_nm > 0

    @property
    def actuation(self) -> str:
        """A short description: "input only", "2-DOF force", "3-DOF force", "6-DOF force+torque"."""
        if not self.has_force:
            return "input only"
        if self.has_torque:
            return "6-DOF force+torque"
        return f"{self.dof_actuated}-DOF force"


def _as_array(value: object, shape: tuple[int, ...]) -> np.ndarray:
    arr = np.asarray(value, dtype=np.float64)
    if arr.shape != shape:
        raise ValueError(f"expected shape {shape}, got {arr.shape}")
    return arr


@dataclass(frozen=True, slots=True)
class DeviceState:
    """One reading of a device.

    Attributes:
        t_s: when the reading was taken, seconds, on the servo clock's time base.
        position_m: tip position in the device frame, m, shape (3,).
        orientation_wxyz: stylus orientation as a unit quaternion (w, x, y, z), shape (4,).
        pressure: tip pressure in [0, 1] (tablets; haptic devices derive it, see the driver).
        buttons: bit i set while button i is held.
        velocity_m_per_s: tip velocity, m/s, shape (3,); filled in by the servo loop's estimator.

    The arrays are not copied (a state is built every tick); treat them as read-only.
    """

    t_s: float
    position_m: np.ndarray
    orientation_wxyz: np.ndarray = field(default_factory=lambda: np.array([1.0, 0.0, 0.0, 0.0]))
    pressure: float = 0.0
    buttons: int = 0
    velocity_m_per_s: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self) -> None:
        object.__setattr__(self, "position_m", _as_array(self.position_m, (3,)))
        object.__setattr__(self, "orientation_wxyz", _as_array(self.orientation_wxyz, (4,)))
        object.__setattr__(self, "velocity_m_per_s", _as_array(self.velocity_m_per_s, (3,)))


@runtime_checkable
class HapticDevice(Protocol):
    """What the servo loop needs from a device. Calls come from the servo thread only.

    ``read`` and ``write`` raise :class:`DeviceError` when the device fails (the loop then stops
    cleanly); ``open`` raises :class:`DeviceNotFoundError` when the device is not there.
    """

    @property
    def info(self) -> DeviceInfo:
        """The device's capabilities and limits (valid after :meth:`open`)."""
        ...

    def open(self) -> None:
        """Connect and prepare; output is zero force until the first write."""
        ...

    def close(self) -> None:
        """Output zero force and disconnect. Safe to call twice."""
        ...

    def read(self) -> DeviceState:
        """The latest state (velocity left zero: the loop estimates it)."""
        ...

    def write(self, force_n: np.ndarray, torque_nm: np.ndarray) -> None:
        """Command a force (N, shape (3,)) and torque (N m, shape (3,)) until the next write."""
        ...
