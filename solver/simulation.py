"""One fluid simulation: state, and the operator-split time step.

A step (Stam 1999, on a MAC grid) is: semi-Lagrangian advection, external forces, move probes and
re-voxelize them (setting the no-slip velocities of their faces, paper eqs. 14-15), domain
boundary conditions, implicit viscosity, Chorin projection, then the stress integral on every
probe.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from common.timing import PhaseTimer
from solver.advection.velocity import SCHEMES, advect_velocity
from solver.boundary import OUTFLOW, DomainBoundary
from solver.bundles import ForceSums, Sides, StressFields, Velocity, Window
from solver.compiled.layers import layer_count
from solver.compiled.threads import (
    AUTO_THREADS,
    BesideJob,
    run_beside,
    run_components,
    thread_count,
    usable_cores,
)
from solver.cutcell.forces import SurfacePatches, cut_surface_force
from solver.cutcell.geometry import UNIT, CutGeometry
from solver.cutcell.projection import (
    CutFaces,
    cut_flux,
    fill_fresh_pressure,
    pressure_system,
    project_cut,
    subtract_cut_gradient,
)
from solver.cutcell.viscosity import (
    CutWalls,
    ViscosityWork,
    assemble_cut,
    diffuse_cut,
    mark_probe_samples,
)
from solver.field_shift import shifted, shifted_by
from solver.forces import drag_models
from solver.forces.momentum_balance import (
    ControlVolume,
    box_momentum,
    box_surface_flux,
    probe_box,
)
from solver.grid import Grid
from solver.interp import sample_cells_fluid, sample_many
from solver.labels import FLUID
from solver.linalg.multigrid import DIFFUSION_SCALES, Multigrid
from solver.linalg.pcg import JacobiPCG, LinearSolve, SolveReport, StencilSystem, solve
from solver.linalg.warm_start import WarmStart
from solver.probes import Probe
from solver.settings import (
    MAX_CORNER_RADIUS_CELLS,
    SolverSettings,
)
from solver.staircase.faces import (
    Component,
    RigidMotion,
    classify_faces,
    label_cells,
    solid_adjacent_faces,
)
from solver.staircase.projection import divergence_sum, project, subtract_gradient
from solver.staircase.stress import stress_integral
from solver.staircase.viscosity import ViscousStep, Walls, diffuse

__all__ = ["Fluid", "ProbeForce", "Simulation", "SolverSettings", "StepStats"]


@dataclass(frozen=True)
class Fluid:
    """Fluid properties: density (kg/m^3), kinematic viscosity (m^2/s), body force (m/s^2)."""

    density_kg_m3: float = 1.0
    viscosity_m2_s: float = 1e-3
    body_force_m_s2: tuple[float, float, float] = (0.0, 0.0, 0.0)

    @property
    def dynamic_viscosity_pa_s(self) -> float:
        return self.density_kg_m3 * self.viscosity_m2_s


@dataclass(frozen=True)
class ProbeForce:
    """Force and torque on a probe (2D: N/m and N m/m per unit depth; 3D: N and N m).

    ``force`` has shape (dim,); ``torque`` is a float in 2D and shape (3,) in 3D, about the probe's
    reference point. ``pressure_force`` and ``viscous_force`` split ``force``.
    """

    force: np.ndarray
    torque: np.ndarray | float
    pressure_force: np.ndarray
    viscous_force: np.ndarray


@dataclass(frozen=True)
class StepStats:
    """What one step cost and how its solves went."""

    time_s: float
    step_ms: float
    substep_ms: dict[str, float]
    pressure: SolveReport
    viscosity: tuple[SolveReport, ...]


@dataclass
class FluidState:
    """Velocity components (always three arrays; w unused in 2D), pressure, cell labels."""

    comps: list[np.ndarray]
    pressure: np.ndarray
    label: np.ndarray
    face_types: list[np.ndarray] = field(default_factory=list)

    @classmethod
    def at_rest(cls, grid: Grid) -> FluidState:
        comps = [np.zeros(grid.face_shape(a)) for a in range(3)]
        return cls(
            comps=comps,
            pressure=np.zeros(grid.cells),
            label=np.full(grid.cells, FLUID, dtype=np.int32),
            face_types=[np.zeros(grid.face_shape(a), dtype=np.int8) for a in range(3)],
        )


#: A box of faces holding any grid's.
ZERO3 = np.zeros(3, dtype=np.int64)
BIG3 = np.full(3, np.iinfo(np.int32).max, dtype=np.int64)


@dataclass
class KeptFaces:
    """What a full face classification (cut cells) was made from, and what the steps after it
    need: the static labels, the sides' kinds, the face type arrays it wrote, the flat indices of
    each component's faces next to a static solid (reset to rest at every step) and the windows
    whose probe samples the last step marked."""

    static: np.ndarray
    kinds: np.ndarray
    face_types: tuple[np.ndarray, ...]
    solid_faces: list[np.ndarray]
    windows: list[tuple[np.ndarray, np.ndarray]] = field(default_factory=list)


class Simulation:
    """A fluid on a MAC grid with moving probes. ``step(dt_s)`` advances it."""

    def __init__(
        self,
        grid: Grid,
        fluid: Fluid,
        boundary: DomainBoundary | None = None,
        probes: list[Probe] | None = None,
        settings: SolverSettings | None = None,
        static_solid: np.ndarray | None = None,
    ) -> None:
        self.grid = grid
        self.fluid = fluid
        self.boundary = boundary or DomainBoundary(grid)
        self.probes = list(probes or [])
        self.settings = settings or SolverSettings()
        self.component_samples = min(int(np.prod(grid.face_shape(a))) for a in range(grid.dim))
        self.component_threads()  # refuses a thread count out of range
        if not 0.0 <= self.settings.corner_radius_cells <= MAX_CORNER_RADIUS_CELLS:  # NaN too
            raise ValueError(
                f"corner_radius_cells must be in [0, {MAX_CORNER_RADIUS_CELLS:g}], "
                f"got {self.settings.corner_radius_cells}"
            )
        self.cut = CutGeometry.empty(grid) if self.settings.boundary_method == "cutcell" else None
        # auto: on threads or one, whichever has cost less lately (solver.compiled.timed_choice): its
        # many short parallel loops each wait for both threads, and with the other core busy
        # the solve took twice as long as on one thread
        mg_threads = self.settings.threads or min(AUTO_THREADS, usable_cores())
        self._pressure_mg = (
            Multigrid(grid.cells, grid.dim, threads=mg_threads, adaptive=self.settings.threads == 0)
            if self.settings.preconditioner == "multigrid"
            else None
        )
        self._pressure_solve: LinearSolve = (
            self._pressure_mg.solve if self._pressure_mg is not None else solve
        )
        self._viscosity_solves: dict[str, list[LinearSolve]] = {}
        #: Each viscosity component's solve, and the incremental pressure's, with ``warm_start``
        #: starts from its last solution (:mod:`solver.linalg.warm_start`).
        self._viscosity_warm = [WarmStart() for _ in range(3)]
        self._pressure_warm = WarmStart()
        self._static_label = np.full(grid.cells, FLUID, dtype=np.int32)
        self._was_active = np.zeros(grid.cells, dtype=np.bool_)
        self.static_solid = (
            np.zeros(grid.cells, dtype=bool)
            if static_solid is None
            else np.array(static_solid, dtype=bool, order="C")  # a copy of its own
        )
        self.state = FluidState.at_rest(grid)
        self.time_s = 0.0
        self.forces: dict[str, ProbeForce] = {}
        self._viscosity_work: list[ViscosityWork] = []
        self._pressure_work: StencilSystem | None = None
        #: What the kept pressure matrix was built from: static labels, side kinds, windows.
        self._pressure_built: (
            tuple[np.ndarray, np.ndarray, list[tuple[np.ndarray, np.ndarray]]] | None
        ) = None
        #: What the kept face classification holds (cut cells; see :meth:`_apply_boundaries`).
        self._faces_built: KeptFaces | None = None
        self._kinds = self.boundary.kinds()
        self._side_vel = self.boundary.velocities()
        self._last_dt = 0.0
        self._previous: tuple | None = None
        self.viscosity_pa_s = np.full(grid.cells, fluid.dynamic_viscosity_pa_s)
        self.drag_per_s: np.ndarray | None = None
        self._rasterize()
        self._apply_boundaries()

    # -- the step ---------------------------------------------------------------------------
    def step(self, dt_s: float, beside: Callable[[], object] | None = None) -> StepStats:
        """Advance by ``dt_s`` seconds (any positive value: the scheme has no stability limit).

        ``beside``: work of the caller's that needs this step's geometry but not its flow (a
        paint model's exchange with the brush). It runs once the probes have moved and the
        boundaries are set: with a second thread, on it, while this one solves the pressure
        (the other thread's slack); with one, after the forces. It must write nothing this
        step reads or writes; it may read the labels, the cut geometry and the probes, which
        the rest of the step leaves as they are. An exception it raises is raised here once the
        step is done and counted (an error of the step's own is raised instead, once the job
        has finished); the wait for it is the sub-step ``beside``."""
        if not (np.isfinite(dt_s) and dt_s > 0):
            raise ValueError(f"dt must be a positive finite number of seconds, got {dt_s}")
        g, st, cfg = self.grid, self.state, self.settings
        clock = PhaseTimer()
        vel = (st.comps[0], st.comps[1], st.comps[2])
        if self._needs_previous_state():
            self._previous = (vel, st.label.copy())
        for probe in self.probes:
            probe.advance(self.time_s, dt_s)
        geometry: list[StencilSystem | None] = []

        def place_probes() -> None:
            # the probes' geometry (and the cut cells' pressure matrix, which depends on
            # nothing else) reads and writes nothing the advection does
            self._rasterize()
            geometry.append(None if self.cut is None else self._assemble_pressure())

        threads = self.component_threads()
        if cfg.advection == "none":  # Stokes flow: no self-advection, the velocity carries over
            keep = self._needs_previous_state()  # the momentum balance keeps the old arrays
            new = [st.comps[a].copy() if keep else st.comps[a] for a in range(g.dim)]
        else:
            scheme = SCHEMES[cfg.advection]
            # with a second thread, the geometry runs beside the advection
            lead = place_probes if threads > 1 else None
            new = advect_velocity(vel, g.dim, g.cell_size_m, dt_s, scheme, threads, lead)
        for a in range(g.dim):
            if self.fluid.body_force_m_s2[a]:
                new[a] += dt_s * self.fluid.body_force_m_s2[a]
            st.comps[a] = new[a]
        clock.mark("advect")
        if not geometry:
            place_probes()
        system = geometry[0]
        self._apply_boundaries()
        if cfg.incremental_pressure:
            active = system.active if system is not None else st.label == FLUID
            self._old_pressure_gradient(active, dt_s)
        clock.mark("boundaries")
        # with a second thread, the pressure's multigrid hierarchy (from the matrix, which the
        # viscosity does not change) is built beside the viscosity solves, in the slack that
        # three components leave on two threads
        preload = (
            self._pressure_mg
            if system is not None and self.cut is not None and self.component_threads() > 1
            else None
        )
        visc = self._diffuse(dt_s, preload, system)
        clock.mark("viscosity")
        job = None if beside is None else BesideJob(beside, threads)
        try:
            report = self._project(dt_s, system, preload)
            clock.mark("projection")
            self._last_dt = dt_s
            self._compute_forces()
        except BaseException:
            if job is not None:
                job.settle()
            raise
        clock.mark("forces")
        self.time_s += dt_s
        if job is not None:
            job.result()
            clock.mark("beside")
        return StepStats(self.time_s, clock.total_ms, clock.ms, report, visc)

    def _project(
        self, dt_s: float, system: StencilSystem | None, preload: Multigrid | None
    ) -> SolveReport:
        """The pressure projection of a step (the cut cells' ``system`` when there is one, its
        hierarchy ``preload``-ed beside the viscosity when given); updates the pressure."""
        g, st, cfg = self.grid, self.state, self.settings
        rho = self.fluid.density_kg_m3
        phi = np.zeros(g.cells) if cfg.incremental_pressure else st.pressure * (dt_s / rho)
        pressure_solve = self._pressure_solve
        if preload is not None:
            pressure_solve = _loaded_solve(preload)
        # (Chorin's scheme starts from the last pressure itself; a closed domain's is fixed
        # only up to a constant, which a warm start would carry from step to step)
        open_domain = bool((self._kinds[: g.dim] == OUTFLOW).any())
        if cfg.warm_start and cfg.incremental_pressure and open_domain:
            pressure_solve = functools.partial(self._pressure_warm.solve, pressure_solve)
        else:
            self._pressure_warm.forget()
        if system is not None and self.cut is not None:
            faces = CutFaces(self.cut.open_frac, self.cut.owner_face, self._rigid)
            report = project_cut(
                st.comps,
                system,
                self._static_label,
                faces,
                g.cell_size_m,
                self._kinds,
                phi,
                cfg.pressure_tolerance,
                cfg.max_iterations,
                pressure_solve,
            )
        else:
            report = project(
                st.comps,
                st.face_types,
                st.label,
                g.dim,
                g.cell_size_m,
                self._kinds,
                phi,
                cfg.pressure_tolerance,
                cfg.max_iterations,
                pressure_solve,
            )
        if cfg.incremental_pressure:
            st.pressure = st.pressure + phi * (rho / dt_s)
        else:
            st.pressure = phi * (rho / dt_s)
        return report

    def _assemble_pressure(self) -> StencilSystem:
        """The cut-cell pressure matrix of this step, in the system kept from step to step.

        Outside the probes' windows every face is wholly open (the cut geometry clears a window
        when its probe leaves it), so the matrix there changes only with the static labels and
        the sides' kinds. While those are what the kept matrix was built from, only the cells
        within a cell of the last step's windows and this step's are assembled again (64³: 1.7
        ms for the whole grid); otherwise all of it. The same values either way."""
        g, cut = self.grid, self.cut
        assert cut is not None
        windows = list(cut.windows)  # each update makes new window arrays
        kept = self._pressure_built
        boxes = None
        if (
            self._pressure_work is not None
            and kept is not None
            and np.array_equal(kept[0], self._static_label)
            and np.array_equal(kept[1], self._kinds)
        ):
            boxes = [(lo - 1, hi + 1) for lo, hi in kept[2] + windows]  # clipped by the assembly
        if self._pressure_work is None:
            self._pressure_work = StencilSystem.empty(g.cells, g.dim)
        system = pressure_system(
            self._static_label, g.dim, self._kinds, cut.open_frac, self._pressure_work, boxes
        )
        # reassembled in boxes, the kept labels already are this step's
        static = kept[0] if boxes is not None and kept is not None else self._static_label.copy()
        self._pressure_built = (static, self._kinds.copy(), windows)
        return system

    def _old_pressure_gradient(self, active: np.ndarray, dt_s: float) -> None:
        """Incremental pressure correction: apply the last pressure's gradient before the
        viscosity solve (the projection then solves only for the increment). Cells that have
        just become active take their first pressure from their neighbours."""
        g, st = self.grid, self.state
        fill_fresh_pressure(st.pressure, self._was_active, active, g.dim)
        self._was_active = active.copy()
        phi_old = st.pressure * (dt_s / self.fluid.density_kg_m3)
        h = g.cell_size_m
        for a in range(g.dim):
            if self.cut is not None:
                subtract_cut_gradient(
                    st.comps[a],
                    self._static_label,
                    self._kinds,
                    self.cut.open_frac[a],
                    a,
                    active,
                    phi_old,
                    h,
                )
            else:
                subtract_gradient(st.comps[a], st.face_types[a], a, phi_old, h)

    def _diffuse(
        self, dt_s: float, preload: Multigrid | None = None, system: StencilSystem | None = None
    ) -> tuple[SolveReport, ...]:
        """The viscosity solves, one per component; ``preload``, when given, loads ``system``
        beside them (a task of its own, on the thread that has a component less)."""
        mu_max = float(self.viscosity_pa_s.max())  # the field is >= 0 (set_viscosity)
        g, st, cfg = self.grid, self.state, self.settings
        if mu_max <= 0.0 and self.drag_per_s is None:
            if preload is not None and system is not None:
                preload.load(system)
            return ()  # inviscid: no viscosity solve at all
        rigid = self._rigid
        rho, h = self.fluid.density_kg_m3, g.cell_size_m
        coupling = 2 * g.dim * mu_max * dt_s / (rho * h * h)
        solves = self._viscosity_solvers(cfg.viscosity_solver(coupling))
        step = self._viscous_step(dt_s)
        tol, max_iter = cfg.viscosity_tolerance, cfg.max_iterations
        if self.cut is None:
            walls = Walls(st.label, rigid, h)
            return tuple(
                run_components(
                    lambda a: diffuse(self._component(a), step, walls, tol, max_iter, solves[a]),
                    g.dim,
                    self.component_threads(),
                )
            )
        if not self._viscosity_work:
            self._viscosity_work = [
                ViscosityWork.for_shape(g.face_shape(a), g.dim) for a in range(g.dim)
            ]

        def task(a: int) -> SolveReport | None:
            if a == g.dim:  # the pressure's hierarchy
                if preload is not None and system is not None:
                    preload.load(system)
                return None
            walls = self._cut_walls(a)
            return diffuse_cut(
                self._component(a), step, walls, tol, max_iter, solves[a], self._viscosity_work[a]
            )

        threads = self.component_threads()
        if threads == 2 and g.dim == 3:
            return self._diffuse_split(task, solves[2], dt_s)
        tasks = g.dim + (1 if preload is not None else 0)
        reports = run_components(task, tasks, threads)
        return tuple(r for r in reports[: g.dim] if r is not None)

    def _viscous_step(self, dt_s: float) -> ViscousStep:
        """What this step's viscosity solves share across the components."""
        sides = Sides(self._kinds, self._side_vel)
        return ViscousStep(
            self.grid.dim,
            self.viscosity_pa_s,
            dt_s,
            self.fluid.density_kg_m3,
            sides,
            self.drag_per_s,
        )

    def _component(self, axis: int) -> Component:
        """Velocity component ``axis`` with its face kinds."""
        st = self.state
        return Component(st.comps[axis], st.face_types[axis], axis)

    def _cut_walls(self, axis: int) -> CutWalls:
        """The probes as walls of component ``axis`` on the cut geometry."""
        cut = self.cut
        assert cut is not None
        h = self.grid.cell_size_m
        phi, owner = cut.phi_face[axis], cut.owner_sample[axis]
        return CutWalls(self._static_label, self._rigid, h, phi, owner)

    def _diffuse_split(
        self, task: Callable[[int], SolveReport | None], last: LinearSolve, dt_s: float
    ) -> tuple[SolveReport, ...]:
        """The three components' viscosity on two threads, evenly: this thread solves the first
        component and the last, the other assembles the last component's system (and loads its
        multigrid hierarchy) first, then does the second component whole and the pressure's
        hierarchy (``task(3)``). Three whole components left one thread with two of them and
        the other with one; the same values."""
        st, cfg = self.state, self.settings
        prepare, solve_last = _prepared(last)
        work = self._viscosity_work[2]

        def assemble_last() -> None:
            assemble_cut(self._component(2), self._viscous_step(dt_s), self._cut_walls(2), work)
            prepare(work.system)

        def own(wait: Callable[[int], object]) -> tuple[SolveReport, SolveReport]:
            first = task(0)
            wait(0)
            third = solve_last(
                work.system, work.rhs, st.comps[2], cfg.viscosity_tolerance, cfg.max_iterations
            )
            assert first is not None
            return first, third

        (first, third), done = run_beside(own, [assemble_last, lambda: task(1), lambda: task(3)])
        second = done[1]
        assert isinstance(second, SolveReport)
        return first, second, third

    def pressure_on_threads(self) -> bool:
        """Whether the pressure solve runs its large levels on threads, or (auto) may, by
        measurement (:attr:`solver.linalg.multigrid.Multigrid.parallel`)."""
        return self._pressure_mg is not None and self._pressure_mg.parallel

    def pressure_threads(self) -> int:
        """The threads the pressure solve's large levels run on when on threads (1: none)."""
        return self._pressure_mg.threads if self.pressure_on_threads() else 1  # type: ignore[union-attr]

    def pressure_threads_adaptive(self) -> bool:
        """Whether each pressure solve picks threads or one by their recent cost (auto)."""
        return self.pressure_on_threads() and self._pressure_mg.adaptive  # type: ignore[union-attr]

    def component_threads(self) -> int:
        """The threads a step runs the velocity components' advection and viscosity solves on
        (:mod:`solver.compiled.threads`)."""
        return thread_count(self.settings.threads, self.component_samples, self.grid.dim)

    def _viscosity_solvers(self, name: str) -> list[LinearSolve]:
        """One solve per velocity component for preconditioner ``name`` (a multigrid keeps its
        hierarchy from step to step), each from the last step's solution with ``warm_start``."""
        if name not in self._viscosity_solves:
            g = self.grid
            self._viscosity_solves[name] = [
                _linear_solver(name, g.face_shape(a), g.dim, DIFFUSION_SCALES) for a in range(g.dim)
            ]
        solves = self._viscosity_solves[name]
        if not self.settings.warm_start:
            for warm in self._viscosity_warm:
                warm.forget()
            return solves
        return [
            functools.partial(self._viscosity_warm[a].solve, solve)
            for a, solve in enumerate(solves)
        ]

    # -- fields the caller may set ---------------------------------------------------------------
    def set_viscosity(self, mu_pa_s: np.ndarray) -> None:
        """Dynamic viscosity per cell (cells' shape, finite, >= 0, Pa s) from the next step on;
        e.g. paint and air. ``fluid.viscosity_m2_s`` only gives the initial, uniform field."""
        mu = np.asarray(mu_pa_s, dtype=np.float64)
        if mu.shape != self.grid.cells:
            raise ValueError(f"viscosity field must have shape {self.grid.cells}, got {mu.shape}")
        if not np.all(np.isfinite(mu)) or np.any(mu < 0.0):
            raise ValueError("viscosity field must be finite and >= 0")
        self.viscosity_pa_s = np.ascontiguousarray(mu)

    def set_drag(self, rate_per_s: np.ndarray | None) -> None:
        """Linear drag ``du/dt = -k u`` with ``k`` per cell (1/s, >= 0), or None for none: the
        friction of the no-slip surface under a thin depth-averaged layer."""
        if rate_per_s is None:
            self.drag_per_s = None
            return
        k = np.asarray(rate_per_s, dtype=np.float64)
        if k.shape != self.grid.cells or not np.all(np.isfinite(k)) or np.any(k < 0.0):
            raise ValueError(f"drag must be finite, >= 0 and of shape {self.grid.cells}")
        self.drag_per_s = np.ascontiguousarray(k)

    # -- moving the grid ------------------------------------------------------------------------
    def shift(self, offset_cells: tuple[float, ...]) -> None:
        """Move the grid by ``offset_cells`` per active axis, keeping the state.

        By whole cells, samples that stay inside the grid keep their values; by a fraction of a
        cell, each sample takes the linear interpolation of the two it now lies between (each
        velocity component and the pressure alike: the fields move as a whole). Cells that enter
        the grid start at rest with zero pressure (a caller may fill them, e.g. from a canvas,
        before the next step).
        """
        g = self.grid
        off = [float(o) for o in offset_cells] + [0.0] * (3 - len(offset_cells))
        if not any(off):
            return
        whole = all(o == round(o) for o in off)
        origin = tuple(g.origin_m[a] + off[a] * g.cell_size_m for a in range(3))
        self.grid = Grid(g.dim, g.cells, g.cell_size_m, origin)  # type: ignore[arg-type]
        st = self.state
        if not whole:
            # the fields' fractional move, beside the geometry sampled afresh at the new cell
            # centres (with a second thread): neither reads what the other writes
            def move_fields() -> None:
                st.comps = [shifted_by(q, off) for q in st.comps]
                st.pressure = shifted_by(st.pressure, off)
                for warm in (*self._viscosity_warm, self._pressure_warm):
                    warm.move(lambda last: shifted_by(last, off))

            job = BesideJob(move_fields, self.component_threads())
            try:
                self._rasterize()
            except BaseException:
                job.settle()
                raise
            job.result()
            self._was_active = shifted(self._was_active, [round(o) for o in off])
            self._apply_boundaries(relax=False)
            return
        cells = [round(o) for o in off]
        st.comps = [shifted(q, cells) for q in st.comps]
        st.pressure = shifted(st.pressure, cells)
        for warm in (*self._viscosity_warm, self._pressure_warm):
            warm.move(lambda last: shifted(last, cells))
        self._was_active = shifted(self._was_active, cells)
        if self.cut is not None and self.cut.shift((cells[0], cells[1], cells[2]), g.cells):
            # the probes stood still: their geometry moves with the grid (no new distances)
            self._rigid, ref = self._rigid_and_reference()
            self._motion = (self._rigid[0], self._rigid[1], self._rigid[2], ref)
            label_cells(st.label, self._static_label, self.static_solid, self.cut.owner_cell, True)
        else:
            self._rasterize()
        self._apply_boundaries(relax=False)

    # -- geometry and boundaries -------------------------------------------------------------
    def _rasterize(self) -> None:
        self._rigid, ref = self._rigid_and_reference()
        self._motion = (self._rigid[0], self._rigid[1], self._rigid[2], ref)
        label = self.state.label
        if self.cut is not None:  # the cut geometry samples the cell centres too
            radius = self.settings.corner_radius_cells * self.grid.cell_size_m
            self.cut.update(self.grid, self.probes, radius)
            label_cells(label, self._static_label, self.static_solid, self.cut.owner_cell, True)
            return
        label_cells(label, self._static_label, self.static_solid, label, False)
        for n, probe in enumerate(self.probes):
            window, mask = probe.voxelize(self.grid)
            sub = label[window]
            sub[mask & (sub == FLUID)] = n

    def rigid_motion(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Per-probe centre, velocity, angular velocity and torque reference, each (n, 3),
        positions relative to the grid origin."""
        rigid, ref = self._rigid_and_reference()
        return rigid[0], rigid[1], rigid[2], ref

    def _rigid_and_reference(self) -> tuple[RigidMotion, np.ndarray]:
        """:meth:`rigid_motion` as the kernels take it: centre, velocity and angular velocity
        (:class:`~solver.staircase.faces.RigidMotion`), and the torque reference (n, 3)."""
        n = max(len(self.probes), 1)
        rigid, ref = RigidMotion(*np.zeros((3, n, 3))), np.zeros((n, 3))
        centre, vel, omega = rigid
        origin = np.asarray(self.grid.origin_m)
        d = self.grid.dim
        for i, probe in enumerate(self.probes):
            centre[i, :d] = probe.centre_m - origin[:d]
            vel[i, :d] = probe.velocity_m_s
            omega[i] = probe.omega3()
            ref[i, :d] = probe.reference_point() - origin[:d]
        return rigid, ref

    def _apply_boundaries(self, relax: bool = True) -> None:
        """Boundary velocities on the faces; ``relax``: the once-per-step relaxation of the
        samples inside cut-cell probes (see :func:`solver.cutcell.viscosity.mark_probe_samples`).

        With cut cells the faces are classified against the static labels alone, and only
        the probes' windows change their types (the samples inside a probe). While the static
        labels, the sides' kinds and the face arrays are what the last full pass classified,
        only the last step's windows are classified again (which clears their marks) and the
        static solids' faces reset to rest; otherwise the whole grid. The same values either
        way."""
        g, st = self.grid, self.state
        rigid = self._rigid
        kept = self._kept_faces()
        label = st.label if self.cut is None else self._static_label
        for a in range(g.dim):
            open_lo = bool(self._kinds[a, 0] == 3)
            open_hi = bool(self._kinds[a, 1] == 3)
            boxes = (
                [(ZERO3, BIG3)] if kept is None else [(lo, hi + UNIT[a]) for lo, hi in kept.windows]
            )
            comp = self._component(a)
            for lo, hi in boxes:
                classify_faces(
                    label, comp, (open_lo, open_hi), rigid, g.cell_size_m, Window(lo, hi)
                )
            if kept is not None:
                st.comps[a].flat[kept.solid_faces[a]] = 0.0
            if self.cut is not None:
                cut = self.cut
                walls = self._cut_walls(a)
                for lo, hi in cut.windows:
                    window = Window(lo, hi + UNIT[a])
                    mark_probe_samples(comp, walls, cut.open_frac[a], window, relax)
        if self.cut is not None:
            if kept is None:
                solid = [
                    solid_adjacent_faces(label, a, st.face_types[a].shape) for a in range(g.dim)
                ]
                kept = KeptFaces(label.copy(), self._kinds.copy(), tuple(st.face_types), solid)
            kept.windows = list(self.cut.windows)
            self._faces_built = kept
        self.boundary.apply_normal(st.comps, self._kinds, self._side_vel)

    def _kept_faces(self) -> KeptFaces | None:
        """The record of the last full classification, where it still holds (see
        :meth:`_apply_boundaries`), else None."""
        kept = self._faces_built
        if self.cut is None or kept is None:
            return None
        if not (
            np.array_equal(kept.static, self._static_label)
            and np.array_equal(kept.kinds, self._kinds)
            and len(kept.face_types) == len(self.state.face_types)
            and all(a is b for a, b in zip(kept.face_types, self.state.face_types, strict=True))
        ):
            return None
        return kept

    # -- forces ---------------------------------------------------------------------------------
    def computes_forces(self) -> bool:
        """Whether a step does any probe force work (there are probes and forces are wanted)."""
        return bool(self.probes) and self.settings.probe_forces

    def _needs_previous_state(self) -> bool:
        """The momentum balance needs the state before the step; nothing else does."""
        return self.computes_forces() and self.settings.force_model == "control_volume"

    def _compute_forces(self) -> None:
        if not self.computes_forces():
            return
        g, st = self.grid, self.state
        d = g.dim
        if self.settings.force_model in ("drag", "viscous_drag"):
            self._approximate_forces()
            return
        ref = self._motion[3]
        n = len(self.probes)
        fp, fv, tq = np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3))
        if self.cut is not None:
            self._cut_forces(ref, fp, fv, tq)
        else:
            sums = ForceSums(fp, fv, tq)
            fields = self._stress_fields()
            stress_integral(st.label, fields, g.cell_size_m, d, self._rigid, ref, sums)
        for i, probe in enumerate(self.probes):
            force, torque = fp[i] + fv[i], tq[i]
            if self.settings.force_model == "control_volume":
                balance = self._momentum_balance(i, ref[i])
                if balance is not None:
                    force, torque = balance
            self.forces[probe.name] = ProbeForce(
                force=force[:d].copy(),
                torque=float(torque[2]) if d == 2 else torque.copy(),
                pressure_force=fp[i, :d].copy(),
                viscous_force=fv[i, :d].copy(),
            )

    def _cut_forces(self, ref: np.ndarray, fp: np.ndarray, fv: np.ndarray, tq: np.ndarray) -> None:
        """The cut-surface integral over the union window of all probes."""
        cut, g = self.cut, self.grid
        fp[:], fv[:], tq[:] = 0.0, 0.0, 0.0
        if cut is None or not cut.windows:
            return
        if len(cut.windows) == 1:
            lo, hi = cut.windows[0]
        else:
            lo = np.min([w[0] for w in cut.windows], axis=0)
            hi = np.max([w[1] for w in cut.windows], axis=0)
        patches = SurfacePatches(cut.open_frac, cut.phi_node, cut.owner_node)
        fields = self._stress_fields()
        sums = ForceSums(fp, fv, tq)
        window = Window(lo, hi)
        cut_surface_force(patches, window, fields, g.cell_size_m, g.dim, self._rigid, ref, sums)

    def _stress_fields(self) -> StressFields:
        """The velocity, pressure and viscosity the probe forces are formed from."""
        st = self.state
        velocity = Velocity(st.comps[0], st.comps[1], st.comps[2])
        return StressFields(velocity, st.pressure, self.viscosity_pa_s)

    def _momentum_balance(
        self, index: int, ref: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """Force and torque on probe ``index`` from the control-volume momentum balance, or None
        when no valid box fits (the caller keeps the surface integral)."""
        g, st = self.grid, self.state
        window = tuple(slice(0, c) for c in g.cells)
        margin = self.settings.control_volume_margin
        box = probe_box(window, st.label == index, g.cells, g.dim, margin)
        if box is None or self._last_dt <= 0.0 or self._previous is None:
            return None
        lo, hi = box
        cv = ControlVolume(Window(lo, hi), g.dim, g.cell_size_m, self.fluid.density_kg_m3, ref)
        surface, now, before = np.zeros(6), np.zeros(6), np.zeros(6)
        fields = self._stress_fields()
        if not box_surface_flux(fields, st.label, cv, surface):
            return None
        box_momentum(fields.velocity, st.label, cv, now)
        (u0, v0, w0), label0 = self._previous
        box_momentum(Velocity(u0, v0, w0), label0, cv, before)
        total = surface - (now - before) / self._last_dt
        return total[:3], total[3:]

    def _approximate_forces(self) -> None:
        d = self.grid.dim
        cfg = self.settings
        for probe in self.probes:
            area_fn = getattr(probe.shape, "cross_section_m", None)
            area = float(area_fn(d)) if area_fn else 2.0 * probe.shape.bounding_radius_m
            v = probe.velocity_m_s
            if cfg.force_model == "drag":
                f = drag_models.quadratic_drag(
                    v, self.fluid.density_kg_m3, area, cfg.drag_coefficient
                )
            else:
                f = drag_models.viscous_drag(
                    v, self.fluid.dynamic_viscosity_pa_s, area, cfg.drag_coefficient
                )
            zero = np.zeros(d)
            self.forces[probe.name] = ProbeForce(
                force=f,
                torque=0.0 if d == 2 else np.zeros(3),
                pressure_force=zero,
                viscous_force=zero,
            )

    # -- diagnostics --------------------------------------------------------------------------
    def fluid_cells(self) -> np.ndarray:
        """Mask of the cells the projection solves for: fluid cells (staircase), or cells with an
        open face (cut cells; a sliver whose faces are all below the minimum fraction is not)."""
        if self.cut is not None:
            g = self.grid
            return pressure_system(
                self._static_label, g.dim, self._kinds, self.cut.open_frac
            ).active
        return self.state.label == FLUID

    def divergence(self) -> np.ndarray:
        """Velocity divergence per cell (1/s), 0 in solid cells."""
        st, g = self.state, self.grid
        out = np.empty(g.cells)
        if self.cut is not None:
            cut = self.cut
            active = pressure_system(self._static_label, g.dim, self._kinds, cut.open_frac).active
            rigid, _ = self._rigid_and_reference()
            velocity = Velocity(st.comps[0], st.comps[1], st.comps[2])
            faces = CutFaces(cut.open_frac, cut.owner_face, rigid)
            cut_flux(velocity, faces, active, g.dim, g.cell_size_m, out, layer_count(out.shape))
            return out / g.cell_size_m
        divergence_sum(st.comps[0], st.comps[1], st.comps[2], st.label, g.dim, out)
        return out / g.cell_size_m

    def cell_velocity(self) -> np.ndarray:
        """Velocity at the cell centres, (dim, nx, ny, nz) m/s: each component the mean of the
        two faces either side of the cell."""
        g, st = self.grid, self.state
        out = np.empty((g.dim, *g.cells))
        for a in range(g.dim):
            q = st.comps[a]
            lo: list[slice] = [slice(None)] * 3
            hi: list[slice] = [slice(None)] * 3
            lo[a] = slice(0, -1)
            hi[a] = slice(1, None)
            out[a] = 0.5 * (q[tuple(lo)] + q[tuple(hi)])
        return out

    def kinetic_energy(self) -> float:
        """Kinetic energy of the fluid, J (2D: J per metre of depth), from face samples."""
        fluid = self.state.label == FLUID
        total = float(np.sum(self.cell_velocity()[:, fluid] ** 2))
        return 0.5 * self.fluid.density_kg_m3 * total * self.grid.cell_volume

    def velocity_at(self, points_m: np.ndarray) -> np.ndarray:
        """Interpolated velocity at world points (n, dim) -> (n, dim)."""
        pts = self._relative(points_m)
        h = self.grid.cell_size_m
        return np.stack(
            [sample_many(self.state.comps[a], a, pts, h) for a in range(self.grid.dim)], axis=1
        )

    def pressure_at(self, points_m: np.ndarray) -> np.ndarray:
        """Pressure (Pa) at world points (n, dim) -> (n,), interpolated from fluid cells only."""
        return sample_cells_fluid(
            self.state.pressure, self.state.label, self._relative(points_m), self.grid.cell_size_m
        )

    def _relative(self, points_m: np.ndarray) -> np.ndarray:
        pts = np.atleast_2d(np.asarray(points_m, dtype=float))
        d = self.grid.dim
        out = np.full((pts.shape[0], 3), 0.5 * self.grid.cell_size_m)
        out[:, :d] = pts[:, :d] - np.asarray(self.grid.origin_m)[:d]
        return out


def _loaded_solve(mg: Multigrid) -> LinearSolve:
    """``mg``'s solve for the system it has already loaded (the ``system`` argument unused)."""

    def solve_loaded(
        system: StencilSystem, b: np.ndarray, x: np.ndarray, tol: float, max_iter: int
    ) -> SolveReport:
        return mg.solve_loaded(b, x, tol, max_iter)

    return solve_loaded


def _prepared(
    solve: LinearSolve,
) -> tuple[Callable[[StencilSystem], None], LinearSolve]:
    """``solve`` cut in two: what may run as soon as the system is assembled (a multigrid's
    hierarchy), and the solve that follows it (from the last solution, where ``solve`` is a
    warm start's)."""
    if isinstance(solve, functools.partial) and isinstance(
        getattr(solve.func, "__self__", None), WarmStart
    ):
        prepare, inner = _prepared(solve.args[0])
        return prepare, functools.partial(solve.func, inner)
    mg = getattr(solve, "__self__", None)
    if isinstance(mg, Multigrid):
        return mg.load, _loaded_solve(mg)
    return lambda system: None, solve


def _linear_solver(
    name: str, shape: tuple[int, int, int], dim: int, scales: tuple[float, float] | None = None
) -> LinearSolve:
    """The solve for systems over ``shape``: MGPCG with a hierarchy kept for the grid (built
    once; the grid's shape never changes), diagonal-preconditioned CG with its scratch kept
    likewise, or MIC(0)-PCG."""
    if name == "mic0":
        return solve
    if name == "jacobi":
        return JacobiPCG(shape).solve
    mg = Multigrid(shape, dim) if scales is None else Multigrid(shape, dim, scales)
    return mg.solve
