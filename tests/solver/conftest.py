"""Shared builders for solver tests."""

from __future__ import annotations

import numpy as np
import pytest

from solver.boundary import DomainBoundary, Side
from solver.grid import Grid
from solver.probes import Probe
from solver.shapes import Ball, Box
from solver.simulation import Fluid, Simulation, SolverSettings


def make_sim(
    n: int = 32,
    dim: int = 2,
    nu: float = 1e-2,
    probes: list[Probe] | None = None,
    sides: dict[str, Side] | None = None,
    settings: SolverSettings | None = None,
    size: float = 1.0,
) -> Simulation:
    grid = Grid.from_size((size,) * dim, (n,) * dim)
    return Simulation(grid, Fluid(1.0, nu), DomainBoundary(grid, sides or {}), probes, settings)


def moving_circle(
    dim: int = 2,
    velocity=(0.5, 0.0, 0.0),
    radius: float = 0.1,
    centre=(0.5, 0.5, 0.5),
    spin=0.0,
    name: str = "probe",
) -> Probe:
    shape = Ball(radius)
    omega = spin if dim == 2 else np.array([0.0, 0.0, spin])
    return Probe(
        name,
        shape,
        dim,
        np.array(centre[:dim]),
        0.0 if dim == 2 else None,
        np.array(velocity[:dim]),
        omega,
    )


def moving_box(
    size=(0.12, 0.12), velocity=(0.5, 0.0), centre=(0.5, 0.5), angle=0.0, spin=0.0
) -> Probe:
    return Probe("box", Box(tuple(size)), 2, np.array(centre), angle, np.array(velocity), spin)


class Builders:
    sim = staticmethod(make_sim)
    circle = staticmethod(moving_circle)
    box = staticmethod(moving_box)


@pytest.fixture
def build() -> type[Builders]:
    """Builders for simulations and probes."""
    return Builders
