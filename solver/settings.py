"""The solver's numerical knobs, apart from the numerics so that reading a scene is light."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, get_args

#: ``SolverSettings.advection``: a semi-Lagrangian scheme, or ``none`` (Stokes flow).
Advection = Literal["linear", "maccormack", "none"]
#: ``SolverSettings.force_model`` (:mod:`solver.forces.drag_models`).
ForceModel = Literal["stress", "control_volume", "drag", "viscous_drag"]
BoundaryMethod = Literal["cutcell", "staircase"]
PressureScheme = Literal["auto", "incremental", "chorin"]
Preconditioner = Literal["multigrid", "mic0"]
#: What a viscosity solve runs with: a preconditioner, or the diagonal (``jacobi``).
ViscositySolver = Literal["jacobi", "multigrid", "mic0"]
#: ``SolverSettings.viscosity_preconditioner``: a viscosity solver, or ``auto`` (chosen per step).
ViscosityPreconditioner = Literal["auto", "jacobi", "multigrid", "mic0"]

ADVECTION_CHOICES: tuple[Advection, ...] = get_args(Advection)
FORCE_MODELS: tuple[ForceModel, ...] = get_args(ForceModel)
BOUNDARY_METHODS: tuple[BoundaryMethod, ...] = get_args(BoundaryMethod)
PRESSURE_SCHEMES: tuple[PressureScheme, ...] = get_args(PressureScheme)
PRECONDITIONERS: tuple[Preconditioner, ...] = get_args(Preconditioner)
VISCOSITY_PRECONDITIONERS: tuple[ViscosityPreconditioner, ...] = get_args(ViscosityPreconditioner)

#: Default relative tolerance of the viscosity solves, the pressure solve's default: the force and
#: velocity then lie nearer those of exact solves than the pressure solve's own tolerance puts
#: them, so a tighter one only costs iterations; a looser one moved the 2D force by more.
VISCOSITY_TOLERANCE = 1e-6


@dataclass(frozen=True)
class SolverSettings:
    """Numerical knobs of a run; the comment above each field says what it takes. The defaults
    are the fastest on the benchmarks (``benchmarks/bench_solver.py``, ``paintapp bench``)."""

    #: ``linear`` | ``maccormack`` | ``none`` (Stokes flow: the velocity's self-advection left
    #: out).
    advection: Advection = "linear"
    #: Relative residual tolerance of the pressure solve.
    pressure_tolerance: float = 1e-6
    #: Relative residual tolerance of the viscosity solves.
    viscosity_tolerance: float = VISCOSITY_TOLERANCE
    #: Iteration cap of every PCG solve.
    max_iterations: int = 1000
    #: Probe force model: the ``stress`` integral; ``control_volume``, a momentum balance over a box
    #: around the probe, far less sensitive to the staircase boundary; or the paper's ``drag`` /
    #: ``viscous_drag`` approximations.
    force_model: ForceModel = "stress"
    drag_coefficient: float = 1.0
    control_volume_margin: int = 3
    #: False skips all force work (nothing reads the forces, e.g. a tablet without force feedback):
    #: ``Simulation.forces`` stays empty.
    probe_forces: bool = True
    #: ``cutcell`` (face fractions from the probes' signed distances, the variational projection,
    #: no-slip at the true surface, force from the cut surface) or ``staircase`` (the paper's
    #: voxelized probe, eqs. 14-18; for comparison).
    boundary_method: BoundaryMethod = "cutcell"
    #: Cut cells only: a box probe's edges and corners are rounded with this radius, in cells (0
    #: keeps them sharp). A corner sharper than the grid cannot be resolved: the flow's pressure
    #: singularity there, sampled wherever the corner sits in its cell, adds jitter to the force
    #: as the corner crosses cells. Rounding lowers that noise and lowers the force a little.
    corner_radius_cells: float = 0.0
    #: ``incremental`` (pressure correction: steady states independent of dt), ``chorin`` (the
    #: paper's non-incremental projection) or ``auto`` (incremental with cut cells, chorin with
    #: the staircase).
    pressure_scheme: PressureScheme = "auto"
    #: Pressure solve: ``multigrid`` (MGPCG: a geometric V-cycle built from the assembled matrix)
    #: or ``mic0`` (modified incomplete Cholesky, the paper's choice).
    preconditioner: Preconditioner = "multigrid"
    #: The same two, ``jacobi`` (the diagonal), or ``auto``: per step, the diagonal while the
    #: system is strongly diagonally dominant (``2 dim nu_max dt / h^2 <=`` :data:`JACOBI_LIMIT`),
    #: multigrid above.
    viscosity_preconditioner: ViscosityPreconditioner = "auto"
    #: The velocity components' advection and viscosity solves on this many threads at once (the
    #: same values); 1 one after the other; 0 two where the cores and the grid's size make it pay
    #: (:mod:`solver.compiled.threads`). A 3D pressure solve of 32768+ cells runs its large levels
    #: on as many (N >= 2), or under 0 on two or one, whichever has cost less lately
    #: (:mod:`solver.compiled.timed_choice`); the same values either way.
    threads: int = 0
    #: Each viscosity component's solve and the incremental pressure's start from the last step's
    #: solutions, moved with the grid (:mod:`solver.linalg.warm_start`): for a grid that rides
    #: with its probe, as the painting grid does (the paint scenes' default); off by default,
    #: where a probe crosses a fixed grid and the advected velocity is the better start.
    warm_start: bool = False

    def __post_init__(self) -> None:
        for name, allowed in _CHOICES.items():
            value = getattr(self, name)
            if value not in allowed:
                raise ValueError(f"{name} must be one of {allowed}, got {value!r}")

    def viscosity_solver(self, coupling: float) -> ViscositySolver:
        """The viscosity preconditioner for a step whose largest ``2 dim nu dt / h^2`` is
        ``coupling``."""
        if self.viscosity_preconditioner != "auto":
            return self.viscosity_preconditioner
        return "jacobi" if coupling <= JACOBI_LIMIT else "multigrid"

    @property
    def incremental_pressure(self) -> bool:
        """Whether the step uses the incremental pressure correction."""
        if self.pressure_scheme == "auto":
            return self.boundary_method == "cutcell"
        return self.pressure_scheme == "incremental"


#: Largest ``2 dim nu_max dt / h^2`` at which ``viscosity_preconditioner = "auto"`` takes the
#: diagonal: where the diagonal and multigrid cost the same on the PhiFlow comparison scene
#: (``benchmarks/bench_solver.py --peer``); multigrid is the cheaper the larger the coupling.
JACOBI_LIMIT = 6.0
MAX_CORNER_RADIUS_CELLS = 4.0
#: The allowed values of each string-valued field, checked at construction.
_CHOICES: dict[str, tuple[str, ...]] = {
    "advection": ADVECTION_CHOICES,
    "force_model": FORCE_MODELS,
    "boundary_method": BOUNDARY_METHODS,
    "pressure_scheme": PRESSURE_SCHEMES,
    "preconditioner": PRECONDITIONERS,
    "viscosity_preconditioner": VISCOSITY_PRECONDITIONERS,
}
