"""The solver's benchmark families: the Ghia cavity, Schaefer-Turek 2D-1, the Taylor-Green
vortex, the paper's square-probe sweep and the simulation rate against the servo rate, each with
the settings it adds to ``--quick`` and to the full sweep."""

from __future__ import annotations

from typing import Any

from paintapp.bench import references, sweep_force
from paintapp.bench.rates import filter_rate
from paintapp.bench.registry import Family

_SOLVER: dict[str, Any] = {
    "advection": "linear",
    "pressure_tolerance": 1e-6,
    "max_iterations": 1000,
    "preconditioner": "multigrid",
}
#: The other pressure preconditioner, as a setting (cost and accuracy rows for both).
_MIC0 = {"preconditioner": "mic0"}
_QUICK_SWEEP = {"reference_cells": 64}


def _cavity() -> Family:
    quick: list[dict[str, Any]]
    quick = [{"cells": c, "advection": a} for c in (16, 32) for a in ("linear", "maccormack")]
    quick += [{"pressure_tolerance": 1e-2, "max_iterations": 5}, _MIC0]
    full: list[dict[str, Any]]
    full = [{"cells": c, "advection": a} for c in (16, 32, 64) for a in ("linear", "maccormack")]
    full += [
        {"pressure_tolerance": t, "max_iterations": m} for t in (1e-2, 1e-4) for m in (5, 1000)
    ]
    full += [{"cells": c, **_MIC0} for c in (32, 64)]
    return Family(
        "cavity",
        references.cavity,
        ("ghia_max_error",),
        {"cells": 32, **_SOLVER, "advection": "maccormack"},
        reference="Ghia et al. (1982), Re = 100, max |u - u_ref| on both centrelines (m/s, lid 1 m/s)",
        quick=tuple(quick),
        full=tuple(full),
    )


def _taylor_green() -> Family:
    quick = [{"cells": c} for c in (16, 32)] + [{"advection": "linear"}]
    full: list[dict[str, Any]]
    full = [{"cells": c, "advection": a} for c in (16, 32, 64) for a in ("linear", "maccormack")]
    full += [{"pressure_tolerance": t} for t in (1e-2, 1e-4)]
    return Family(
        "taylor_green",
        references.taylor_green,
        ("decay_rate_rel_error",),
        {"cells": 32, **_SOLVER, "advection": "maccormack"},
        reference="Taylor-Green vortex, |rate / (4 nu k^2) - 1|",
        quick=tuple(quick),
        full=tuple(full),
    )


def _schaefer_turek() -> Family:
    quick = [{"force_model": m} for m in ("stress", "control_volume")]
    full: list[dict[str, Any]]
    full = [{"force_model": m} for m in ("stress", "control_volume", "drag", "viscous_drag")]
    full += [{"advection": "linear"}]
    full += [{"dh": 20, "force_model": m} for m in ("stress", "control_volume")]
    full += [
        {"boundary_method": "cutcell", "force_model": "stress"},
        {"dh": 20, "boundary_method": "cutcell", "force_model": "stress"},
    ]
    return Family(
        "schaefer_turek",
        references.schaefer_turek,
        ("cd_rel_error",),
        {"dh": 10, **_SOLVER, "advection": "maccormack", "force_model": "control_volume"},
        reference="Schaefer & Turek (1996) 2D-1, |c_D / 5.5795 - 1|",
        quick=tuple(quick),
        full=tuple(full),
    )


def _sweep() -> Family:
    quick: list[dict[str, Any]] = [{"cells": c, **_QUICK_SWEEP} for c in (32, 64)]
    quick += [
        {"cells": 32, "force_model": m, **_QUICK_SWEEP}
        for m in ("control_volume", "drag", "viscous_drag")
    ]
    quick += [{"cells": 32, "pressure_tolerance": 1e-3, **_QUICK_SWEEP}]
    quick += [{"cells": 64, **_MIC0, **_QUICK_SWEEP}]
    quick += [{"cells": 16, "dim": 3}]
    full: list[dict[str, Any]] = [
        {"cells": c, "force_model": m} for c in (32, 64, 128) for m in ("stress", "control_volume")
    ]
    full += [{"force_model": m} for m in ("drag", "viscous_drag")]
    full += [{"advection": "maccormack"}]
    full += [{"pressure_tolerance": t} for t in (1e-3, 1e-7)]
    full += [{"max_iterations": 10}]
    full += [{"cells": c, **_MIC0} for c in (64, 128)]
    full += [{"cells": c, "boundary_method": "cutcell"} for c in (32, 64)]
    full += [{"cells": c, "dim": 3} for c in (16, 32)]
    return Family(
        "sweep",
        sweep_force.sweep_force,
        ("force_noise", "force_error"),
        {
            "cells": 64,
            "dim": 2,
            **_SOLVER,
            "pressure_tolerance": 1e-5,
            "force_model": "stress",
            "reference_cells": 128,
        },
        reference="paper square sweep: relative noise; error against a fine smoothed stress force",
        quick=tuple(quick),
        full=tuple(full),
        cleanup=sweep_force.clear_cache,
    )


def _rates() -> Family:
    quick = [
        {"cells": 32, "sim_rate_hz": r, "filter": f}
        for r in (30.0, 120.0)
        for f in ("zoh", "linear", "fir")
    ]
    full = [
        {"sim_rate_hz": r, "filter": f}
        for r in (30.0, 60.0, 120.0, 250.0)
        for f in ("zoh", "linear", "fir")
    ]
    return Family(
        "rates",
        filter_rate,
        ("reconstruction_error", "tick_jump"),
        {"cells": 64, "sim_rate_hz": 60.0, "filter": "fir", "servo_rate_hz": 1000.0},
        cost_key="compute_ms_per_s",
        reference="the sweep simulated at the servo rate, smoothed, read at each servo tick",
        quick=tuple(quick),
        full=tuple(full),
        cleanup=sweep_force.clear_cache,
    )


def solver_families() -> list[Family]:
    """The solver's families, in the order the table lists them."""
    return [_cavity(), _taylor_green(), _schaefer_turek(), _sweep(), _rates()]
