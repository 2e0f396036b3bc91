"""Kernels against plain numpy and Python references, 2D (one layer: a loop of its own) and 3D:
the pressure gradient, the fresh cells' pressure, the face viscosity, the stencil product, the
lattice offsets of the cut geometry and its 2D sub-lattices taken in one pass, the domain sides'
normal faces, the pressure's right-hand side, the cut flux compiled for one layer, and the cut
geometry's window fill. The same values, bit for bit."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from solver.boundary import INFLOW, OUTFLOW, SLIP, WALL, set_normal_faces
from solver.bundles import Velocity
from solver.compiled.layers import layer_count
from solver.cutcell.geometry import (
    _fill,
    _take_closer,
    lattice_offsets_2d,
    lattice_offsets_3d,
    take_closer_2d,
)
from solver.cutcell.projection import (
    CutFaces,
    cut_flux,
    fill_fresh_pressure,
    pressure_rhs,
    remove_mean,
    subtract_cut_gradient,
)
from solver.linalg.pcg import apply_stencil
from solver.staircase.faces import RigidMotion
from solver.staircase.viscosity import face_viscosity


def _reference_gradient(q, kinds, wf, axis, active, phi, h):
    """``q`` less ``(phi_hi - phi_lo) / h`` on the open faces between two active cells (or an
    active cell and an outflow side, whose ghost pressure is 0)."""
    pad = [(0, 0)] * 3
    pad[axis] = (1, 1)
    ghost_phi = np.pad(phi, pad)
    ghost_active = np.pad(active, pad)
    lo_side = [slice(None)] * 3
    hi_side = [slice(None)] * 3
    lo_side[axis], hi_side[axis] = 0, -1
    ghost_active[tuple(lo_side)] = kinds[axis, 0] == OUTFLOW
    ghost_active[tuple(hi_side)] = kinds[axis, 1] == OUTFLOW
    lo = [slice(None)] * 3
    hi = [slice(None)] * 3
    lo[axis], hi[axis] = slice(0, -1), slice(1, None)
    mask = (wf > 0.0) & ghost_active[tuple(lo)] & ghost_active[tuple(hi)]
    out = q.copy()
    step = (ghost_phi[tuple(hi)] - ghost_phi[tuple(lo)]) / h
    out[mask] -= step[mask]
    return out


@settings(max_examples=40, deadline=None)
@given(
    dim=st.sampled_from([2, 3]),
    n=st.integers(2, 7),
    axis=st.integers(0, 2),
    sides=st.sampled_from([(WALL, WALL), (OUTFLOW, WALL), (WALL, OUTFLOW), (OUTFLOW, OUTFLOW)]),
    seed=st.integers(0, 2**31),
)
def test_subtract_cut_gradient_is_the_reference(dim, n, axis, sides, seed):
    axis = axis % dim
    rng = np.random.default_rng(seed)
    cells = (n, n + 1, n + 2 if dim == 3 else 1)
    faces = tuple(c + (1 if a == axis else 0) for a, c in enumerate(cells))
    kinds = np.full((3, 2), WALL, dtype=np.int64)
    kinds[axis] = sides
    wf = np.where(rng.random(faces) < 0.2, 0.0, rng.random(faces))
    active = rng.random(cells) > 0.2
    phi = rng.standard_normal(cells)
    q = rng.standard_normal(faces)
    face = [0, 0, 0]
    face[axis] = 1  # one open face between two active cells at least: the test moves something
    lo = list(face)
    lo[axis] = 0
    wf[tuple(face)] = 0.5
    active[tuple(face)] = active[tuple(lo)] = True
    phi[tuple(face)] = phi[tuple(lo)] + 1.0
    static = np.zeros(cells, dtype=np.int32)
    got = q.copy()
    subtract_cut_gradient(got, static, kinds, wf, axis, active, phi, 0.1)
    np.testing.assert_array_equal(got, _reference_gradient(q, kinds, wf, axis, active, phi, 0.1))
    assert not np.array_equal(got, q)


@settings(max_examples=40, deadline=None)
@given(dim=st.sampled_from([2, 3]), n=st.integers(2, 7), seed=st.integers(0, 2**31))
def test_fresh_cells_take_their_old_neighbours_mean_pressure(dim, n, seed):
    rng = np.random.default_rng(seed)
    cells = (n, n + 1, n + 2 if dim == 3 else 1)
    p = rng.standard_normal(cells)
    was = rng.random(cells) > 0.3
    active = rng.random(cells) > 0.3
    want = p.copy()
    for i, j, k in np.ndindex(cells):
        if not active[i, j, k]:
            want[i, j, k] = 0.0
        elif not was[i, j, k]:
            total, count = 0.0, 0
            for b in range(dim):
                for s in (-1, 1):
                    nb = [i, j, k]
                    nb[b] += s
                    if 0 <= nb[b] < cells[b] and was[tuple(nb)]:
                        total += p[tuple(nb)]
                        count += 1
            want[i, j, k] = total / count if count else 0.0
    got = p.copy()
    fill_fresh_pressure(got, was, active, dim)
    np.testing.assert_array_equal(got, want)


@settings(max_examples=30, deadline=None)
@given(dim=st.sampled_from([2, 3]), n=st.integers(1, 7), axis=st.integers(0, 2),
       seed=st.integers(0, 2**31))  # fmt: skip
def test_face_viscosity_is_the_mean_of_the_cells_beside_the_face(dim, n, axis, seed):
    axis = axis % dim
    cells = (n, n + 1, n + 2 if dim == 3 else 1)
    mu = np.random.default_rng(seed).random(cells)
    edge = [(0, 0)] * 3
    edge[axis] = (1, 1)
    padded = np.pad(mu, edge, mode="edge")  # a side face takes its one cell
    lo = [slice(None)] * 3
    hi = [slice(None)] * 3
    lo[axis], hi[axis] = slice(0, -1), slice(1, None)
    out = np.empty(tuple(c + (1 if a == axis else 0) for a, c in enumerate(cells)))
    face_viscosity(mu, axis, out)
    np.testing.assert_array_equal(out, 0.5 * (padded[tuple(lo)] + padded[tuple(hi)]))


@settings(max_examples=40, deadline=None)
@given(
    dim=st.sampled_from([2, 3]),
    nx=st.integers(1, 8),
    ny=st.integers(1, 8),
    nz=st.integers(1, 8),
    seed=st.integers(0, 2**31),
)
def test_the_stencil_product_is_the_reference(dim, nx, ny, nz, seed):
    nz = nz if dim == 3 else 1
    size = nx * ny * nz
    strides = (ny * nz, nz, 1 if dim == 3 else 0)
    rng = np.random.default_rng(seed)
    diag, offx, offy, offz, x = (rng.standard_normal(size) for _ in range(5))
    active = rng.random(size) > 0.2
    want = np.zeros(size)
    for n in range(size):  # each product in the kernel's order
        if not active[n]:
            continue
        s = diag[n] * x[n]
        for stride, off in zip(strides, (offx, offy, offz), strict=True):
            if stride > 0:
                if n >= stride:
                    s += off[n - stride] * x[n - stride]
                if n + stride < size:
                    s += off[n] * x[n + stride]
        want[n] = s
    got = np.full(size, np.nan)
    apply_stencil(diag, offx, offy, offz, active, strides, x, got)
    np.testing.assert_array_equal(got, want)


@settings(max_examples=30, deadline=None)
@given(dim=st.sampled_from([2, 3]), step=st.sampled_from([1, 2]), seed=st.integers(0, 2**31))
def test_lattice_offsets_are_numpy_s_grid_less_the_centre(dim, step, seed):
    rng = np.random.default_rng(seed)
    origin = rng.uniform(-1, 1, 3)
    lo = rng.integers(0, 40, 3)
    h = rng.uniform(1e-4, 0.1)
    counts = rng.integers(1, 12, dim)
    # the half-cell lattice's axes as numpy builds them, every ``step``-th point
    axes = [(origin[a] + (lo[a] + 0.5 * np.arange(step * counts[a])) * h)[::step]
            for a in range(dim)]  # fmt: skip
    centre = rng.uniform(-1, 1, dim)
    want = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1) - centre
    got = np.empty(want.shape)
    (lattice_offsets_2d if dim == 2 else lattice_offsets_3d)(origin, lo, h, step, centre, got)
    np.testing.assert_array_equal(got, want)


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**31))
def test_the_2d_sub_lattices_taken_in_one_pass_are_each_taken_alone(seed):
    """``take_closer_2d`` on a half-cell lattice's SDF gives the nodes, both faces and the cells
    what ``_take_closer`` gives each of them on its own sub-lattice."""
    rng = np.random.default_rng(seed)
    n = rng.integers(2, 9, 2)  # the grid's cells
    lo = np.array([rng.integers(0, n[0]), rng.integers(0, n[1]), 0])
    hi = np.array([rng.integers(lo[0] + 1, n[0] + 1), rng.integers(lo[1] + 1, n[1] + 1), 1])
    sdf = rng.uniform(-1, 1, (2 * (hi[0] - lo[0]) + 1, 2 * (hi[1] - lo[1]) + 1))
    shapes = [(n[0] + 1, n[1] + 1, 1), (n[0] + 1, n[1], 1), (n[0], n[1] + 1, 1), (n[0], n[1], 1)]
    phis = [rng.uniform(-1, 1, s) for s in shapes]
    owners = [rng.integers(-1, 3, s).astype(np.int32) for s in shapes]
    want_phi, want_owner = [p.copy() for p in phis], [o.copy() for o in owners]
    even, odd = slice(0, None, 2), slice(1, None, 2)
    for t, (sx, sy) in enumerate([(even, even), (even, odd), (odd, even), (odd, odd)]):
        _take_closer(sdf[sx, sy, None], want_phi[t], want_owner[t], lo, 5, t == 3)
    take_closer_2d(sdf, lo, 5, *(a for pair in zip(phis, owners, strict=True) for a in pair))
    for t in range(4):
        np.testing.assert_array_equal(phis[t], want_phi[t])
        np.testing.assert_array_equal(owners[t], want_owner[t])


@settings(max_examples=30, deadline=None)
@given(dim=st.sampled_from([2, 3]), seed=st.integers(0, 2**31))
def test_the_sides_normal_faces_are_the_numpy_slices(dim, seed):
    """``set_normal_faces``: a wall's or slip wall's normal velocity on its faces, an outflow
    side's neighbour values, an inflow side untouched."""
    rng = np.random.default_rng(seed)
    cells = tuple(int(c) for c in rng.integers(2, 6, dim)) + (1,) * (3 - dim)
    kinds = rng.choice([WALL, SLIP, INFLOW, OUTFLOW], (3, 2)).astype(np.int64)
    velocities = rng.uniform(-1, 1, (3, 2, 3))
    for axis in range(dim):
        shape = list(cells)
        shape[axis] += 1
        q = rng.uniform(-1, 1, shape)
        want = q.copy()
        for end in range(2):
            face = [slice(None)] * 3
            face[axis] = 0 if end == 0 else shape[axis] - 1
            inner = list(face)
            inner[axis] = 1 if end == 0 else shape[axis] - 2
            if kinds[axis, end] == OUTFLOW:
                want[tuple(face)] = want[tuple(inner)]
            elif kinds[axis, end] != INFLOW:
                want[tuple(face)] = velocities[axis, end, axis]
        set_normal_faces(q, axis, kinds, velocities)
        np.testing.assert_array_equal(q, want)


