"""``advection = "none"``: Stokes flow, the momentum advection left out."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from solver.boundary import DomainBoundary
from solver.grid import Grid
from solver.probes import Probe
from solver.shapes import Ball
from solver.simulation import Fluid, Simulation, SolverSettings

TIGHT = SolverSettings(pressure_tolerance=1e-10, viscosity_tolerance=1e-10)


def drag(nu: float, advection: str, steps: int = 12) -> np.ndarray:
    """Force on a disk of diameter 0.3 moving at 0.3 m/s through a closed unit box (2D, 24^2)."""
    grid = Grid.from_size((1.0, 1.0), (24, 24))
    probe = Probe("p", Ball(0.15), 2, np.array([0.35, 0.5]), 0.0, np.array([0.3, 0.0]), 0.0)
    settings = dataclasses.replace(TIGHT, advection=advection)
    sim = Simulation(grid, Fluid(1.0, nu), DomainBoundary(grid), [probe], settings)
    for _ in range(steps):
        sim.step(0.02)
    return sim.forces["p"].force


def test_creeping_flow_feels_the_same_drag_without_advection_and_inertial_flow_does_not():
    """The advection term is Re times the viscous one: at Re = U D / nu = 0.09 leaving it out
    moves the drag by under 1 % (measured 0.8 %); at Re = 90 by 17 %."""
    slow = {a: drag(1.0, a) for a in ("linear", "none")}
    assert slow["linear"][0] < 0.0  # the drag opposes the motion (+x)
    np.testing.assert_allclose(
        slow["none"], slow["linear"], rtol=0.01, atol=1e-3 * abs(slow["linear"][0])
    )
    fast = {a: drag(1e-3, a) for a in ("linear", "none")}
    change = np.linalg.norm(fast["none"] - fast["linear"]) / np.linalg.norm(fast["linear"])
    assert change > 0.05


def test_stokes_flow_carries_the_velocity_over_unchanged():
    """Without advection, viscosity or probes, a divergence-free field in a closed box is a
    steady state of the step; linear advection moves it."""
    grid = Grid.from_size((1.0, 1.0), (16, 16))
    out = {}
    for advection in ("linear", "none"):
        settings = dataclasses.replace(TIGHT, advection=advection)
        sim = Simulation(grid, Fluid(1.0, 0.0), DomainBoundary(grid), [], settings)
        x, y = np.meshgrid(np.linspace(0.0, 1.0, 17), np.linspace(0.0, 1.0, 17), indexing="ij")
        psi = (np.sin(np.pi * x) * np.sin(np.pi * y)) ** 2  # stream function, zero flux at walls
        u = (psi[:, 1:] - psi[:, :-1]) * 16.0  # u = d psi / dy on x faces
        v = -(psi[1:, :] - psi[:-1, :]) * 16.0  # v = -d psi / dx on y faces
        sim.state.comps[0][...] = u[:, :, None]
        sim.state.comps[1][...] = v[:, :, None]
        before = [c.copy() for c in sim.state.comps[:2]]
        sim.step(0.01)
        out[advection] = max(
            np.abs(c - b).max() for c, b in zip(sim.state.comps[:2], before, strict=True)
        )
    assert out["none"] < 1e-9
    assert out["linear"] > 1e-3


def test_a_scene_may_name_none_and_the_settings_reject_an_unknown_scheme():
    # the settings check their modes when they are made, so no simulation sees a bad one
    with pytest.raises(ValueError, match="none"):
        dataclasses.replace(TIGHT, advection="stokes")  # type: ignore[arg-type]
