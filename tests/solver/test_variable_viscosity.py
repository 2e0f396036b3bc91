"""A simulation with a per-cell viscosity field (``Simulation.set_viscosity``)."""

from __future__ import annotations

import numpy as np

from solver.boundary import DomainBoundary, Side
from solver.grid import Grid
from solver.probes import Probe
from solver.shapes import Ball
from solver.simulation import Fluid, Simulation, SolverSettings

TIGHT = SolverSettings(pressure_tolerance=1e-10, viscosity_tolerance=1e-10)


def build(cls, mu: float = 0.05, dim: int = 3):
    grid = Grid.from_size((1.0,) * dim, (14,) * dim)
    sides = {"z_max": Side("outflow")} if dim == 3 else {}
    probe = Probe("p", Ball(0.15), dim, np.array([0.4, 0.5, 0.5][:dim]),
                  None if dim == 3 else 0.0, np.array([0.3, 0.1, 0.0][:dim]),
                  np.array([0.0, 0.0, 1.0]) if dim == 3 else 1.0)  # fmt: skip
    return cls(grid, Fluid(1.0, mu), DomainBoundary(grid, sides), [probe], TIGHT)


def test_a_uniform_field_set_between_steps_matches_a_fluid_of_that_viscosity():
    """The per-cell field path and the scalar fluid viscosity give the same flow and force."""
    for dim in (2, 3):
        a = build(Simulation, mu=0.2, dim=dim)
        b = build(Simulation, mu=0.05, dim=dim)
        b.set_viscosity(np.full(b.grid.cells, 0.2))  # rho = 1: dynamic = kinematic
        for _ in range(3):
            a.step(0.05)
            b.step(0.05)
        for qa, qb in zip(a.state.comps, b.state.comps, strict=True):
            np.testing.assert_allclose(qb, qa, atol=1e-12)
        np.testing.assert_allclose(b.forces["p"].force, a.forces["p"].force, rtol=1e-9)
        np.testing.assert_allclose(
            b.forces["p"].torque, a.forces["p"].torque, rtol=1e-9, atol=1e-15
        )
        c = build(Simulation, mu=0.05, dim=dim)
        for _ in range(3):
            c.step(0.05)
        assert not np.allclose(c.forces["p"].force, a.forces["p"].force, rtol=0.05)


def test_force_grows_with_the_viscosity_of_the_fluid_next_to_the_probe():
    """Slow (Stokes) flow: the drag is proportional to the viscosity around the probe, and thin
    fluid far away hardly matters."""
    drags = {}
    for name, factor in (("thin", 1.0), ("thick", 10.0)):
        sim = build(Simulation, mu=1.0)
        mu = np.full(sim.grid.cells, 1.0)
        centres = sim.grid.cell_centres()
        near = np.linalg.norm(centres - np.array([0.4, 0.5, 0.5]), axis=-1) < 0.35
        mu[near] *= factor
        sim.set_viscosity(mu)
        for _ in range(2):
            sim.step(0.02)
        drags[name] = sim.forces["p"].force[0]
    assert drags["thin"] < 0.0 and drags["thick"] < 0.0  # opposes the motion (+x)
    assert 5.0 < drags["thick"] / drags["thin"] < 11.0


def test_linear_drag_decays_a_free_flow_at_its_rate():
    grid = Grid.from_size((1.0, 1.0), (8, 8))
    sides = {"x_min": Side("outflow"), "x_max": Side("outflow"), "y_min": Side("slip"),
             "y_max": Side("slip")}  # fmt: skip
    sim = Simulation(grid, Fluid(1.0, 0.0), DomainBoundary(grid, sides), [], TIGHT)
    sim.set_viscosity(np.zeros(grid.cells))
    sim.state.comps[0][:] = 1.0  # uniform flow along x through open ends: divergence-free
    sim.set_drag(np.full(grid.cells, 5.0))
    dt = 0.01
    for _ in range(10):
        sim.step(dt)
    np.testing.assert_allclose(sim.state.comps[0], (1.0 + 5.0 * dt) ** -10, rtol=1e-6)
