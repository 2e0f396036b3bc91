"""The safety stage: finite output, limits, rate limit, engage and ramp."""

from __future__ import annotations

import math

import numpy as np
import pytest

from paintapp.haptics.device import DeviceInfo
from paintapp.haptics.safety import ForceSafety, SafetyConfig, SafetyState

INFO = DeviceInfo(
    "test",
    "test",
    6,
    6,
    max_force_n=5.0,
    max_torque_nm=0.2,
    max_stiffness_n_per_m=1000.0,
    max_damping_ns_per_m=5.0,
)
DT = 1e-3
Z = np.zeros(3)


def engaged(config: SafetyConfig | None = None) -> ForceSafety:
    s = ForceSafety(INFO, config or SafetyConfig(ramp_time_s=0.01))
    for _ in range(20):
        s.apply(Z, Z, DT)
    assert s.state is SafetyState.ENGAGED
    return s


def settle(s: ForceSafety, force: np.ndarray, torque: np.ndarray = Z, ticks: int = 100):
    for _ in range(ticks):
        out = s.apply(force, torque, DT)
    return out


def test_non_finite_becomes_zero_is_counted_and_restarts_the_ramp() -> None:
    s = engaged()
    settle(s, np.array([1.0, 0.0, 0.0]))
    for bad in (np.array([np.nan, 0, 0]), np.array([0, np.inf, 0])):
        f, t = s.apply(bad, Z, DT)
        assert np.all(f == 0) and np.all(t == 0)
    f, t = s.apply(Z, np.array([0, 0, -np.inf]), DT)
    assert np.all(f == 0) and np.all(t == 0)
    assert s.nonfinite_count == 3 and s.fault_count == 3
    assert s.state is SafetyState.WAITING or s.gain < 1.0


def test_force_and_torque_are_clamped_keeping_direction() -> None:
    s = engaged()
    f, t = settle(s, np.array([30.0, 40.0, 0.0]), np.array([0.0, 0.0, 3.0]))
    assert np.linalg.norm(f) == pytest.approx(5.0)
    np.testing.assert_allclose(f / np.linalg.norm(f), [0.6, 0.8, 0.0])
    assert np.linalg.norm(t) == pytest.approx(0.2)
    assert s.clamped_count > 0


def test_rate_of_change_is_limited() -> None:
    s = engaged(SafetyConfig(ramp_time_s=0.01, full_scale_time_s=0.01))
    outs = [np.linalg.norm(s.apply(np.array([0.0, 0.0, 5.0]), Z, DT)[0]) for _ in range(15)]
    steps = np.diff([0.0, *outs])
    assert np.max(steps) <= 5.0 * DT / 0.01 + 1e-12  # full scale in 10 ms at most
    assert outs[9] == pytest.approx(5.0) and outs[8] < 5.0


def test_waits_for_a_small_force_then_ramps_over_the_ramp_time() -> None:
    s = ForceSafety(INFO, SafetyConfig(ramp_time_s=0.1, engage_fraction=0.1))
    big = np.array([0.0, 0.0, 2.0])
    for _ in range(500):
        f, _ = s.apply(big, Z, DT)
        assert np.all(f == 0)  # 2 N > 10 % of 5 N: never engages
    assert s.state is SafetyState.WAITING
    small = np.array([0.0, 0.0, 0.4])
    outs = [s.apply(small, Z, DT)[0][2] for _ in range(150)]
    assert s.state is SafetyState.ENGAGED
    assert outs[49] == pytest.approx(0.4 * 0.5, rel=0.02)  # half-way through the 100 ms ramp
    assert outs[120] == pytest.approx(0.4)


def test_input_only_device_never_outputs_force() -> None:
    tablet = DeviceInfo("tablet", "test", 3, 0)
    s = ForceSafety(tablet)
    for _ in range(1000):
        f, t = s.apply(np.array([1.0, 2.0, 3.0]), np.ones(3), DT)
    assert np.all(f == 0) and np.all(t == 0)


def test_random_garbage_never_escapes() -> None:
    rng = np.random.default_rng(7)
    s = ForceSafety(INFO, SafetyConfig(ramp_time_s=0.005))
    prev = Z
    for _ in range(5000):
        f = rng.normal(0, 10, 3) * 10.0 ** rng.integers(-3, 300)
        if rng.random() < 0.05:
            f[rng.integers(3)] = rng.choice([np.nan, np.inf, -np.inf])
        out, tq = s.apply(f, rng.normal(0, 1, 3), DT)
        assert np.all(np.isfinite(out)) and np.all(np.isfinite(tq))
        assert np.linalg.norm(out) <= 5.0 + 1e-9 and np.linalg.norm(tq) <= 0.2 + 1e-9
        step = np.linalg.norm(out - prev)
        assert step <= 5.0 * DT / 0.01 + 1e-9 or np.all(out == 0)
        prev = out


@pytest.mark.parametrize("name", ["ramp_time_s", "engage_fraction", "full_scale_time_s"])
def test_config_rejects_non_positive(name: str) -> None:
    from common.errors import InputError

    with pytest.raises(InputError):
        SafetyConfig(**{name: 0.0})
    with pytest.raises(InputError):
        SafetyConfig(**{name: math.nan})
