"""The machine's own timing floor: the servo process's clock with nothing to do.

A servo loop can keep time no better than the machine lets a process wake up: a virtual machine's
host, the kernel's own threads and interrupts can hold a core for milliseconds, whatever the
process on it does. :func:`measure_bare_loop` runs, in a process of its own, the servo process's
clock (:class:`~paintapp.haptics.clock.RealTimeClock`, 1 kHz, sleeping then spinning to each
deadline) with the same real-time treatment (:func:`~paintapp.haptics.realtime.apply_realtime`:
priority, the same pinned core, no garbage collector, locked memory) and an empty tick: no device,
no filter, no shared memory. Its lateness is the floor the servo's own lateness should be read
against (as ``cyclictest`` is for a real-time kernel): a servo stall the bare loop also shows is
the machine's, not the loop's. It also lists the *stalls*, the ticks that started more than
:data:`STALL_S` late, with when they came.

``paintapp haptics-check`` prints it beside the servo's own runs; ``benchmarks/bench_app.py``
runs it for the same seconds after each round's window.
"""

from __future__ import annotations

import multiprocessing as mp
import time
from dataclasses import dataclass
from multiprocessing.connection import Connection

import numpy as np

from paintapp.haptics.clock import RealTimeClock
from paintapp.haptics.metrics import TimingReport
from paintapp.haptics.process import spin_for
from paintapp.haptics.realtime import Granted, apply_realtime

#: A gap between two ticks' starts longer than the period by more than this is a stall (s).
STALL_S = 2e-3
#: Stalls listed at most (the count covers them all).
MAX_LISTED = 50


@dataclass(frozen=True)
class BareLoopResult:
    """What the bare loop measured.

    Attributes:
        timing: its timing report (lateness percentiles, missed deadlines, rate).
        granted: what the OS granted it (one line).
        stalls: how many ticks started more than :data:`STALL_S` later than a period after the
            tick before them.
        listed: the first :data:`MAX_LISTED` of them, as (seconds into the run, lateness s).
    """

    timing: TimingReport
    granted: str
    stalls: int
    listed: tuple[tuple[float, float], ...]

    def describe(self) -> str:
        """One line: lateness p99 and max, the stalls over :data:`STALL_S`."""
        t = self.timing
        return (
            f"bare 1 kHz loop (own process, {self.granted}, empty tick): lateness p99 "
            f"{1e3 * t.lateness_p99_s:.3f} ms, max {1e3 * t.lateness_max_s:.2f} ms, "
            f"{self.stalls} ticks over {1e3 * STALL_S:g} ms late in {t.duration_s:.1f} s"
        )


def _child(seconds: float, period_s: float, out: Connection) -> None:
    try:
        granted: Granted = apply_realtime()
        clock = RealTimeClock(period_s, spin_s=spin_for(granted))
        ticks = max(1, round(seconds / period_s))
        starts = np.zeros(ticks)  # written in place: the tick allocates nothing

        def tick(index: int, t_s: float) -> bool:
            starts[index] = t_s
            return True

        timing = clock.run(tick, ticks)
        late = np.flatnonzero(np.diff(starts) > period_s + STALL_S)
        listed = tuple(
            (float(starts[i + 1] - starts[0]), float(starts[i + 1] - starts[i] - period_s))
            for i in late[:MAX_LISTED]
        )
        out.send(("ok", timing, granted.describe(), int(late.size), listed))
    except Exception as exc:  # reported to the parent, which says what failed
        out.send(("error", f"{type(exc).__name__}: {exc}"))
    finally:
        out.close()


def measure_bare_loop(seconds: float, period_s: float = 1e-3) -> BareLoopResult:
    """Run the bare loop for ``seconds`` in a process of its own (module docstring).

    Raises:
        RuntimeError: the process failed, or did not report within ``seconds`` plus a minute.
    """
    ctx = mp.get_context("spawn")
    parent, child = ctx.Pipe(duplex=False)
    proc = ctx.Process(target=_child, args=(seconds, period_s, child), name="bare-loop")
    proc.start()
    child.close()
    try:
        deadline = time.monotonic() + seconds + 60.0
        while not parent.poll(0.1):
            if not proc.is_alive() and not parent.poll(0.1):
                raise RuntimeError(f"the bare loop's process died (exit code {proc.exitcode})")
            if time.monotonic() > deadline:
                raise RuntimeError(f"the bare loop did not report within {seconds + 60:g} s")
        try:
            message = parent.recv()
        except EOFError:
            raise RuntimeError("the bare loop's process ended without a report") from None
    finally:
        proc.join(5.0)
        if proc.is_alive():
            proc.kill()
            proc.join(1.0)
        parent.close()
    if message[0] != "ok":
        raise RuntimeError(f"the bare loop failed: {message[1]}")
    _, timing, granted, stalls, listed = message
    return BareLoopResult(timing, granted, stalls, listed)
