"""Wall time of the consecutive phases of a step, for the step reports (``StepStats``,
``PaintStep``)."""

from __future__ import annotations

import time


class PhaseTimer:
    """Wall time of consecutive phases of a step, in ms.

    Each :meth:`mark` charges the time since the previous mark (or the start) to a phase; a
    phase marked twice accumulates. :attr:`ms` maps phase names to milliseconds.
    """

    def __init__(self) -> None:
        self.start = self._last = time.perf_counter()
        self.ms: dict[str, float] = {}

    def mark(self, phase: str) -> None:
        """The time since the previous mark (or the start) was spent in ``phase``."""
        now = time.perf_counter()
        self.ms[phase] = self.ms.get(phase, 0.0) + 1e3 * (now - self._last)
        self._last = now

    @property
    def total_ms(self) -> float:
        """Time since the start, ms."""
        return 1e3 * (time.perf_counter() - self.start)
