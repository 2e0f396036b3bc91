"""Lock-free latest-value records in shared memory, between the app and the servo process.

The servo loop runs in its own process (:mod:`paintapp.haptics.process`); it and the app exchange
only latest values, through one :class:`SharedBlock` (a shared-memory segment laid out as fixed
float64/int64 arrays): the latest force sample (app -> servo) and device state (servo -> app),
each a :class:`SeqlockRecord`; the simulated hand's target and the app's heartbeat (app ->
servo); the tick-timing ring the HUD reads and the device-write audit (servo -> app).

Seqlock: one writer makes the version odd, writes the values, makes it even again; a reader
copies the values between two reads of the version and keeps the copy only if both are the same
even number. Nobody waits on a lock: a reader retries a bounded number of times and otherwise
reports "no new value", so a writer killed mid-write cannot stall it (the servo loop keeps its
last value and its watchdog fades the force). Plain numpy stores suffice on x86-64 (program
order); on weakly ordered CPUs a torn read is one stale or mixed sample, checked like any other.

:class:`SharedForceChannel` and :class:`SharedStateChannel` give these records the interface of
:class:`~paintapp.haptics.channel.ForceChannel` and :class:`~paintapp.haptics.channel.StateChannel`,
so the same :class:`~paintapp.haptics.servo.ServoLoop` and the same painting session use them.
"""

from __future__ import annotations

import time
from multiprocessing import resource_tracker, shared_memory

import numpy as np
import numpy.typing as npt

from paintapp.haptics.channel import ForceChannel, ForceSample, StateChannel
from paintapp.haptics.device import DeviceState
from paintapp.haptics.metrics import interval_stats

#: Width of one force record: t_s, force (3), torque (3).
FORCE_WIDTH = 7
#: Width of one state record: t_s, position (3), orientation (4), pressure, buttons, velocity (3).
STATE_WIDTH = 13
#: Width of the target record: position (3), velocity (3).
TARGET_WIDTH = 6
#: Ticks kept in the timing ring (2 s at 1 kHz).
RING_TICKS = 2000
#: Audit counters: writes, non-finite writes, over-limit writes, max |force|, max |torque|,
#: last |force|, last |torque|, the app's longest silence since it armed the watchdog (s).
AUDIT_WIDTH = 8
#: Header int64 slots: magic, child pid, phase, armed (the heartbeat watchdog counts).
HEADER_INTS = 4
MAGIC = 0x5345_5256_4F31  # "SERVO1"

# Phases of the servo process, in the header.
PHASE_STARTING = 0
PHASE_RUNNING = 1
PHASE_STOPPING = 2
PHASE_EXITED = 3
PHASE_FAILED = 4


class SeqlockRecord:
    """A seqlock-protected record of ``width`` float64 values at ``offset`` of ``buf``.

    One process writes (:meth:`write`); any process reads (:meth:`read`). The version counts
    half-writes: even when stable, odd while a write is under way; ``version // 2`` is the number
    of completed writes.
    """

    def __init__(self, buf: memoryview, offset: int, width: int, keep: object = None) -> None:
        self._keep = keep  # the mapping must outlive these views (see SharedBlock.close)
        self._version = np.ndarray((1,), np.int64, buf, offset)
        self.data = np.ndarray((width,), np.float64, buf, offset + 8)
        self.width = width

    @staticmethod
    def nbytes(width: int) -> int:
        """Bytes a record of ``width`` values occupies."""
        return 8 * (width + 1)

    def write(self, values: npt.ArrayLike) -> int:
        """Publish ``values`` (shape (width,)); returns the number of completed writes."""
        v = int(self._version[0])
        self._version[0] = v + 1
        self.data[:] = values
        self._version[0] = v + 2
        return (v + 2) // 2

    def read(self, out: np.ndarray, retries: int = 200) -> int | None:
        """Copy a consistent record into ``out``; the write count it belongs to, or None when no
        consistent copy was had within ``retries`` attempts (``out`` is then unspecified)."""
        for _ in range(retries):
            v1 = int(self._version[0])
            if v1 & 1:
                continue
            out[:] = self.data
            if int(self._version[0]) == v1:
                return v1 // 2
        return None

    @property
    def count(self) -> int:
        """Completed writes so far (a cheap read of the version, no copy)."""
        return int(self._version[0]) // 2


