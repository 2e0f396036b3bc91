"""Semi-Lagrangian advection: the face kernels, which start the trace from the face's own
samples, give exactly the general kernel's values, walls and far departures included."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from solver.advection.velocity import (
    LINEAR,
    advect,
    advect_component,
    advect_face_2d,
    advect_face_3d,
    advect_velocity,
)
from solver.bundles import Velocity


def _fields(cells, seed, speed):
    rng = np.random.default_rng(seed)
    nx, ny, nz = cells
    shapes = [(nx + 1, ny, nz), (nx, ny + 1, nz), (nx, ny, nz + 1)]
    return [speed * rng.standard_normal(s) for s in shapes]


@settings(max_examples=30, deadline=None)
@given(
    nx=st.integers(2, 9),
    ny=st.integers(2, 9),
    nz=st.integers(2, 9),
    axis=st.integers(0, 2),
    seed=st.integers(0, 2**31),
    speed=st.sampled_from([0.05, 1.0, 40.0]),  # departures within a cell, a few, far outside
)
def test_face_kernel_gives_the_general_kernel_s_values(nx, ny, nz, axis, seed, speed):
    u, v, w = _fields((nx, ny, nz), seed, speed)
    q = (u, v, w)[axis]
    h, dt = 0.1, 0.07
    general = np.empty_like(q)
    advect_component(q, axis, Velocity(u, v, w), 3, h, dt, general, (general, general), False)
    fast = np.empty_like(q)
    advect_face_3d(q, axis, u, v, w, h, dt, fast, 0, q.shape[0])
    np.testing.assert_array_equal(fast, general)
    assert not np.array_equal(general, q)  # the field did move


@settings(max_examples=30, deadline=None)
@given(
    nx=st.integers(2, 12),
    ny=st.integers(2, 12),
    axis=st.integers(0, 1),
    seed=st.integers(0, 2**31),
    speed=st.sampled_from([0.05, 1.0, 40.0]),
)
def test_2d_face_kernel_gives_the_general_kernel_s_values(nx, ny, axis, seed, speed):
    u, v, _ = _fields((nx, ny, 1), seed, speed)
    u, v = u[:, :, :1].copy(), v[:, :, :1].copy()
    w = np.zeros((nx, ny, 2))
    q = (u, v)[axis]
    h, dt = 0.1, 0.07
    general = np.empty_like(q)
    advect_component(q, axis, Velocity(u, v, w), 2, h, dt, general, (general, general), False)
    fast = np.empty_like(q)
    advect_face_2d(q, axis, u, v, h, dt, fast, 0, q.shape[0])
    np.testing.assert_array_equal(fast, general)
    assert not np.array_equal(general, q)


def test_a_uniform_flow_carries_a_linear_profile_exactly():
    # u = U everywhere, a component linear in x: the departure point is x - U dt and linear
    # interpolation is exact for a linear profile, away from the inflow wall
    nx, ny, nz = 12, 6, 5
    h, dt, speed = 0.1, 0.05, 0.6
    u = np.full((nx + 1, ny, nz), speed)
    v = np.zeros((nx, ny + 1, nz))
    w = np.zeros((nx, ny, nz + 1))
    x = (np.arange(nx) + 0.5) * h
    q = np.broadcast_to((2.0 * x)[:, None, None], (nx, ny + 1, nz)).copy()
    out = np.empty_like(q)
    advect_face_3d(q, 1, u, v, w, h, dt, out, 0, q.shape[0])
    expect = 2.0 * (x - speed * dt)
    np.testing.assert_allclose(out[1:, :, :], np.broadcast_to(expect[1:, None, None],
                                                              out[1:].shape), atol=1e-12)  # fmt: skip


@settings(max_examples=20, deadline=None)
@given(
    dim=st.sampled_from([2, 3]),
    n=st.integers(2, 9),
    threads=st.integers(2, 4),
    seed=st.integers(0, 2**31),
)
def test_slabs_on_threads_give_the_whole_components_values(dim, n, threads, seed):
    u, v, w = _fields((n, n + 1, n if dim == 3 else 1), seed, 1.0)
    if dim == 2:
        u, v, w = u[:, :, :1].copy(), v[:, :, :1].copy(), np.zeros((n, n + 1, 2))
    velocity = (u, v, w)
    whole = [advect(velocity[a], a, velocity, dim, 0.1, 0.07) for a in range(dim)]
    slabs = advect_velocity(velocity, dim, 0.1, 0.07, LINEAR, threads)
    for a in range(dim):
        np.testing.assert_array_equal(slabs[a], whole[a])
