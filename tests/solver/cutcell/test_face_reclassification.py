"""The cut-cell face classification kept from step to step and made again only in the last
step's windows: every step gives what a full classification gives, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from solver.cutcell import geometry as cut_geometry
from solver.grid import Grid
from solver.probes import Probe
from solver.shapes import Box
from solver.simulation import Fluid, Simulation, SolverSettings
from tests.solver.cutcell.test_pressure_reassembly import N, _path


def _pair(dim: int, steps: int, dt: float, solid: np.ndarray | None) -> list[Simulation]:
    path = _path(dim, 3 * steps, dt)
    grid = Grid.from_size((1.0,) * dim, (N,) * dim)
    sims = []
    for _ in range(2):
        probe = Probe("box", Box((0.12,) * dim), dim, path[0, 1 : 1 + dim].copy(), path=path)
        settings = SolverSettings()
        sims.append(Simulation(grid, Fluid(1.0, 1e-3), probes=[probe], static_solid=solid,
                               settings=settings))  # fmt: skip
    return sims


def _step_alike(kept: Simulation, full: Simulation, dt: float) -> None:
    full._faces_built = None  # classify the whole grid again
    kept.step(dt)
    full.step(dt)
    assert kept._faces_built is not None and kept._faces_built.windows
    for a in range(kept.grid.dim):
        np.testing.assert_array_equal(kept.state.face_types[a], full.state.face_types[a])
        np.testing.assert_array_equal(kept.state.comps[a], full.state.comps[a])
    np.testing.assert_array_equal(kept.state.pressure, full.state.pressure)


@pytest.mark.parametrize("margin", [2, 0])
@pytest.mark.parametrize("dim", [2, 3])
def test_the_kept_face_classification_steps_as_a_full_one(dim, margin, monkeypatch):
    """A box that jumps 8 cells at every step (leaving its last window wholly) beside a static
    obstacle, with the cut geometry's margin as is and at 0; then the obstacle grows (a full
    pass again), and the grid moves under the probe."""
    window = cut_geometry.probe_window
    monkeypatch.setattr(cut_geometry, "probe_window", lambda g, p: window(g, p, margin))
    dt, steps = 0.01, 6
    solid = np.zeros((N,) * dim, dtype=bool)
    solid[N - 5 : N - 3, 3:7] = True
    kept, full = _pair(dim, steps, dt, solid)
    for _ in range(steps):
        _step_alike(kept, full, dt)
    assert kept._faces_built is not None and kept._faces_built.solid_faces[0].size > 0
    for sim in (kept, full):
        grown = sim.static_solid.copy()
        grown[2:4, N - 6 : N - 3] = True
        sim.static_solid = grown
    for _ in range(2):
        _step_alike(kept, full, dt)
    for sim in (kept, full):
        sim.shift((2, -1) if dim == 2 else (2, -1, 1))
    for _ in range(steps):
        _step_alike(kept, full, dt)
