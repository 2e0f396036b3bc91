"""CPU time the host took from this machine: the steal counter of Linux's ``/proc/stat``.

On a virtual machine the hypervisor may run other work on the cores this machine believes it
has. Time in which a virtual CPU had work but was not running is counted as *steal*. A servo tick
due while its CPU is stolen starts late however the OS schedules it, and the paint steps slow
down with it, so the timing checks (``paintapp haptics-check``, ``benchmarks/bench_app.py``) print
the steal share of each run beside its figures: a run in which the host took a tenth of the
CPU time says more about the host than about the program.

Where ``/proc/stat`` cannot be read or has no steal column, the share is unknown (None), never
a guess.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from pathlib import Path

STAT_PATH = Path("/proc/stat")
#: Columns of the ``cpu`` line summed as its total: user, nice, system, idle, iowait, irq,
#: softirq, steal (the guest columns after them are already inside user and nice).
COLUMNS = 8
STEAL = 7


@dataclass(frozen=True)
class CpuTimes:
    """The machine's CPU time so far, summed over its CPUs, in clock ticks.

    Attributes:
        total: all of it (:data:`COLUMNS`).
        steal: the part the host took.
    """

    total: int
    steal: int


def parse_cpu_times(text: str) -> CpuTimes | None:
    """The aggregate ``cpu`` line of a ``/proc/stat`` text, or None when it has none, or one
    with fewer than :data:`COLUMNS` non-negative integer columns."""
    for line in text.splitlines():
        fields = line.split()
        if not fields or fields[0] != "cpu":
            continue
        if len(fields) < 1 + COLUMNS:
            return None
        try:
            values = [int(v) for v in fields[1 : 1 + COLUMNS]]
        except ValueError:
            return None
        if min(values) < 0:
            return None
        return CpuTimes(total=sum(values), steal=values[STEAL])
    return None


def read_cpu_times(path: Path = STAT_PATH) -> CpuTimes | None:
    """:func:`parse_cpu_times` of ``path``; None where it cannot be read (not Linux)."""
    try:
        text = path.read_text(encoding="ascii", errors="replace")
    except OSError:
        return None
    return parse_cpu_times(text)


def steal_share(before: CpuTimes | None, after: CpuTimes | None) -> float | None:
    """The share of the CPU time between two readings that the host took (0-1), or None when
    either reading is missing or the counters did not advance (or went back)."""
    if before is None or after is None:
        return None
    total = after.total - before.total
    steal = after.steal - before.steal
    if total <= 0 or steal < 0 or steal > total:
        return None
    return steal / total


def format_share(share: float | None) -> str:
    """A steal share for a table: ``"2.4 %"``, or ``"-"`` when unknown."""
    return "-" if share is None else f"{100.0 * share:.1f} %"


def describe_steal(share: float | None, peak: float | None) -> str:
    """``"0.4 % (peak 9.3 %)"`` for a block's share and its worst interval's, or ``"-"`` when
    unknown."""
    if share is None or peak is None:
        return "-"
    return f"{format_share(share)} (peak {format_share(peak)})"


class StealMonitor:
    """The steal share over a block, and its largest over any ``interval_s`` within it, from a
    daemon thread that reads ``/proc/stat`` once per interval (a file read: no measurable load).

    Use as a context manager; :attr:`share` and :attr:`peak` are set on exit (None: unknown).
    """

    def __init__(self, interval_s: float = 0.5, path: Path = STAT_PATH) -> None:
        if not interval_s > 0:
            raise ValueError(f"interval_s must be positive, got {interval_s}")
        self.interval_s = float(interval_s)
        self.path = path
        self.share: float | None = None
        self.peak: float | None = None
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._first: CpuTimes | None = None
        self._peak: float | None = None

    def __enter__(self) -> StealMonitor:
        self._first = read_cpu_times(self.path)
        self._thread = threading.Thread(target=self._sample, name="steal-monitor", daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(5.0)
        self.share = steal_share(self._first, read_cpu_times(self.path))
        if self.share is None:
            self.peak = None
        else:  # a block shorter than an interval has only its own share
            self.peak = self.share if self._peak is None else max(self._peak, self.share)

    def describe(self) -> str:
        """:func:`describe_steal` of this block."""
        return describe_steal(self.share, self.peak)

    def _sample(self) -> None:
        last = self._first
        while not self._stop.wait(self.interval_s):
            now = read_cpu_times(self.path)
            if now is None:  # a failed read: the next interval starts from the last good one
                continue
            share = steal_share(last, now)
            if share is not None:
                self._peak = share if self._peak is None else max(self._peak, share)
            last = now
