"""The trilinear read of staggered samples (``solver.interp``): exact on linear fields, clamped to
the samples' range (NaN to the first sample), bilinear one sample deep, and its stencil's range."""

from __future__ import annotations

import numpy as np
import pytest

from solver.interp import sample, sample_range, velocity_at

H = 0.5
OFFSETS = {-1: (0.5, 0.5, 0.5), 0: (0.0, 0.5, 0.5), 1: (0.5, 0.0, 0.5), 2: (0.5, 0.5, 0.0)}


def _positions(axis: int, shape: tuple[int, int, int]) -> np.ndarray:
    """(nx, ny, nz, 3) positions (m) of the samples of component ``axis`` (-1: cell centres)."""
    offset = OFFSETS[axis]
    grids = np.meshgrid(
        *[(np.arange(n) + o) * H for n, o in zip(shape, offset, strict=True)], indexing="ij"
    )
    return np.stack(grids, axis=-1)


@pytest.mark.parametrize("axis", [-1, 0, 1, 2])
def test_a_linear_field_is_read_exactly_inside_the_samples(axis):
    shape = (6, 5, 4)
    at = _positions(axis, shape)
    field = 0.3 + at @ np.array([1.5, -2.0, 0.75])
    rng = np.random.default_rng(7)
    lo, hi = at.reshape(-1, 3).min(axis=0), at.reshape(-1, 3).max(axis=0)
    for p in rng.uniform(lo, hi, size=(200, 3)):
        expected = 0.3 + p @ np.array([1.5, -2.0, 0.75])
        assert sample(field, axis, p[0], p[1], p[2], H) == pytest.approx(expected, abs=1e-12)


def test_points_beyond_the_samples_read_the_nearest_edge_and_nan_reads_the_first_sample():
    rng = np.random.default_rng(3)
    q = rng.normal(size=(4, 3, 5))
    # cell centres sit at (i + 1/2) h: far outside, the outermost samples hold
    assert sample(q, -1, -7.0, -7.0, -7.0, H) == q[0, 0, 0]
    assert sample(q, -1, 50.0, 50.0, 50.0, H) == q[-1, -1, -1]
    assert sample(q, -1, np.inf, -np.inf, 50.0, H) == q[-1, 0, -1]
    assert sample(q, -1, np.nan, np.nan, np.nan, H) == q[0, 0, 0]
    # along x only: clamped in x, linear in the others at sample positions
    assert sample(q, -1, 50.0, 1.5 * H, 2.5 * H, H) == q[-1, 1, 2]


def test_one_sample_deep_reads_bilinearly_and_ignores_depth():
    rng = np.random.default_rng(5)
    q = rng.normal(size=(5, 4, 1))
    x, y = 1.3, 0.9  # cell-centre coordinates (i + 1/2) h
    s0, s1 = x / H - 0.5, y / H - 0.5
    i, j = int(s0), int(s1)
    fx, fy = s0 - i, s1 - j
    a = q[i, j, 0] + fx * (q[i + 1, j, 0] - q[i, j, 0])
    b = q[i, j + 1, 0] + fx * (q[i + 1, j + 1, 0] - q[i, j + 1, 0])
    expected = a + fy * (b - a)
    for z in (-3.0, 0.0, 0.25, 9.0, np.nan):
        assert sample(q, -1, x, y, z, H) == pytest.approx(expected, abs=1e-15)


@pytest.mark.parametrize("shape", [(6, 5, 4), (6, 5, 1), (1, 5, 4), (2, 2, 2)])
def test_the_stencil_range_bounds_the_read_and_is_reached(shape):
    rng = np.random.default_rng(11)
    q = rng.normal(size=shape)
    for p in rng.uniform(-1.0, 4.0, size=(300, 3)):
        lo, hi = sample_range(q, -1, p[0], p[1], p[2], H)
        value = sample(q, -1, p[0], p[1], p[2], H)
        assert lo - 1e-15 <= value <= hi + 1e-15
        assert lo in q and hi in q


def test_velocity_reads_each_component_at_its_own_faces():
    shape = (4, 4, 4)
    u = np.zeros((shape[0] + 1, shape[1], shape[2]))
    v = np.zeros((shape[0], shape[1] + 1, shape[2]))
    w = np.zeros((shape[0], shape[1], shape[2] + 1))
    u[...] = _positions(0, u.shape)[..., 0]  # u = x
    v[...] = 2.0 * _positions(1, v.shape)[..., 1]  # v = 2 y
    w[...] = -_positions(2, w.shape)[..., 2]  # w = -z
    vx, vy, vz = velocity_at(u, v, w, 3, 0.7, 1.1, 0.4, H)
    assert (vx, vy, vz) == pytest.approx((0.7, 2.2, -0.4), abs=1e-12)
    assert velocity_at(u, v, w, 2, 0.7, 1.1, 0.4, H)[2] == 0.0
