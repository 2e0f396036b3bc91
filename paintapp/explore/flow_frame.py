"""One frame as a reader found it, before the units and the fluid's properties are settled."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class Frame:
    """One frame read from a file: the fields and what the file says about them."""

    source: str
    origin: np.ndarray
    spacing: np.ndarray
    pressure: np.ndarray
    velocity: np.ndarray
    fluid: np.ndarray | None
    time_s: float | None
    density: float | None
    viscosity: float | None
    pressure_units: str | None
