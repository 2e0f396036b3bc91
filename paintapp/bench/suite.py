"""The benchmark families and the settings ``paintapp bench`` sweeps.

A *family* is one accuracy reference with a function that runs a setting of the knobs and returns
a :class:`~paintapp.bench.measure.Measurement`. Other parts of the application add their own
families (for example painting replays at each fidelity) with :func:`register_family`; the table,
the JSON and the Pareto plot pick them up.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any

from paintapp.bench import references, sweep_force
from paintapp.bench.measure import Measurement
from paintapp.bench.rates import filter_rate


@dataclass(frozen=True)
class Family:
    """One kind of benchmark.

    Attributes:
        name: identifier (``cavity``, ``sweep``, ...).
        run: ``run(**knobs) -> Measurement``.
        errors: the error figures to plot, most important first (dimensionless or as named).
        defaults: knobs every setting of the family starts from.
        cost_key: the cost figure to plot against (a key of ``Measurement.cost``).
        reference: one line saying what the errors are measured against.
        quick, full: knob changes of the settings this family adds to ``--quick`` and to the
            full sweep (the built-in families list theirs in :func:`quick_settings` and
            :func:`full_settings` instead).
    """

    name: str
    run: Callable[..., Measurement]
    errors: tuple[str, ...]
    defaults: dict[str, Any]
    cost_key: str = "median_step_ms"
    reference: str = ""
    quick: tuple[dict[str, Any], ...] = ()
    full: tuple[dict[str, Any], ...] = ()


@dataclass(frozen=True)
class Setting:
    """A family and the knobs that differ from its defaults."""

    family: str
    changes: dict[str, Any] = field(default_factory=dict)

    def knobs(self) -> dict[str, Any]:
        """Every knob of this setting (the family's defaults, then the changes)."""
        return {**FAMILIES[self.family].defaults, **self.changes}

    @property
    def label(self) -> str:
        parts = [f"{_short(k)}={v:g}" if isinstance(v, float) else f"{_short(k)}={v}"
                 for k, v in self.changes.items() if k not in HIDDEN]  # fmt: skip
        return f"{self.family} " + " ".join(parts) if parts else self.family


HIDDEN = ("reference_cells",)  # knobs left out of labels (still in the JSON)


def _short(key: str) -> str:
    return {"pressure_tolerance": "tol", "max_iterations": "cap", "force_model": "force",
            "sim_rate_hz": "rate", "advection": "adv"}.get(key, key)  # fmt: skip


FAMILIES: dict[str, Family] = {}


def register_family(family: Family) -> None:
    """Add (or replace) a benchmark family."""
    FAMILIES[family.name] = family


_SOLVER = {"advection": "linear", "pressure_tolerance": 1e-6, "max_iterations": 1000}
register_family(Family(
    "cavity", references.cavity, ("ghia_max_error",),
    {"cells": 32, **_SOLVER, "advection": "maccormack"},
    reference="Ghia et al. (1982), Re = 100, max |u - u_ref| on both centrelines (m/s, lid 1 m/s)",
))  # fmt: skip
register_family(Family(
    "schaefer_turek", references.schaefer_turek, ("cd_rel_error",),
    {"dh": 10, **_SOLVER, "advection": "maccormack", "force_model": "control_volume"},
    reference="Schaefer & Turek (1996) 2D-1, |c_D / 5.5795 - 1|",
))  # fmt: skip
register_family(Family(
    "taylor_green", references.taylor_green, ("decay_rate_rel_error",),
    {"cells": 32, **_SOLVER, "advection": "maccormack"},
    reference="Taylor-Green vortex, |rate / (4 nu k^2) - 1|",
))  # fmt: skip
register_family(Family(
    "sweep", sweep_force.sweep_force, ("force_noise", "force_error"),
    {"cells": 64, "dim": 2, **_SOLVER, "pressure_tolerance": 1e-5, "force_model": "stress",
     "reference_cells": 128},
    reference="paper square sweep: relative noise; error against a fine smoothed stress force",
))  # fmt: skip
register_family(Family(
    "rates", filter_rate, ("reconstruction_error", "tick_jump"),
    {"cells": 64, "sim_rate_hz": 60.0, "filter": "fir", "servo_rate_hz": 1000.0},
    cost_key="compute_ms_per_s",
    reference="the sweep simulated at the servo rate, smoothed, read at each servo tick",
))  # fmt: skip


def quick_settings() -> list[Setting]:
    """A small subset that runs in well under a minute once the kernels are compiled."""
    s = [Setting("cavity", {"cells": c, "advection": a})
         for c in (16, 32) for a in ("linear", "maccormack")]  # fmt: skip
    s += [Setting("cavity", {"pressure_tolerance": 1e-2, "max_iterations": 5})]
    s += [Setting("taylor_green", {"cells": c}) for c in (16, 32)]
    s += [Setting("taylor_green", {"advection": "linear"})]
    s += [Setting("schaefer_turek", {"force_model": m}) for m in ("stress", "control_volume")]
    quick_sweep = {"reference_cells": 64}
    s += [Setting("sweep", {"cells": c, **quick_sweep}) for c in (32, 64)]
    s += [Setting("sweep", {"cells": 32, "force_model": m, **quick_sweep})
          for m in ("control_volume", "drag", "viscous_drag")]  # fmt: skip
    s += [Setting("sweep", {"cells": 32, "pressure_tolerance": 1e-3, **quick_sweep})]
    s += [Setting("sweep", {"cells": 16, "dim": 3})]
    s += [Setting("rates", {"cells": 32, "sim_rate_hz": r, "filter": f})
          for r in (30.0, 120.0) for f in ("zoh", "linear", "fir")]  # fmt: skip
    return s + [Setting(f.name, c) for f in FAMILIES.values() for c in f.quick]


def full_settings() -> list[Setting]:
    """Every knob in turn (several minutes on two cores)."""
    s = [Setting("cavity", {"cells": c, "advection": a})
         for c in (16, 32, 64) for a in ("linear", "maccormack")]  # fmt: skip
    s += [Setting("cavity", {"pressure_tolerance": t, "max_iterations": m})
          for t in (1e-2, 1e-4) for m in (5, 1000)]  # fmt: skip
    s += [Setting("taylor_green", {"cells": c, "advection": a})
          for c in (16, 32, 64) for a in ("linear", "maccormack")]  # fmt: skip
    s += [Setting("taylor_green", {"pressure_tolerance": t}) for t in (1e-2, 1e-4)]
    s += [Setting("schaefer_turek", {"force_model": m})
          for m in ("stress", "control_volume", "drag", "viscous_drag")]  # fmt: skip
    s += [Setting("schaefer_turek", {"advection": "linear"})]
    s += [Setting("schaefer_turek", {"dh": 20, "force_model": m})
          for m in ("stress", "control_volume")]  # fmt: skip
    s += [Setting("sweep", {"cells": c, "force_model": m})
          for c in (32, 64, 128) for m in ("stress", "control_volume")]  # fmt: skip
    s += [Setting("sweep", {"force_model": m}) for m in ("drag", "viscous_drag")]
    s += [Setting("sweep", {"advection": "maccormack"})]
    s += [Setting("sweep", {"pressure_tolerance": t}) for t in (1e-3, 1e-7)]
    s += [Setting("sweep", {"max_iterations": 10})]
    s += [Setting("sweep", {"cells": c, "dim": 3}) for c in (16, 32)]
    s += [Setting("rates", {"sim_rate_hz": r, "filter": f})
          for r in (30.0, 60.0, 120.0, 250.0) for f in ("zoh", "linear", "fir")]  # fmt: skip
    return s + [Setting(f.name, c) for f in FAMILIES.values() for c in f.full]


def run_setting(setting: Setting) -> dict[str, Any]:
    """Run one setting; the JSON-ready record (a failure is recorded, not raised)."""
    family = FAMILIES[setting.family]
    knobs = setting.knobs()
    record: dict[str, Any] = {"name": setting.label, "family": family.name, "knobs": knobs}
    try:
        m = family.run(**knobs)
    except (ValueError, RuntimeError, FloatingPointError) as exc:
        record.update(errors={}, cost={}, failed=f"{type(exc).__name__}: {exc}")
        return record
    record.update(cost=m.cost, errors=m.errors, reference=family.reference, notes=m.notes)
    if m.extra:
        record["measured"] = m.extra
    return record


def run_settings(
    settings: Iterable[Setting], progress: Callable[[Setting], None] | None = None
) -> list[dict[str, Any]]:
    """Run settings in order; ``progress(setting)`` is called before each."""
    records = []
    for setting in settings:
        if progress:
            progress(setting)
        records.append(run_setting(setting))
    sweep_force.clear_cache()
    return records


# The painting families register themselves (they replay strokes through the painting session).
from paintapp.bench import painting as _painting  # noqa: E402, F401
