"""Velocity estimation, canvas contact and stylus orientation."""

from __future__ import annotations

import numpy as np
import pytest

from common.errors import InputError
from common.tilt import axis_from_tilt, quat_to_matrix
from paintapp.haptics.contact import CanvasContact, ContactConfig
from paintapp.haptics.device import DeviceInfo
from paintapp.haptics.orientation import quat_from_tilt_twist, tilt_twist_from_quat
from paintapp.haptics.velocity import VelocityEstimator

INFO = DeviceInfo(
    "t", "t", 6, 6, max_force_n=8.0, max_stiffness_n_per_m=2000.0, max_damping_ns_per_m=10.0
)


def test_velocity_of_a_uniform_motion_from_irregular_timestamps() -> None:
    rng = np.random.default_rng(2)
    est = VelocityEstimator(tau_s=5e-3)
    v_true = np.array([0.1, -0.2, 0.05])
    t = np.cumsum(rng.uniform(0.5e-3, 1.5e-3, 200))
    for ti in t:
        v = est.update(ti, 0.3 + v_true * ti)
    np.testing.assert_allclose(v, v_true, rtol=1e-9)


def test_velocity_filter_reduces_quantization_noise() -> None:
    rng = np.random.default_rng(3)
    raw, filtered = VelocityEstimator(tau_s=0.0), VelocityEstimator(tau_s=5e-3)
    errs_raw, errs_f = [], []
    for k in range(2000):
        t = k * 1e-3
        x = np.round((0.05 * t + rng.normal(0, 2e-6, 3)) / 1e-5) * 1e-5  # 10 um encoder
        errs_raw.append(raw.update(t, x)[0] - 0.05)
        errs_f.append(filtered.update(t, x)[0] - 0.05)
    assert np.std(errs_f[100:]) < 0.3 * np.std(errs_raw[100:])


def test_velocity_ignores_repeats_and_non_finite_and_restarts_after_a_gap() -> None:
    est = VelocityEstimator(tau_s=0.0, max_gap_s=0.1)
    est.update(0.0, np.zeros(3))
    v = est.update(0.001, np.array([0.001, 0.0, 0.0]))
    assert v[0] == pytest.approx(1.0)
    assert est.update(0.001, np.array([5.0, 0, 0]))[0] == pytest.approx(1.0)  # same time stamp
    assert est.update(0.002, np.array([np.nan, 0, 0]))[0] == pytest.approx(1.0)
    assert est.update(1.0, np.array([1.0, 0, 0]))[0] == 0.0  # long gap: no spike


def test_canvas_contact_is_a_one_sided_spring_damper() -> None:
    c = CanvasContact(
        INFO, ContactConfig(height_m=0.01, stiffness_fraction=0.5, damping_fraction=0.5)
    )
    assert np.all(c.force(np.array([0, 0, 0.011]), np.zeros(3)) == 0)
    np.testing.assert_allclose(c.force(np.array([0, 0, 0.008]), np.zeros(3)), [0, 0, 2.0])
    f_in = c.force(np.array([0, 0, 0.008]), np.array([0, 0, -0.1]))[2]
    assert f_in == pytest.approx(2.0 + 0.5)  # damping resists moving in
    assert c.force(np.array([0, 0, 0.0099]), np.array([0, 0, 1.0]))[2] == 0.0  # never pulls
    assert c.pressure(np.array([0, 0, 0.008])) == pytest.approx(0.5)


def test_contact_config_is_checked() -> None:
    with pytest.raises(InputError):
        ContactConfig(stiffness_fraction=1.5)
    with pytest.raises(InputError):
        ContactConfig(height_m=float("nan"))


@pytest.mark.parametrize("tilt", [(0.0, 0.0), (0.4, -0.2), (-1.0, 0.7), (1.2, 0.0)])
@pytest.mark.parametrize("twist", [0.0, 0.8, -2.9])
def test_tilt_twist_round_trip_and_axis_convention(tilt, twist: float) -> None:
    q = quat_from_tilt_twist(np.array(tilt), twist)
    assert np.linalg.norm(q) == pytest.approx(1.0) and q[0] >= 0
    np.testing.assert_allclose(quat_to_matrix(q)[:, 2], axis_from_tilt(np.array(tilt)), atol=1e-12)
    back_tilt, back_twist = tilt_twist_from_quat(q)
    np.testing.assert_allclose(back_tilt, tilt, atol=1e-12)
    assert back_twist == pytest.approx(twist, abs=1e-12)


def test_device_info_rejects_bad_limits() -> None:
    with pytest.raises(InputError):
        DeviceInfo("x", "x", 6, 6, max_force_n=-1.0)
    with pytest.raises(InputError):
        DeviceInfo("x", "x", 5, 6)
    assert DeviceInfo("x", "x", 3, 0).actuation == "input only"
    assert INFO.actuation == "6-DOF force"  # six actuated axes but no torque limit
