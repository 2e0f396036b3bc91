"""In-memory HID device models: the device side of both protocols, for tests without hardware.

Each model implements :class:`HidTransport` and decodes the reports the way firmware would:
:class:`StylusDeviceModel` is a 6-DOF stylus whose mechanics are a :class:`SimulatedDevice` (so a
servo loop over HID closes the same physical loop as the simulated device), with the device-side
duties of the protocol -- enable flag, own force limits, output watchdog. :class:`PidJoystickModel`
is a two-axis force-feedback joystick that keeps PID effect blocks and exposes the force its
motors would produce. Both send input reports at 1 kHz of their ``time_source`` and can be
unplugged, after which every call fails as hidapi does (``OSError``).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable

import numpy as np

from paintapp.haptics.device import DeviceInfo
from paintapp.haptics.devices import hid_pid as pid
from paintapp.haptics.devices import hid_stylus as sty
from paintapp.haptics.devices.simulated import SimulatedDevice


class _ReportSource:
    """Input reports generated once per ``period_s`` of device time, queued (at most 8)."""

    def __init__(self, time_source: Callable[[], float], period_s: float = 1e-3) -> None:
        self.time_source = time_source
        self.period_s = period_s
        self.queue: deque[bytes] = deque(maxlen=8)
        self.plugged = True
        self.silent = False  # True: the device stops sending input reports (but still answers)
        self._next_s: float | None = None

    def unplug(self) -> None:
        """Simulate pulling the cable: every later call raises ``OSError``."""
        self.plugged = False

    def _check(self) -> None:
        if not self.plugged:
            raise OSError("read error")

    def make_report(self) -> bytes:  # pragma: no cover - overridden
        raise NotImplementedError

    def read(self, size: int, timeout_ms: int = 0) -> bytes:
        self._check()
        now = self.time_source()
        if self._next_s is None:
            self._next_s = now
        while self._next_s <= now + 1e-12:
            if not self.silent:
                self.queue.append(self.make_report())
            self._next_s += self.period_s
        return self.queue.popleft()[:size] if self.queue else b""

    def close(self) -> None:
        self.queue.clear()


class StylusDeviceModel(_ReportSource):
    """A raw-protocol 6-DOF stylus around simulated mechanics.

    Args:
        mechanics: the simulated hand and stylus (opened by the model).
        watchdog_ms: output watchdog the device enforces.
    """

    def __init__(self, mechanics: SimulatedDevice, watchdog_ms: int = 50) -> None:
        super().__init__(mechanics.time_source)
        self.mechanics = mechanics
        self.info: DeviceInfo = mechanics.info
        self.watchdog_ms = watchdog_ms
        self.enabled = False
        self.fault = False  # True: the device reports a fault (e.g. an emergency stop)
        self.applied_force_n = np.zeros(3)
        self.applied_torque_nm = np.zeros(3)
        self.max_applied_force_n = 0.0
        self.output_reports = 0
        self._seq = 0
        self._last_output_s: float | None = None
        mechanics.open()

    def _watchdog_expired(self) -> bool:
        last = self._last_output_s
        return last is None or self.time_source() - last > self.watchdog_ms * 1e-3

    def make_report(self) -> bytes:
        if self._watchdog_expired() and np.any(self.applied_force_n):
            self._apply(np.zeros(3), np.zeros(3))
        state = self.mechanics.read()
        self._seq += 1
        status = (
            (sty.STATUS_ENABLED if self.enabled else 0)
            | (sty.STATUS_WATCHDOG if self._watchdog_expired() else 0)
            | (sty.STATUS_FAULT if self.fault else 0)
        )
        pressure = min(max(-float(state.position_m[2]) / 0.004, 0.0), 1.0)
        return sty.encode_input(
            sty.StylusInput(
                self._seq,
                0,
                status,
                int(self.time_source() * 1e6),
                state.position_m,
                state.orientation_wxyz,
                pressure,
            )
        )

    def _apply(self, force: np.ndarray, torque: np.ndarray) -> None:
        def clamp(v: np.ndarray, limit: float) -> np.ndarray:
            n = float(np.linalg.norm(v))
            return v * (limit / n) if n > limit else v

        self.applied_force_n = clamp(force, self.info.max_force_n)
        self.applied_torque_nm = clamp(torque, self.info.max_torque_nm)
        self.max_applied_force_n = max(self.max_applied_force_n, float(np.linalg.norm(force)))
        self.mechanics.write(self.applied_force_n, self.applied_torque_nm)

    def write(self, report: bytes) -> int:
        self._check()
        decoded = sty.decode_output(bytes(report))
        if decoded is None:
            return -1
        _, flags, force, torque = decoded
        self.enabled = bool(flags & sty.FLAG_ENABLE)
        self._last_output_s = self.time_source()
        self.output_reports += 1
        if not self.enabled:
            force, torque = np.zeros(3), np.zeros(3)
        self._apply(force, torque)
        return len(report)

    def get_feature_report(self, report_id: int, size: int) -> bytes:
        self._check()
        if report_id != sty.INFO_ID:
            return b""
        return sty.encode_info(self.info, 1000, self.watchdog_ms)[:size]

    def send_feature_report(self, report: bytes) -> int:
        self._check()
        return -1

    def report_descriptor(self) -> bytes:
        return sty.REPORT_DESCRIPTOR


def _item(prefix: int, value: int, size: int) -> list[int]:
    code = {0: 0, 1: 1, 2: 2, 4: 3}[size]
    return [prefix | code, *value.to_bytes(size, "little", signed=value < 0)] if size else [prefix]


def _bytes_report(kind_prefix: int, report_id: int, usage: int, payload: int) -> list[int]:
    """A PID-page report declared as ``payload`` opaque bytes (sizes are what matter here)."""
    return [
        *_item(0x85, report_id, 1),
        *_item(0x09, usage, 1),
        *_item(0xA1, 0x02, 1),  # Collection (Logical)
        *_item(0x09, usage, 1),
        *_item(0x15, 0, 1),
        *_item(0x26, 255, 2),
        *_item(0x75, 8, 1),
        *_item(0x95, payload, 1),
        *_item(kind_prefix, 0x02, 1),
        0xC0,
    ]


def joystick_pid_descriptor(layout: pid.PidLayout | None = None) -> bytes:
    """Report descriptor of :class:`PidJoystickModel`: report 1 = X, Y (16-bit signed) and
    8 buttons; the PID reports of ``layout`` on usage page 0x0F."""
    lay = layout or pid.PidLayout()
    d = [*_item(0x05, 0x01, 1), *_item(0x09, 0x04, 1), *_item(0xA1, 0x01, 1)]
    d += [*_item(0x85, 1, 1), *_item(0x09, 0x30, 1), *_item(0x09, 0x31, 1)]
    d += [*_item(0x16, -32767, 2), *_item(0x26, 32767, 2), *_item(0x75, 16, 1)]
    d += [*_item(0x95, 2, 1), *_item(0x81, 0x02, 1)]
    d += [*_item(0x05, 0x09, 1), *_item(0x19, 1, 1), *_item(0x29, 8, 1)]
    d += [*_item(0x15, 0, 1), *_item(0x25, 1, 1), *_item(0x75, 1, 1), *_item(0x95, 8, 1)]
    d += [*_item(0x81, 0x02, 1), *_item(0x05, 0x0F, 1)]
    outputs = {
        lay.set_effect_id: 0x21,
        lay.set_constant_force_id: 0x73,
        lay.effect_operation_id: 0x77,
        lay.block_free_id: 0x90,
        lay.device_control_id: 0x96,
        lay.device_gain_id: 0x7D,
    }
    for report_id, size in lay.outputs().items():
        d += _bytes_report(0x91, report_id, outputs[report_id], size)
    d += _bytes_report(0xB1, lay.create_new_effect_id, 0xAB, pid.CREATE_NEW_EFFECT.size - 1)
    d += _bytes_report(0xB1, lay.block_load_id, 0x89, pid.BLOCK_LOAD.size - 1)
    return bytes([*d, 0xC0])


class PidJoystickModel(_ReportSource):
    """A two-axis force-feedback joystick speaking HID PID (constant-force effects only).

    Args:
        time_source: the device's clock, s.
        max_force_n: force at full magnitude and full gains, N.
        layout: its report IDs (the host must use the same).
        max_effects: effect blocks available.
    """

    def __init__(
        self,
        time_source: Callable[[], float],
        max_force_n: float = 2.0,
        layout: pid.PidLayout | None = None,
        max_effects: int = 4,
    ) -> None:
        super().__init__(time_source)
        self.layout = layout or pid.PidLayout()
        self.max_force_n = max_force_n
        self.max_effects = max_effects
        self.effects: dict[int, dict[str, int]] = {}
        self.actuators_enabled = False
        self.device_gain = 255
        self.stick = (0.0, 0.0)
        self.buttons = 0
        self.reports_written = 0
        self._last_load = (0, pid.LOAD_ERROR)

    def make_report(self) -> bytes:
        x, y = (round(max(-1.0, min(1.0, float(v))) * 32767) for v in self.stick)
        return (
            bytes([1])
            + x.to_bytes(2, "little", signed=True)
            + y.to_bytes(2, "little", signed=True)
            + bytes([self.buttons & 0xFF])
        )

    def applied_force_n(self) -> np.ndarray:
        """The (x, y) force the motors produce now, N."""
        total = np.zeros(2)
        if not self.actuators_enabled:
            return total
        for e in self.effects.values():
            if e.get("playing") and e.get("type") == pid.EFFECT_CONSTANT:
                size = e.get("magnitude", 0) / self.layout.magnitude_max
                gain = e.get("gain", 255) / 255 * self.device_gain / 255
                total += size * gain * self.max_force_n * pid.direction_vector(e.get("dir", 0))
        return total

    def write(self, report: bytes) -> int:
        self._check()
        self.reports_written += 1
        handler = {
            self.layout.set_effect_id: self._set_effect,
            self.layout.set_constant_force_id: self._set_constant,
            self.layout.effect_operation_id: self._operation,
            self.layout.block_free_id: lambda r: self.effects.pop(r[1], None),
            self.layout.device_control_id: self._control,
            self.layout.device_gain_id: lambda r: setattr(self, "device_gain", r[1]),
        }.get(report[0])
        if handler is None:
            return -1
        handler(bytes(report))
        return len(report)

    def _block(self, index: int) -> dict[str, int]:
        if index not in self.effects:
            raise OSError(f"effect block {index} does not exist")  # firmware would STALL
        return self.effects[index]

    def _set_effect(self, r: bytes) -> None:
        f = pid.SET_EFFECT.unpack_from(r)
        self._block(f[1]).update(type=f[2], gain=f[6], dir=f[9])

    def _set_constant(self, r: bytes) -> None:
        _, block, magnitude = pid.SET_CONSTANT_FORCE.unpack_from(r)
        self._block(block)["magnitude"] = max(
            -self.layout.magnitude_max, min(self.layout.magnitude_max, magnitude)
        )

    def _operation(self, r: bytes) -> None:
        _, block, op, _ = pid.EFFECT_OPERATION.unpack_from(r)
        if op == pid.OP_START_SOLO:
            for e in self.effects.values():
                e["playing"] = 0
        self._block(block)["playing"] = int(op in (pid.OP_START, pid.OP_START_SOLO))

    def _control(self, r: bytes) -> None:
        if r[1] == pid.CTRL_ENABLE:
            self.actuators_enabled = True
        elif r[1] == pid.CTRL_DISABLE:
            self.actuators_enabled = False
        elif r[1] == pid.CTRL_STOP_ALL:
            for e in self.effects.values():
                e["playing"] = 0
        elif r[1] == pid.CTRL_RESET:
            self.effects.clear()
            self.actuators_enabled = False

    def send_feature_report(self, report: bytes) -> int:
        self._check()
        if report[0] != self.layout.create_new_effect_id:
            return -1
        free = [i for i in range(1, self.max_effects + 1) if i not in self.effects]
        if not free:
            self._last_load = (0, pid.LOAD_FULL)
        else:
            self.effects[free[0]] = {"type": report[1], "magnitude": 0, "playing": 0}
            self._last_load = (free[0], pid.LOAD_SUCCESS)
        return len(report)

    def get_feature_report(self, report_id: int, size: int) -> bytes:
        self._check()
        if report_id != self.layout.block_load_id:
            return b""
        return pid.BLOCK_LOAD.pack(report_id, *self._last_load, 0xFFFF)[:size]

    def report_descriptor(self) -> bytes:
        return joystick_pid_descriptor(self.layout)
