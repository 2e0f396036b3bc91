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
    e.g. a tablet without force feedback): ``Simulation.forces`` stays empty."""

    advection: str = "linear"
    pressure_tolerance: float = 1e-6
    viscosity_tolerance: float = 1e-8
    max_iterations: int = 1000
    force_model: str = "stress"
    drag_coefficient: float = 1.0
    control_volume_margin: int = 3
    probe_forces: bool = True
