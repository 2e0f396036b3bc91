"""The servo loop in a process of its own, owning the device; the app talks to it through shared memory.

The app side is :class:`ServoProcess`; the ``spawn``-started child runs :func:`child_main`: it
imports no Qt, numba, GL or solver, builds the device from its text description (HID handles
cannot cross processes) and runs the :class:`~paintapp.haptics.servo.ServoLoop` on a
:class:`~paintapp.haptics.clock.RealTimeClock` with real-time treatment where granted.

State crosses in shared memory (:mod:`paintapp.haptics.shared_state`, seqlocks, nobody waits);
commands go down a queue polled every :data:`COMMAND_EVERY` ticks, events come up a pipe. Every
device write passes the :class:`GatedDevice` (fade gain; non-finite and over-limit writes are
counted into the shared audit and must stay zero). Fail-safe exits:

- the app dies or stops beating for ``heartbeat_timeout_s`` once it has armed the watchdog (at
  once, or at :meth:`ServoProcess.arm`, after start-up stalls no heartbeat can cover; unarmed
  after ``arm_timeout_s`` counts as gone): the output fades to zero over ``exit_fade_s``;
- a ``stop`` command or SIGTERM: the same fade; a device failure: zero force, the fault sent up;
- the child dies: :attr:`ServoProcess.fault` says so.
"""

from __future__ import annotations

import contextlib
import math
import multiprocessing as mp
import os
import queue
import signal
import sys
import threading
import time
from dataclasses import dataclass, field, replace
from multiprocessing.connection import Connection
from typing import Any

import numpy as np

from common.errors import InputError
from paintapp.haptics.clock import RealTimeClock
from paintapp.haptics.device import DeviceInfo, DeviceNotFoundError, DeviceState, HapticDevice
from paintapp.haptics.devices.simulated import SimulatedDevice
from paintapp.haptics.realtime import Granted, apply_realtime
from paintapp.haptics.servo import ServoConfig, ServoLoop, ServoReport
from paintapp.haptics.shared_state import (
    PHASE_EXITED,
    PHASE_FAILED,
    PHASE_RUNNING,
    PHASE_STOPPING,
    SharedBlock,
    SharedForceChannel,
    SharedStateChannel,
    SharedTarget,
)

#: Ticks between looks at the command queue.
COMMAND_EVERY = 10
#: Ticks between checks that the app (the parent process) is still there.
PARENT_EVERY = 20
#: Seconds between the app's heartbeats.
BEAT_S = 0.02
#: Modules the servo process must not import (checked and reported at start).
HEAVY_MODULES = ("numba", "PySide6", "moderngl", "matplotlib", "solver", "brushes", "paintapp.app")


@dataclass(frozen=True)
class ProcessOptions:
    """How the servo process runs (picklable: it crosses to the child).

    Attributes:
        device: ``sim`` (the hand follows the shared target), ``sim:stroke`` (its built-in circle),
            ``hid:VID:PID[:stylus|pid]``, or a vendor backend (``openhaptics[:NAME]``, ``dhd``,
            ``haply[:ID]``: :mod:`~paintapp.haptics.devices.backends`).
        config: the servo loop's configuration.
        realtime: ask for real-time priority, a pinned core, GC off, locked memory.
        pin: pin to a core (with ``realtime``) when there are several.
        heartbeat_timeout_s: the app is gone after this long without a heartbeat (once armed).
        arm_at_start: the heartbeat watchdog counts from the start; False: from the app's
            :meth:`ServoProcess.arm` (until then only the app's exit ends the child).
        arm_timeout_s: with ``arm_at_start`` False, the app is gone if not armed this long after
            the child started.
        exit_fade_s: the whole output fades to zero over this time before the child exits.
        duration_s: stop by itself after this long (None: until told or orphaned).
        start_m: where the simulated hand starts (canvas frame, m).
        spin_s: the clock spins this long before each deadline (None: by the OS, :func:`spin_for`).
    """

    device: str = "sim"
    config: ServoConfig = field(default_factory=lambda: ServoConfig(record=False))
    realtime: bool = True
    pin: bool = True
    heartbeat_timeout_s: float = 1.0
    arm_at_start: bool = True
    arm_timeout_s: float = 600.0
    exit_fade_s: float = 0.25
    duration_s: float | None = None
    start_m: tuple[float, float, float] = (0.0, 0.0, 0.005)
    spin_s: float | None = None

    def __post_init__(self) -> None:
        spin = self.spin_s
        if spin is not None and not (math.isfinite(spin) and 0.0 <= spin <= self.config.tick_s):
            raise InputError(
                f"spin_s: expected None or seconds in [0, {self.config.tick_s:g}], got {spin}",
                key="spin_s",
            )


