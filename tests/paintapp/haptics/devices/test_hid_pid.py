"""HID PID force feedback end to end against an in-memory joystick that decodes the reports."""

from __future__ import annotations

import math

import numpy as np
import pytest

from paintapp.haptics.clock import VirtualClock
from paintapp.haptics.device import DeviceError, DeviceNotFoundError
from paintapp.haptics.devices import hid_pid as pid
from paintapp.haptics.devices import hid_stylus as sty
from paintapp.haptics.devices.hid import HidDevice
from paintapp.haptics.devices.hid_descriptor import INPUT, OUTPUT, PAGE_PID, parse_report_descriptor
from paintapp.haptics.devices.simulated import SimulatedDevice
from paintapp.haptics.safety import SafetyConfig
from paintapp.haptics.servo import ServoConfig, ServoLoop
from tests.support.hid_models import PidJoystickModel, StylusDeviceModel, joystick_pid_descriptor

CONFIG = pid.PidConfig(max_force_n=2.0)


def joystick(clock: VirtualClock, **kw) -> tuple[PidJoystickModel, HidDevice]:
    model = PidJoystickModel(clock.now_s, max_force_n=2.0, **kw)
    return model, HidDevice(lambda: model, "pid", clock.now_s, pid_config=CONFIG)


def test_descriptor_declares_axes_buttons_and_pid_reports() -> None:
    d = parse_report_descriptor(joystick_pid_descriptor())
    assert d.uses_page(PAGE_PID) and d.numbered
    x, _ = d.find(INPUT, 0x01, 0x30)
    _, iy = d.find(INPUT, 0x01, 0x31)
    assert (x.size, x.logical_min, x.logical_max, iy) == (16, -32767, 32767, 1)
    for report_id, size in pid.PidLayout().outputs().items():
        assert d.report_bytes(OUTPUT, report_id) == size


@pytest.mark.parametrize("angle_deg", [0.0, 37.0, 90.0, 181.0, 300.0])
@pytest.mark.parametrize("size_n", [0.3, 1.7, 5.0])
def test_commanded_force_is_what_the_motors_produce(angle_deg: float, size_n: float) -> None:
    clock = VirtualClock()
    model, device = joystick(clock)
    device.open()
    a = math.radians(angle_deg)
    command = size_n * np.array([math.sin(a), math.cos(a), 0.0])
    device.write(command, np.zeros(3))
    applied = model.applied_force_n()
    expected_size = min(size_n, 2.0)  # clamped to the stick's full magnitude
    assert np.linalg.norm(applied) == pytest.approx(expected_size, abs=2.0 / 10000)
    cross = command[0] * applied[1] - command[1] * applied[0]
    angle_error = math.degrees(math.atan2(cross, command[:2] @ applied))
    assert abs(angle_error) <= 360 / 256 / 2 + 1e-9


def test_unchanged_force_sends_no_reports_and_close_frees_the_effect() -> None:
    clock = VirtualClock()
    model, device = joystick(clock)
    device.open()
    assert model.actuators_enabled and len(model.effects) == 1
    device.write(np.array([0.5, 0.5, 0.0]), np.zeros(3))
    sent = model.reports_written
    for _ in range(100):
        device.write(np.array([0.5, 0.5, 0.0]), np.zeros(3))
    assert model.reports_written == sent
    device.write(np.array([0.0, 0.0, 0.0]), np.zeros(3))
    assert np.all(model.applied_force_n() == 0)
    device.close()
    assert not model.effects and not model.actuators_enabled


def test_stick_and_button_become_a_tip_position() -> None:
    clock = VirtualClock()
    model, device = joystick(clock)
    device.open()
    model.stick, model.buttons = (0.5, -1.0), 0b1
    clock.run(lambda i, t: True, 2)
    s = device.read()
    np.testing.assert_allclose(s.position_m, [0.05, -0.1, -CONFIG.pen_down_depth_m], atol=1e-5)
    assert s.pressure == 1.0 and s.buttons == 1
    model.buttons = 0
    clock.run(lambda i, t: True, 1)
    assert device.read().position_m[2] == pytest.approx(CONFIG.hover_m)


def test_servo_loop_drives_the_joystick_with_the_fluid_force() -> None:
    clock = VirtualClock()
    model, device = joystick(clock)
    model.buttons = 1  # pen down: the canvas force (z) cannot be shown on a stick
    loop = ServoLoop(device, config=ServoConfig(safety=SafetyConfig(ramp_time_s=0.05)))
    loop.open()

    def tick(i: int, t: float) -> bool:
        if i % 16 == 0:
            loop.forces.publish_force(t, [0.1, -0.05, 0.3])
        return loop.tick(t)

    clock.run(tick, 500)
    # scale 4; the direction byte quantizes the angle to 1.4 degrees
    np.testing.assert_allclose(model.applied_force_n(), [0.4, -0.2], atol=0.006)
    loop.close()
    assert not model.effects


def test_devices_that_do_not_speak_pid_are_refused_clearly() -> None:
    clock = VirtualClock()
    not_pid = StylusDeviceModel(SimulatedDevice(clock.now_s))
    with pytest.raises(DeviceNotFoundError, match="HID PID"):
        HidDevice(lambda: not_pid, "pid", clock.now_s).open()
    other_layout = PidJoystickModel(clock.now_s, layout=pid.PidLayout(set_effect_id=0x11))
    with pytest.raises(DeviceNotFoundError, match="PidLayout"):
        HidDevice(lambda: other_layout, "pid", clock.now_s).open()
    assert not other_layout.queue  # closed again after the failed open


def test_full_effect_pool_and_unplugging_are_device_errors() -> None:
    clock = VirtualClock()
    _, device = joystick(clock, max_effects=0)
    with pytest.raises(DeviceError, match="constant-force"):
        device.open()
    model, device = joystick(clock)
    device.open()
    model.unplug()
    with pytest.raises(OSError):
        device.write(np.array([1.0, 0.0, 0.0]), np.zeros(3))
    device.close()  # quietly: the device is gone


def test_direction_byte_round_trip() -> None:
    for b in range(256):
        v = pid.direction_vector(b)
        assert pid.direction_byte(v[0], v[1]) == b
    assert pid.direction_byte(0.0, 1.0) == 0 and pid.direction_byte(1.0, 0.0) == 64
    assert sty.OUTPUT_SIZE == 32  # the stylus reports stay one full-speed packet