@settings(max_examples=30, deadline=None)
@given(closed=st.booleans(), seed=st.integers(0, 2**31))
def test_the_pressure_right_hand_side_in_one_pass_is_the_numpy_one(closed, seed):
    """``pressure_rhs``: the flux times ``-h``, less its mean over the active cells when the
    domain is closed, and the warm start zeroed off them, as the numpy expressions give it."""
    rng = np.random.default_rng(seed)
    size = int(rng.integers(1, 200))
    flux, phi = rng.uniform(-1, 1, size), rng.uniform(-1, 1, size)
    active = rng.random(size) < 0.7
    h = float(rng.uniform(1e-3, 0.1))
    want_rhs, want_phi = flux.copy(), phi.copy()
    want_rhs *= -h
    if closed:
        remove_mean(want_rhs, active)
    want_phi[~active] = 0.0
    pressure_rhs(flux, active, h, closed, phi)
    np.testing.assert_array_equal(flux, want_rhs)
    np.testing.assert_array_equal(phi, want_phi)


@settings(max_examples=25, deadline=None)
@given(st.integers(2, 12), st.integers(2, 12), st.integers(0, 2**31))
def test_a_2d_flux_compiled_for_one_layer_is_the_general_loops(nx, ny, seed):
    """``cut_flux`` given ``layers`` None (a loop of one pass that the compiler removes) against
    the same kernel looping over the layer count 1, with faces partly solid and probes."""
    rng = np.random.default_rng(seed)
    cells = (nx, ny, 1)
    shapes = [tuple(c + (a == b) for a, c in enumerate(cells)) for b in range(3)]
    comps = [rng.standard_normal(s) for s in shapes]
    open_frac = [np.where(rng.random(s) < 0.3, rng.random(s), 1.0) for s in shapes]
    owners = [np.where(f < 1.0, 0, -1).astype(np.int32) for f in open_frac]
    active = rng.random(cells) < 0.9
    rigid = RigidMotion(*rng.standard_normal((3, 1, 3)))
    faces = CutFaces(tuple(open_frac), tuple(owners), rigid)
    outs = [np.full(cells, np.nan), np.full(cells, np.nan)]
    for out, layers in zip(outs, (layer_count(cells), 1), strict=True):
        cut_flux(Velocity(*comps), faces, active, 2, 0.1, out, layers)
    assert layer_count(cells) is None
    np.testing.assert_array_equal(outs[0], outs[1])


@settings(max_examples=60, deadline=None)
@given(
    shape=st.tuples(st.integers(1, 7), st.integers(1, 7), st.integers(1, 5)),
    window=st.lists(st.integers(0, 9), min_size=6, max_size=6),
    dtype=st.sampled_from([np.float64, np.int32]),
)
def test_a_window_fill_is_numpy_s_slice_assignment(shape, window, dtype):
    """The cut geometry's window fill against ``a[lo:hi] = value``: windows across the whole
    last axis (a contiguous run per first index, every 2D window) and windows within it, empty
    ones, and ones past the array's end."""
    lo = np.array(window[:3], dtype=np.int64)
    hi = lo + np.array(window[3:], dtype=np.int64)
    if window[2] % 2 == 0:  # half of them across the whole last axis
        lo[2], hi[2] = 0, shape[2] + window[5] % 2
    got = np.arange(np.prod(shape), dtype=dtype).reshape(shape)
    want = got.copy()
    _fill(got, lo, hi, dtype(-7))
    want[lo[0] : hi[0], lo[1] : hi[1], lo[2] : hi[2]] = -7
    np.testing.assert_array_equal(got, want)
