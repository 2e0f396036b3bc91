"""The scene of ``bench_solver.py --peer`` in PhiFlow 3.4 with its JAX backend.

Not a dependency of the package: install PhiFlow into a virtual environment of its own together
with this package and run the benchmark with that environment's python (README.md, "Solver
benchmark"). Importing this module makes JAX PhiFlow's default backend and switches PhiFlow to
float64, the precision of our solver.

The step, jit-compiled as a whole (``math.jit_compile``):

1. semi-Lagrangian advection of the staggered velocity with a midpoint back-trace, the same
   trace and linear interpolation as ours (PhiFlow's default integrator is Euler);
2. implicit (backward Euler) viscosity per velocity component, by CG (``diffuse.implicit`` on the
   whole ``StaggeredGrid`` raises inside PhiFlow 3.4 with closed walls; per component it works),
   from PhiFlow's default first guess, the advected velocity;
3. ``fluid.make_incompressible`` with the box as a moving ``Obstacle``: CG for the pressure from a
   zero first guess. Warm-starting it from the last step's pressure, as ours does, costs PhiFlow
   more iterations on this scene (about 210 against 180 on 64x64), so it starts cold.

Both solves stop at our criterion ``||b - A x|| <= tol ||b||``. PhiFlow's relative tolerance is
relative to the initial residual: from a zero guess that is ``||b||``; for the viscosity, whose
guess is not zero, the stop is an absolute tolerance of ``tol ||b||``. No preconditioner: PhiFlow's
(``ilu``, ``cluster``) fail under ``jit_compile`` when the matrix changes with the obstacle every
step. ``rank_deficiency=0``: the closed box's pressure is defined up to a constant, and CG needs no
extra constraint for that (PhiFlow would warn and ask). Domain walls are PhiFlow's ``ZERO``
extrapolation: zero normal velocity, and a tangential ghost value of 0 where ours reflects it
about the wall.
"""

from __future__ import annotations

import importlib.metadata
from typing import Any

import jax
import numpy as np
from phi.jax.flow import (
    Box,
    Obstacle,
    Solve,
    StaggeredGrid,
    advect,
    diffuse,
    dual,
    extrapolation,
    field,
    fluid,
    math,
    vec,
)

math.set_global_precision(64)


def versions() -> str:
    """The installed PhiFlow, phiml and JAX versions, for the report."""
    return (
        f"PhiFlow {importlib.metadata.version('phiflow')}, "
        f"phiml {importlib.metadata.version('phiml')}, JAX {jax.__version__}"
    )


def _midpoint(data: Any, velocity: Any, dt: float, v0: Any = None) -> Any:
    """Midpoint back-trace, in the signature of PhiFlow's integrators (``advect.euler``)."""
    if v0 is None:
        v0 = field.sample(velocity, data.geometry, at=data.sampled_at, boundary=data.boundary)
    half = data.points + 0.5 * dt * v0
    v_half = field.sample(velocity, half, at=data.sampled_at, boundary=data.boundary)
    return data.points + dt * v_half


class PeerScene:
    """A square box obstacle on a keyframed path through fluid at rest in a closed unit box.

    ``keyframes``: rows ``[t, x, y, angle]`` (the angle unused: the box does not turn), linearly
    interpolated in time, as :class:`solver.probes.Probe` reads its path. Within a step the
    obstacle moves at the step's average velocity and the projection sees it where the step ends,
    as ours.
    """

    def __init__(
        self,
        n: int,
        keyframes: np.ndarray,
        size_m: float,
        viscosity_m2_s: float,
        dt_s: float,
        pressure_tolerance: float,
        viscosity_tolerance: float,
    ) -> None:
        self.n = n
        self.dt_s = dt_s
        self.size_m = size_m
        self.keyframes = np.asarray(keyframes, dtype=float)
        self.time_s = 0.0
        self.centre_m = self.position(0.0)
        self.velocity: Any = StaggeredGrid(0, extrapolation.ZERO, x=n, y=n, bounds=Box(x=1, y=1))
        self.pressure: Any = None
        half = 0.5 * size_m

        def step(v: Any, centre: Any, obstacle_velocity: Any) -> tuple[Any, Any]:
            obstacle = Obstacle(Box(centre - half, centre + half), velocity=obstacle_velocity)
            v = advect.semi_lagrangian(v, v, dt_s, integrator=_midpoint)
            components = []
            for axis in v.vector.item_names:
                u = v.vector[axis]
                b_norm = math.sqrt(math.sum(u.values**2))
                solve = Solve("CG", 0, viscosity_tolerance * b_norm, x0=u)
                components.append(diffuse.implicit(u, viscosity_m2_s, dt_s, solve=solve).values)
            v = v.with_values(math.stack(components, dual(vector=v.vector.item_names)))
            solve = Solve("CG", pressure_tolerance, 0, rank_deficiency=0)
            return fluid.make_incompressible(v, obstacle, solve)

        self._physics = step
        self._step = math.jit_compile(step)

    def position(self, t_s: float) -> np.ndarray:
        """The obstacle's centre at ``t_s`` on the keyframed path (held outside it)."""
        k = self.keyframes
        return np.array([np.interp(t_s, k[:, 0], k[:, 1]), np.interp(t_s, k[:, 0], k[:, 2])])

    def _motion(self) -> tuple[Any, Any, np.ndarray]:
        """The obstacle's centre at the end of the next step and its average velocity."""
        c1 = self.position(self.time_s + self.dt_s)
        v = (c1 - self.centre_m) / self.dt_s
        return vec(x=c1[0], y=c1[1]), vec(x=v[0], y=v[1]), c1

    def step(self) -> None:
        """Advance by one time step and wait for its velocity and pressure."""
        centre, velocity, c1 = self._motion()
        self.velocity, self.pressure = self._step(self.velocity, centre, velocity)
        self.centre_m = c1
        self.time_s += self.dt_s
        self.block()

    def block(self) -> None:
        """Wait until JAX has computed the current state."""
        arrays = [t.native(t.shape) for t in math.unstack(self.velocity.values, dual("vector"))]
        if self.pressure is not None:
            arrays.append(self.pressure.values.native(self.pressure.values.shape))
        jax.block_until_ready(arrays)

    def solve_iterations(self) -> tuple[int, ...]:
        """CG iterations of the next step's solves (viscosity x, viscosity y, pressure), from one
        untimed step outside ``jit_compile`` whose result is dropped."""
        centre, velocity, _ = self._motion()
        with math.SolveTape() as tape:
            self._physics(self.velocity, centre, velocity)
        return tuple(int(s.iterations) for s in tape.solves)

    def kinetic_energy(self, density_kg_m3: float = 1.0) -> float:
        """Kinetic energy of the fluid, J per metre of depth: cell-centre velocities over the
        cells whose centre lies outside the obstacle, as ``Simulation.kinetic_energy``."""
        h = 1.0 / self.n
        u = self.velocity.at_centers().values.numpy("vector,x,y")
        centres = (np.arange(self.n) + 0.5) * h
        outside_x = np.abs(centres - self.centre_m[0]) > 0.5 * self.size_m
        outside_y = np.abs(centres - self.centre_m[1]) > 0.5 * self.size_m
        fluid_cells = outside_x[:, None] | outside_y[None, :]
        return 0.5 * density_kg_m3 * float(np.sum(u[:, fluid_cells] ** 2)) * h * h
