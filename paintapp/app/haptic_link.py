"""The haptic side of the app: the device, the 1 kHz servo loop (process or thread), its timing.

``--device`` chooses the input route:

- ``none``: no haptic device; the tablet or mouse feeds the painting session directly.
- ``sim``: a :class:`~paintapp.haptics.devices.simulated.SimulatedDevice` whose hand follows the
  pointer: pen up, it hovers 5 mm above the canvas; pen down, it pushes the tip into the paint as
  deep as the pen's pressure asks. The force the loop writes acts back on the hand.
- ``hid:VID:PID`` (``hid:VID:PID:pid`` for a force-feedback joystick): a HID device.
- ``openhaptics[:NAME]``, ``dhd``, ``haply[:ID]``: a vendor backend
  (:mod:`~paintapp.haptics.devices.backends`).

With a device the servo loop runs by default in a process of its own
(:class:`~paintapp.haptics.process.ServoProcess`: it owns the device; shared memory carries forces,
device states, the hand's target and tick timings), so the GUI and simulation never hold it up.
The thread form (``mode="thread"``) runs it here on a :class:`MeteredClock` (a
:class:`~paintapp.haptics.clock.RealTimeClock` keeping the last ticks' intervals). Either way the
simulation worker turns the latest published pose into stylus samples (:func:`sample_from_state`).
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from brushes import StylusSample
from common.errors import InputError
from paintapp.haptics.channel import ForceChannel, StateChannel
from paintapp.haptics.clock import RealTimeClock
from paintapp.haptics.device import DeviceNotFoundError, DeviceState, HapticDevice
from paintapp.haptics.devices.backends import (
    VENDOR_NAMES,
    VENDOR_SYNTAX,
    build_vendor_device,
    split_device,
)
from paintapp.haptics.devices.hid import HidDevice
from paintapp.haptics.devices.hid_transport import open_hid, parse_ids
from paintapp.haptics.devices.simulated import SimulatedDevice
from paintapp.haptics.metrics import interval_stats
from paintapp.haptics.orientation import tilt_twist_from_quat
from paintapp.haptics.process import ProcessOptions, ServoProcess
from paintapp.haptics.servo import ServoConfig, ServoLoop, ServoReport

#: Height the simulated hand hovers above the canvas with the pen up, m.
HOVER_M = 0.005
#: How deep (m) the simulated hand pushes the tip below the paint at full pressure.
PRESS_M = 0.002
#: Ring buffer of tick intervals kept for the live figures.
METER_TICKS = 2000


@dataclass(frozen=True)
class DeviceSpec:
    """A parsed ``--device`` value: ``kind`` is "none", "sim", "hid" or a vendor backend's name
    (``arg`` then holds what follows the colon)."""

    kind: str
    vendor_id: int | None = None
    product_id: int | None = None
    protocol: str = "stylus"
    arg: str = ""

    @property
    def label(self) -> str:
        """Short text for the HUD."""
        if self.kind == "hid":
            return f"hid {self.vendor_id:04x}:{self.product_id:04x} ({self.protocol})"
        if self.kind in VENDOR_NAMES:
            return f"{self.kind} {self.arg}".strip()
        return {"none": "tablet/mouse", "sim": "simulated haptic stylus"}[self.kind]


def parse_device(text: str) -> DeviceSpec:
    """Parse ``none``, ``sim``, ``hid:VID:PID[:stylus|pid]`` or a vendor backend
    (``openhaptics[:NAME]``, ``dhd``, ``haply[:ID]``); :class:`InputError` otherwise."""
    if text in ("none", "sim"):
        return DeviceSpec(text)
    try:
        vendor = split_device(text)
    except DeviceNotFoundError as exc:
        raise InputError(str(exc), key="--device") from exc
    if vendor is not None:
        return DeviceSpec(vendor[0], arg=vendor[1])
    parts = text.split(":")
    if parts[0] != "hid" or len(parts) not in (3, 4):
        raise InputError(
            f"expected none, sim, hid:VID:PID (hex) or {VENDOR_SYNTAX}, got {text!r}",
            key="--device",
        )
    vid, pid = parse_ids(f"{parts[1]}:{parts[2]}")
    protocol = parts[3] if len(parts) == 4 else "stylus"
    if protocol not in ("stylus", "pid"):
        raise InputError(f"expected protocol stylus or pid, got {protocol!r}", key="--device")
    return DeviceSpec("hid", vid, pid, protocol)


class PointerTarget:
    """The simulated hand's target: the latest pointer position (thread-safe latest value).

    Canvas-frame metres; the device frame equals the canvas frame (the canvas plane at z = 0).
    ``sink`` also receives every new position (the process form's shared target).
    """

    def __init__(
        self, x_m: float = 0.0, y_m: float = 0.0, sink: Callable[[np.ndarray], None] | None = None
    ) -> None:
        self._lock = threading.Lock()
        self._pos = np.array([x_m, y_m, HOVER_M])
        self._sink = sink

    def set(self, x_m: float, y_m: float, pressure: float, down: bool) -> None:
        """Aim at (x, y); pen down pushes ``pressure * PRESS_M`` below the canvas plane."""
        z = -PRESS_M * pressure if down else HOVER_M
        if not all(math.isfinite(v) for v in (x_m, y_m, z)):
            return
        with self._lock:
            self._pos = np.array([x_m, y_m, z])
            if self._sink is not None:  # the servo process's shared target
                self._sink(self._pos)

    def __call__(self, _t_s: float) -> tuple[np.ndarray, np.ndarray]:
        with self._lock:
            return self._pos.copy(), np.zeros(3)


class MeteredClock(RealTimeClock):
    """A real-time clock that also keeps the intervals between its last ticks' starts."""

    def __init__(self, period_s: float = 1e-3) -> None:
        super().__init__(period_s)
        self._intervals = np.zeros(METER_TICKS)
        self._count = 0
        self._last: float | None = None

    def start(self, tick, max_ticks: int | None = None) -> None:  # type: ignore[override]
        """Start the background thread; each tick's start time is metered."""

        def metered(index: int, t_s: float) -> bool:
            if self._last is not None:
                self._intervals[self._count % METER_TICKS] = t_s - self._last
                self._count += 1
            self._last = t_s
            return tick(index, t_s)

        super().start(metered, max_ticks)

    def live(self) -> tuple[float, float, int]:
        """(rate Hz, jitter p99 ms, intervals seen) over the last ticks; jitter is the 99th
        percentile of |interval - period|."""
        n = min(self._count, METER_TICKS)
        if n < 2:
            return 0.0, 0.0, n
        rate, jitter = interval_stats(self._intervals[:n].copy(), self.period_s)
        return rate, jitter, n


def make_device(spec: DeviceSpec, clock: RealTimeClock, target: PointerTarget) -> HapticDevice:
    """The device ``spec`` names, not yet opened."""
    if spec.kind == "sim":
        return SimulatedDevice(clock.now_s, target=target, tilt_rad=(0.0, 0.0))
    if spec.kind == "hid":
        vid, pid = spec.vendor_id, spec.product_id
        return HidDevice(lambda: open_hid(vid, pid), spec.protocol, clock.now_s)
    if spec.kind in VENDOR_NAMES:
        return build_vendor_device(spec.kind, spec.arg, clock.now_s)
    raise InputError("no device to open", key="--device")


class HapticLink:
    """A device and its 1 kHz servo loop: in a process of its own (``mode="process"``, the
    default) or in a background thread of the app (``mode="thread"``).

    Both forms offer the same surface: :attr:`forces` (the channel the painting session
    publishes into), :attr:`states` (the latest device state), :attr:`target` (the simulated
    hand's), :meth:`live`, :attr:`fault`, :attr:`granted`, :meth:`set_force_scale`,
    :meth:`start` and :meth:`stop`.

    Args:
        spec: the device.
        forces: the channel the painting session publishes into (thread form; the process form
            brings its shared one).
        force_scale: the initial force scale.
        target: the simulated hand's target (``sim`` only; thread form).
        mode: "process" or "thread".
        armed: the servo process's heartbeat watchdog counts from the start; False: from
            :meth:`arm` (a window arms it once its first frame is drawn and its simulation
            prepared: shader and kernel compilation hold the interpreter lock for seconds).
        surface: the canvas surface whose tooth the canvas contact follows
            (:mod:`paintapp.haptics.contact`; :meth:`set_surface` changes it).
    """

    def __init__(
        self,
        spec: DeviceSpec,
        forces: ForceChannel | None = None,
        force_scale: float = 4.0,
        target: PointerTarget | None = None,
        mode: str = "process",
        armed: bool = True,
        surface: str = "smooth",
    ) -> None:
        if mode not in ("process", "thread"):
            raise InputError(f"expected servo mode process or thread, got {mode!r}", key="servo")
        self.spec = spec
        self.mode = mode
        config = ServoConfig(record=False)
        config = replace(config, fluid=replace(config.fluid, force_scale=force_scale))
        config = replace(config, contact=replace(config.contact, surface=surface))
        self.process: ServoProcess | None = None
        self.loop: ServoLoop | None = None
        self.report: ServoReport | None = None
        if mode == "process":
            options = ProcessOptions(device=device_text(spec), config=config, arm_at_start=armed)
            self.process = ServoProcess(options)
            self.target = PointerTarget(sink=self.process.target.set_position)
            self.forces: ForceChannel = self.process.forces
            self.states: StateChannel = self.process.states
            self.granted = "not started"
        else:
            self.target = target or PointerTarget()
            self.clock = MeteredClock()
            device = make_device(spec, self.clock, self.target)
            self.loop = ServoLoop(device, forces or ForceChannel(), config)
            self.forces, self.states = self.loop.forces, self.loop.states
            self.granted = "thread in the app process (no priority change)"
        self.started_at = time.perf_counter()

    def start(self) -> None:
        """Open the device and start the loop (DeviceNotFoundError if it cannot be opened)."""
        if self.process is not None:
            self.process.start()
            self.granted = self.process.granted
        elif self.loop is not None:
            self.loop.start(self.clock)

    def set_surface(self, surface: str) -> None:
        """Let the canvas contact follow ``surface``'s tooth from now on (a new canvas)."""
        if self.process is not None:
            self.process.set_surface(surface)
        elif self.loop is not None and hasattr(self.loop, "contact"):
            self.loop.contact.set_surface(surface)

    def arm(self) -> None:
        """The app is up: the servo process's heartbeat watchdog counts from now (the thread
        form has none)."""
        if self.process is not None:
            self.process.arm()

    def stop(self) -> ServoReport | None:
        """Stop the loop and close the device (zero force); the final report (kept, so a second
        call returns the same)."""
        if self.report is not None:
            return self.report
        if self.process is not None:
            self.report = self.process.stop()
        elif self.loop is not None:
            self.report = self.loop.stop()
            self.loop.close()
        return self.report

    @property
    def fault(self) -> str | None:
        """Why the servo loop stopped on its own (device failure, servo process died), or None."""
        if self.process is not None:
            return self.process.fault
        return self.loop.device_fault if self.loop is not None else None

    def live(self) -> tuple[float, float, int]:
        """(rate Hz, tick-interval jitter p99 ms, intervals seen) over the last ticks."""
        if self.process is not None:
            return self.process.live()
        return self.clock.live()

    def set_force_scale(self, scale: float) -> None:
        """Change the force scale while running (the loop takes it at its next tick, or within
        a few ticks in the process form)."""
        if not (math.isfinite(scale) and 0.0 <= scale <= 20.0):
            raise InputError(f"expected a force scale in [0, 20], got {scale}", key="force_scale")
        if self.process is not None:
            self.process.set_force_scale(scale)
        elif self.loop is not None:
            self.loop.set_force_scale(scale)


def device_text(spec: DeviceSpec) -> str:
    """The servo process's description of ``spec`` (it builds the device itself)."""
    if spec.kind == "sim":
        return "sim"
    if spec.kind == "hid":
        return f"hid:{spec.vendor_id:04x}:{spec.product_id:04x}:{spec.protocol}"
    if spec.kind in VENDOR_NAMES:
        return f"{spec.kind}:{spec.arg}" if spec.arg else spec.kind
    raise InputError("no device to open", key="--device")


def sample_from_state(state: DeviceState, t_s: float) -> StylusSample | None:
    """A haptic stylus sample (canvas frame) from a device state, or None if it is unusable."""
    pos = np.asarray(state.position_m, np.float64)
    if not np.all(np.isfinite(pos)):
        return None
    try:
        tilt, twist = tilt_twist_from_quat(state.orientation_wxyz)
    except (ValueError, ZeroDivisionError, FloatingPointError):
        tilt, twist = np.zeros(2), 0.0
    limit = 0.5 * math.pi - 1e-6
    tilt = np.clip(np.nan_to_num(tilt), -limit, limit)
    twist = float(twist) if math.isfinite(twist) else 0.0
    pressure = float(np.clip(np.nan_to_num(state.pressure), 0.0, 1.0))
    return StylusSample(t_s, pos, pressure, tilt, twist, int(state.buttons) & 0xFF)
