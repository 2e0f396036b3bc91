"""A simulated haptic device: a hand holding a 6-DOF stylus, headless and deterministic.

The hand is a mass-spring-damper pulled toward a target trajectory (where the painter means the
tip to be); the force the device writes acts back on it, so the closed loop of hand, device and
fluid force is physical. Rotation is modelled the same way for small angular deviations from a
target orientation, driven by the written torque. Between calls the last written force is held,
as a device's amplifier holds it, and the motion is integrated in substeps (semi-implicit Euler).

Time comes from ``time_source`` (a clock's ``now_s``): a :class:`VirtualClock` makes a run exactly
repeatable, a :class:`RealTimeClock` makes the hand move in real time. The target trajectory's
time starts at zero when the device is opened.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from common.tilt import quat_multiply
from paintapp.haptics.device import DeviceError, DeviceInfo, DeviceState
from paintapp.haptics.orientation import quat_from_tilt_twist

Target = Callable[[float], tuple[np.ndarray, np.ndarray]]
"""Target trajectory: time in s -> (position m (3,), velocity m/s (3,))."""

SIMULATED_INFO = DeviceInfo(
    name="simulated 6-DOF stylus",
    kind="simulated",
    dof_sensed=6,
    dof_actuated=6,
    max_force_n=8.0,
    max_torque_nm=0.4,
    max_stiffness_n_per_m=2000.0,
    max_damping_ns_per_m=10.0,
    workspace_m=(0.4, 0.3, 0.2),
)


@dataclass(frozen=True)
class HandParams:
    """The hand's grip, as a mass-spring-damper toward the target (typical human values).

    Attributes:
        mass_kg: effective mass of hand and stylus.
        stiffness_n_per_m: grip stiffness toward the target.
        damping_ns_per_m: grip damping.
        inertia_kg_m2: rotational inertia about the tip.
        rot_stiffness_nm_per_rad: rotational grip stiffness.
        rot_damping_nms_per_rad: rotational grip damping.
    """

    mass_kg: float = 0.25
    stiffness_n_per_m: float = 300.0
    damping_ns_per_m: float = 3.0
    inertia_kg_m2: float = 2e-4
    rot_stiffness_nm_per_rad: float = 1.0
    rot_damping_nms_per_rad: float = 0.01


def circle_stroke(
    center_m: tuple[float, float, float] = (0.0, 0.0, -0.002),
    radius_m: float = 0.03,
    period_s: float = 1.0,
    hover_m: float = 0.01,
    approach_s: float = 0.3,
) -> Target:
    """A stirring stroke: the tip comes down from ``hover_m`` above the canvas to the circle's
    height over ``approach_s`` (a half-cosine), while going round a horizontal circle of
    ``radius_m`` about ``center_m`` at constant speed. Time counts from the first query, so the
    approach happens whatever the clock's time base (a servo process's clock does not start at
    0; a hand already pressed into the canvas at the start would keep the loop from engaging)."""
    c = np.asarray(center_m, dtype=np.float64)
    w = 2.0 * math.pi / period_s
    start: list[float] = []

    def target(t_abs: float) -> tuple[np.ndarray, np.ndarray]:
        if not start:
            start.append(t_abs)
        t_s = t_abs - start[0]
        s, co = math.sin(w * t_s), math.cos(w * t_s)
        pos = c + radius_m * np.array([co, s, 0.0])
        vel = radius_m * w * np.array([-s, co, 0.0])
        if t_s < approach_s:
            phase = math.pi * max(t_s, 0.0) / approach_s
            lift = hover_m - c[2]
            pos[2] += lift * 0.5 * (1.0 + math.cos(phase))
            vel[2] = -lift * 0.5 * math.sin(phase) * math.pi / approach_s
        return pos, vel

    return target


def hold_at(position_m: tuple[float, float, float]) -> Target:
    """A target that stays put."""
    p = np.asarray(position_m, dtype=np.float64)
    return lambda _t: (p, np.zeros(3))


class SimulatedDevice:
    """A simulated stylus in a simulated hand (implements :class:`HapticDevice`).

    Args:
        time_source: returns the current time in seconds.
        target: where the hand wants the tip; :func:`circle_stroke` by default.
        hand: the hand's parameters.
        info: the device's limits; :data:`SIMULATED_INFO` by default.
        tilt_rad: the target stylus tilt (2,), radians.
        substep_s: integration substep.
    """

    def __init__(
        self,
        time_source: Callable[[], float],
        target: Target | None = None,
        hand: HandParams | None = None,
        info: DeviceInfo | None = None,
        tilt_rad: tuple[float, float] = (0.3, 0.0),
        substep_s: float = 5e-4,
    ) -> None:
        self.time_source = time_source
        self.target = target or circle_stroke()
        self.hand = hand or HandParams()
        self._info = info or SIMULATED_INFO
        self._target_q = quat_from_tilt_twist(np.asarray(tilt_rad), 0.0)
        self._target_q_list = self._target_q.tolist()
        self.substep_s = float(substep_s)
        self.is_open = False
        self.max_force_written_n = 0.0
        self.nonfinite_writes = 0
        self._t_s = self._t0_s = 0.0
        self._started = False
        # The hand's state as Python floats: a tick integrates two substeps of 3-vectors, where
        # numpy's per-call cost would be most of the servo process's tick.
        self._x = [0.0, 0.0, 0.0]
        self._v = [0.0, 0.0, 0.0]
        self._theta = [0.0, 0.0, 0.0]
        self._omega = [0.0, 0.0, 0.0]
        self._force = [0.0, 0.0, 0.0]
        self._torque = [0.0, 0.0, 0.0]

    @property
    def info(self) -> DeviceInfo:
        return self._info

    def open(self) -> None:
        self._started = False
        self._t_s = self._t0_s = self.time_source()
        x, _ = self.target(0.0)
        self._x = [float(c) for c in x]
        self._v = [0.0, 0.0, 0.0]
        self._theta, self._omega = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
        self._force, self._torque = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
        self.is_open = True

    def close(self) -> None:
        self._force, self._torque = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
        self.is_open = False

    def _substep(self, t_s: float, h: float) -> None:
        """One semi-implicit Euler step of ``h`` seconds, component by component (the same
        operations, in the same order, as the vector form ``v += h (k (x_t - x) + c (v_t - v) +
        f) / m``, ``x += h v``, and its rotational twin)."""
        p = self.hand
        xt, vt = self.target(t_s - self._t0_s)  # the target's time counts from open()
        xt, vt = xt.tolist(), vt.tolist()
        k, c, m = p.stiffness_n_per_m, p.damping_ns_per_m, p.mass_kg
        kr, cr, inertia = p.rot_stiffness_nm_per_rad, p.rot_damping_nms_per_rad, p.inertia_kg_m2
        x, v, theta, omega = self._x, self._v, self._theta, self._omega
        f, tq = self._force, self._torque
        for i in range(3):
            acc = k * (xt[i] - x[i]) + c * (vt[i] - v[i])
            v[i] = v[i] + h * (acc + f[i]) / m
            x[i] = x[i] + h * v[i]
            alpha = (-kr * theta[i] - cr * omega[i] + tq[i]) / inertia
            omega[i] = omega[i] + h * alpha
            theta[i] = theta[i] + h * omega[i]

    def advance(self, t_s: float) -> None:
        """Integrate the hand up to time ``t_s`` with the last written force held."""
        dt = t_s - self._t_s
        if dt <= 0.0:
            return
        n = min(max(1, math.ceil(dt / self.substep_s - 1e-9)), 800)
        h = dt / n
        for i in range(n):
            self._substep(self._t_s + (i + 1) * h, h)
        self._t_s = t_s

    def orientation_wxyz(self) -> np.ndarray:
        """The stylus orientation: the target orientation turned by the hand's deviation."""
        dx, dy, dz = (0.5 * a for a in self._theta)
        n = math.sqrt(1.0 + dx * dx + dy * dy + dz * dz)
        q = quat_multiply(self._target_q_list, (1.0 / n, dx / n, dy / n, dz / n))
        return q if q[0] >= 0 else -q

    def read(self) -> DeviceState:
        if not self.is_open:
            raise DeviceError("simulated device is not open")
        now = self.time_source()
        if not self._started:
            # the hand starts moving at the first read: the time a loop spends setting up after
            # opening the device must not carry the stroke past its approach
            self._started = True
            self._t_s = self._t0_s = now
        self.advance(now)
        return DeviceState(self._t_s, np.array(self._x), self.orientation_wxyz())

    def write(self, force_n: np.ndarray, torque_nm: np.ndarray) -> None:
        if not self.is_open:
            raise DeviceError("simulated device is not open")
        force = np.asarray(force_n, dtype=np.float64).reshape(3).tolist()
        torque = np.asarray(torque_nm, dtype=np.float64).reshape(3).tolist()
        if not all(map(math.isfinite, force + torque)):
            self.nonfinite_writes += 1
            force, torque = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
        self._force, self._torque = force, torque
        self.max_force_written_n = max(self.max_force_written_n, math.hypot(*force))

    def energy_j(self) -> float:
        """Mechanical energy of the hand's deviation from its target, J (kinetic + grip spring)."""
        p = self.hand
        xt, vt = self.target(self._t_s - self._t0_s)
        dv, dx = np.array(self._v) - vt, np.array(self._x) - xt
        omega, theta = np.array(self._omega), np.array(self._theta)
        linear = 0.5 * p.mass_kg * float(dv @ dv) + 0.5 * p.stiffness_n_per_m * float(dx @ dx)
        angular = 0.5 * p.inertia_kg_m2 * float(omega @ omega)
        return linear + angular + 0.5 * p.rot_stiffness_nm_per_rad * float(theta @ theta)

    @property
    def position_m(self) -> np.ndarray:
        """Current tip position, m, shape (3,)."""
        return np.array(self._x)

    @property
    def velocity_m_per_s(self) -> np.ndarray:
        """Current tip velocity (ground truth, for tests), m/s, shape (3,)."""
        return np.array(self._v)
