"""Flux-corrected transport of cell-centred scalars (solver.advection.fct, through
``transport(..., scheme="fct")``): conserved, within its neighbourhoods' range, and a front that
stays sharp where upwind smears it."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from solver.advection.scalars import transport
from solver.labels import BOUNDARY, FREE
from tests.solver.advection.test_scalar_transport import (
    lid_driven_block,
    stirred_sim,
    uniform_flow,
)


def moved(fields: np.ndarray, speed: float, dt: float, scheme: str, steps: int = 1) -> np.ndarray:
    """``fields`` (n cells along x, one field) after ``steps`` steps of ``dt`` in a uniform
    flow of ``speed`` cells a second (h = 1)."""
    out = fields.reshape(1, -1, 1, 1).copy()
    comps, types = uniform_flow(out.shape[1], speed)
    for _ in range(steps):
        transport(out, comps, types, 2, 1.0, dt, scheme=scheme)
    return out[0, :, 0, 0]


def front_width(profile: np.ndarray, top: float) -> int:
    """Cells holding between 5 % and 95 % of ``top``."""
    return int(np.count_nonzero((profile > 0.05 * top) & (profile < 0.95 * top)))


@pytest.mark.parametrize("dim", [2, 3])
def test_a_stirred_grid_conserves_every_field_to_round_off_and_stays_non_negative(dim):
    sim = stirred_sim(dim)
    rng = np.random.default_rng(dim)
    fields = rng.random((3, *sim.grid.cells))
    fields[1] *= fields[1] > 0.7  # sharp fronts, many zeros
    fields[2] = 0.0
    fields[2][tuple(slice(2, 6) for _ in range(dim))] = 1.0  # one block
    before = fields.sum(axis=(1, 2, 3))
    comps, types = sim.state.comps, sim.state.face_types
    substeps = transport(fields, comps, types, dim, sim.grid.cell_size_m, 0.5, scheme="fct")
    assert substeps > 1
    np.testing.assert_allclose(fields.sum(axis=(1, 2, 3)), before, rtol=1e-13)
    assert fields.min() >= 0.0
    assert np.isfinite(fields).all()


def test_a_divergence_free_flow_keeps_values_within_their_initial_range():
    """A lid-driven box: no new extremum (the limiter's bounds) where upwind keeps none."""
    sim, fields = lid_driven_block()
    comps, types = sim.state.comps, sim.state.face_types
    transport(fields, comps, types, 3, sim.grid.cell_size_m, 0.3, scheme="fct")
    assert fields.max() <= 1.0 + 1e-5  # the projection's divergence tolerance
    assert fields.min() >= 0.0
    assert np.count_nonzero(fields > 1e-6) > 5 * 6 * 4  # it did move


@pytest.mark.parametrize(("dt", "steps"), [(0.5, 40), (0.2, 100), (2.5, 8)])
def test_a_moving_front_stays_a_few_cells_wide_where_upwind_smears_it(dt, steps):
    """A top-hat 10 cells wide carried 20 cells at Courant numbers 0.5, 0.2 and 0.83 (three
    sub-steps a step): upwind spreads each front over 6-11 cells (5-95 %), a width that grows
    as the root of the distance; the correction keeps each within 5 cells, the plateau near
    its height, and the profile nearer the exact shift (L1) by more than half."""
    x = np.arange(64)
    hat = ((x >= 10) & (x < 20)).astype(float)
    exact = ((x >= 30) & (x < 40)).astype(float)
    upwind = moved(hat, 1.0, dt, "upwind", steps)
    fct = moved(hat, 1.0, dt, "fct", steps)
    assert front_width(fct[:35], 1.0) <= 5 and front_width(fct[35:], 1.0) <= 5
    assert front_width(upwind[:35], 1.0) >= 6
    assert fct[32:38].min() > 0.9 and fct.max() <= 1.0 + 1e-12
    assert np.abs(fct - exact).sum() < 0.5 * np.abs(upwind - exact).sum()
    assert fct.sum() == pytest.approx(10.0, rel=1e-13) and fct.min() >= 0.0


def test_a_corrected_front_does_not_widen_with_the_distance_it_travels():
    """Carried 20 and then 60 cells, upwind's front widens (as the root of the distance, by
    about 1.4 here); the corrected one keeps its width."""
    x = np.arange(100)
    hat = ((x >= 10) & (x < 20)).astype(float)
    widths = {}
    for scheme in ("upwind", "fct"):
        near, far = (moved(hat, 1.0, 0.5, scheme, steps) for steps in (40, 120))
        widths[scheme] = (front_width(near[:35], 1.0), front_width(far[:75], 1.0))
    assert widths["upwind"][1] >= 1.3 * widths["upwind"][0]
    assert widths["fct"][1] <= widths["fct"][0] <= 5


def test_a_smooth_bump_keeps_its_peak_and_moves_at_the_flow_speed():
    """A Gaussian of 5 cells carried 20 cells: upwind loses a quarter of its peak; the corrected
    bump keeps over 0.9 of it, its error (L1) under a third of upwind's, and its centre of mass
    moves with the flow (a symmetric bump's correction is symmetric)."""
    x = np.arange(80) + 0.5
    bump = np.exp(-(((x - 15.0) / 5.0) ** 2))
    exact = np.exp(-(((x - 35.0) / 5.0) ** 2))
    upwind = moved(bump, 1.0, 0.5, "upwind", 40)
    fct = moved(bump, 1.0, 0.5, "fct", 40)
    assert upwind.max() < 0.8 < 0.9 < fct.max() <= 1.0
    assert np.abs(fct - exact).sum() < np.abs(upwind - exact).sum() / 3.0
    centre = float((fct * x).sum() / fct.sum())
    assert centre == pytest.approx(35.0, abs=0.05)


def test_a_linear_ramp_is_moved_as_upwind_moves_it():
    """On a straight ramp the upwind step is exact and every face's correction is the same, so
    the correction changes nothing (away from the ramp's ends)."""
    ramp = np.linspace(0.0, 1.0, 40)
    upwind = moved(ramp, 0.7, 0.5, "upwind")
    fct = moved(ramp, 0.7, 0.5, "fct")
    np.testing.assert_allclose(fct[3:-3], upwind[3:-3], rtol=0, atol=1e-14)


def test_still_fluid_leaves_the_fields_alone():
    fields = np.random.default_rng(3).random((2, 6, 5, 4))
    comps = [np.zeros((7, 5, 4)), np.zeros((6, 6, 4)), np.zeros((6, 5, 5))]
    types = [np.zeros(c.shape, dtype=np.int8) for c in comps]
    before = fields.copy()
    transport(fields, comps, types, 3, 0.1, 0.2, scheme="fct")
    np.testing.assert_array_equal(fields, before)


def test_no_flux_through_closed_faces_or_domain_sides():
    n = 20
    comps, types = uniform_flow(n, 1.0)
    types[0][10] = BOUNDARY  # a solid face between cells 9 and 10
    fields = np.zeros((1, n, 1, 1))
    fields[0, 2:6] = 1.0
    fields[0, 14:16] = 0.5
    transport(fields, comps, types, 2, 0.01, 1.0, scheme="fct")  # long enough for both walls
    assert np.isclose(fields[0, :10].sum(), 4.0) and np.isclose(fields[0, 10:].sum(), 1.0)
    assert fields[0, 9, 0, 0] > 0.99 and fields[0, n - 1, 0, 0] > 0.49  # piled at the walls


@pytest.mark.parametrize("dim", [2, 3])
def test_fields_split_over_threads_give_the_same_bits(dim):
    sim = stirred_sim(dim)
    fields = np.random.default_rng(11).uniform(0.0, 1.0, (3, *sim.grid.cells))
    one, two = fields.copy(), fields.copy()
    comps, types, h = sim.state.comps, sim.state.face_types, sim.grid.cell_size_m
    transport(one, comps, types, dim, h, 0.4, threads=1, scheme="fct")
    transport(two, comps, types, dim, h, 0.4, threads=2, scheme="fct")
    np.testing.assert_array_equal(two, one)
    assert not np.array_equal(one, fields)


def test_an_unknown_scheme_is_refused():
    comps, types = uniform_flow(8, 1.0)
    with pytest.raises(ValueError, match="unknown transport scheme 'muscl'"):
        transport(np.zeros((1, 8, 1, 1)), comps, types, 2, 1.0, 0.1, scheme="muscl")


@settings(max_examples=60, deadline=None)
@given(
    st.integers(0, 2**32 - 1),
    st.sampled_from([(1, 5, 6, 1), (2, 4, 3, 5), (3, 6, 5, 4)]),
    st.floats(0.01, 3.0),
)
def test_any_flow_conserves_each_field_and_stays_within_the_upwind_result_s_range(seed, shape, dt):
    """Random fields (sparse, with zeros), random face velocities (not divergence-free: paint
    piles and thins, as next to a moving tip) and face types: each field's total is kept to
    round-off, nothing goes negative or non-finite, and no cell exceeds the largest value the
    upwind step itself left (the correction adds no extremum)."""
    rng = np.random.default_rng(seed)
    n, nx, ny, nz = shape
    dim = 3 if nz > 1 else 2
    comps = [rng.normal(size=(nx + 1, ny, nz)), rng.normal(size=(nx, ny + 1, nz)),
             rng.normal(size=(nx, ny, nz + 1))]  # fmt: skip
    types = [np.where(rng.random(c.shape) < 0.85, FREE, BOUNDARY).astype(np.int8) for c in comps]
    fields = rng.random((n, nx, ny, nz)) * (rng.random((n, nx, ny, nz)) < 0.6)
    upwind, fct = fields.copy(), fields.copy()
    transport(upwind, comps[:dim], types[:dim], dim, 1.0, dt)
    transport(fct, comps[:dim], types[:dim], dim, 1.0, dt, scheme="fct")
    np.testing.assert_allclose(fct.sum(axis=(1, 2, 3)), fields.sum(axis=(1, 2, 3)), rtol=1e-12)
    assert np.isfinite(fct).all() and fct.min() >= 0.0
    assert (fct.max(axis=(1, 2, 3)) <= upwind.max(axis=(1, 2, 3)) * (1 + 1e-12)).all()
