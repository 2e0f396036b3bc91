"""Simulation rate against servo rate, for each reconstruction filter.

The sweep is simulated with ``dt = 1 / sim_rate_hz`` (a slower simulation takes larger steps), and
each force sample is handed to a reconstruction filter of :mod:`paintapp.haptics.filters` at the
time its step ends, as if the simulation kept pace with the wall clock. The filter is read once
per servo tick (``servo_rate_hz``). The result is compared with a reference: the same sweep
simulated at the servo rate itself (``dt = 1 / servo_rate_hz``), smoothed as in
:mod:`paintapp.bench.noise` and read at the ticks. Figures (moving part, t <= 2 s):

* ``reconstruction_error``: ``RMS |F_out - F_ref| / RMS |F_ref|`` (xy force); it counts the time
  step's own error, the filter's delay and what is left of the staircase noise;
* ``output_noise``: the relative noise of the filtered force at the servo rate (how rough it
  feels);
* ``tick_jump``: RMS of the change of the output force from one tick to the next, relative to the
  RMS output force: the stair-stepping the filter is there to remove (the paper's Fig. 3);
* cost ``compute_ms_per_s``: solver milliseconds per second of simulated time
  (``median_step_ms * sim_rate_hz``; above 1000 the simulation cannot keep pace on one core),
  and ``filter_us_per_tick``.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from paintapp.bench.measure import Measurement
from paintapp.bench.noise import relative_deviation, relative_noise, rms_norm, smooth
from paintapp.bench.square_sweep import MOTION_END_S, SweepTrace
from paintapp.bench.sweep_force import traced_sweep
from paintapp.haptics.filters import make_filter


def reconstruct(
    trace: SweepTrace, kind: str, tick_s: float, **filter_args: Any
) -> tuple[np.ndarray, np.ndarray, float]:
    """Feed the trace's samples (force x, y and torque) through a filter read every ``tick_s``.

    Returns the tick times (n,), the outputs (n, 3) and the mean seconds per tick spent in the
    filter.
    """
    flt = make_filter(kind, tick_s, 3, **filter_args)
    values = np.column_stack([trace.force, trace.torque])
    ticks = np.arange(0.0, trace.time_s[-1] + 0.5 * tick_s, tick_s)
    out = np.zeros((len(ticks), 3))
    nxt = 0
    t0 = time.perf_counter()
    for i, t in enumerate(ticks):
        while nxt < len(trace.time_s) and trace.time_s[nxt] <= t + 1e-12:
            flt.push(float(trace.time_s[nxt]), values[nxt])
            nxt += 1
        out[i] = flt.output(float(t))
    per_tick = (time.perf_counter() - t0) / len(ticks)
    return ticks, out, per_tick


def reference_at_ticks(cells: int, servo_rate_hz: float, ticks: np.ndarray) -> np.ndarray:
    """The smoothed xy force of the sweep simulated at the servo rate, at ``ticks``, (n, 2)."""
    ref, _ = traced_sweep(cells, 2, 1.0 / servo_rate_hz)
    smoothed = smooth(ref.force, ref.dt_s)
    times = np.concatenate([[0.0], ref.time_s])
    values = np.vstack([np.zeros((1, 2)), smoothed])
    return np.column_stack([np.interp(ticks, times, values[:, a]) for a in range(2)])


def filter_rate(
    cells: int = 32,
    sim_rate_hz: float = 60.0,
    filter: str = "fir",
    servo_rate_hz: float = 1000.0,
    **filter_args: Any,
) -> Measurement:
    """Measure one (simulation rate, filter) setting on the sweep at ``cells`` per side."""
    trace, cost = traced_sweep(cells, 2, 1.0 / sim_rate_hz)
    tick = 1.0 / servo_rate_hz
    ticks, out, per_tick = reconstruct(trace, filter, tick, **filter_args)
    ref = reference_at_ticks(cells, servo_rate_hz, ticks)
    on = ticks <= MOTION_END_S
    delay = make_filter(filter, tick, 3, **filter_args).delay_s(1.0 / sim_rate_hz)
    cost = dict(cost)
    cost["compute_ms_per_s"] = cost["median_step_ms"] * sim_rate_hz
    cost["filter_us_per_tick"] = per_tick * 1e6
    return Measurement(
        errors={
            "reconstruction_error": relative_deviation(out[on, :2], ref[on]),
            "output_noise": relative_noise(out[on, :2], tick),
            "tick_jump": rms_norm(np.diff(out[on, :2], axis=0))
            / max(rms_norm(out[on, :2]), 1e-300),
        },
        cost=cost,
        notes=f"paper sweep 2D {cells}x{cells} at {sim_rate_hz:g} Hz, {filter} filter read at "
        f"{servo_rate_hz:g} Hz; reference: the sweep at dt = 1/{servo_rate_hz:g} s, smoothed",
        extra={"nominal_delay_ms": 1e3 * delay},
    )
