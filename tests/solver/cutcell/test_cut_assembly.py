"""The cut-cell assemblies against the staircase's where they must agree.

Without a probe a cut face is fully open or closed by a static solid, exactly as on the
staircase: the cut viscosity system, the cut pressure matrix and the cut gradient correction
must then equal the staircase's entry for entry, on random grids with static solids, every kind
of domain side, a varying viscosity and a drag. Each cut kernel takes a short path between fluid
cells and a general one elsewhere; the random solids send many rows down each.
"""

from __future__ import annotations

import numpy as np
import pytest

from solver.boundary import INFLOW, OUTFLOW, WALL
from solver.bundles import Sides, Window
from solver.compiled.layers import layer_count
from solver.cutcell.projection import build_cut_pressure_system, subtract_cut_gradient
from solver.cutcell.viscosity import CutWalls, build_cut_system
from solver.labels import BOUNDARY, FLUID, FREE, INTERIOR, STATIC_SOLID
from solver.staircase.faces import Component, RigidMotion, classify_faces
from solver.staircase.projection import build_pressure_system, subtract_gradient
from solver.staircase.viscosity import (
    Diffusion,
    DiffusionArrays,
    Walls,
    build_variable_system,
    face_viscosity,
)

FAR = 1e9


def _grid(rng, dim):
    cells = (
        int(rng.integers(3, 9)),
        int(rng.integers(3, 9)),
        int(rng.integers(3, 8)) if dim == 3 else 1,
    )
    label = np.where(rng.random(cells) < 0.2, STATIC_SOLID, FLUID).astype(np.int32)
    kinds = rng.choice([WALL, INFLOW, OUTFLOW], size=(3, 2)).astype(np.int64)
    return cells, label, kinds


def _faces(label, dim, kinds, shape, axis, rng):
    face_type = np.zeros(shape, dtype=np.int8)
    values = rng.standard_normal(shape)
    none = np.zeros((1, 3))
    whole = Window(np.zeros(3, dtype=np.int64), np.array(shape, dtype=np.int64))
    open_ends = (kinds[axis, 0] == OUTFLOW, kinds[axis, 1] == OUTFLOW)
    rigid = RigidMotion(none, none, none)
    classify_faces(label, Component(values, face_type, axis), open_ends, rigid, 0.1, whole)
    return face_type, values


@pytest.mark.parametrize("dim", [2, 3])
def test_cut_viscosity_system_without_probes_is_the_staircases(dim):
    rng = np.random.default_rng(10 + dim)
    for _ in range(25):
        cells, label, kinds = _grid(rng, dim)
        mu = rng.uniform(0.01, 3.0, cells)
        side_vel = rng.standard_normal((3, 2, 3))
        rigid = RigidMotion(*np.zeros((3, 1, 3)))
        for axis in range(dim):
            shape = tuple(c + (a == axis) for a, c in enumerate(cells))
            face_type, q = _faces(label, dim, kinds, shape, axis, rng)
            mu_face = np.empty(shape)
            face_viscosity(mu, axis, mu_face)
            drag = rng.uniform(0.0, 0.5, shape)
            phi, owner = np.full(shape, FAR), np.full(shape, -1, dtype=np.int32)
            built = []
            for cut in (True, False):
                arrays = (*(np.full(shape, 7.0) for _ in range(4)), np.zeros(shape, dtype=bool))
                rhs = np.full(shape, 7.0)
                comp = Component(q, face_type, axis)
                coeffs, sides = Diffusion(mu_face, 0.8, drag), Sides(kinds, side_vel)
                out = DiffusionArrays(*arrays, rhs)
                if cut:
                    walls = CutWalls(label, rigid, 0.1, phi, owner)
                    build_cut_system(comp, dim, coeffs, sides, walls, out, layer_count(shape))
                else:
                    build_variable_system(comp, dim, coeffs, sides, Walls(label, rigid, 0.1), out)
                built.append((*arrays, rhs))
            for a, b in zip(*built, strict=True):
                np.testing.assert_array_equal(a, b)
            assert built[0][4].any() and not built[0][4].all()  # both paths ran


