"""MIC(0)-preconditioned CG against a direct sparse solve."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from solver.pcg import StencilSystem, solve


def _random_system(shape, dim, seed=0):
    rng = np.random.default_rng(seed)
    s = StencilSystem.empty(shape, dim)
    s.active[:] = rng.random(shape) > 0.15
    for b in range(dim):
        off = -rng.uniform(0.2, 1.0, shape)
        sl = [slice(None)] * 3
        sl[b] = slice(-1, None)
        off[tuple(sl)] = 0.0
        nb = np.roll(s.active, -1, axis=b)
        off[~(s.active & nb)] = 0.0
        s.off[b][:] = off
    # diagonal dominance makes it SPD
    diag = np.full(shape, 0.5)
    for b in range(dim):
        diag += -s.off[b] - np.roll(s.off[b], 1, axis=b)
    s.diag[:] = np.where(s.active, diag, 0.0)
    return s


def _to_sparse(s: StencilSystem) -> tuple[sp.csr_matrix, np.ndarray]:
    idx = np.flatnonzero(s.active.ravel())
    pos = -np.ones(s.active.size, dtype=int)
    pos[idx] = np.arange(idx.size)
    rows, cols, vals = list(idx), list(idx), list(s.diag.ravel()[idx])
    strides = [s.active.shape[1] * s.active.shape[2], s.active.shape[2], 1]
    for b in range(s.dim):
        off = s.off[b].ravel()
        for n in idx:
            if off[n] != 0.0:
                m = n + strides[b]
                rows += [n, m]
                cols += [m, n]
                vals += [off[n], off[n]]
    a = sp.coo_matrix((vals, (pos[rows], pos[cols])), shape=(idx.size, idx.size)).tocsr()
    return a, idx


def test_pcg_matches_direct_solve_2d_and_3d():
    for shape, dim in (((17, 13, 1), 2), ((7, 9, 6), 3)):
        s = _random_system(shape, dim)
        rng = np.random.default_rng(1)
        b = np.where(s.active, rng.standard_normal(shape), 0.0)
        x = np.zeros(shape)
        report = solve(s, b, x, 1e-10, 500)
        a, idx = _to_sparse(s)
        exact = spla.spsolve(a, b.ravel()[idx])
        assert report.converged and report.residual <= 1e-10
        assert 0 < report.iterations < 200
        np.testing.assert_allclose(x.ravel()[idx], exact, rtol=1e-7, atol=1e-9)
        assert np.all(x[~s.active] == 0.0)


def test_warm_start_from_the_solution_takes_no_iterations():
    s = _random_system((20, 20, 1), 2, seed=3)
    b = np.where(s.active, 1.0, 0.0)
    x = np.zeros(s.active.shape)
    first = solve(s, b, x, 1e-8, 500)
    second = solve(s, b, x, 1e-8, 500)
    assert first.iterations > 5
    assert second.iterations == 0


def test_iteration_cap_reports_not_converged():
    s = _random_system((30, 30, 1), 2, seed=4)
    b = np.where(s.active, 1.0, 0.0)
    report = solve(s, b, np.zeros(s.active.shape), 1e-14, 2)
    assert report.iterations == 2
    assert not report.converged
    assert report.residual > 1e-14
