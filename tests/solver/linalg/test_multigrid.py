"""Multigrid-preconditioned CG: exact against a direct solve, a symmetric positive
preconditioner, few iterations on Poisson problems, and the same flow as MIC(0)-PCG."""

from __future__ import annotations

from unittest import mock

import numpy as np
import pytest
import scipy.sparse.linalg as spla
from hypothesis import given, settings
from hypothesis import strategies as st

from solver.boundary import OUTFLOW
from solver.grid import Grid
from solver.labels import FLUID, STATIC_SOLID
from solver.linalg import multigrid
from solver.linalg.multigrid import Multigrid, level_shapes, v_cycle
from solver.linalg.pcg import StencilSystem, solve
from solver.probes import Probe
from solver.shapes import Ball, Box
from solver.simulation import Fluid, Simulation, SolverSettings
from solver.staircase.projection import build_pressure_system
from tests.support.stencil_systems import random_system, to_sparse


def _poisson(n: int, dim: int, outflow: bool) -> tuple[StencilSystem, np.ndarray]:
    """The staircase pressure matrix of a unit box with a ball-shaped obstacle, and a random
    right-hand side (mean-free over the fluid when no side is open)."""
    shape = (n, n, n if dim == 3 else 1)
    label = np.full(shape, FLUID, dtype=np.int32)
    c = (np.indices(shape) + 0.5) / n
    r2 = (c[0] - 0.31) ** 2 + (c[1] - 0.52) ** 2 + ((c[2] - 0.5) ** 2 if dim == 3 else 0.0)
    label[r2 < 0.08**2] = STATIC_SOLID
    kinds = np.zeros((3, 2), dtype=np.int64)
    if outflow:
        kinds[0, 1] = OUTFLOW
    s = StencilSystem.empty(shape, dim)
    build_pressure_system(label, dim, kinds, s.diag, s.off[0], s.off[1], s.off[2], s.active)
    b = np.where(s.active, np.random.default_rng(n).standard_normal(shape), 0.0)
    if not outflow:
        b[s.active] -= b[s.active].mean()
    return s, b


def _hierarchy(s: StencilSystem) -> Multigrid:
    """A multigrid whose levels are built from ``s`` (as a solve builds them)."""
    mg = Multigrid(s.diag.shape, s.dim)
    mg.load(s)
    return mg


def _precondition(mg: Multigrid, r: np.ndarray) -> np.ndarray:
    z = np.zeros(r.size)
    v_cycle(mg.hierarchy, r.reshape(-1).copy(), z, mg.work[4], mg.work[5])
    return z


@pytest.mark.parametrize(
    ("shape", "dim"), [((17, 13, 1), 2), ((33, 20, 1), 2), ((7, 9, 6), 3), ((13, 11, 10), 3)]
)
def test_mgpcg_matches_direct_solve(shape, dim):
    s = random_system(shape, dim, seed=sum(shape))
    b = np.where(s.active, np.random.default_rng(1).standard_normal(shape), 0.0)
    x = np.zeros(shape)
    report = Multigrid(shape, dim).solve(s, b, x, 1e-10, 500)
    a, idx = to_sparse(s)
    exact = spla.spsolve(a, b.ravel()[idx])
    assert report.converged and report.residual <= 1e-10
    np.testing.assert_allclose(x.ravel()[idx], exact, rtol=1e-7, atol=1e-9)
    assert np.all(x[~s.active] == 0.0)


@pytest.mark.parametrize(("shape", "dim"), [((6, 9, 7), 3), ((9, 7, 6), 3), ((12, 10, 1), 2)])
def test_a_solve_into_strided_arrays_gives_what_a_contiguous_one_gives(shape, dim):
    """The grid's order (and strides) of ``b`` and ``x`` differ from the kernels' (shortest axis
    first) or match it; either way the solve writes the same values into ``x`` and nothing
    else of the array it is a view of."""
    s = random_system(shape, dim, seed=3)
    b = np.where(s.active, np.random.default_rng(2).standard_normal(shape), 0.0)
    x = np.full(shape, 0.25)
    Multigrid(shape, dim).solve(s, b, x, 1e-9, 200)
    strided_b = np.zeros((2, *shape))
    strided_b[1] = b
    holder = np.full((*shape, 2), 7.0)
    strided_x = holder[..., 0]
    strided_x[...] = 0.25
    Multigrid(shape, dim).solve(s, strided_b[1], strided_x, 1e-9, 200)
    np.testing.assert_array_equal(strided_x, x)
    assert np.all(holder[..., 1] == 7.0)


