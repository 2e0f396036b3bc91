"""One frame as a reader found it, before the units and the fluid's properties are settled; the
times of a series of them."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from common.errors import InputError


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


def series_times(stated: list[float | None], frame_dt_s: float | None, source: str) -> np.ndarray:
    """The times (s) of a series of ``len(stated)`` frames: those the files state, else
    ``frame_dt_s`` apart from 0; :class:`InputError` when neither is there or the times are not
    finite and strictly increasing."""
    if all(t is not None for t in stated):
        times = np.array(stated, dtype=float)
    elif frame_dt_s is not None:
        times = frame_dt_s * np.arange(len(stated))
    else:
        raise InputError(
            "the files state no TimeValue; give --frame-dt SECONDS", source, "TimeValue"
        )
    if not (np.all(np.isfinite(times)) and np.all(np.diff(times) > 0)):
        raise InputError("expected finite, strictly increasing frame times", source, "times")
    return times