class TimingRing:
    """The last :data:`RING_TICKS` ticks' start intervals and work times, s (one writer)."""

    def __init__(self, buf: memoryview, offset: int, keep: object = None) -> None:
        self._keep = keep
        self._count = np.ndarray((1,), np.int64, buf, offset)
        self.rows = np.ndarray((RING_TICKS, 2), np.float64, buf, offset + 8)

    @staticmethod
    def nbytes() -> int:
        return 8 + 16 * RING_TICKS

    def record(self, interval_s: float, cost_s: float) -> None:
        """Append one tick (overwriting the oldest)."""
        n = int(self._count[0])
        row = self.rows[n % RING_TICKS]
        row[0] = interval_s
        row[1] = cost_s
        self._count[0] = n + 1

    def live(self, period_s: float) -> tuple[float, float, int]:
        """(rate Hz, jitter p99 ms, intervals seen) over the ring; jitter is the 99th percentile
        of |interval - period|. Rows being overwritten meanwhile only blur the statistics."""
        n = min(int(self._count[0]), RING_TICKS)
        if n < 2:
            return 0.0, 0.0, n
        rate, jitter = interval_stats(self.rows[:n, 0].copy(), period_s)
        return rate, jitter, n


class SharedBlock:
    """The shared-memory segment of one servo process and its records.

    Args:
        name: attach to this existing segment; None creates a new one (the creator owns it and
            unlinks it in :meth:`close`).
        track: leave an attached segment registered with this process's resource tracker (Python
            < 3.13 registers every attach). Processes started by ``multiprocessing`` share their
            parent's tracker, so for them the registration is a no-op and the tracker removes the
            segment once they have all exited, even if the owner was killed. An unrelated process
            that merely looks at a block passes False, so its own tracker never removes it.
    """

    def __init__(self, name: str | None = None, track: bool = True) -> None:
        sizes = [
            8 * HEADER_INTS,
            8,  # heartbeat (time.monotonic of the app's last beat)
            SeqlockRecord.nbytes(FORCE_WIDTH),
            SeqlockRecord.nbytes(STATE_WIDTH),
            SeqlockRecord.nbytes(TARGET_WIDTH),
            TimingRing.nbytes(),
            8 * AUDIT_WIDTH,
        ]
        self.owner = name is None
        if name is None:
            self.shm = shared_memory.SharedMemory(create=True, size=sum(sizes))
        else:
            self.shm = shared_memory.SharedMemory(name=name)
            if not track:  # Python < 3.13 registers every attach; undo that
                resource_tracker.unregister(self.shm._name, "shared_memory")  # type: ignore[attr-defined]
        buf = self.shm.buf
        assert buf is not None
        offsets = np.cumsum([0, *sizes]).tolist()
        self.header = np.ndarray((HEADER_INTS,), np.int64, buf, offsets[0])
        self._heartbeat = np.ndarray((1,), np.float64, buf, offsets[1])
        self.force = SeqlockRecord(buf, offsets[2], FORCE_WIDTH, self.shm)
        self.state = SeqlockRecord(buf, offsets[3], STATE_WIDTH, self.shm)
        self.target = SeqlockRecord(buf, offsets[4], TARGET_WIDTH, self.shm)
        self.ring = TimingRing(buf, offsets[5], self.shm)
        self.audit = np.ndarray((AUDIT_WIDTH,), np.float64, buf, offsets[6])
        if self.owner:
            self.header[:] = 0
            self.header[0] = MAGIC
            self.beat()
        elif int(self.header[0]) != MAGIC:
            raise ValueError(f"shared memory {name!r} is not a servo block")

    @property
    def name(self) -> str:
        """The segment's name (what another process attaches to)."""
        return self.shm.name

    # --- header -------------------------------------------------------------------------------
    @property
    def phase(self) -> int:
        return int(self.header[2])

    @phase.setter
    def phase(self, value: int) -> None:
        self.header[2] = value

    @property
    def pid(self) -> int:
        return int(self.header[1])

    @pid.setter
    def pid(self, value: int) -> None:
        self.header[1] = value

    @property
    def armed(self) -> bool:
        """Whether the heartbeat watchdog counts (the app is up)."""
        return bool(self.header[3])

    @armed.setter
    def armed(self, value: bool) -> None:
        self.header[3] = int(value)

    # --- heartbeat ------------------------------------------------------------------------------
    def beat(self) -> None:
        """The app is alive (``time.monotonic``, the same clock in every process)."""
        self._heartbeat[0] = time.monotonic()

    def heartbeat_age_s(self) -> float:
        """Seconds since the app's last beat."""
        return time.monotonic() - float(self._heartbeat[0])

    def audit_counts(self) -> dict[str, float]:
        """What the servo process wrote to its device (see :data:`AUDIT_WIDTH`)."""
        a = self.audit.tolist()
        return {
            "writes": a[0],
            "nonfinite_writes": a[1],
            "over_limit_writes": a[2],
            "max_force_n": a[3],
            "max_torque_nm": a[4],
            "last_force_n": a[5],
            "last_torque_nm": a[6],
            "longest_app_silence_s": a[7],
        }

    def close(self) -> None:
        """Remove the segment's name (the owner; attachers do nothing).

        The mapping itself stays until the last record over it is garbage: numpy views into it
        do not pin it, so unmapping here could leave a channel still in use (a worker thread
        publishing its last force) pointing at unmapped memory. Each record keeps the
        :class:`~multiprocessing.shared_memory.SharedMemory` alive; it unmaps on collection.
        """
        if self.owner:
            try:
                self.shm.unlink()
            except FileNotFoundError:
                pass