@pytest.mark.parametrize(("n", "dim"), [(64, 2), (128, 2), (32, 3)])
@pytest.mark.parametrize("outflow", [False, True])
def test_poisson_takes_few_iterations_where_mic0_takes_many(n, dim, outflow):
    s, b = _poisson(n, dim, outflow)
    x_mg, x_ic = np.zeros(b.shape), np.zeros(b.shape)
    mg = Multigrid(b.shape, dim).solve(s, b, x_mg, 1e-6, 500)
    ic = solve(s, b, x_ic, 1e-6, 500)
    assert mg.converged and ic.converged
    assert mg.iterations <= 10
    assert ic.iterations >= 3 * mg.iterations
    # the same pressure up to the constant a closed domain leaves free
    d = x_mg - x_ic
    if not outflow:
        d[s.active] -= d[s.active].mean()
    assert np.abs(d[s.active]).max() <= 1e-4 * np.abs(x_ic[s.active]).max()


@settings(max_examples=25, deadline=None)
@given(
    nx=st.integers(2, 19),
    ny=st.integers(2, 19),
    nz=st.integers(1, 7),
    seed=st.integers(0, 2**31),
    margin=st.sampled_from([0.0, 1e-3, 0.5]),
    low=st.sampled_from([1e-4, 0.2]),
)
def test_v_cycle_is_symmetric_and_positive(nx, ny, nz, seed, margin, low):
    dim = 2 if nz == 1 else 3
    s = random_system((nx, ny, nz), dim, seed=seed, margin=margin, low=low)
    mg = _hierarchy(s)
    rng = np.random.default_rng(seed + 1)
    act = s.active.reshape(-1)
    r1 = np.where(act, rng.standard_normal(act.size), 0.0)
    r2 = np.where(act, rng.standard_normal(act.size), 0.0)
    z1, z2 = _precondition(mg, r1), _precondition(mg, r2)
    scale = np.linalg.norm(z1) * np.linalg.norm(r2) + np.linalg.norm(z2) * np.linalg.norm(r1)
    assert abs(z1 @ r2 - r1 @ z2) <= 1e-10 * scale
    unknowns = mg.active[: act.size]  # active entries with a non-zero row
    if unknowns.any():
        assert z1 @ r1 > 0.0
    assert np.all(z1[~unknowns] == 0.0)


def test_coarse_levels_keep_a_closed_domain_s_constant_null_space():
    s, _ = _poisson(48, 3, outflow=False)
    mg = _hierarchy(s)
    for lev in range(mg.levels):
        nx, ny, nz = mg.shapes[lev]
        o = mg.starts[lev]
        size = nx * ny * nz
        diag = mg.diag[o : o + size].reshape(nx, ny, nz)
        offs = [mg.off[a][o : o + size].reshape(nx, ny, nz) for a in range(3)]
        act = mg.active[o : o + size].reshape(nx, ny, nz)
        rows = diag.copy()
        for a in range(3):
            rows += offs[a] + np.roll(offs[a], 1, axis=a)
        assert act.any()
        assert np.abs(rows[act]).max() <= 1e-12 * diag[act].max()
        # coarse couplings are those of the 2h operator: half the sum of the fine faces
        assert np.all(np.concatenate([o_[act] for o_ in offs]) <= 0.0)


def test_level_shapes_halve_until_a_few_cells():
    assert level_shapes((1, 64, 64)) == [(1, 64, 64), (1, 32, 32), (1, 16, 16), (1, 8, 8),
                                         (1, 4, 4)]  # fmt: skip
    assert level_shapes((33, 32, 12))[-1] == (3, 2, 1)
    assert level_shapes((3, 4, 1)) == [(3, 4, 1)]


def _flow(settings: SolverSettings, dim: int) -> Simulation:
    if dim == 2:
        grid = Grid.from_size((1.0, 1.0), (48, 48))
        shape = Ball(0.08)
        probe = Probe("p", shape, 2, np.array([0.3, 0.5]), 0.0, np.array([0.6, 0.1]), 2.0)
    else:
        grid = Grid.from_size((1.0, 1.0, 1.0), (20, 20, 20))
        probe = Probe("p", Box((0.2, 0.2, 0.2)), 3, np.array([0.4, 0.5, 0.5]), None,
                      np.array([0.5, 0.1, 0.0]), np.array([0.0, 0.0, 2.0]))  # fmt: skip
    return Simulation(grid, Fluid(1.0, 1e-3), probes=[probe], settings=settings)


