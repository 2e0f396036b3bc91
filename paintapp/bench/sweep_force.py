"""Force quality on the paper's square-probe sweep: noise, and error against a fine reference.

For a setting (grid, 2D or 3D, force model, advection, pressure tolerance, iteration cap) the
sweep is run once and measured:

* ``force_noise`` and ``torque_noise`` (:mod:`paintapp.bench.noise`: the RMS of the signal minus
  its Savitzky-Golay smoothing over 0.1 s, relative to the RMS of the smoothing);
* ``force_error`` (2D only): ``RMS |F - F_ref| / RMS |F_ref|`` over the moving part, where
  ``F_ref`` is the *smoothed* stress-integral force of a fine 2D run (``reference_cells``) on the
  same time steps. It counts both the noise and any bias, so the cheap drag formulas, which have
  no noise at all, still show what they miss.

Traces are cached per setting, so a reference that is also a setting runs once.
"""

from __future__ import annotations

from typing import Any

from paintapp.bench.measure import SOLVER_KEYS, Measurement, step_cost
from paintapp.bench.noise import relative_deviation, smooth
from paintapp.bench.square_sweep import (
    MOTION_END_S,
    SweepTrace,
    run_sweep,
    sweep_scene,
    sweep_summary,
)

_CACHE: dict[tuple, tuple[SweepTrace, dict[str, Any]]] = {}


def traced_sweep(
    cells: int, dim: int = 2, dt_s: float | None = None, **solver: Any
) -> tuple[SweepTrace, dict[str, Any]]:
    """The sweep's trace and its cost (cached on the arguments)."""
    key = (cells, dim, dt_s, tuple(sorted(solver.items())))
    if key not in _CACHE:
        scene = sweep_scene(cells, dim=dim, dt_s=dt_s, solver=solver)
        sim = scene.build()
        trace = run_sweep(scene, sim=sim)
        _CACHE[key] = (trace, step_cost(trace.stats, sim, scene.run.dt_s))
    return _CACHE[key]


def clear_cache() -> None:
    """Forget cached sweeps (frees their memory)."""
    _CACHE.clear()


def sweep_force(
    cells: int = 64, dim: int = 2, reference_cells: int | None = 128, **knobs: Any
) -> Measurement:
    """Measure one sweep setting; ``knobs`` are scene ``[solver]`` keys (and ``dt_s``)."""
    dt = knobs.pop("dt_s", None)
    solver = {k: knobs.pop(k) for k in SOLVER_KEYS if k in knobs}
    if knobs:
        raise ValueError(f"unknown sweep knobs {sorted(knobs)}")
    trace, cost = traced_sweep(cells, dim, dt, **solver)
    summary = sweep_summary(trace)
    errors: dict[str, float | None] = {
        "force_noise": summary["force_noise"],
        "torque_noise": summary["torque_noise"],
        "force_error": None,
    }
    ref_note = ""
    if dim == 2 and reference_cells:
        ref, _ = traced_sweep(reference_cells, 2, dt, force_model="stress")
        on = trace.time_s <= MOTION_END_S + 1e-9
        target = smooth(ref.force, ref.dt_s)[on]
        errors["force_error"] = relative_deviation(trace.force[on], target)
        ref_note = f"; force_error against the smoothed stress force at {reference_cells}^2"
    shape = "x".join(str(c) for c in trace.cells)
    return Measurement(
        errors=errors,
        cost=cost,
        notes=f"paper sweep {dim}D {shape}, dt = {trace.dt_s:g} s, t = 2.2 s{ref_note}",
        extra={k: v for k, v in summary.items() if k not in errors},
    )
