"""Incompressibility: the divergence left after projection is within the solver tolerance."""

from __future__ import annotations

import numpy as np
import pytest

from solver.boundary import Side
from solver.simulation import SolverSettings


@pytest.mark.parametrize("dim", [2, 3])
def test_projection_removes_divergence_with_moving_probe(build, dim):
    n = 32 if dim == 2 else 16
    tol = 1e-8
    probe = build.circle(dim, velocity=(0.8, 0.3, 0.2), spin=3.0, radius=0.15)
    sim = build.sim(
        n, dim, nu=1e-3, probes=[probe], settings=SolverSettings(pressure_tolerance=tol)
    )
    rng = np.random.default_rng(0)
    for a in range(dim):  # a rough, strongly divergent start
        sim.state.comps[a] += rng.standard_normal(sim.state.comps[a].shape)
    div_before = np.linalg.norm(sim.divergence())
    assert div_before > 10.0
    for _ in range(5):
        st = sim.step(0.01)
        assert st.pressure.converged and st.pressure.residual <= tol
        # the pressure system's right-hand side is the divergence: the residual bounds it
        assert np.linalg.norm(sim.divergence()) <= 10 * tol * div_before


@pytest.mark.parametrize("dim", [2, 3])
def test_closed_box_at_rest_stays_at_rest(build, dim):
    sim = build.sim(12, dim, nu=0.1)
    for _ in range(3):
        sim.step(0.05)
    assert sim.kinetic_energy() == 0.0
    assert np.all(sim.state.pressure == 0.0)


def test_inflow_outflow_channel_carries_the_inflow_flux(build):
    sides = {"x_min": Side("inflow", (0.5, 0.0), "uniform"), "x_max": Side("outflow")}
    sim = build.sim(24, 2, nu=1e-2, sides=sides)
    for _ in range(20):
        sim.step(0.02)
    u = sim.state.comps[0]
    h = sim.grid.cell_size_m
    inflow = u[0].sum() * h
    for i in (5, 12, 24):  # the same flux through every cross-section
        assert u[i].sum() * h == pytest.approx(inflow, rel=1e-4)
    assert np.abs(sim.divergence()).max() < 1e-4
