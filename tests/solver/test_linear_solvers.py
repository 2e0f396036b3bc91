"""MIC(0)- and diagonally preconditioned CG against a direct sparse solve."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from solver.pcg import solve, solve_jacobi
from solver.solver_settings import JACOBI_LIMIT, SolverSettings
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
