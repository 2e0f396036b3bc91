"""Solves started from the last step's solution (``SolverSettings.warm_start``)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from solver.boundary import DomainBoundary, Side
from solver.grid import Grid
from solver.linalg.pcg import SolveReport, StencilSystem
from solver.linalg.warm_start import WarmStart
from solver.probes import Probe
from solver.scenes.scene import load_scene
from solver.shapes import Ball
from solver.simulation import Fluid, Simulation, SolverSettings


def test_a_warm_solve_starts_from_the_last_solution_on_the_unknowns_only():
    system = StencilSystem.empty((3, 2, 1), 2)
    system.diag[:] = 1.0
    system.active[:2] = True  # the last row is no unknown: a caller's boundary values
    system.diag[1, 1] = 0.0  # nor is an active entry with an empty row (solves leave it)
    starts: list[np.ndarray] = []

    def record(system, b, x, tol, max_iter) -> SolveReport:
        starts.append(x.copy())
        x[system.active] += 1.0  # "solves"
        return SolveReport(1, 0.0, True)

    warm = WarmStart()
    x = np.full((3, 2, 1), 5.0)
    warm.solve(record, system, np.zeros_like(x), x, 1e-6, 10)
    np.testing.assert_array_equal(starts[0], 5.0)  # nothing kept yet: the caller's start
    y = np.full((3, 2, 1), -2.0)
    warm.solve(record, system, np.zeros_like(y), y, 1e-6, 10)
    unknown = system.active & (system.diag > 0.0)
    np.testing.assert_array_equal(starts[1][unknown], 6.0)  # the last solution on the unknowns
    np.testing.assert_array_equal(starts[1][~unknown], -2.0)  # the caller's values elsewhere
    warm.move(lambda last: last + 10.0)
    z = np.zeros((3, 2, 1))
    warm.solve(record, system, np.zeros_like(z), z, 1e-6, 10)
    np.testing.assert_array_equal(starts[2][unknown], 17.0)  # moved with the grid
    warm.forget()
    w = np.zeros((3, 2, 1))
    warm.solve(record, system, np.zeros_like(w), w, 1e-6, 10)
    np.testing.assert_array_equal(starts[3], 0.0)
    other = np.zeros((2, 2, 1))  # another shape: the caller's start
    warm.solve(record, StencilSystem.empty((2, 2, 1), 2), np.zeros_like(other), other, 1e-6, 10)
    np.testing.assert_array_equal(starts[4], 0.0)


def riding(
    warm: bool, tolerance: float = 1e-4, closed: bool = False
) -> tuple[Simulation, list[int], list[int]]:
    """A ball moving at 0.2 m/s through thick fluid (nu dt / h^2 about 10) on a grid that moves
    with it, as the paint grid rides with the brush: 0.3 cells a step; the viscosity and
    pressure iterations of every step after the first few."""
    grid = Grid.from_size((1.0, 1.0, 0.5), (16, 16, 8))
    speed, dt = 0.2, 0.0234375
    probe = Probe("ball", Ball(0.12), 3, np.array([0.5, 0.5, 0.25]), None,
                  np.array([speed, 0.0, 0.0]), np.zeros(3))  # fmt: skip
    settings = SolverSettings(pressure_tolerance=tolerance, viscosity_tolerance=tolerance,
                              warm_start=warm)  # fmt: skip
    sides = {} if closed else {"z_max": Side("outflow")}
    sim = Simulation(grid, Fluid(1.0, 0.4), DomainBoundary(grid, sides), [probe], settings)
    viscosity, pressure = [], []
    for n in range(24):
        stats = sim.step(dt)
        sim.shift((speed * dt / grid.cell_size_m, 0.0, 0.0))
        if n >= 4:
            viscosity.append(sum(r.iterations for r in stats.viscosity))
            pressure.append(stats.pressure.iterations)
    return sim, viscosity, pressure


@pytest.mark.parametrize("closed", [False, True])
def test_a_grid_riding_with_its_probe_solves_in_fewer_iterations_to_the_same_solution(closed):
    """Fewer viscosity iterations (and, with an outflow side, pressure iterations) for the same
    tolerance, within its reach of the exact solves; solved tightly, the exact solution: a
    warm start changes where the solve starts, not what it converges to (a closed box's pressure,
    fixed only up to a constant, starts cold: carried over, that constant moved the flow by
    1.1e-3 of its speed at every tolerance)."""
    cold, cold_visc, cold_p = riding(False, closed=closed)
    warm, warm_visc, warm_p = riding(True, closed=closed)
    assert sum(warm_visc) < 0.7 * sum(cold_visc)
    assert sum(warm_p) < 0.8 * sum(cold_p) if not closed else sum(warm_p) == sum(cold_p)
    exact, _, _ = riding(False, 1e-11, closed)
    tight, _, _ = riding(True, 1e-11, closed)
    scale = np.abs(exact.state.comps[0]).max()
    for a in range(3):
        assert np.abs(tight.state.comps[a] - exact.state.comps[a]).max() < 1e-9 * scale
        for sim in (cold, warm):
            assert np.abs(sim.state.comps[a] - exact.state.comps[a]).max() < 1e-4 * scale
    assert not np.array_equal(warm.state.comps[0], cold.state.comps[0])  # another start
    force = exact.forces["ball"].force
    assert np.abs(warm.forces["ball"].force - force).max() < 1e-4 * np.abs(force).max()


def test_without_the_setting_no_solution_is_kept():
    sim, _, _ = riding(False)
    assert sim._pressure_warm.last is None
    assert all(w.last is None for w in sim._viscosity_warm)
    on, _, _ = riding(True)
    assert on._pressure_warm.last is not None
    on.settings = dataclasses.replace(on.settings, warm_start=False)
    on.step(0.02)  # switched off: the kept solutions go
    assert on._pressure_warm.last is None
    assert all(w.last is None for w in on._viscosity_warm)


@pytest.mark.parametrize("value", [True, False])
def test_a_scene_file_sets_the_warm_start(tmp_path, value):
    from tests.solver.scenes.test_scene_files import GOOD, _write

    text = GOOD.replace("[run]", f"[solver]\nwarm_start = {str(value).lower()}\n\n[run]", 1)
    assert load_scene(_write(tmp_path, text)).settings.warm_start is value
