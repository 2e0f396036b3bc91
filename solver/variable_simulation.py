"""A simulation whose dynamic viscosity is a field over the cells (for example paint and air).

:class:`VariableViscositySimulation` is a :class:`~solver.simulation.Simulation` whose implicit
viscosity step (:mod:`solver.viscosity_field`) and stress-integral forces
(:mod:`solver.stress_field`) use ``viscosity_pa_s``, one dynamic viscosity per cell, which the
caller may change between steps (:meth:`set_viscosity`). Density stays uniform
(``fluid.density_kg_m3``); ``fluid.viscosity_m2_s`` only gives the initial field. An optional
per-cell linear drag toward rest, ``drag_per_s`` (:meth:`set_drag`), models the friction of a
no-slip surface under a thin layer in depth-averaged (2D) use.
"""

from __future__ import annotations

import numpy as np

from solver.boundary import DomainBoundary
from solver.grid import Grid
from solver.pcg import SolveReport
from solver.probes import Probe
from solver.simulation import Fluid, ProbeForce, Simulation, SolverSettings
from solver.stress_field import stress_integral_field
from solver.viscosity_field import diffuse_variable


class VariableViscositySimulation(Simulation):
    """A :class:`Simulation` with a per-cell dynamic viscosity field ``viscosity_pa_s`` (Pa s)."""

    def __init__(
        self,
        grid: Grid,
        fluid: Fluid,
        boundary: DomainBoundary | None = None,
        probes: list[Probe] | None = None,
        settings: SolverSettings | None = None,
        static_solid: np.ndarray | None = None,
    ) -> None:
        super().__init__(grid, fluid, boundary, probes, settings, static_solid)
        self.viscosity_pa_s = np.full(grid.cells, fluid.dynamic_viscosity_pa_s)
        self.drag_per_s: np.ndarray | None = None

    def set_viscosity(self, mu_pa_s: np.ndarray) -> None:
        """Use ``mu_pa_s`` (cells' shape, finite, >= 0, Pa s) from the next step on."""
        mu = np.asarray(mu_pa_s, dtype=np.float64)
        if mu.shape != self.grid.cells:
            raise ValueError(f"viscosity field must have shape {self.grid.cells}, got {mu.shape}")
        if not np.all(np.isfinite(mu)) or np.any(mu < 0.0):
            raise ValueError("viscosity field must be finite and >= 0")
        self.viscosity_pa_s = np.ascontiguousarray(mu)

    def set_drag(self, rate_per_s: np.ndarray | None) -> None:
        """Linear drag ``du/dt = -k u`` with ``k`` per cell (1/s, >= 0), or None for none."""
        if rate_per_s is None:
            self.drag_per_s = None
            return
        k = np.asarray(rate_per_s, dtype=np.float64)
        if k.shape != self.grid.cells or not np.all(np.isfinite(k)) or np.any(k < 0.0):
            raise ValueError(f"drag must be finite, >= 0 and of shape {self.grid.cells}")
        self.drag_per_s = np.ascontiguousarray(k)

    def _diffuse(self, dt_s: float) -> tuple[SolveReport, ...]:
        if not np.any(self.viscosity_pa_s > 0.0) and self.drag_per_s is None:
            return ()
        g, st, cfg = self.grid, self.state, self.settings
        centre, vel, omega, _ = self.rigid_motion()
        rigid = np.stack([centre, vel, omega])
        return tuple(
            diffuse_variable(
                st.comps[a],
                st.face_types[a],
                a,
                g.dim,
                self.viscosity_pa_s,
                dt_s,
                self.fluid.density_kg_m3,
                self._kinds,
                self._side_vel,
                st.label,
                rigid,
                g.cell_size_m,
                cfg.viscosity_tolerance,
                cfg.max_iterations,
                self.drag_per_s,
            )
            for a in range(g.dim)
        )

    def _compute_forces(self) -> None:
        if not self.computes_forces() or self.settings.force_model != "stress":
            super()._compute_forces()
            return
        g, st = self.grid, self.state
        d = g.dim
        centre, vel, omega, ref = self.rigid_motion()
        n = len(self.probes)
        fp, fv, tq = np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3))
        stress_integral_field(
            st.label,
            st.comps[0],
            st.comps[1],
            st.comps[2],
            st.pressure,
            self.viscosity_pa_s,
            g.cell_size_m,
            d,
            (centre, vel, omega),
            ref,
            fp,
            fv,
            tq,
        )
        for i, probe in enumerate(self.probes):
            self.forces[probe.name] = ProbeForce(
                force=(fp[i, :d] + fv[i, :d]).copy(),
                torque=float(tq[i, 2]) if d == 2 else tq[i].copy(),
                pressure_force=fp[i, :d].copy(),
                viscous_force=fv[i, :d].copy(),
            )