@pytest.mark.parametrize(("dim", "method"), [(2, "cutcell"), (2, "staircase"), (3, "staircase")])
def test_multigrid_and_mic0_give_the_same_flow_and_forces(dim, method):
    def settings(pre: str) -> SolverSettings:
        return SolverSettings(boundary_method=method, preconditioner=pre,
                              viscosity_preconditioner=pre, pressure_tolerance=1e-9,
                              viscosity_tolerance=1e-10)  # fmt: skip

    sims = {pre: _flow(settings(pre), dim) for pre in ("multigrid", "mic0")}
    for _ in range(12):
        reports = {pre: sim.step(0.01) for pre, sim in sims.items()}
    assert reports["multigrid"].pressure.iterations < reports["mic0"].pressure.iterations
    mg, ic = sims["multigrid"], sims["mic0"]
    for a in range(dim):
        scale = np.abs(ic.state.comps[a]).max()
        assert np.abs(mg.state.comps[a] - ic.state.comps[a]).max() <= 1e-6 * scale
    f_mg, f_ic = mg.forces["p"].force, ic.forces["p"].force
    assert np.abs(f_mg - f_ic).max() <= 1e-5 * np.abs(f_ic).max()


@settings(max_examples=25, deadline=None)
@given(
    nx=st.integers(2, 13),
    ny=st.integers(1, 12),
    nz=st.integers(2, 11),
    seed=st.integers(0, 10_000),
    margin=st.sampled_from([0.0, 0.5]),
)
def test_the_parallel_kernels_give_the_serial_bits(nx, ny, nz, seed, margin):
    """Every level on two threads (the threshold lowered to one cell): the same solution and
    iterations, bit for bit, as one thread, on random systems with holes and odd sizes."""
    s = random_system((nx, ny, nz), 3, seed=seed, margin=margin)
    rng = np.random.default_rng(seed)
    b = np.where(s.active, rng.standard_normal(s.diag.shape), 0.0)
    if margin == 0.0:
        b[s.active] -= b[s.active].mean()
    x0 = np.where(s.active, rng.standard_normal(s.diag.shape), 0.0)
    got = []
    for threads in (1, 2):
        mg = Multigrid(s.diag.shape, 3, threads=threads)
        x = x0.copy()
        with mock.patch.object(multigrid, "PARALLEL_MIN_CELLS", 1):
            report = mg.solve(s, b, x, 1e-9, 200)
        got.append((x, report))
    (x1, r1), (x2, r2) = got
    assert np.array_equal(x1, x2)
    assert r1 == r2
    assert r1.iterations > 0  # the solve did move x


def test_a_large_3d_solve_takes_the_parallel_path_and_keeps_the_bits():
    s, b = _poisson(34, 3, outflow=True)  # 39304 cells: above the threshold
    assert s.diag.size >= multigrid.PARALLEL_MIN_CELLS
    one, two = Multigrid(s.diag.shape, 3), Multigrid(s.diag.shape, 3, threads=2)
    x1, x2 = np.zeros_like(b), np.zeros_like(b)
    r1, r2 = one.solve(s, b, x1, 1e-8, 50), two.solve(s, b, x2, 1e-8, 50)
    assert r1.converged and r1 == r2
    assert np.array_equal(x1, x2)
    a, idx = to_sparse(s)
    exact = spla.spsolve(a.tocsc(), b.reshape(-1)[idx])
    assert np.abs(x2.reshape(-1)[idx] - exact).max() <= 1e-6 * np.abs(exact).max()


def test_an_adaptive_solve_tries_both_ways_and_keeps_the_serial_bits():
    """Auto's pressure solve (every level parallel here): it runs on threads or on one as its
    timings say, and every solve gives what a one-thread solve gives."""
    s = random_system((9, 10, 11), 3, seed=7)
    rng = np.random.default_rng(7)
    adaptive = Multigrid(s.diag.shape, 3, threads=2, adaptive=True)
    serial = Multigrid(s.diag.shape, 3)
    ways = []
    with mock.patch.object(multigrid, "PARALLEL_MIN_CELLS", 1):
        assert adaptive.parallel and adaptive.adaptive
        for _ in range(6):
            b = np.where(s.active, rng.standard_normal(s.diag.shape), 0.0)
            x1, x2 = np.zeros_like(b), np.zeros_like(b)
            r1, r2 = serial.solve(s, b, x1, 1e-9, 200), adaptive.solve(s, b, x2, 1e-9, 200)
            assert r1 == r2 and np.array_equal(x1, x2)
            ways.append(adaptive.last_on_threads)
    assert ways[:2] == [False, True]  # each way tried first
    assert adaptive.choice.cost(0) is not None and adaptive.choice.cost(1) is not None


def test_a_multigrid_refuses_no_threads():
    with pytest.raises(ValueError, match="threads"):
        Multigrid((8, 8, 8), 3, threads=0)
