"""Clocks that drive the servo loop: a deterministic virtual clock and a real 1 kHz clock.

Both run a tick function ``tick(index, t_s) -> keep_going`` on a fixed schedule and record how
well they kept it (:mod:`paintapp.haptics.metrics`). :class:`VirtualClock` never sleeps: each tick
happens exactly on schedule in virtual time, so tests and replays are deterministic. It still
measures the real time each tick's work takes, which is how the cost of one tick is measured.

:class:`RealTimeClock` sleeps until shortly before each deadline and spins the rest of the way.

Thread or process: a thread's ticks are late wherever a neighbour thread runs Python for a
stretch, since the interpreter hands the GIL over once per switch interval (5 ms by default);
:class:`RealTimeClock` lowers the interval while it runs. Beside the GUI and the simulation
worker that is still not enough, so the painting window runs the loop in a process of its own
(:mod:`paintapp.haptics.process`, shared memory through :mod:`paintapp.haptics.shared_state`,
``SCHED_FIFO`` and a pinned core where granted: :mod:`paintapp.haptics.realtime`). The thread
form serves tests, ``haptics-check --form thread`` and the fallback when no process can start.
The measurements behind the choice are in ``docs/performance.md``.
"""

from __future__ import annotations

import sys
import threading
import time
from collections.abc import Callable
from typing import Protocol

from common.errors import InputError
from paintapp.haptics.metrics import TimingRecorder, TimingReport

TickFn = Callable[[int, float], bool]
"""A tick: called with the tick index and the clock time in seconds; returns False to stop."""


class Clock(Protocol):
    """A source of periodic ticks and of the current time on the same time base."""

    period_s: float

    def now_s(self) -> float:
        """The current time in seconds."""
        ...

    def run(
        self, tick: TickFn, max_ticks: int | None = None, stop: threading.Event | None = None
    ) -> TimingReport:
        """Call ``tick`` once per period until it returns False, ``max_ticks`` ran, or ``stop``."""
        ...


def _check_period(period_s: float) -> float:
    if not period_s > 0:
        raise InputError(f"clock period must be positive, got {period_s}", key="period_s")
    return float(period_s)


class VirtualClock:
    """Deterministic ticks in virtual time; no sleeping. Successive runs continue the timeline.

    Args:
        period_s: tick period in seconds.
        start_s: virtual time of the first tick.
    """

    def __init__(self, period_s: float = 1e-3, start_s: float = 0.0) -> None:
        self.period_s = _check_period(period_s)
        self._next_index = 0
        self._start_s = float(start_s)
        self._now_s = float(start_s)

    def now_s(self) -> float:
        return self._now_s

    @property
    def next_index(self) -> int:
        """The index of the next tick (ticks run or skipped so far)."""
        return self._next_index

    def skip(self, ticks: int) -> None:
        """Move the timeline on by ``ticks`` ticks without running them (a replay's long pause)."""
        if ticks > 0:
            self._next_index += int(ticks)
            self._now_s = self._start_s + (self._next_index - 1) * self.period_s

    def run(
        self, tick: TickFn, max_ticks: int | None = None, stop: threading.Event | None = None
    ) -> TimingReport:
        recorder = TimingRecorder(self.period_s)
        count = 0
        while (max_ticks is None or count < max_ticks) and not (stop and stop.is_set()):
            index = self._next_index
            self._next_index += 1
            self._now_s = self._start_s + index * self.period_s
            begin = time.perf_counter()
            keep_going = tick(index, self._now_s)
            recorder.record(0.0, time.perf_counter() - begin)
            count += 1
            if not keep_going:
                break
        recorder.duration_s = count * self.period_s
        return recorder.report()


class RealTimeClock:
    """Ticks at a real rate, paced by :func:`time.perf_counter`; sleeps then spins to a deadline.

    Args:
        period_s: tick period in seconds (1 ms for 1 kHz).
        spin_s: how long before a deadline to stop sleeping and spin.
        switch_interval_s: the interpreter switch interval to use while running (see the module
            docstring); None leaves it alone. The previous value is restored afterwards.
    """

    def __init__(
        self,
        period_s: float = 1e-3,
        spin_s: float = 2e-4,
        switch_interval_s: float | None = 5e-4,
    ) -> None:
        self.period_s = _check_period(period_s)
        self.spin_s = float(spin_s)
        self.switch_interval_s = switch_interval_s
        self._thread: threading.Thread | None = None
        self._stop = threading.Event()
        self._report: TimingReport | None = None

    def now_s(self) -> float:
        return time.perf_counter()

    def _wait_until(self, deadline_s: float) -> float:
        remaining = deadline_s - time.perf_counter()
        if remaining > self.spin_s:
            time.sleep(remaining - self.spin_s)
        now = time.perf_counter()
        while now < deadline_s:
            now = time.perf_counter()
        return now

    def run(
        self, tick: TickFn, max_ticks: int | None = None, stop: threading.Event | None = None
    ) -> TimingReport:
        recorder = TimingRecorder(self.period_s)
        old_interval = sys.getswitchinterval()
        if self.switch_interval_s is not None:
            sys.setswitchinterval(self.switch_interval_s)
        try:
            self._loop(tick, recorder, max_ticks, stop)
        finally:
            sys.setswitchinterval(old_interval)
        return recorder.report()

    def _loop(
        self,
        tick: TickFn,
        recorder: TimingRecorder,
        max_ticks: int | None,
        stop: threading.Event | None,
    ) -> None:
        period = self.period_s
        t0 = time.perf_counter() + period
        slot = 0
        count = 0
        while (max_ticks is None or count < max_ticks) and not (stop and stop.is_set()):
            deadline = t0 + slot * period
            now = self._wait_until(deadline)
            lateness = now - deadline
            keep_going = tick(count, now)
            recorder.record(lateness, time.perf_counter() - now)
            count += 1
            skipped = int(lateness // period)
            recorder.skip(skipped)
            slot += 1 + skipped
            if not keep_going:
                break
        recorder.duration_s = time.perf_counter() - t0

    def start(self, tick: TickFn, max_ticks: int | None = None) -> None:
        """Run the ticks in a background thread until :meth:`stop` (or the tick says stop)."""
        if self._thread is not None:
            raise RuntimeError("clock already running")
        self._stop.clear()
        self._report = None

        def target() -> None:
            self._report = self.run(tick, max_ticks, self._stop)

        self._thread = threading.Thread(target=target, name="haptic-servo", daemon=True)
        self._thread.start()

    def stop(self, timeout_s: float = 5.0) -> TimingReport | None:
        """Stop the background thread and return its timing report (None if it did not start)."""
        if self._thread is None:
            return None
        self._stop.set()
        self._thread.join(timeout_s)
        self._thread = None
        return self._report

    @property
    def running(self) -> bool:
        """Whether a background run is still going."""
        return self._thread is not None and self._thread.is_alive()
