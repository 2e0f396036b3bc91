"""A HID haptic device: a transport plus one of the two protocols, as a :class:`HapticDevice`.

``HidDevice(opener, "stylus")`` speaks the raw 6-DOF stylus protocol
(:mod:`paintapp.haptics.devices.hid_stylus`); ``HidDevice(opener, "pid")`` drives a force-feedback
joystick through HID PID (:mod:`paintapp.haptics.devices.hid_pid`). ``opener`` returns an open
:class:`HidTransport`: :func:`paintapp.haptics.devices.hid_transport.open_hid` for hardware, or an
in-memory model from :mod:`tests.support.hid_models` in tests.

Timestamps: stylus readings carry the device's microsecond clock, unwrapped and mapped onto the
host clock (re-synchronized if the two drift apart by more than 20 ms), which keeps USB jitter
out of the velocity estimate; joystick readings are stamped on arrival. A device that sends no
input report for ``input_timeout_s`` is treated as failed.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import numpy as np

from paintapp.haptics.device import DeviceError, DeviceInfo, DeviceNotFoundError, DeviceState
from paintapp.haptics.devices.hid_pid import JoystickInput, PidConfig, PidDriver
from paintapp.haptics.devices.hid_stylus import StylusDriver, StylusInput
from paintapp.haptics.devices.hid_transport import HidTransport

PROTOCOLS = ("stylus", "pid")
_RESYNC_S = 0.02


class DeviceClock:
    """Maps a wrapping 32-bit microsecond device clock onto the host's seconds."""

    def __init__(self) -> None:
        self._last_us: int | None = None
        self._device_s = 0.0
        self._offset_s = 0.0

    def host_time(self, timestamp_us: int, host_now_s: float) -> float:
        """Host time of a reading stamped ``timestamp_us`` that arrived at ``host_now_s``."""
        first = self._last_us is None
        if first:
            self._device_s = timestamp_us * 1e-6
        else:
            self._device_s += ((timestamp_us - (self._last_us or 0)) % 2**32) * 1e-6
        self._last_us = timestamp_us
        t = self._device_s + self._offset_s
        if first or abs(t - host_now_s) > _RESYNC_S or t > host_now_s:
            self._offset_s = host_now_s - self._device_s
            t = host_now_s
        return t


class HidDevice:
    """A HID device as a :class:`HapticDevice`.

    Args:
        opener: returns an open transport (called by :meth:`open`).
        protocol: "stylus" or "pid".
        time_source: host clock in seconds (the servo clock's ``now_s``).
        pid_config: joystick force scale and axis mapping (PID only).
        name: for messages.
        input_timeout_s: longest silence tolerated from the device.
    """

    def __init__(
        self,
        opener: Callable[[], HidTransport],
        protocol: str = "stylus",
        time_source: Callable[[], float] = time.perf_counter,
        pid_config: PidConfig | None = None,
        name: str | None = None,
        input_timeout_s: float = 0.5,
    ) -> None:
        if protocol not in PROTOCOLS:
            raise DeviceNotFoundError(f"unknown HID protocol {protocol!r}; use stylus or pid")
        self.opener = opener
        self.protocol = protocol
        self.time_source = time_source
        self.pid_config = pid_config or PidConfig()
        self.name = name or ("6-DOF stylus" if protocol == "stylus" else "force-feedback joystick")
        self.input_timeout_s = input_timeout_s
        self._transport: HidTransport | None = None
        self._driver: StylusDriver | PidDriver | None = None
        self._info: DeviceInfo | None = None
        self._state: DeviceState | None = None
        self._last_input_s = 0.0
        self._clock = DeviceClock()

    @property
    def info(self) -> DeviceInfo:
        if self._info is None:
            raise DeviceError(f"{self.name} is not open")
        return self._info

    def open(self) -> None:
        self._transport = self.opener()
        if self.protocol == "stylus":
            self._driver = StylusDriver(self._transport, self.name)
        else:
            self._driver = PidDriver(self._transport, self.pid_config, name=self.name)
        try:
            self._info = self._driver.start()
        except BaseException:
            self._transport.close()
            self._transport = self._driver = None
            raise
        self._last_input_s = self.time_source()
        self._state = DeviceState(self._last_input_s, np.zeros(3))

    def close(self) -> None:
        if self._transport is None:
            return
        try:
            if self._driver is not None:
                self._driver.stop()
        except (DeviceError, OSError):
            pass  # unplugged: nothing more to tell it
        finally:
            self._transport.close()
            self._transport = self._driver = None

    def _from_stylus(self, s: StylusInput, now: float) -> DeviceState:
        t = self._clock.host_time(s.timestamp_us, now)
        return DeviceState(t, s.position_m, s.orientation_wxyz, s.pressure, s.buttons)

    def _from_joystick(self, j: JoystickInput, now: float) -> DeviceState:
        cfg = self.pid_config
        down = bool(j.buttons & 1)
        z = -cfg.pen_down_depth_m if down else cfg.hover_m
        pos = np.array([0.5 * cfg.workspace_m[0] * j.x, 0.5 * cfg.workspace_m[1] * j.y, z])
        return DeviceState(now, pos, pressure=1.0 if down else 0.0, buttons=j.buttons)

    def read(self) -> DeviceState:
        if self._driver is None or self._state is None:
            raise DeviceError(f"{self.name} is not open")
        now = self.time_source()
        reading = self._driver.poll()
        if reading is None:
            if now - self._last_input_s > self.input_timeout_s:
                raise DeviceError(f"{self.name}: no input for {self.input_timeout_s:.2f} s")
            return self._state
        self._last_input_s = now
        if isinstance(reading, StylusInput):
            self._state = self._from_stylus(reading, now)
        else:
            self._state = self._from_joystick(reading, now)
        return self._state

    def write(self, force_n: np.ndarray, torque_nm: np.ndarray) -> None:
        if self._driver is None:
            raise DeviceError(f"{self.name} is not open")
        if not all(math.isfinite(float(v)) for v in (*force_n, *torque_nm)):
            force_n, torque_nm = np.zeros(3), np.zeros(3)  # the servo never sends these
        if isinstance(self._driver, StylusDriver):
            self._driver.send(force_n, torque_nm)
        else:
            self._driver.send(force_n)
