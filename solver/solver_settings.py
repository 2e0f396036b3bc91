"""The solver's numerical knobs, apart from the numerics so that reading a scene is light."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class SolverSettings:
    """Numerical knobs: advection scheme (``linear`` | ``maccormack``), relative residual
    tolerances and iteration cap of the PCG solves, and the probe force model
    (``stress`` integral; ``control_volume``, a momentum balance over a box around the probe that
    is far less sensitive to the staircase boundary; or the paper's ``drag`` / ``viscous_drag``
    approximations). ``probe_forces = False`` skips all force work (nothing reads the forces,
    e.g. a tablet without force feedback): ``Simulation.forces`` stays empty.

    ``boundary_method``: ``cutcell`` (face fractions from the probes' signed distances, the
    variational projection, no-slip at the true surface, force from the cut surface) or
    ``staircase`` (the paper's voxelized probe, eqs. 14-18). ``pressure_scheme``: ``incremental``
    (pressure correction: steady states independent of dt), ``chorin`` (the paper's
    non-incremental projection) or ``auto`` (incremental with cut cells, chorin with the
    staircase).

    ``preconditioner`` (pressure solve) and ``viscosity_preconditioner`` (implicit viscosity):
    ``multigrid`` (MGPCG: a geometric V-cycle built from the assembled matrix) or ``mic0``
    (modified incomplete Cholesky, the paper's choice). The defaults are the faster of the two
    on the benchmarks: multigrid for the pressure; MIC(0) for viscosity, whose systems are
    diagonally dominant unless the viscosity is high (thick paint), where multigrid pays."""

    advection: str = "linear"
    pressure_tolerance: float = 1e-6
    viscosity_tolerance: float = 1e-8
    max_iterations: int = 1000
    force_model: str = "stress"
    drag_coefficient: float = 1.0
    control_volume_margin: int = 3
    probe_forces: bool = True
    boundary_method: str = "staircase"
    pressure_scheme: str = "auto"
    preconditioner: str = "multigrid"
    viscosity_preconditioner: str = "mic0"

    @property
    def incremental_pressure(self) -> bool:
        """Whether the step uses the incremental pressure correction."""
        if self.pressure_scheme == "auto":
            return self.boundary_method == "cutcell"
        return self.pressure_scheme == "incremental"


BOUNDARY_METHODS = ("cutcell", "staircase")
PRESSURE_SCHEMES = ("auto", "incremental", "chorin")
PRECONDITIONERS = ("multigrid", "mic0")
