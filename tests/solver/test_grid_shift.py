"""A grid moved by whole cells under standing probes: the cut geometry moves with it instead of
being computed again, and the state is the one a fresh computation gives."""

from __future__ import annotations

import numpy as np
import pytest

from solver.cutcell.geometry import CutGeometry
from solver.field_shift import shifted_by, shifted_by_axes
from solver.grid import Grid
from solver.probes import Probe
from solver.shapes import Box
from solver.simulation import Fluid, Simulation, SolverSettings
from tests.solver.cutcell.test_pressure_reassembly import _path

N = 24
FIELDS = ("phi_node", "owner_node", "fluid_frac", "phi_cell", "owner_cell")
FACE_FIELDS = ("phi_face", "open_frac", "owner_face", "owner_sample")


def _moving_box(dim: int) -> Simulation:
    grid = Grid.from_size((1.0,) * dim, (N,) * dim)
    path = _path(dim, 12, 0.01)
    probe = Probe("box", Box((0.12,) * dim), dim, path[0, 1 : 1 + dim].copy(), path=path)
    sim = Simulation(grid, Fluid(1.0, 1e-3), probes=[probe], settings=SolverSettings())
    for _ in range(3):
        sim.step(0.01)
    return sim


def _assert_same(a: Simulation, b: Simulation) -> None:
    assert a.cut is not None and b.cut is not None
    for name in FIELDS:
        np.testing.assert_allclose(getattr(a.cut, name), getattr(b.cut, name), rtol=0, atol=1e-12)
    for name in FACE_FIELDS:
        for x, y in zip(getattr(a.cut, name), getattr(b.cut, name), strict=True):
            np.testing.assert_allclose(x, y, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(a.state.label, b.state.label)
    for x, y in zip(a.state.face_types, b.state.face_types, strict=True):
        np.testing.assert_array_equal(x, y)
    for x, y in zip(a.state.comps, b.state.comps, strict=True):
        np.testing.assert_allclose(x, y, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("dim", [2, 3])
def test_a_shift_moves_the_probes_geometry_as_a_fresh_computation_finds_it(dim, monkeypatch):
    moved, fresh = _moving_box(dim), _moving_box(dim)
    offset = (2, -1) if dim == 2 else (2, -1, 1)
    updates = []
    real_update = CutGeometry.update
    monkeypatch.setattr(
        CutGeometry, "update", lambda self, *a, **k: (updates.append(1), real_update(self, *a, **k))
    )
    moved.shift(offset)
    assert updates == []  # moved, not computed again
    assert fresh.cut is not None
    monkeypatch.setattr(fresh.cut, "shift", lambda *a: False)  # the full computation
    fresh.shift(offset)
    assert updates == [1]
    _assert_same(moved, fresh)
    for sim in (moved, fresh):
        sim.step(0.01)
    _assert_same(moved, fresh)


def test_a_window_that_touches_a_side_it_moves_across_is_computed_again():
    sim = _moving_box(3)
    assert sim.cut is not None
    lo, hi = sim.cut.windows[0]
    before = sim.cut.phi_node.copy()
    assert not sim.cut.shift((int(lo[0]) + 1, 0, 0), sim.grid.cells)  # would leave the grid
    assert not sim.cut.shift((-(N - int(hi[0])) - 1, 0, 0), sim.grid.cells)
    np.testing.assert_array_equal(sim.cut.phi_node, before)  # refused: nothing changed


def test_the_compiled_fractional_shift_is_the_axis_by_axis_one_bit_for_bit():
    """Every mix of whole and fractional offsets, negative ones, offsets past the grid's size
    and axes left alone: the one compiled pass gives what the numpy passes give."""
    rng = np.random.default_rng(7)
    for trial in range(200):
        shape = tuple(int(n) for n in rng.integers(1, 7, size=3))
        q = rng.standard_normal(shape)
        off = [float(rng.choice([0.0, rng.integers(-8, 8), rng.uniform(-8, 8)])) for _ in range(3)]
        np.testing.assert_array_equal(shifted_by(q, off), shifted_by_axes(q, off),
                                      err_msg=f"trial {trial}, {shape}, {off}")  # fmt: skip
