"""The cut-cell pressure matrix kept from step to step and assembled again only around the
probes' windows: at every step it equals a fresh assembly of the whole grid."""

from __future__ import annotations

import math

import numpy as np
import pytest

from solver.cutcell import geometry as cut_geometry
from solver.cutcell.projection import pressure_system
from solver.grid import Grid
from solver.probes import Probe
from solver.shapes import Box
from solver.simulation import Fluid, Simulation, SolverSettings

N = 20


def _path(dim: int, steps: int, dt: float) -> np.ndarray:
    """Keyframes of a box that jumps 8 cells back and forth at every step (leaving its last
    window wholly) and turns."""
    rows = []
    for n in range(steps + 2):
        t = n * dt
        x = 0.25 + (0.4 if n % 2 else 0.0) + 0.3 / N * n
        angle = 0.4 * n
        if dim == 2:
            rows.append([t, x, 0.45, angle])
        else:
            rows.append([t, x, 0.45, 0.5, math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2)])
    return np.array(rows)


def _assert_kept_is_fresh(sim: Simulation) -> None:
    kept = sim._pressure_work
    assert kept is not None and sim.cut is not None
    fresh = pressure_system(sim._static_label, sim.grid.dim, sim._kinds, sim.cut.open_frac)
    np.testing.assert_array_equal(kept.diag, fresh.diag)
    for a, b in zip(kept.off, fresh.off, strict=True):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(kept.active, fresh.active)


@pytest.mark.parametrize("margin", [2, 0])
@pytest.mark.parametrize("dim", [2, 3])
def test_the_kept_pressure_matrix_is_a_fresh_one_at_every_step(dim, margin, monkeypatch):
    """Also with windows that hug the probe (no margin), where cut faces lie on a window's
    far faces and the cells beyond them change too."""
    window = cut_geometry.probe_window
    monkeypatch.setattr(cut_geometry, "probe_window", lambda g, p: window(g, p, margin))
    dt, steps = 0.01, 8
    grid = Grid.from_size((1.0,) * dim, (N,) * dim)
    path = _path(dim, 3 * steps, dt)
    probe = Probe("box", Box((0.12,) * dim), dim, path[0, 1 : 1 + dim].copy(), path=path)
    sim = Simulation(grid, Fluid(1.0, 1e-3), probes=[probe], settings=SolverSettings())
    for _ in range(steps):
        sim.step(dt)
        _assert_kept_is_fresh(sim)
    assert len(sim.cut.windows) == 1  # the probe stayed in the grid: windows were reassembled
    # a static obstacle that appears: the whole grid again
    solid = np.zeros(grid.cells, dtype=bool)
    solid[N - 4 : N - 2, 2:6] = True
    sim.static_solid = solid
    for _ in range(2):
        sim.step(dt)
        _assert_kept_is_fresh(sim)
    # the grid moves by whole cells under the probe
    sim.shift((2, -1) if dim == 2 else (2, -1, 1))
    for _ in range(steps):
        sim.step(dt)
        _assert_kept_is_fresh(sim)
