"""What a benchmark is: families of settings, and a registry that runs them.

A *family* is one accuracy reference with a function that runs a setting of the knobs and returns
a :class:`~paintapp.bench.measure.Measurement`; it lists the knob changes it adds to ``--quick``
and to the full sweep. A :class:`Registry` holds the families a run knows about: ``paintapp
bench`` composes it from the solver families (:mod:`paintapp.bench.solver_families`) and the
painting families (:mod:`paintapp.bench.painting_families`), so neither depends on the other.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any

from paintapp.bench.measure import Measurement

Record = dict[str, Any]


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
            full sweep.
        cleanup: called once after a run of settings (drops cached reference runs).
    """

    name: str
    run: Callable[..., Measurement]
    errors: tuple[str, ...]
    defaults: dict[str, Any]
    cost_key: str = "median_step_ms"
    reference: str = ""
    quick: tuple[dict[str, Any], ...] = ()
    full: tuple[dict[str, Any], ...] = ()
    cleanup: Callable[[], None] | None = None


@dataclass(frozen=True)
class Setting:
    """A family and the knobs that differ from its defaults."""

    family: str
    changes: dict[str, Any] = field(default_factory=dict)

    @property
    def label(self) -> str:
        parts = [
            f"{_short(k)}={v:g}" if isinstance(v, float) else f"{_short(k)}={v}"
            for k, v in self.changes.items()
            if k not in HIDDEN
        ]
        return f"{self.family} " + " ".join(parts) if parts else self.family


HIDDEN = ("reference_cells",)  # knobs left out of labels (still in the JSON)


def _short(key: str) -> str:
    return {
        "pressure_tolerance": "tol",
        "max_iterations": "cap",
        "force_model": "force",
        "sim_rate_hz": "rate",
        "advection": "adv",
    }.get(key, key)


class Registry:
    """The benchmark families of one run, in the order they were given."""

    def __init__(self, families: Iterable[Family]) -> None:
        self.families: dict[str, Family] = {}
        for family in families:
            if family.name in self.families:
                raise ValueError(f"two benchmark families named {family.name!r}")
            self.families[family.name] = family

    def knobs(self, setting: Setting) -> dict[str, Any]:
        """Every knob of ``setting`` (its family's defaults, then the changes)."""
        return {**self.families[setting.family].defaults, **setting.changes}

    def quick_settings(self) -> list[Setting]:
        """A small subset that runs in about a minute once the kernels are compiled."""
        return [Setting(f.name, c) for f in self.families.values() for c in f.quick]

    def full_settings(self) -> list[Setting]:
        """Every knob in turn (several minutes on two cores)."""
        return [Setting(f.name, c) for f in self.families.values() for c in f.full]

    def run_setting(self, setting: Setting) -> Record:
        """Run one setting; the JSON-ready record (a failure is recorded, not raised)."""
        family = self.families[setting.family]
        knobs = self.knobs(setting)
        record: Record = {"name": setting.label, "family": family.name, "knobs": knobs}
        try:
            m = family.run(**knobs)
        except (ValueError, RuntimeError, FloatingPointError) as exc:
            record.update(errors={}, cost={}, failed=f"{type(exc).__name__}: {exc}")
            return record
        record.update(cost=m.cost, errors=m.errors, reference=family.reference, notes=m.notes)
        if m.extra:
            record["measured"] = m.extra
        return record

    def cleanup(self) -> None:
        """Drop every family's cached reference runs."""
        for family in self.families.values():
            if family.cleanup is not None:
                family.cleanup()
