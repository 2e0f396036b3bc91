"""Cost of a setting: step time from the solver's own step reports, and memory.

* time: the median of ``StepStats.step_ms`` over the timed steps (the first step is left out: it
  may include loading or compiling the numba kernels);
* memory: ``state_mib``, the bytes of the simulation's persistent arrays (velocity components,
  pressure, labels, face types), and ``peak_step_mib``, the peak of the temporary arrays one step
  allocates through numpy (measured with :mod:`tracemalloc` on one extra step; allocations made
  inside numba kernels are not traced, so this is a lower bound).
"""

from __future__ import annotations

import tracemalloc
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from solver import Simulation, StepStats

MIB = 1024.0 * 1024.0
#: The knobs of a benchmark setting that are solver settings (the scene's ``[solver]`` table).
SOLVER_KEYS = (
    "advection",
    "pressure_tolerance",
    "max_iterations",
    "force_model",
    "boundary_method",
    "corner_radius_cells",
    "preconditioner",
    "viscosity_preconditioner",
)


@dataclass
class Measurement:
    """What one benchmark setting produced: its errors, its cost and notes on how it was run.

    Attributes:
        errors: accuracy figures (dimensionless or in the units their names carry).
        cost: timing and memory figures (``median_step_ms``, ``state_mib``, ...).
        notes: how the run was scaled down or what the reference was.
        extra: anything else worth keeping in the JSON (measured values such as c_D).
    """

    errors: dict[str, float | None]
    cost: dict[str, Any]
    notes: str = ""
    extra: dict[str, Any] = field(default_factory=dict)


def state_bytes(sim: Simulation) -> int:
    """Bytes held by the simulation's persistent arrays."""
    st = sim.state
    arrays = [*st.comps, st.pressure, st.label, *st.face_types]
    return int(sum(a.nbytes for a in arrays))


def traced_step_peak(sim: Simulation, dt_s: float) -> int:
    """Peak bytes of numpy temporaries during one more step of ``dt_s`` (advances ``sim``)."""
    was_tracing = tracemalloc.is_tracing()
    if not was_tracing:
        tracemalloc.start()
    tracemalloc.reset_peak()
    base = tracemalloc.get_traced_memory()[0]
    sim.step(dt_s)
    peak = tracemalloc.get_traced_memory()[1] - base
    if not was_tracing:
        tracemalloc.stop()
    return max(int(peak), 0)


def step_cost(stats: Sequence[StepStats], sim: Simulation | None = None, dt_s: float = 0.0) -> dict:
    """Cost figures of a run from its step reports; memory too when ``sim`` is given.

    Pass ``sim`` only once its results have been read: measuring the memory takes one more step.
    """
    timed = list(stats[1:]) if len(stats) > 1 else list(stats)
    step_ms = np.array([s.step_ms for s in timed])
    iters = np.array([s.pressure.iterations for s in timed])
    out: dict[str, Any] = {
        "median_step_ms": float(np.median(step_ms)),
        "steps": len(stats),
        "pressure_iterations_mean": float(iters.mean()),
        "unconverged_solves": int(
            sum(
                (not s.pressure.converged) + sum(not r.converged for r in s.viscosity)
                for s in stats
            )
        ),
        "viscosity_solves_per_step": float(np.mean([len(s.viscosity) for s in timed])),
    }
    substeps = timed[0].substep_ms.keys() if timed else ()
    out["substep_median_ms"] = {
        k: float(np.median([s.substep_ms[k] for s in timed])) for k in substeps
    }
    if sim is not None:
        out["state_mib"] = state_bytes(sim) / MIB
        out["peak_step_mib"] = traced_step_peak(sim, dt_s) / MIB
    return out
