"""The fluid force path: freshness, rejection of bad samples, watchdog fade, scale."""

from __future__ import annotations

import numpy as np
import pytest

from common.errors import InputError
from paintapp.haptics.channel import ForceChannel
from paintapp.haptics.filters import make_filter
from paintapp.haptics.fluid import FluidConfig, FluidForceInput

DT = 1e-3


def make(scale: float = 2.0, timeout: float = 0.05, fade: float = 0.02, kind: str = "zoh"):
    ch = ForceChannel()
    cfg = FluidConfig(force_scale=scale, watchdog_timeout_s=timeout, fade_time_s=fade)
    return ch, FluidForceInput(ch, make_filter(kind, DT, 6), cfg, max_force_n=5.0)


def run(fluid: FluidForceInput, t0: float, ticks: int) -> np.ndarray:
    return np.array([fluid.update(t0 + i * DT, DT)[0] for i in range(ticks)])


def test_scaled_force_after_fade_in() -> None:
    ch, fluid = make(scale=3.0)
    ch.publish_force(0.0, [0.1, 0.2, 0.0], [0.0, 0.0, 0.01])
    out = run(fluid, 0.0, 40)
    np.testing.assert_allclose(out[-1], [0.3, 0.6, 0.0])
    assert out[0][0] < out[-1][0]  # faded in over fade_time_s, not switched on
    _, torque = fluid.update(0.04, DT)
    assert torque[2] == pytest.approx(0.03)
    assert fluid.fresh_samples == 1


def test_stalled_simulation_fades_to_zero_and_does_not_come_back_stale() -> None:
    ch, fluid = make(timeout=0.05, fade=0.02)
    ch.publish_force(0.0, [1.0, 0.0, 0.0])
    out = run(fluid, 0.0, 200)[:, 0]
    assert out[40] == pytest.approx(2.0)
    assert np.all(out[75:] == 0.0)  # 50 ms timeout + 20 ms fade
    assert np.all(np.diff(out[50:75]) <= 0)
    assert fluid.watchdog_trips == 1
    ch.publish_force(0.2, [-0.5, 0.0, 0.0])  # the simulation comes back
    out = run(fluid, 0.2, 40)[:, 0]
    assert np.all(out <= 0.0)  # no stale +2 N flash
    assert out[-1] == pytest.approx(-1.0)


def test_non_finite_and_spike_samples_are_rejected_and_counted() -> None:
    ch, fluid = make(scale=2.0)
    ch.publish_force(0.0, [0.5, 0.0, 0.0])
    run(fluid, 0.0, 30)
    ch.publish_force(0.03, [np.nan, 0.0, 0.0])
    run(fluid, 0.03, 5)
    ch.publish_force(0.035, [1e6, 0.0, 0.0])  # 2e6 N scaled: far above 10 x 5 N
    out = run(fluid, 0.035, 5)
    np.testing.assert_allclose(out[-1], [1.0, 0.0, 0.0])
    assert fluid.rejected_nonfinite == 1 and fluid.rejected_spikes == 1


def test_garbage_only_simulation_counts_as_stalled() -> None:
    ch, fluid = make(timeout=0.05, fade=0.02)
    ch.publish_force(0.0, [1.0, 0.0, 0.0])
    run(fluid, 0.0, 30)
    for k in range(20):
        ch.publish_force(0.03 + k * 0.01, [np.nan, 0.0, 0.0])
        out = run(fluid, 0.03 + k * 0.01, 10)
    assert np.all(out == 0.0)


def test_same_sample_is_used_once() -> None:
    ch, fluid = make()
    ch.publish_force(0.0, [1.0, 0.0, 0.0])
    run(fluid, 0.0, 100)
    assert fluid.fresh_samples == 1


def test_zero_scale_turns_the_fluid_off() -> None:
    ch, fluid = make(scale=0.0)
    ch.publish_force(0.0, [1.0, 1.0, 1.0])
    assert np.all(run(fluid, 0.0, 50) == 0.0)


def test_force_scale_changes_while_running_and_refuses_bad_values() -> None:
    ch, fluid = make(scale=3.0)
    ch.publish_force(0.0, [0.1, 0.0, 0.0], [0.0, 0.0, 0.01])
    run(fluid, 0.0, 40)
    fluid.set_scale(5.0)
    force, torque = fluid.update(0.04, DT)
    assert force[0] == pytest.approx(0.5)
    assert torque[2] == pytest.approx(0.05)
    for bad in (-1.0, float("nan"), float("inf")):
        with pytest.raises(InputError):
            fluid.set_scale(bad)
    assert fluid.update(0.041, DT)[0][0] == pytest.approx(0.5)  # unchanged by refused values
