"""The 1 kHz servo loop: read the device, compute the force, make it safe, write the device.

Per tick (:meth:`ServoLoop.tick`):

1. read the device; estimate the tip velocity from timestamped positions;
2. publish the state (canvas frame: z = 0 on the canvas) for the painting session;
3. force = canvas contact (spring-damper below the canvas plane)
   + force scale x filtered fluid force (latest sample the simulation published, watchdog);
   torque = torque scale x filtered fluid torque where the device outputs torque;
4. pass both through :class:`ForceSafety` and write them;
5. log the tick.

The loop never calls the solver. A device that fails (read/write error, unplugged, or any other
exception from its driver) stops the loop: the fault is kept in the report, zero force is written
if the device still answers, and the tick log keeps everything recorded up to the failure.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass, field, replace

import numpy as np

from paintapp.haptics.channel import ForceChannel, StateChannel
from paintapp.haptics.clock import Clock, RealTimeClock
from paintapp.haptics.contact import CanvasContact, ContactConfig
from paintapp.haptics.device import DeviceError, DeviceState, HapticDevice
from paintapp.haptics.filters import FilterConfig
from paintapp.haptics.fluid import FluidConfig, FluidForceInput
from paintapp.haptics.metrics import TimingReport
from paintapp.haptics.safety import ForceSafety, SafetyConfig
from paintapp.haptics.tick_log import TickLog
from paintapp.haptics.velocity import VelocityEstimator

_ZERO3 = np.zeros(3)
_ZERO3.flags.writeable = False


@dataclass(frozen=True)
class ServoConfig:
    """Everything the servo loop is configured with.

    Attributes:
        tick_s: servo period in seconds (1 ms).
        filter: the reconstruction filter for the fluid force.
        fluid: force scale and watchdog.
        safety: ramp, engage and rate limits.
        contact: canvas plane and wall gains.
        velocity_tau_s: velocity estimator time constant.
        record: keep a per-tick log.
    """

    tick_s: float = 1e-3
    filter: FilterConfig = field(default_factory=FilterConfig)
    fluid: FluidConfig = field(default_factory=FluidConfig)
    safety: SafetyConfig = field(default_factory=SafetyConfig)
    contact: ContactConfig = field(default_factory=ContactConfig)
    velocity_tau_s: float = 5e-3
    record: bool = True


@dataclass(frozen=True)
class ServoReport:
    """How a run ended and what happened in it.

    Attributes:
        ticks: ticks executed by this loop so far.
        timing: the clock's timing figures for the last run (None if not run by a clock).
        safety: safety event counts (non-finite, clamped, rate-limited, faults).
        fluid: fluid path counts (fresh samples, rejected, watchdog trips).
        device_fault: the device error that stopped the loop, or None.
        stopped_by: "limit" (duration/ticks/stop request), "device fault" or "device finished".
    """

    ticks: int
    timing: TimingReport | None
    safety: dict[str, int]
    fluid: dict[str, int]
    device_fault: str | None
    stopped_by: str


class ServoLoop:
    """Runs the haptic servo for one device.

    Args:
        device: the device (opened by :meth:`open` or the context manager).
        forces: the channel the simulation publishes into; a new one if None.
        config: servo configuration.
        states: the channel the loop publishes device states into; a new one if None.
    """

    def __init__(
        self,
        device: HapticDevice,
        forces: ForceChannel | None = None,
        config: ServoConfig | None = None,
        states: StateChannel | None = None,
    ) -> None:
        self.device = device
        self.forces = forces if forces is not None else ForceChannel()
        self.states = states if states is not None else StateChannel()
        self.config = config or ServoConfig()
        self.log = TickLog()
        self.ticks = 0
        self.device_fault: str | None = None
        self.finished = False
        self._opened = False
        self._last_t_s: float | None = None
        self._clock: RealTimeClock | None = None
        self._timing: TimingReport | None = None

    def open(self) -> None:
        """Open the device and set up the force path from its capabilities."""
        self.device.open()
        self._opened = True
        info = self.device.info
        cfg = self.config
        self.safety = ForceSafety(info, cfg.safety)
        self.contact = CanvasContact(info, cfg.contact, cfg.tick_s)
        # no torque output: filter the force alone (no torque work in the loop)
        dim = 6 if info.has_torque else 3
        self.fluid = FluidForceInput(
            self.forces, cfg.filter.build(cfg.tick_s, dim), cfg.fluid, info.max_force_n
        )
        self.velocity = VelocityEstimator(cfg.velocity_tau_s)
        self._has_force = info.has_force
        self._has_torque = info.has_torque
        self._canvas_origin = np.array([0.0, 0.0, cfg.contact.height_m])
        # A 2-DOF device (joystick) pushes in x and y only: drop z before the safety stage.
        self._drop_z = info.dof_actuated == 2

    def close(self) -> None:
        """Stop any background run and close the device (it outputs zero force)."""
        self.stop()
        if self._opened:
            self._opened = False
            try:
                self.device.close()
            except (DeviceError, OSError) as exc:
                self.device_fault = self.device_fault or f"close failed: {exc}"

    def __enter__(self) -> ServoLoop:
        self.open()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def set_force_scale(self, force_scale: float, torque_scale: float | None = None) -> None:
        """Change the user-set force scale while the loop runs (from any thread)."""
        self.config = replace(
            self.config,
            fluid=replace(self.config.fluid, force_scale=force_scale, torque_scale=torque_scale),
        )
        fluid = getattr(self, "fluid", None)
        if fluid is not None:
            fluid.set_scale(force_scale, torque_scale)

    def _fail(self, exc: Exception) -> bool:
        self.device_fault = f"{type(exc).__name__}: {exc}"
        self.safety.fault()
        try:
            self.device.write(_ZERO3, _ZERO3)
        except Exception:  # the device is gone or broken: nothing more to tell it
            pass
        return False

    def _guarded_tick(self, _index: int, t_s: float) -> bool:
        """A tick that never lets an exception escape the clock: any error stops the loop."""
        try:
            return self.tick(t_s)
        except Exception as exc:
            return self._fail(exc)

    def _dt(self, t_s: float) -> float:
        last, self._last_t_s = self._last_t_s, t_s
        if last is None:
            return self.config.tick_s
        dt = t_s - last
        return min(max(dt, 0.0), 0.1) if math.isfinite(dt) else 0.0

    def tick(self, t_s: float) -> bool:
        """One servo tick at clock time ``t_s`` seconds; False when the loop must stop."""
        if self.device_fault is not None or self.finished:
            return False
        dt = self._dt(t_s)
        try:
            state = self.device.read()
        except Exception as exc:  # any driver failure stops the loop with zero force
            return self._fail(exc)
        velocity = self.velocity.update(state.t_s, state.position_m)
        self._publish(state, velocity)
        contact = self.contact.force(state.position_m, velocity) if self._has_force else _ZERO3
        fluid_f, fluid_t = self.fluid.update(t_s, dt)
        if not self._has_force:
            fluid_f = _ZERO3
        if not self._has_torque:
            fluid_t = _ZERO3
        total = contact + fluid_f
        if self._drop_z:
            total[2] = 0.0
        force, torque = self.safety.apply(total, fluid_t, dt)
        try:
            self.device.write(force, torque)
        except Exception as exc:
            return self._fail(exc)
        self.ticks += 1
        if self.config.record:
            self._record(t_s, state, velocity, contact, fluid_f, fluid_t, force, torque)
        if getattr(self.device, "finished", False):
            self.finished = True
            return False
        return True

    def _publish(self, state: DeviceState, velocity: np.ndarray) -> None:
        position = state.position_m - self._canvas_origin
        pressure = state.pressure
        if self._has_force:
            pressure = max(pressure, self.contact.pressure(state.position_m))
        self.states.publish(
            DeviceState(
                state.t_s, position, state.orientation_wxyz, pressure, state.buttons, velocity
            )
        )

    def _record(self, t_s: float, state: DeviceState, *vectors: np.ndarray) -> None:
        row = self.log.next_row()
        row[0] = t_s
        row[1:4] = state.position_m
        for i, v in enumerate(vectors):
            row[4 + 3 * i : 7 + 3 * i] = v

    def run(
        self,
        clock: Clock,
        duration_s: float | None = None,
        max_ticks: int | None = None,
        stop: threading.Event | None = None,
    ) -> ServoReport:
        """Run ticks on ``clock`` (opening the device if needed) until a limit, a stop request,
        a device fault or the device's end; the device stays open."""
        if not self._opened:
            self.open()
        if duration_s is not None:
            ticks = max(1, round(duration_s / clock.period_s))
            max_ticks = ticks if max_ticks is None else min(max_ticks, ticks)
        self._timing = clock.run(self._guarded_tick, max_ticks, stop)
        return self.report()

    def start(self, clock: RealTimeClock, duration_s: float | None = None) -> None:
        """Run on a real-time clock in its background thread; :meth:`stop` ends it."""
        if not self._opened:
            self.open()
        max_ticks = None if duration_s is None else max(1, round(duration_s / clock.period_s))
        self._clock = clock
        clock.start(self._guarded_tick, max_ticks)

    def stop(self) -> ServoReport:
        """Stop a background run (if any) and return the report."""
        if self._clock is not None:
            self._timing = self._clock.stop()
            self._clock = None
        return self.report()

    def report(self) -> ServoReport:
        """The current report."""
        opened = hasattr(self, "safety")
        if self.device_fault is not None:
            stopped_by = "device fault"
        elif self.finished:
            stopped_by = "device finished"
        else:
            stopped_by = "limit"
        return ServoReport(
            ticks=self.ticks,
            timing=self._timing,
            safety=self.safety.counters() if opened else {},
            fluid=self.fluid.counters() if opened else {},
            device_fault=self.device_fault,
            stopped_by=stopped_by,
        )
