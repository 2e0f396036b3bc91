"""What the command line states about the fluid where a file does not, and how a stated value
is settled: density kg/m^3, dynamic viscosity Pa s, frame interval s, pressure units."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from common.errors import InputError

PRESSURE_UNITS = ("Pa", "m2/s2")


@dataclass(frozen=True)
class FluidOverrides:
    """Values the command line gives for what a file does not state (None: the file's)."""

    density_kg_m3: float | None = None
    viscosity_pa_s: float | None = None
    frame_dt_s: float | None = None
    pressure_units: str | None = None


def given(override: float | None, stated: float | None, source: str, key: str, unit: str) -> float:
    value = override if override is not None else stated
    if value is None:
        raise InputError(
            f"the file does not state the fluid's {key} ({unit}); add it to the file or give "
            f"--{key}",
            source,
            key,
        )
    if not (np.isfinite(value) and value > 0):
        raise InputError(f"expected a finite {key} > 0 ({unit}), got {value!r}", source, key)
    return float(value)
