"""The solver's numerical knobs, apart from the numerics so that reading a scene is light."""

from __future__ import annotations

from dataclasses import dataclass

# The viscosity solves stop where the pressure solve does by default. Measured on
# ``benchmarks/bench_solver.py``'s scene against solves to 1e-11 (pressure to 1e-5, 200 steps at
# 64², 80 at 32³): at 1e-6 the force trace moves by at most 3.0e-6 / 9.2e-7 of its RMS and the
# velocity by 2.5e-6 / 2.6e-7 of its largest value, below what the pressure solve's own 1e-5 moves
# the force (5.4e-6 / 4.6e-5); a step's viscosity solves take 8 / 12 iterations in all, against
# 11.4 / 15 to 1e-8. At 1e-5 the 2D force moved by 6.7e-5, more than the pressure solve's part.
VISCOSITY_TOLERANCE = 1e-6


@dataclass(frozen=True)
class SolverSettings:
    """Numerical knobs: advection scheme (``linear`` | ``maccormack`` | ``none``: Stokes flow,
    the velocity's self-advection left out), relative residual
    tolerances and iteration cap of the PCG solves, and the probe force model
    (``stress`` integral; ``control_volume``, a momentum balance over a box around the probe that
    is far less sensitive to the staircase boundary; or the paper's ``drag`` / ``viscous_drag``
    approximations). ``probe_forces = False`` skips all force work (nothing reads the forces,
    e.g. a tablet without force feedback): ``Simulation.forces`` stays empty.

    ``boundary_method``: ``cutcell`` (the default: face fractions from the probes' signed
    distances, the variational projection, no-slip at the true surface, force from the cut
    surface) or ``staircase`` (the paper's voxelized probe, eqs. 14-18; for comparison).
    ``corner_radius_cells`` (cut cells only): a box probe's edges and corners are rounded with
    this radius, in cells (0, the default, keeps them sharp). A corner sharper than the grid
    cannot be resolved: the flow's pressure singularity there, sampled wherever the corner sits in
    its cell, adds jitter as the corner crosses cells. The paper's square sweep at 64^2 (force /
    torque noise; staircase 0.366 / 2.65): sharp 0.041 / 0.346, 0.5 cell 0.033 / 0.209, 0.75
    cell 0.028 / 0.178, 1 cell 0.026 / 0.186. The rounding costs force: the 64^2 sweep's smoothed
    force is 18.7 % off a sharp 128^2 run with sharp corners, 21.0 % at 0.75 cell.
    ``pressure_scheme``: ``incremental``
    (pressure correction: steady states independent of dt), ``chorin`` (the paper's
    non-incremental projection) or ``auto`` (incremental with cut cells, chorin with the
    staircase).

    ``preconditioner`` (pressure solve): ``multigrid`` (MGPCG: a geometric V-cycle built from
    the assembled matrix) or ``mic0`` (modified incomplete Cholesky, the paper's choice).
    ``viscosity_preconditioner``: the same two, ``jacobi`` (the diagonal), or ``auto``: per step,
    the diagonal while the system is strongly diagonally dominant (``2 dim nu_max dt / h^2 <=
    JACOBI_LIMIT``), multigrid above (measured: as fast as MIC(0) for thick paint, 1.7x faster
    at ``2 dim nu dt / h^2 ~ 10``). The limit is where the two cost the same on the PhiFlow
    comparison scene (``benchmarks/bench_solver.py --peer``'s, 64² to 128², interleaved runs;
    per step, by ``2 dim nu dt / h^2``): the diagonal 0.53 against 0.72 ms at 2.7, 1.64 / 1.75 ms at 6.1, 2.43 /
    2.48 ms at 8.4, 3.72 / 3.40 ms at 10.9. The defaults are the fastest on the benchmarks (``benchmarks/bench_solver.py``,
    ``paintapp bench``).

    ``threads``: the velocity components' advection and viscosity solves on this many threads
    at once (the same values); 1 one after the other; 0 (the default) two where the cores and
    the grid's size make it pay (:mod:`solver.compiled.threads`). A 3D pressure solve of
    32768+ cells runs its large levels on as many (N >= 2), or under 0 on two or one, whichever
    has cost less lately (:mod:`solver.compiled.timed_choice`); the same values either way.

    ``warm_start``: each viscosity component's solve and the incremental pressure's start from
    the last step's solutions, moved with the grid (:mod:`solver.linalg.warm_start`): for a grid that
    rides with its probe, as the painting grid does (the paint scenes' default); off by default,
    where a probe crosses a fixed grid and the advected velocity is the better start."""

    advection: str = "linear"
    pressure_tolerance: float = 1e-6
    viscosity_tolerance: float = VISCOSITY_TOLERANCE
    max_iterations: int = 1000
    force_model: str = "stress"
    drag_coefficient: float = 1.0
    control_volume_margin: int = 3
    probe_forces: bool = True
    boundary_method: str = "cutcell"
    corner_radius_cells: float = 0.0
    pressure_scheme: str = "auto"
    preconditioner: str = "multigrid"
    viscosity_preconditioner: str = "auto"
    threads: int = 0
    warm_start: bool = False

    def viscosity_solver(self, coupling: float) -> str:
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


JACOBI_LIMIT = 6.0
BOUNDARY_METHODS = ("cutcell", "staircase")
MAX_CORNER_RADIUS_CELLS = 4.0
PRESSURE_SCHEMES = ("auto", "incremental", "chorin")
PRECONDITIONERS = ("multigrid", "mic0")
VISCOSITY_PRECONDITIONERS = ("auto", "jacobi", "multigrid", "mic0")