#: The clock's spin before each deadline with a real-time scheduling class, and without one, s.
#: A real-time task wakes within tens of microseconds of its deadline (no timer slack, nothing of
#: lower class runs first), well inside the lateness target, and a spin would take a share of the
#: core beside the simulation's. Without real-time priority a wake-up can come later, and the spin
#: stays.
REALTIME_SPIN_S = 0.0
NORMAL_SPIN_S = 2e-4


def spin_for(granted: Granted, spin_s: float | None = None) -> float:
    """The clock's spin: ``spin_s`` when given, else by ``granted`` (see :data:`REALTIME_SPIN_S`)."""
    if spin_s is not None:
        return float(spin_s)
    return REALTIME_SPIN_S if granted.realtime else NORMAL_SPIN_S


def build_device(text: str, time_source: Any, target: SharedTarget | None) -> HapticDevice:
    """The device ``text`` names (see :class:`ProcessOptions`), not yet opened."""
    if text == "sim":
        return SimulatedDevice(time_source, target=target, tilt_rad=(0.0, 0.0))
    if text == "sim:stroke":
        return SimulatedDevice(time_source)
    parts = text.split(":")
    if parts[0] == "hid" and len(parts) in (3, 4):
        from paintapp.haptics.devices.hid import HidDevice
        from paintapp.haptics.devices.hid_transport import open_hid, parse_ids

        vid, pid = parse_ids(f"{parts[1]}:{parts[2]}")
        protocol = parts[3] if len(parts) == 4 else "stylus"
        return HidDevice(lambda: open_hid(vid, pid), protocol, time_source)
    from paintapp.haptics.devices.backends import VENDOR_SYNTAX, build_vendor_device, split_device

    vendor = split_device(text)
    if vendor is not None:
        return build_vendor_device(vendor[0], vendor[1], time_source)
    raise DeviceNotFoundError(
        f"unknown device {text!r} (sim, sim:stroke, hid:VID:PID or {VENDOR_SYNTAX})"
    )


class GatedDevice:
    """A device wrapper that applies an output gain (the exit fade) and audits every write.

    Args:
        device: the real device.
        audit: the shared audit counters (see :data:`~paintapp.haptics.shared_state.AUDIT_WIDTH`).
        step: how much the gain falls per write while fading out (tick / fade time).
    """

    def __init__(self, device: HapticDevice, audit: np.ndarray, step: float) -> None:
        self.device = device
        self.audit = audit
        self.step = float(step)
        self.gain = 1.0
        self.fading = False
        self._force = np.zeros(3)
        self._torque = np.zeros(3)

    @property
    def info(self) -> DeviceInfo:
        return self.device.info

    @property
    def finished(self) -> bool:
        return bool(getattr(self.device, "finished", False))

    def open(self) -> None:
        self.device.open()

    def close(self) -> None:
        self.write(np.zeros(3), np.zeros(3), gate=False)
        self.device.close()

    def read(self) -> DeviceState:
        return self.device.read()

    def write(self, force_n: np.ndarray, torque_nm: np.ndarray, gate: bool = True) -> None:
        if self.fading and gate:
            self.gain = max(0.0, self.gain - self.step)
        g = self.gain if gate else 0.0
        np.multiply(force_n, g, out=self._force)
        np.multiply(torque_nm, g, out=self._torque)
        self._audit(self._force, self._torque)
        self.device.write(self._force, self._torque)

    def _audit(self, force: np.ndarray, torque: np.ndarray) -> None:
        a = self.audit
        fn = math.hypot(*force.tolist())
        tn = math.hypot(*torque.tolist())
        a[0] += 1
        info = self.device.info
        if not (math.isfinite(fn) and math.isfinite(tn)):
            a[1] += 1
        elif (
            fn > info.max_force_n * (1 + 1e-9) + 1e-12
            or tn > info.max_torque_nm * (1 + 1e-9) + 1e-12
        ):
            a[2] += 1
        if math.isfinite(fn):
            a[3] = max(a[3], fn)
        if math.isfinite(tn):
            a[4] = max(a[4], tn)
        a[5], a[6] = fn, tn


