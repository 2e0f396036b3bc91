"""Conservative upwind transport of cell-centred scalars (solver.advection.scalars)."""

from __future__ import annotations

import numpy as np
import pytest

from solver.advection.scalars import face_rates, gather_substep, transport, upwind_substep
from solver.boundary import DomainBoundary, Side
from solver.grid import Grid
from solver.labels import BOUNDARY, FREE
from solver.probes import Probe
from solver.shapes import Ball
from solver.simulation import Fluid, Simulation


def stirred_sim(dim: int) -> Simulation:
    """A closed box (open top in 3D) with a ball moving and spinning through it, one step taken."""
    n = 12
    grid = Grid.from_size((1.0,) * dim, (n,) * dim)
    sides = {"z_max": Side("outflow")} if dim == 3 else {}
    centre = np.array([0.4, 0.5, 0.5][:dim])
    spin = np.array([0.0, 0.0, 3.0]) if dim == 3 else 3.0
    probe = Probe("ball", Ball(0.15), dim, centre, None if dim == 3 else 0.0,
                  np.array([0.6, 0.2, -0.1][:dim]), spin)  # fmt: skip
    sim = Simulation(grid, Fluid(1.0, 1e-2), DomainBoundary(grid, sides), [probe])
    sim.step(0.05)
    return sim


def uniform_flow(n: int, speed: float) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """A 2D n x 1 channel with velocity ``speed`` along x on every face, all faces open."""
    comps = [np.full((n + 1, 1, 1), speed), np.zeros((n, 2, 1)), np.zeros((n, 1, 2))]
    types = [np.full(c.shape, FREE, dtype=np.int8) for c in comps]
    return comps, types


def test_closed_grid_conserves_every_scalar_to_round_off_and_stays_non_negative():
    for dim in (2, 3):
        sim = stirred_sim(dim)
        rng = np.random.default_rng(dim)
        fields = rng.random((3, *sim.grid.cells))
        fields[1] *= fields[1] > 0.7  # sharp fronts, many zeros
        before = fields.sum(axis=(1, 2, 3))
        # a long step: many CFL sub-steps
        substeps = transport(fields, sim.state.comps, sim.state.face_types, dim,
                             sim.grid.cell_size_m, 0.5)  # fmt: skip
        assert substeps > 1
        np.testing.assert_allclose(fields.sum(axis=(1, 2, 3)), before, rtol=1e-13)
        assert fields.min() >= -1e-15


def lid_driven_block() -> tuple[Simulation, np.ndarray]:
    """A 12³ box whose lid drives the flow (three steps taken), and one field: a block of 1."""
    grid = Grid.from_size((1.0, 1.0, 1.0), (12, 12, 12))
    lid = {"z_max": Side("wall", velocity=(2.0, 0.5, 0.0))}
    sim = Simulation(grid, Fluid(1.0, 1e-2), DomainBoundary(grid, lid))
    for _ in range(3):
        sim.step(0.05)
    fields = np.zeros((1, *sim.grid.cells))
    fields[0, 3:8, 3:9, 6:10] = 1.0
    return sim, fields


def test_divergence_free_flow_keeps_values_within_their_initial_range():
    """A lid-driven box: every interior face carries flux and the flow is divergence-free over
    them, so upwind transport obeys the maximum principle."""
    sim, fields = lid_driven_block()
    transport(fields, sim.state.comps, sim.state.face_types, 3, sim.grid.cell_size_m, 0.3)
    assert fields.max() <= 1.0 + 1e-5  # the projection's divergence tolerance
    assert fields.min() >= -1e-15
    assert np.count_nonzero(fields) > 5 * 6 * 4  # it did move


def test_uniform_flow_moves_the_centre_of_mass_at_the_flow_speed():
    n, h, speed, dt = 80, 0.01, 0.3, 0.4
    comps, types = uniform_flow(n, speed)
    x = (np.arange(n) + 0.5) * h
    fields = np.exp(-(((x - 0.2) / 0.03) ** 2)).reshape(1, n, 1, 1)
    before = float((fields[0, :, 0, 0] * x).sum() / fields.sum())
    transport(fields, comps, types, 2, h, dt)
    after = float((fields[0, :, 0, 0] * x).sum() / fields.sum())
    assert abs((after - before) - speed * dt) < 1e-9


def test_no_flux_through_closed_faces_or_domain_sides():
    n, h = 20, 0.01
    comps, types = uniform_flow(n, 1.0)
    types[0][10] = BOUNDARY  # a solid face between cells 9 and 10
    fields = np.zeros((1, n, 1, 1))
    fields[0, 2:6] = 1.0
    fields[0, 14:16] = 0.5
    transport(fields, comps, types, 2, h, 1.0)  # long enough to reach both walls
    assert np.isclose(fields[0, :10].sum(), 4.0) and np.isclose(fields[0, 10:].sum(), 1.0)
    assert fields[0, 9, 0, 0] > 3.9 and fields[0, n - 1, 0, 0] > 0.99  # piled against the walls


@pytest.mark.parametrize("dim", [2, 3])
def test_the_gathered_substep_is_the_face_by_face_one_bit_for_bit(dim):
    """Each cell summing its own faces (at their rates, formed once) gives what the face-by-face
    pass gives, on random fields, velocities and face types, thin grids included."""
    rng = np.random.default_rng(40 + dim)
    for trial in range(40):
        cells = (int(rng.integers(1, 7)), int(rng.integers(1, 7)),
                 int(rng.integers(1, 7)) if dim == 3 else 1)  # fmt: skip
        comps = [rng.standard_normal(tuple(c + (a == b) for a, c in enumerate(cells)))
                 for b in range(3)]  # fmt: skip
        types = [rng.choice([FREE, FREE, FREE, BOUNDARY], size=c.shape).astype(np.int8)
                 for c in comps]  # fmt: skip
        fields = rng.uniform(0.0, 1.0, (3, *cells))
        rate = float(rng.uniform(0.01, 0.2))
        w, tw = (
            (comps[2], types[2])
            if dim == 3
            else (np.zeros((1, 1, 2)), np.zeros((1, 1, 2), np.int8))
        )
        face_out, gathered = np.empty_like(fields), np.empty_like(fields)
        upwind_substep(fields, comps[0], comps[1], w, types[0], types[1], tw, dim, rate, face_out)
        rates = [np.full(comps[0].shape, 7.0), np.full(comps[1].shape, 7.0), np.full(w.shape, 7.0)]
        face_rates(comps[0], comps[1], w, types[0], types[1], tw, dim, rate, *rates)
        gather_substep(fields, *rates, dim, gathered)
        np.testing.assert_array_equal(gathered, face_out, err_msg=f"trial {trial}, {cells}")


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("count", [1, 2, 3, 5])
def test_fields_split_over_threads_give_the_same_bits(dim, count):
    """The fields cut into groups, each through every sub-step on its own thread: the values
    one thread gives, for any number of fields (one left whole), and the same sub-steps."""
    sim = stirred_sim(dim)
    rng = np.random.default_rng(7 + count)
    fields = rng.uniform(0.0, 1.0, (count, *sim.grid.cells))
    one, two = fields.copy(), fields.copy()
    comps, types = sim.state.comps, sim.state.face_types
    n_one = transport(one, comps, types, dim, sim.grid.cell_size_m, 0.4, threads=1)
    n_two = transport(two, comps, types, dim, sim.grid.cell_size_m, 0.4, threads=2)
    assert n_one == n_two > 1  # several sub-steps: each group swaps its own buffers
    np.testing.assert_array_equal(two, one)
    assert not np.array_equal(one, fields)  # the flow moved them
