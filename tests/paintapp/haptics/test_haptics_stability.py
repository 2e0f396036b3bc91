"""Closed loop of simulated hand, servo and a delayed fluid drag: the paper's force-scale
instability, and the safety layer containing it under NaNs, spikes and stalls."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from paintapp.haptics.devices.simulated import SIMULATED_INFO, HandParams
from paintapp.haptics.fluid import FluidConfig
from paintapp.haptics.servo import ServoConfig

HAND = HandParams()
F_MAX = SIMULATED_INFO.max_force_n
# Energy a force bounded by F_MAX can keep in the hand: the grip damping b dissipates b v^2, so in a
# sustained oscillation |v| <= F_MAX / b; add the grip spring's static deflection energy.
ENERGY_BOUND_J = 0.5 * HAND.mass_kg * (F_MAX / HAND.damping_ns_per_m) ** 2 + F_MAX**2 / (
    2 * HAND.stiffness_n_per_m
)
UNLIMITED = replace(SIMULATED_INFO, max_force_n=1e9, max_torque_nm=1e9)


def config(scale: float) -> ServoConfig:
    return ServoConfig(fluid=FluidConfig(force_scale=scale, spike_limit_n=1e12))


def test_high_force_scale_is_unstable_without_limits(closed_loop) -> None:
    """The paper's warning (section 5.1): the delayed fluid force pumps energy into the hand."""
    energies = {}
    for scale in (2.0, 100.0):
        cl = closed_loop(config=config(scale), info=UNLIMITED)
        cl.run(3.0)
        energies[scale] = cl.max_energy_j
    assert energies[2.0] < 0.01  # about the stroke's own start-up energy
    assert energies[100.0] > 1000 * ENERGY_BOUND_J


@pytest.mark.parametrize("scale", [0.0, 2.0, 10.0, 30.0, 100.0])
def test_safety_contains_any_force_scale(closed_loop, scale: float) -> None:
    cl = closed_loop(config=config(scale))
    cl.run(3.0)
    forces = cl.loop.log.arrays()["force_n"]
    assert np.all(np.isfinite(forces))
    assert np.max(np.linalg.norm(forces, axis=1)) <= F_MAX + 1e-9
    assert cl.max_energy_j < ENERGY_BOUND_J
    assert cl.device.nonfinite_writes == 0
    if scale <= 10.0:
        assert cl.loop.safety.clamped_count == 0  # the paper's working range never hits the limit


@pytest.mark.parametrize("scale", [2.0, 10.0, 100.0])
def test_nans_spikes_and_stalls_never_reach_the_hand(closed_loop, scale: float) -> None:
    cl = closed_loop(config=ServoConfig(fluid=FluidConfig(force_scale=scale)), seed=4)
    rng = np.random.default_rng(11)
    events = {"nan": 0, "spike": 0, "huge": 0}

    def on_sim(t: float) -> bool:
        if 1.0 < t < 1.4:  # the simulation stalls: nothing published
            return True
        r = rng.random()
        if r < 0.1:
            cl.loop.forces.publish_force(t, [np.nan, 1.0, np.inf], [0.0, np.nan, 0.0])
            events["nan"] += 1
        elif r < 0.2:
            cl.loop.forces.publish_force(t, rng.normal(0, 20.0, 3))  # large but plausible
            events["spike"] += 1
        elif r < 0.25:
            cl.loop.forces.publish_force(t, [1e30, -1e30, 0.0])
            events["huge"] += 1
        else:
            return False
        return True

    cl.run(3.0, on_sim)
    log = cl.loop.log.arrays()
    forces, torques = log["force_n"], log["torque_nm"]
    assert np.all(np.isfinite(forces)) and np.all(np.isfinite(torques))
    assert np.max(np.linalg.norm(forces, axis=1)) <= F_MAX + 1e-9
    assert np.max(np.linalg.norm(torques, axis=1)) <= SIMULATED_INFO.max_torque_nm + 1e-9
    assert cl.max_energy_j < ENERGY_BOUND_J
    fluid = cl.loop.fluid.counters()
    assert fluid["rejected_nonfinite"] == events["nan"] > 0
    assert fluid["rejected_spikes"] >= events["huge"] > 0
    assert fluid["watchdog_trips"] >= 1  # the stall faded the fluid force out
    t = log["t_s"]
    stalled = (t > 1.0 + 0.1 + 0.1) & (t < 1.4)  # after the timeout and the fade
    assert np.all(log["fluid_force_n"][stalled] == 0.0)
