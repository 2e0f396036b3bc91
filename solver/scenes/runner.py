"""Running a scene to the end and collecting its results as plain JSON-ready data."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from solver.scenes.scene import Scene
from solver.simulation import Simulation, StepStats


class NonFiniteError(RuntimeError):
    """The simulation produced NaN or Inf (a bug or an impossible setting); the run stops."""


def run_scene(scene: Scene, progress: Callable[[int], None] | None = None) -> dict[str, Any]:
    """Run ``scene`` for its number of steps; returns the results dictionary.

    ``progress`` is called with the number of steps just completed (1 each call).
    """
    sim = scene.build()
    times: list[float] = []
    forces: dict[str, dict[str, list]] = {
        p.name: {"force": [], "torque": [], "pressure_force": [], "viscous_force": []}
        for p in sim.probes
    }
    stats: list[StepStats] = []
    for n in range(scene.run.steps):
        st = sim.step(scene.run.dt_s)
        _check_solves(st)
        stats.append(st)
        times.append(sim.time_s)
        for name, f in sim.forces.items():
            if not (np.all(np.isfinite(f.force)) and np.all(np.isfinite(f.torque))):
                raise NonFiniteError(f"non-finite force on probe {name!r} at t = {sim.time_s:g} s")
            rec = forces[name]
            rec["force"].append(f.force.tolist())
            rec["torque"].append(
                f.torque.tolist() if isinstance(f.torque, np.ndarray) else f.torque
            )
            rec["pressure_force"].append(f.pressure_force.tolist())
            rec["viscous_force"].append(f.viscous_force.tolist())
        if n % 50 == 49 or n == scene.run.steps - 1:
            _check_finite(sim)
        if progress:
            progress(1)
    return {
        "scene": scene.name,
        "dim": scene.grid.dim,
        "cells": list(scene.grid.cells[: scene.grid.dim]),
        "cell_size_m": scene.grid.cell_size_m,
        "dt_s": scene.run.dt_s,
        "steps": scene.run.steps,
        "time": times,
        "probes": forces,
        "lines": _lines(sim, scene),
        "points": _points(sim, scene),
        "timing": timing_summary(stats),
        "diagnostics": {
            "max_abs_divergence_per_s": float(np.abs(sim.divergence()).max()),
            "kinetic_energy_j": sim.kinetic_energy(),
        },
    }


def _check_solves(stats: StepStats) -> None:
    """A non-finite residual means the solve broke down (values beyond floating point's range)."""
    reports = [("pressure", stats.pressure)] + [("viscosity", r) for r in stats.viscosity]
    for name, report in reports:
        if not np.isfinite(report.residual):
            raise NonFiniteError(
                f"the {name} solve broke down (non-finite residual) at t = {stats.time_s:g} s; "
                "are the velocities or the time step beyond a sensible range?"
            )


def _check_finite(sim: Simulation) -> None:
    st = sim.state
    for a in range(sim.grid.dim):
        if not np.all(np.isfinite(st.comps[a])):
            raise NonFiniteError(f"non-finite velocity at t = {sim.time_s:g} s")
    if not np.all(np.isfinite(st.pressure)):
        raise NonFiniteError(f"non-finite pressure at t = {sim.time_s:g} s")
    if not np.isfinite(sim.kinetic_energy()):
        raise NonFiniteError(f"the kinetic energy overflows at t = {sim.time_s:g} s")


def _lines(sim: Simulation, scene: Scene) -> dict[str, Any]:
    out = {}
    for line in scene.lines:
        f = np.linspace(0.0, 1.0, line.points)[:, None]
        pts = (1 - f) * np.asarray(line.start_m) + f * np.asarray(line.end_m)
        velocity = sim.velocity_at(pts)
        out[line.name] = {"points": pts.tolist(), "velocity": _finite_or_none(velocity)}
        if not np.all(np.isfinite(velocity)):
            out[line.name]["note"] = NO_FLUID_NOTE
    return out


#: Why a sampled value is null in the results: no fluid cell to sample (inside a probe).
NO_FLUID_NOTE = "null: no fluid cell is near the point, it lies inside a probe"


def _finite_or_none(values: Any) -> Any:
    """``values`` as nested lists of floats, each non-finite entry None (JSON null)."""
    if np.ndim(values) == 0:
        value = float(values)
        return value if np.isfinite(value) else None
    return [_finite_or_none(v) for v in values]


def _points(sim: Simulation, scene: Scene) -> dict[str, Any]:
    """Pressure and velocity at each output point; a value with no fluid cell near the point
    (inside a probe) is None, with a ``note`` saying why, so the results stay valid JSON."""
    out = {}
    for point in scene.points:
        pts = np.asarray([point.at_m])
        pressure, velocity = sim.pressure_at(pts)[0], sim.velocity_at(pts)[0]
        out[point.name] = {
            "at": list(point.at_m),
            "pressure": _finite_or_none(pressure),
            "velocity": _finite_or_none(velocity),
        }
        if not (np.isfinite(pressure) and np.all(np.isfinite(velocity))):
            out[point.name]["note"] = NO_FLUID_NOTE
    return out


def timing_summary(stats: list[StepStats]) -> dict[str, Any]:
    """Median step time (ms), per-substep medians, and PCG iteration/residual figures."""
    if not stats:
        return {}
    step_ms = np.array([s.step_ms for s in stats])
    keys = stats[0].substep_ms.keys()
    p_it = np.array([s.pressure.iterations for s in stats])
    v_it = np.array([sum(r.iterations for r in s.viscosity) for s in stats])
    return {
        "median_step_ms": float(np.median(step_ms)),
        "mean_step_ms": float(step_ms.mean()),
        "first_step_ms": float(step_ms[0]),
        "substep_median_ms": {k: float(np.median([s.substep_ms[k] for s in stats])) for k in keys},
        "pressure_iterations": {"mean": float(p_it.mean()), "max": int(p_it.max())},
        "pressure_max_residual": float(max(s.pressure.residual for s in stats)),
        "viscosity_iterations": {"mean": float(v_it.mean()), "max": int(v_it.max())},
        "unconverged_solves": int(
            sum(
                (not s.pressure.converged) + sum(not r.converged for r in s.viscosity)
                for s in stats
            )
        ),
    }
