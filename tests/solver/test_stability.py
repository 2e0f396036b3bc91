"""Extremes: fast probes, any viscosity, any time step. Nothing may blow up."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from solver.simulation import SolverSettings

VISCOSITIES = (0.0, 1e-6, 1.0, 1e3)
TIME_STEPS = (1e-4, 1e-2, 1.0)


def _check_bounded(sim, speed):
    st = sim.state
    for a in range(sim.grid.dim):
        assert np.all(np.isfinite(st.comps[a]))
        # the fastest fluid is at most a few times the probe speed (it squeezes past the probe)
        assert np.abs(st.comps[a]).max() <= 20.0 * speed
    assert np.all(np.isfinite(st.pressure))
    volume = float(np.prod(sim.grid.size_m))
    assert sim.kinetic_energy() <= 50.0 * 0.5 * speed**2 * volume
    for f in sim.forces.values():
        assert np.all(np.isfinite(f.force)) and np.all(np.isfinite(f.torque))


@pytest.mark.parametrize(("nu", "dt"), list(itertools.product(VISCOSITIES, TIME_STEPS)))
@pytest.mark.parametrize("advection", ["linear", "maccormack"])
def test_fast_spinning_probe_2d(build, nu, dt, advection):
    n = 24
    h = 1.0 / n
    speed = 4.0 * h / dt  # four cells per step
    probe = build.box(
        size=(0.2, 0.1), velocity=(speed, 0.3 * speed), centre=(0.5, 0.5), spin=1.0 / dt
    )
    sim = build.sim(
        n,
        2,
        nu=nu,
        probes=[probe],
        settings=SolverSettings(advection=advection, max_iterations=400),
    )
    for _ in range(12):  # it crosses the box and pushes into the wall
        sim.step(dt)
        _check_bounded(sim, speed)


@pytest.mark.parametrize(("nu", "dt"), [(0.0, 1.0), (1e3, 1e-4), (1e-6, 1e-2), (1.0, 1.0)])
def test_fast_probe_3d(build, nu, dt):
    n = 12
    speed = 3.0 * (1.0 / n) / dt
    probe = build.circle(3, velocity=(speed, 0.0, 0.5 * speed), radius=0.2, spin=2.0 / dt)
    sim = build.sim(n, 3, nu=nu, probes=[probe])
    for _ in range(6):
        sim.step(dt)
        _check_bounded(sim, speed)


def test_probe_leaving_through_the_wall_leaves_clean_fluid(build):
    probe = build.circle(2, velocity=(2.0, 0.0), centre=(0.8, 0.5), radius=0.1)
    sim = build.sim(20, 2, nu=1e-3, probes=[probe])
    for _ in range(10):
        sim.step(0.05)
    assert np.all(sim.state.label == -1)  # it has left the domain entirely
    assert np.all(np.isfinite(sim.state.comps[0]))
    assert np.abs(sim.divergence()).max() < 1e-4


@pytest.mark.parametrize("dt", [0.0, -0.1, float("nan"), float("inf")])
def test_impossible_time_step_is_refused(build, dt):
    sim = build.sim(8, 2)
    with pytest.raises(ValueError, match="dt"):
        sim.step(dt)
