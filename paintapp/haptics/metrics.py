"""How well a periodic loop keeps its schedule: rate, lateness percentiles, missed deadlines.

A clock records, for every tick it runs, how late the tick started relative to its scheduled time
and how long the tick's work took. A tick that starts one period or more late has let at least one
scheduled slot pass; those slots are counted as missed deadlines (the clock skips them rather than
running a burst of catch-up ticks).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

_CHUNK = 4096


def interval_stats(intervals: np.ndarray, period_s: float) -> tuple[float, float]:
    """(rate Hz, jitter p99 ms) of a loop from the intervals between its ticks' starts (at
    least two): the rate from their mean, the jitter the 99th percentile of
    ``|interval - period|`` (numpy's linear interpolation, from a partial sort: the HUD asks ten
    times a second, holding the interpreter lock)."""
    n = len(intervals)
    mean = float(np.mean(intervals))
    deviation = np.abs(intervals - period_s)
    pos = 0.99 * (n - 1)
    lo = int(pos)
    hi = min(lo + 1, n - 1)
    part = np.partition(deviation, (lo, hi))
    jitter = float(part[lo] + (pos - lo) * (part[hi] - part[lo]))
    return (1.0 / mean if mean > 0 else 0.0), 1e3 * jitter


@dataclass(frozen=True)
class TimingReport:
    """Timing figures of one run of a periodic loop. Times in seconds unless named otherwise.

    Attributes:
        period_s: the scheduled period.
        ticks: ticks executed.
        duration_s: time from the first scheduled tick to the end of the last tick.
        achieved_rate_hz: ``ticks / duration_s``.
        lateness_p50_s, lateness_p99_s, lateness_p999_s, lateness_max_s: start lateness
            percentiles (0.5, 0.99, 0.999) and maximum.
        missed_deadlines: scheduled slots skipped because a tick started a period or more late.
        tick_cost_p50_s, tick_cost_p99_s: time spent inside the tick function.
    """

    period_s: float
    ticks: int
    duration_s: float
    achieved_rate_hz: float
    lateness_p50_s: float
    lateness_p99_s: float
    lateness_p999_s: float
    lateness_max_s: float
    missed_deadlines: int
    tick_cost_p50_s: float
    tick_cost_p99_s: float

    def rows(self) -> list[tuple[str, str]]:
        """Human-readable (label, value) rows, times in milliseconds or microseconds."""
        return [
            ("ticks", f"{self.ticks}"),
            ("achieved rate (Hz)", f"{self.achieved_rate_hz:.1f}"),
            ("lateness p50 (ms)", f"{self.lateness_p50_s * 1e3:.3f}"),
            ("lateness p99 (ms)", f"{self.lateness_p99_s * 1e3:.3f}"),
            ("lateness p99.9 (ms)", f"{self.lateness_p999_s * 1e3:.3f}"),
            ("lateness max (ms)", f"{self.lateness_max_s * 1e3:.3f}"),
            ("missed deadlines", f"{self.missed_deadlines}"),
            ("tick cost p50 (us)", f"{self.tick_cost_p50_s * 1e6:.1f}"),
            ("tick cost p99 (us)", f"{self.tick_cost_p99_s * 1e6:.1f}"),
        ]


class TimingRecorder:
    """Collects per-tick lateness and cost without allocating on every tick.

    Args:
        period_s: the scheduled period in seconds.
    """

    def __init__(self, period_s: float) -> None:
        self.period_s = float(period_s)
        self._chunks: list[np.ndarray] = []
        self._row = _CHUNK
        self.missed_deadlines = 0
        self.duration_s = 0.0

    def record(self, lateness_s: float, cost_s: float) -> None:
        """Record one tick: how late it started and how long its work took, in seconds."""
        if self._row == _CHUNK:
            self._chunks.append(np.empty((_CHUNK, 2)))
            self._row = 0
        chunk = self._chunks[-1]
        chunk[self._row, 0] = lateness_s
        chunk[self._row, 1] = cost_s
        self._row += 1

    def skip(self, slots: int) -> None:
        """Count ``slots`` scheduled ticks that were skipped because the loop ran late."""
        self.missed_deadlines += int(slots)

    @property
    def ticks(self) -> int:
        """Ticks recorded so far."""
        return 0 if not self._chunks else (len(self._chunks) - 1) * _CHUNK + self._row

    def samples(self) -> np.ndarray:
        """All records, shape (ticks, 2): lateness and cost in seconds."""
        if not self._chunks:
            return np.zeros((0, 2))
        return np.concatenate([*self._chunks[:-1], self._chunks[-1][: self._row]])

    def report(self) -> TimingReport:
        """Summarize the ticks recorded so far."""
        data = self.samples()
        ticks = len(data)
        # each column's percentiles from one sort (a replay asks after every record)
        late = np.percentile(data[:, 0], [50, 99, 99.9, 100]) if ticks else np.zeros(4)
        cost = np.percentile(data[:, 1], [50, 99]) if ticks else np.zeros(2)
        rate = ticks / self.duration_s if self.duration_s > 0 else 0.0
        return TimingReport(
            period_s=self.period_s,
            ticks=ticks,
            duration_s=self.duration_s,
            achieved_rate_hz=rate,
            lateness_p50_s=float(late[0]),
            lateness_p99_s=float(late[1]),
            lateness_p999_s=float(late[2]),
            lateness_max_s=float(late[3]),
            missed_deadlines=self.missed_deadlines,
            tick_cost_p50_s=float(cost[0]),
            tick_cost_p99_s=float(cost[1]),
        )
