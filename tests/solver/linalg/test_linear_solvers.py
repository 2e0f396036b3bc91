"""MIC(0)- and diagonally preconditioned CG against a direct sparse solve; the diagonal one's
kept scratch."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from solver.linalg.pcg import JacobiPCG, solve, solve_jacobi
from solver.settings import JACOBI_LIMIT, SolverSettings
from tests.support.stencil_systems import random_system, to_sparse


@pytest.mark.parametrize("linear_solve", [solve, solve_jacobi])
def test_pcg_matches_direct_solve_2d_and_3d(linear_solve):
    for shape, dim in (((17, 13, 1), 2), ((7, 9, 6), 3)):
        s = random_system(shape, dim)
        rng = np.random.default_rng(1)
        b = np.where(s.active, rng.standard_normal(shape), 0.0)
        x = np.zeros(shape)
        report = linear_solve(s, b, x, 1e-10, 500)
        a, idx = to_sparse(s)
        exact = spla.spsolve(a, b.ravel()[idx])
        assert report.converged and report.residual <= 1e-10
        assert 0 < report.iterations < 200
        np.testing.assert_allclose(x.ravel()[idx], exact, rtol=1e-7, atol=1e-9)
        assert np.all(x[~s.active] == 0.0)


def test_warm_start_from_the_solution_takes_no_iterations():
    s = random_system((20, 20, 1), 2, seed=3)
    b = np.where(s.active, 1.0, 0.0)
    x = np.zeros(s.active.shape)
    first = solve(s, b, x, 1e-8, 500)
    second = solve(s, b, x, 1e-8, 500)
    assert first.iterations > 5
    assert second.iterations == 0


def test_iteration_cap_reports_not_converged():
    s = random_system((30, 30, 1), 2, seed=4)
    b = np.where(s.active, 1.0, 0.0)
    report = solve(s, b, np.zeros(s.active.shape), 1e-14, 2)
    assert report.iterations == 2
    assert not report.converged
    assert report.residual > 1e-14


def test_auto_viscosity_preconditioner_follows_the_coupling():
    auto = SolverSettings()
    assert auto.viscosity_solver(0.1) == "jacobi"
    assert auto.viscosity_solver(JACOBI_LIMIT) == "jacobi"
    assert auto.viscosity_solver(10.0 * JACOBI_LIMIT) == "multigrid"
    assert SolverSettings(viscosity_preconditioner="mic0").viscosity_solver(0.1) == "mic0"


def test_a_kept_jacobi_solver_gives_each_system_what_a_fresh_one_gives():
    """Its scratch (inverse diagonal, residual, direction, product) is rebuilt by every solve:
    a solve after another system's gives the bits of a first solve; a non-contiguous x gets its
    solution."""
    shape = (9, 8, 7)
    kept = JacobiPCG(shape)
    for seed in (5, 6, 5):
        s = random_system(shape, 3, seed=seed)
        b = np.where(s.active, np.random.default_rng(seed).standard_normal(shape), 0.0)
        x_kept, x_fresh = np.zeros(shape), np.zeros(shape)
        kept_report = kept.solve(s, b, x_kept, 1e-9, 300)
        fresh_report = JacobiPCG(shape).solve(s, b, x_fresh, 1e-9, 300)
        assert kept_report == fresh_report and kept_report.converged
        assert np.array_equal(x_kept, x_fresh)
    holder = np.zeros((2 * shape[0], *shape[1:]))
    strided = holder[::2]
    report = kept.solve(s, b, strided, 1e-9, 300)
    assert report == fresh_report and np.array_equal(strided, x_fresh)
    assert np.all(holder[1::2] == 0.0)
    with pytest.raises(ValueError, match="shape"):
        kept.solve(s, b[:-1], x_kept[:-1], 1e-9, 300)
