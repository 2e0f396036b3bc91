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
from solver.cut_projection import build_cut_pressure_system, subtract_cut_gradient
from solver.cut_viscosity import build_cut_system
from solver.faces import FLUID, STATIC_SOLID, classify_faces
from solver.layers import layer_count
from solver.projection import build_pressure_system, subtract_gradient
from solver.viscosity import build_variable_system, face_viscosity

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
    whole = (np.zeros(3, dtype=np.int64), np.array(shape, dtype=np.int64))
    classify_faces(label, axis, kinds[axis, 0] == OUTFLOW, kinds[axis, 1] == OUTFLOW, none, none,
                   none, 0.1, face_type, values, *whole)  # fmt: skip
    return face_type, values


@pytest.mark.parametrize("dim", [2, 3])
def test_cut_viscosity_system_without_probes_is_the_staircases(dim):
    rng = np.random.default_rng(10 + dim)
    for _ in range(25):
        cells, label, kinds = _grid(rng, dim)
        mu = rng.uniform(0.01, 3.0, cells)
        side_vel = rng.standard_normal((3, 2, 3))
        rigid = np.zeros((3, 1, 3))
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
                common = (q, face_type, axis, dim, mu_face, 0.8, drag, kinds, side_vel, label,
                          rigid, 0.1)  # fmt: skip
                if cut:
                    build_cut_system(*common, phi, owner, arrays, rhs, layer_count(shape))
                else:
                    build_variable_system(*common, arrays, rhs)
                built.append((*arrays, rhs))
            for a, b in zip(*built, strict=True):
                np.testing.assert_array_equal(a, b)
            assert built[0][4].any() and not built[0][4].all()  # both paths ran


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
                whole = (np.zeros(3, dtype=np.int64), np.array(cells, dtype=np.int64))
                build_cut_pressure_system(
                    label, dim, kinds, *opened, *arrays, *whole, layer_count(cells)
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