class _Host:
    """The child's tick: the servo tick plus metering, commands, and the exit checks."""

    def __init__(
        self,
        loop: ServoLoop,
        device: GatedDevice,
        block: SharedBlock,
        commands: Any,
        events: Connection,
        options: ProcessOptions,
        parent_pid: int,
    ) -> None:
        self.loop, self.device, self.block = loop, device, block
        self.commands, self.events, self.options = commands, events, options
        self.parent_pid = parent_pid
        self.leaving: str | None = None
        self._last: float | None = None
        self._started_s: float | None = None

    def leave(self, reason: str) -> None:
        """Fade the output out and stop (once)."""
        if self.leaving is None:
            self.leaving = reason
            self.device.fading = True
            self.block.phase = PHASE_STOPPING

    def tick(self, index: int, t_s: float) -> bool:
        keep = self.loop._guarded_tick(index, t_s)
        last, self._last = self._last, t_s
        self.block.ring.record(0.0 if last is None else t_s - last, time.perf_counter() - t_s)
        if index % COMMAND_EVERY == 0:
            self._poll_commands()
        if self.leaving is None:
            self._watch(index, t_s)
        if not keep:
            return False
        return not (self.leaving is not None and self.device.gain <= 0.0)

    def _watch(self, index: int, t_s: float) -> None:
        """The exit checks: the app's heartbeat (once armed) and its presence."""
        block, options = self.block, self.options
        if block.armed:
            silence = block.heartbeat_age_s()
            if silence > block.audit[7]:
                block.audit[7] = silence
            if silence > options.heartbeat_timeout_s:
                self.leave(f"no heartbeat from the app for {options.heartbeat_timeout_s:g} s")
                return
        elif self._started_s is None:
            self._started_s = t_s
        elif t_s - self._started_s > options.arm_timeout_s:
            self.leave(f"the app did not finish starting within {options.arm_timeout_s:g} s")
            return
        if index % PARENT_EVERY == 0 and os.getppid() != self.parent_pid:
            self.leave("the app exited")

    def _poll_commands(self) -> None:
        while True:
            try:
                command = self.commands.get_nowait()
            except (queue.Empty, EOFError, OSError, ValueError):
                return
            self.apply(command)

    def apply(self, command: tuple) -> None:
        kind = command[0]
        if kind == "scale":
            self.loop.set_force_scale(float(command[1]), command[2])
        elif kind == "engage":
            if command[1]:
                self.device.fading, self.device.gain = False, 1.0
                self.loop.safety.reset()  # ramp in again from zero
            else:
                self.device.fading = True
        elif kind == "surface":
            self.loop.contact.set_surface(str(command[1]))  # built beside the loop, then swapped
        elif kind == "stop":
            self.leave("stopped by the app")


def _send(events: Connection, message: tuple) -> None:
    with contextlib.suppress(OSError, ValueError):
        events.send(message)