@pytest.mark.parametrize("dim", [2, 3])
def test_cut_viscosity_short_path_gives_the_general_paths_system(dim):
    """Around probes (cut couplings, faces inside solids, every kind of side, sides' velocities
    and a drag), the short path leaves every sample it takes exactly as the general path would
    have built it, and hands it every other one."""
    rng = np.random.default_rng(30 + dim)
    for trial in range(30):
        cells, _, kinds = _grid(rng, dim)
        label = rng.choice([-1, -1, -1, 0, 1], size=cells).astype(np.int32)
        rigid = RigidMotion(*rng.standard_normal((3, 2, 3)))
        side_vel = rng.standard_normal((3, 2, 3))
        for axis in range(dim):
            shape = tuple(c + (a == axis) for a, c in enumerate(cells))
            # mostly unknowns, so that long runs of them take the short path's rows
            face_type = rng.choice([FREE, FREE, FREE, FREE, BOUNDARY, INTERIOR], size=shape)
            face_type = face_type.astype(np.int8)
            q = rng.standard_normal(shape)
            mu_face = rng.uniform(0.01, 3.0, shape)
            drag = rng.uniform(0.0, 0.5, shape)
            phi = np.where(face_type == FREE, 1.0, rng.uniform(-0.2, 0.1, shape))
            owner = np.where(phi <= 0.0, rng.integers(-1, 2, shape), -1).astype(np.int32)
            built = []
            for short in (True, False):
                arrays = (*(np.full(shape, 7.0) for _ in range(4)), np.zeros(shape, dtype=bool))
                rhs = np.full(shape, 7.0)
                build_cut_system(
                    Component(q, face_type, axis),
                    dim,
                    Diffusion(mu_face, 0.8, drag),
                    Sides(kinds, side_vel),
                    CutWalls(label, rigid, 0.1, phi, owner),
                    DiffusionArrays(*arrays, rhs),
                    layer_count(shape),
                    short,
                )
                built.append((*arrays, rhs))
            for a, b in zip(*built, strict=True):
                np.testing.assert_array_equal(a, b, err_msg=f"trial {trial}, axis {axis}")
    # an all-unknown grid: every sample's row, side and end goes through the short path
    shape = (6, 5, 4) if dim == 3 else (6, 5, 1)
    free = np.zeros(shape, dtype=np.int8)
    ones = np.ones(shape)
    built = []
    for short in (True, False):
        arrays = (*(np.full(shape, 7.0) for _ in range(4)), np.zeros(shape, dtype=bool))
        rhs = np.full(shape, 7.0)
        build_cut_system(
            Component(ones, free, 0),
            dim,
            Diffusion(ones, 0.8, 0.1 * ones),
            Sides(np.zeros((3, 2), np.int64), np.ones((3, 2, 3))),
            CutWalls(
                np.full(shape, -1, np.int32),
                RigidMotion(*np.zeros((3, 1, 3))),
                0.1,
                ones,
                np.full(shape, -1, np.int32),
            ),
            DiffusionArrays(*arrays, rhs),
            layer_count(shape),
            short,
        )
        built.append((*arrays, rhs))
    for a, b in zip(*built, strict=True):
        np.testing.assert_array_equal(a, b)
    assert built[0][4].all()


@pytest.mark.parametrize("dim", [2, 3])
def test_cut_pressure_matrix_and_correction_without_probes_are_the_staircases(dim):
    rng = np.random.default_rng(20 + dim)
    for _ in range(25):
        cells, label, kinds = _grid(rng, dim)
        opened = [np.ones(tuple(c + (a == b) for a, c in enumerate(cells))) for b in range(3)]
        systems = []
        for cut in (True, False):
            arrays = (*(np.full(cells, 7.0) for _ in range(4)), np.zeros(cells, dtype=bool))
            if cut:
                whole = Window(np.zeros(3, dtype=np.int64), np.array(cells, dtype=np.int64))
                build_cut_pressure_system(
                    label, dim, kinds, tuple(opened), arrays, whole, layer_count(cells)
                )
            else:
                build_pressure_system(label, dim, kinds, *arrays)
            systems.append(arrays)
        for a, b in zip(systems[0][:4], systems[1][:4], strict=True):
            np.testing.assert_array_equal(a, b)
        # a fluid cell walled in on every side is an unknown of the staircase's matrix with an
        # empty row, and no unknown of the cut one (its rows are its open faces)
        active, stair_active = systems[0][4], systems[1][4]
        np.testing.assert_array_equal(active, stair_active & (systems[1][0] > 0.0))
        phi = np.where(active, rng.standard_normal(cells), 0.0)
        for axis in range(dim):
            shape = opened[axis].shape
            face_type, q = _faces(label, dim, kinds, shape, axis, rng)
            weights = np.where(face_type == 0, 1.0, 0.0)  # the staircase corrects FREE faces
            cut_q, stair_q = q.copy(), q.copy()
            subtract_cut_gradient(cut_q, label, kinds, weights, axis, active, phi, 0.1)
            subtract_gradient(stair_q, face_type, axis, phi, 0.1)
            np.testing.assert_array_equal(cut_q, stair_q)
