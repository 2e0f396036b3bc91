"""The simulated hand: its integration in Python floats is the vector form's, and it obeys its
mass-spring-damper physics."""

from __future__ import annotations

import math

import numpy as np

from common.quaternion import multiply
from paintapp.haptics.devices.simulated import HandParams, SimulatedDevice, circle_stroke, hold_at


class VectorHand:
    """The hand's semi-implicit Euler step written with numpy vectors (the reference)."""

    def __init__(self, device: SimulatedDevice, x0: np.ndarray) -> None:
        self.p, self.target = device.hand, device.target
        self.q0 = device._target_q
        self.x, self.v = np.array(x0, dtype=np.float64), np.zeros(3)
        self.theta, self.omega = np.zeros(3), np.zeros(3)
        self.force, self.torque = np.zeros(3), np.zeros(3)

    def substep(self, t_s: float, h: float) -> None:
        p = self.p
        xt, vt = self.target(t_s)
        acc = p.stiffness_n_per_m * (xt - self.x) + p.damping_ns_per_m * (vt - self.v)
        self.v = self.v + h * (acc + self.force) / p.mass_kg
        self.x = self.x + h * self.v
        alpha = (
            -p.rot_stiffness_nm_per_rad * self.theta
            - p.rot_damping_nms_per_rad * self.omega
            + self.torque
        ) / p.inertia_kg_m2
        self.omega = self.omega + h * alpha
        self.theta = self.theta + h * self.omega

    def orientation(self) -> np.ndarray:
        dx, dy, dz = 0.5 * self.theta
        n = math.sqrt(1.0 + dx * dx + dy * dy + dz * dz)
        q = multiply(self.q0, np.array([1.0, dx, dy, dz]) / n)
        return q if q[0] >= 0 else -q


def test_the_hand_in_floats_is_its_vector_form_bit_for_bit() -> None:
    """Random forces and torques written every tick, a moving target, uneven ticks (one to three
    substeps each): positions and orientations equal the numpy vector form's exactly."""
    rng = np.random.default_rng(3)
    now = [0.0]
    device = SimulatedDevice(lambda: now[0], target=circle_stroke(), substep_s=5e-4)
    device.open()
    device.read()  # starts the hand
    reference = VectorHand(device, device.position_m)
    t_ref = now[0]
    for _ in range(600):
        dt = float(rng.choice([1e-3, 4e-4, 1.3e-3]))
        now[0] += dt
        state = device.read()
        dt = now[0] - t_ref  # the step the device takes: the clock's difference
        n = min(max(1, math.ceil(dt / device.substep_s - 1e-9)), 800)
        for i in range(n):
            reference.substep(t_ref + (i + 1) * (dt / n), dt / n)
        t_ref = now[0]
        np.testing.assert_array_equal(state.position_m, reference.x)
        np.testing.assert_array_equal(device.velocity_m_per_s, reference.v)
        np.testing.assert_array_equal(state.orientation_wxyz, reference.orientation())
        force, torque = rng.normal(size=3), 0.02 * rng.normal(size=3)
        device.write(force, torque)
        reference.force, reference.torque = force, torque


def test_a_held_force_deflects_the_grip_by_force_over_stiffness() -> None:
    """Static equilibrium of the grip spring: a constant force F moves the tip F / k from a
    target that stays put; a constant torque turns the stylus by about tau / k_rot."""
    hand = HandParams()
    now = [0.0]
    device = SimulatedDevice(
        lambda: now[0], target=hold_at((0.0, 0.0, 0.05)), hand=hand, tilt_rad=(0.0, 0.0)
    )
    device.open()
    device.read()
    force = np.array([0.6, -0.3, 0.0])
    torque = np.array([0.0, 0.0, 0.01])
    for _ in range(5000):  # 5 s: the grip's damping settles it
        now[0] += 1e-3
        device.read()
        device.write(force, torque)
    x = device.position_m
    np.testing.assert_allclose(x[:2], force[:2] / hand.stiffness_n_per_m, rtol=1e-6)
    q = device.read().orientation_wxyz
    angle = 2.0 * math.atan2(math.hypot(*q[1:]), q[0])
    assert math.isclose(angle, torque[2] / hand.rot_stiffness_nm_per_rad, rel_tol=1e-3)


def test_a_non_finite_write_holds_zero_force_and_is_counted() -> None:
    now = [0.0]
    device = SimulatedDevice(lambda: now[0], target=hold_at((0.0, 0.0, 0.05)))
    device.open()
    device.read()
    device.write(np.array([np.nan, 0.0, 0.0]), np.zeros(3))
    device.write(np.zeros(3), np.array([0.0, np.inf, 0.0]))
    assert device.nonfinite_writes == 2
    for _ in range(100):
        now[0] += 1e-3
        state = device.read()
    assert np.all(np.isfinite(state.position_m))
    np.testing.assert_allclose(state.position_m, [0.0, 0.0, 0.05], atol=1e-12)