class SharedForceChannel(ForceChannel):
    """A :class:`ForceChannel` over a shared :class:`SeqlockRecord` (see the module docstring).

    ``latest()`` copies the record only when its write count changed, so the servo loop's
    per-tick look costs one integer read; a sample is built only for a fresh record.
    """

    def __init__(self, record: SeqlockRecord) -> None:
        super().__init__()
        self.record = record
        self._buf = np.empty(FORCE_WIDTH)
        self._out = np.empty(FORCE_WIDTH)
        self._cached: tuple[int, ForceSample | None] = (0, None)

    def publish(self, value: ForceSample) -> int:
        self._buf[0] = value.t_s
        self._buf[1:4] = value.force
        self._buf[4:7] = value.torque
        return self.record.write(self._buf)

    def latest(self) -> tuple[int, ForceSample | None]:
        count = self.record.count
        if count == self._cached[0]:
            return self._cached
        got = self.record.read(self._out)
        if got is None:  # the writer is mid-write (or died there): keep what we had
            return self._cached
        v = self._out
        self._cached = (got, ForceSample(float(v[0]), v[1:4], v[4:7]))
        return self._cached

    @property
    def seq(self) -> int:
        return self.record.count


class SharedStateChannel(StateChannel):
    """A :class:`StateChannel` over a shared :class:`SeqlockRecord` (canvas-frame states)."""

    def __init__(self, record: SeqlockRecord) -> None:
        super().__init__()
        self.record = record
        self._buf = np.empty(STATE_WIDTH)
        self._out = np.empty(STATE_WIDTH)
        self._cached: tuple[int, DeviceState | None] = (0, None)

    def publish(self, value: DeviceState) -> int:
        b = self._buf
        b[0] = value.t_s
        b[1:4] = value.position_m
        b[4:8] = value.orientation_wxyz
        b[8] = value.pressure
        b[9] = value.buttons
        b[10:13] = value.velocity_m_per_s
        return self.record.write(b)

    def latest(self) -> tuple[int, DeviceState | None]:
        count = self.record.count
        if count == self._cached[0]:
            return self._cached
        got = self.record.read(self._out)
        if got is None:
            return self._cached
        v = self._out.copy()
        buttons = int(v[9]) if np.isfinite(v[9]) else 0
        state = DeviceState(float(v[0]), v[1:4], v[4:8], float(v[8]), buttons, v[10:13])
        self._cached = (got, state)
        return self._cached

    @property
    def seq(self) -> int:
        return self.record.count


class SharedTarget:
    """The simulated hand's target over a shared record: the app sets it, the device reads it.

    Callable like a stroke target: ``target(t_s) -> (position m (3,), velocity m/s (3,))``.
    """

    def __init__(self, record: SeqlockRecord, start_m: npt.ArrayLike = (0.0, 0.0, 0.005)) -> None:
        self.record = record
        self._buf = np.zeros(TARGET_WIDTH)
        self._out = np.empty(TARGET_WIDTH)
        self._last = np.zeros(TARGET_WIDTH)
        self._last[:3] = np.asarray(start_m, np.float64)
        self._seen = -1

    def set_position(
        self, position_m: npt.ArrayLike, velocity_m_per_s: npt.ArrayLike = (0, 0, 0)
    ) -> None:
        """Aim the hand at ``position_m`` (canvas frame, m) moving at ``velocity_m_per_s``."""
        self._buf[:3] = position_m
        self._buf[3:] = velocity_m_per_s
        self.record.write(self._buf)

    def __call__(self, _t_s: float) -> tuple[np.ndarray, np.ndarray]:
        count = self.record.count
        if count != self._seen and count > 0 and self.record.read(self._out) is not None:
            if np.all(np.isfinite(self._out)):
                self._last[:] = self._out
            self._seen = count
        return self._last[:3].copy(), self._last[3:].copy()