def child_main(block_name: str, options: ProcessOptions, commands: Any, events: Connection) -> None:
    """The servo process (see the module docstring)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl+C reaches the app; it stops us
    block = SharedBlock(block_name)
    block.pid = os.getpid()
    parent_pid = os.getppid()
    config = options.config
    clock = RealTimeClock(config.tick_s, spin_s=spin_for(Granted(), options.spin_s))
    try:
        target = SharedTarget(block.target, options.start_m)
        raw = build_device(options.device, clock.now_s, target)
        device = GatedDevice(raw, block.audit, config.tick_s / options.exit_fade_s)
        loop = ServoLoop(
            device, SharedForceChannel(block.force), config, SharedStateChannel(block.state)
        )
        loop.open()
    except Exception as exc:
        block.phase = PHASE_FAILED
        _send(events, ("error", type(exc).__name__, str(exc)))
        return
    host = _Host(loop, device, block, commands, events, options, parent_pid)
    signal.signal(signal.SIGTERM, lambda *_: host.leave("terminated"))
    granted = apply_realtime(pin=options.pin) if options.realtime else Granted()
    clock.spin_s = spin_for(granted, options.spin_s)
    heavy = [m for m in HEAVY_MODULES if m in sys.modules]
    described = f"{granted.describe()}, spins {1e6 * clock.spin_s:.0f} us before each tick"
    _send(events, ("ready", described, heavy))
    block.phase = PHASE_RUNNING
    max_ticks = (
        None if options.duration_s is None else max(1, round(options.duration_s / clock.period_s))
    )
    try:
        # One tick before the clock starts: it absorbs the first-time costs (a simulated hand
        # integrating the time since it was opened, first calls into numpy) so that they do not
        # show up as the first timed tick's lateness.
        loop._guarded_tick(0, clock.now_s())
        timing = clock.run(host.tick, max_ticks)
    finally:
        loop.close()  # zero force, device closed
    report = replace(loop.report(), timing=timing)
    if report.device_fault is not None:
        _send(events, ("fault", report.device_fault))
    _send(events, ("report", report, host.leaving, block.audit_counts()))
    block.phase = PHASE_EXITED
    block.close()


class ServoProcess:
    """The app's side of a servo process (see the module docstring).

    Args:
        options: how the child runs.
        heartbeat: beat from a background thread of this process (False: the caller calls
            :meth:`beat`, as a test harness that wants to stop beating does).

    Attributes:
        forces: the channel the painting session publishes into (shared).
        states: the latest device state the child published (canvas frame).
        target: the simulated hand's target (``sim``).
        granted: what the OS granted the child (after :meth:`start`).
        heavy_modules: heavy modules the child had imported (should be empty).
    """

    def __init__(self, options: ProcessOptions | None = None, heartbeat: bool = True) -> None:
        self.options = options or ProcessOptions()
        self.block = SharedBlock()
        self.forces = SharedForceChannel(self.block.force)
        self.states = SharedStateChannel(self.block.state)
        self.target = SharedTarget(self.block.target, self.options.start_m)
        self.target.set_position(self.options.start_m)
        self.block.armed = self.options.arm_at_start
        self.granted = "not started"
        self.heavy_modules: list[str] = []
        self.report: ServoReport | None = None
        self.left_because: str | None = None
        self.final_audit: dict[str, float] | None = None
        ctx = mp.get_context("spawn")
        self._commands = ctx.Queue()
        self._events, self._child_events = ctx.Pipe(duplex=False)
        self._proc = ctx.Process(
            target=child_main,
            args=(self.block.name, self.options, self._commands, self._child_events),
            name="haptic-servo",
            daemon=True,
        )
        self._lock = threading.Lock()
        self._fault: str | None = None
        self._started = self._stopped = self._stopping = False
        self._beating = heartbeat
        self._beat_stop = threading.Event()
        self._beat_thread: threading.Thread | None = None

    @property
    def pid(self) -> int | None:
        """The child's process id (after :meth:`start`)."""
        return self._proc.pid

    def start(self, timeout_s: float = 60.0) -> None:
        """Start the child and wait until it runs.

        Raises:
            DeviceNotFoundError: the child could not open the device.
            RuntimeError: the child failed otherwise or did not start within ``timeout_s``.
        """
        self._proc.start()
        self._child_events.close()
        self._started = True
        if self._beating:
            self._beat_thread = threading.Thread(
                target=self._beat_loop, name="servo-heartbeat", daemon=True
            )
            self._beat_thread.start()
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            message = self._next_event(0.05)
            if message is not None and message[0] == "ready":
                self.granted, self.heavy_modules = message[1], list(message[2])
                return
            if message is not None and message[0] == "error":
                self.stop()
                if message[1] in ("DeviceNotFoundError", "InputError"):
                    raise DeviceNotFoundError(message[2])
                raise RuntimeError(f"servo process failed to start: {message[1]}: {message[2]}")
            if message is None and not self._proc.is_alive():
                self._drain()
                self.stop()
                raise RuntimeError(
                    f"servo process died while starting (exit code {self._proc.exitcode})"
                )
        self.stop()
        raise RuntimeError(f"servo process did not start within {timeout_s:g} s")

    def _beat_loop(self) -> None:
        while not self._beat_stop.wait(BEAT_S):
            self.beat()

    def arm(self) -> None:
        """The app's start-up is over: from now on the child counts the heartbeat's silence
        (see :class:`ProcessOptions`; a no-op when already armed)."""
        if not self._stopped:
            self.block.beat()
            self.block.armed = True

    def beat(self) -> None:
        """Tell the child the app is alive."""
        if not self._stopped:
            self.block.beat()

    def _next_event(self, timeout_s: float = 0.0) -> tuple | None:
        with self._lock:
            try:
                if not self._events.poll(timeout_s):
                    return None
                message = self._events.recv()
            except (EOFError, OSError):
                return None
        self._handle(message)
        return message

    def _handle(self, message: tuple) -> None:
        if message[0] == "fault":
            self._fault = self._fault or str(message[1])
        elif message[0] == "report":
            self.report, self.left_because, self.final_audit = message[1], message[2], message[3]

    def _drain(self) -> None:
        while self._next_event() is not None:
            pass

    @property
    def alive(self) -> bool:
        """Whether the child is running."""
        return self._started and self._proc.is_alive()

    @property
    def fault(self) -> str | None:
        """Why the servo loop is not running (device fault, the child died or left), or None."""
        if not self._started or self._stopping:
            return self._fault
        self._drain()
        if self._fault is None and not self._proc.is_alive():
            self._drain()
            if self._fault is None:
                why = self.left_because or f"exit code {self._proc.exitcode}"
                self._fault = f"servo process stopped ({why})"
        return self._fault

    def command(self, *command: Any) -> None:
        """Queue a command for the child (see :meth:`_Host.apply`)."""
        if self.alive:
            self._commands.put(command)

    def set_force_scale(self, force_scale: float, torque_scale: float | None = None) -> None:
        """Change the force scale (the child takes it within :data:`COMMAND_EVERY` ticks)."""
        self.command("scale", float(force_scale), torque_scale)

    def set_surface(self, surface: str) -> None:
        """Let the canvas contact follow ``surface``'s tooth (the child builds its tile)."""
        self.command("surface", str(surface))

    def engage(self, on: bool) -> None:
        """Fade the output out (False) or ramp it back in (True)."""
        self.command("engage", bool(on))

    def live(self) -> tuple[float, float, int]:
        """(rate Hz, tick-interval jitter p99 ms, ticks seen) over the last two seconds."""
        if self._stopped:
            return 0.0, 0.0, 0
        return self.block.ring.live(self.options.config.tick_s)

    def audit(self) -> dict[str, float]:
        """The device-write audit (live, or final after :meth:`stop`)."""
        if self._stopped:
            return dict(self.final_audit or {})
        return self.block.audit_counts()

    def stop(self, timeout_s: float = 5.0) -> ServoReport | None:
        """Stop the child (it fades out and exits with zero force) and free the shared block."""
        if self._stopped:
            return self.report
        self._stopping = True
        if self._started:
            if self._proc.is_alive():
                with contextlib.suppress(OSError, ValueError):
                    self._commands.put(("stop",))
            end = time.monotonic() + timeout_s
            while self._proc.is_alive() and time.monotonic() < end:
                self._next_event(0.05)
            if self._proc.is_alive():
                self._proc.terminate()
                self._proc.join(1.0)
            if self._proc.is_alive():
                self._proc.kill()
            self._proc.join(1.0)
            self._drain()
            if self.final_audit is None:
                self.final_audit = self.block.audit_counts()
        self._beat_stop.set()
        if self._beat_thread is not None:
            self._beat_thread.join(1.0)
        self._stopped = True
        self._commands.cancel_join_thread()
        self._commands.close()
        self._events.close()
        self.block.close()
        return self.report
