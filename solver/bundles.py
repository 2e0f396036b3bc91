"""Small typed bundles of the arrays that travel together into the kernels.

Each is a ``typing.NamedTuple``: numba takes one as a single argument (fields of arrays and
scalars alike) and compiles a field's access away, so a kernel reads ``fields.pressure`` as
cheaply as an argument of its own. Bundles of one subpackage's concept live beside it (the probes'
rigid motion in :mod:`solver.staircase.faces`, the viscosity system's in
:mod:`solver.staircase.viscosity`); those here are shared across the subpackages.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class Velocity(NamedTuple):
    """The three MAC velocity components (m/s), each of its own face shape (2D: ``w`` unused)."""

    u: np.ndarray
    v: np.ndarray
    w: np.ndarray


class StressFields(NamedTuple):
    """The fields the fluid's stress is formed from: the velocity, the pressure (Pa, cells'
    shape) and the dynamic viscosity (Pa s, cells' shape)."""

    velocity: Velocity
    pressure: np.ndarray
    mu_cell: np.ndarray


class Window(NamedTuple):
    """An index box ``lo <= (i, j, k) < hi``, each (3,) int64."""

    lo: np.ndarray
    hi: np.ndarray


class ForceSums(NamedTuple):
    """Per-probe sums, each (n_probes, 3): pressure force, viscous force and torque (3D: N and
    N m; 2D: per unit depth)."""

    f_pressure: np.ndarray
    f_viscous: np.ndarray
    torque: np.ndarray


class Sides(NamedTuple):
    """The domain's sides: their kinds (3, 2) int64 (:mod:`solver.boundary`; axis, low/high) and
    their prescribed velocities (3, 2, 3), m/s."""

    kinds: np.ndarray
    velocity: np.ndarray
