"""The raw 6-DOF stylus protocol: the documented byte layout, and end to end over an in-memory
device model through the servo loop."""

from __future__ import annotations

import numpy as np
import pytest

from paintapp.haptics.clock import VirtualClock
from paintapp.haptics.device import DeviceError
from paintapp.haptics.devices import hid_stylus as sty
from paintapp.haptics.devices.hid import DeviceClock, HidDevice
from paintapp.haptics.devices.hid_descriptor import FEATURE, INPUT, OUTPUT, parse_report_descriptor
from paintapp.haptics.devices.simulated import SIMULATED_INFO, SimulatedDevice
from paintapp.haptics.servo import ServoLoop
from tests.support.hid_models import StylusDeviceModel


def stylus(clock: VirtualClock) -> tuple[StylusDeviceModel, HidDevice]:
    model = StylusDeviceModel(SimulatedDevice(clock.now_s))
    return model, HidDevice(lambda: model, "stylus", clock.now_s)


def test_input_report_byte_layout() -> None:
    report = sty.encode_input(
        sty.StylusInput(
            7,
            0b101,
            sty.STATUS_ENABLED,
            0x01020304,
            np.array([0.001, -0.002, 0.5]),
            np.array([1.0, 0, 0, 0]),
            0.5,
        )
    )
    expected = bytes.fromhex(
        "01 07 05 01  04 03 02 01  e8 03 00 00  30 f8 ff ff  20 a1 07 00"
        "ff 7f 00 00 00 00 00 00  00 80  00 00"
    )
    assert report == expected and len(report) == 32
    decoded = sty.decode_input(report)
    np.testing.assert_allclose(decoded.position_m, [0.001, -0.002, 0.5])
    assert decoded.buttons == 5 and decoded.timestamp_us == 0x01020304
    assert decoded.pressure == pytest.approx(0.5, abs=1e-4)


def test_output_report_byte_layout() -> None:
    report = sty.encode_output(
        9, sty.FLAG_ENABLE, np.array([1.5, -0.25, 0.0]), np.array([0.0, 0.0, 0.001])
    )
    expected = bytes.fromhex(
        "02 09 01 00  60 e3 16 00  70 2f fc ff  00 00 00 00"
        "00 00 00 00  00 00 00 00  e8 03 00 00  00 00 00 00"
    )
    assert report == expected
    seq, flags, force, torque = sty.decode_output(report)
    assert (seq, flags) == (9, 1)
    np.testing.assert_allclose(force, [1.5, -0.25, 0.0])
    np.testing.assert_allclose(torque, [0.0, 0.0, 0.001])


def test_info_report_round_trip_and_descriptor_sizes() -> None:
    info, rate, watchdog = sty.decode_info(sty.encode_info(SIMULATED_INFO, 1000, 50), "x")
    assert (rate, watchdog) == (1000, 50)
    assert info.max_force_n == pytest.approx(SIMULATED_INFO.max_force_n)
    assert info.max_torque_nm == pytest.approx(SIMULATED_INFO.max_torque_nm)
    assert info.max_stiffness_n_per_m == pytest.approx(SIMULATED_INFO.max_stiffness_n_per_m)
    assert info.workspace_m == pytest.approx(SIMULATED_INFO.workspace_m)
    assert info.has_torque and info.dof_sensed == 6
    d = parse_report_descriptor(sty.REPORT_DESCRIPTOR)
    assert d.numbered
    assert d.report_bytes(INPUT, sty.INPUT_ID) == sty.INPUT_SIZE - 1
    assert d.report_bytes(OUTPUT, sty.OUTPUT_ID) == sty.OUTPUT_SIZE - 1
    assert d.report_bytes(FEATURE, sty.INFO_ID) == sty.INFO_SIZE - 1


def test_servo_loop_over_hid_matches_the_simulated_device() -> None:
    """The same closed loop, once direct and once through reports: the same motion."""
    clock = VirtualClock()
    direct = ServoLoop(SimulatedDevice(clock.now_s))
    direct.run(clock, 1.5)
    clock = VirtualClock()
    model, device = stylus(clock)
    over_hid = ServoLoop(device)
    report = over_hid.run(clock, 1.5)
    assert report.stopped_by == "limit" and device.info.kind == "hid-stylus"
    a, b = direct.log.arrays(), over_hid.log.arrays()
    assert np.max(np.abs(a["position_m"] - b["position_m"])) < 2e-5
    assert np.max(np.abs(a["force_n"] - b["force_n"])) < 0.05
    assert np.max(b["force_n"][:, 2]) > 0.3  # the canvas was felt
    np.testing.assert_allclose(model.applied_force_n, b["force_n"][-1], atol=1e-6)
    over_hid.close()
    assert not model.enabled and np.all(model.applied_force_n == 0)


def test_device_side_watchdog_zeroes_force_when_the_host_goes_quiet() -> None:
    clock = VirtualClock()
    model, device = stylus(clock)
    device.open()
    device.write(np.array([0.0, 0.0, 1.0]), np.zeros(3))
    assert model.applied_force_n[2] == pytest.approx(1.0)
    clock.run(lambda i, t: True, 60)  # 60 ms without an output report
    inp = sty.decode_input(model.read(64))
    assert inp.status & sty.STATUS_WATCHDOG
    assert np.all(model.applied_force_n == 0)


def test_unplugged_mid_stroke_stops_the_loop_and_keeps_the_log() -> None:
    clock = VirtualClock()
    model, device = stylus(clock)
    loop = ServoLoop(device)

    def tick(i: int, t: float) -> bool:
        if i == 400:
            model.unplug()
        return loop.tick(t)

    loop.open()
    clock.run(tick, 1000)
    report = loop.report()
    assert report.stopped_by == "device fault" and "read error" in report.device_fault
    assert len(loop.log) == 400
    loop.close()  # no exception from a device that is gone


def test_device_fault_status_and_silence_are_device_errors() -> None:
    clock = VirtualClock()
    model, device = stylus(clock)
    device.open()
    clock.run(lambda i, t: True, 2)
    model.fault = True
    with pytest.raises(DeviceError, match="fault"):
        device.read()
    model.fault = False
    model.silent = True
    device.read()  # drains what was queued
    clock.run(lambda i, t: True, 600)
    with pytest.raises(DeviceError, match="no input"):
        device.read()


def test_dropped_input_reports_are_counted() -> None:
    clock = VirtualClock()
    _, device = stylus(clock)
    device.open()
    device.read()
    clock.run(lambda i, t: True, 21)  # to t = 20 ms: 20 more reports, the device queue keeps 8
    device.read()
    assert device._driver.dropped_reports == 12


def test_device_clock_unwraps_and_follows_the_host() -> None:
    clk = DeviceClock()
    t0 = clk.host_time(2**32 - 500, 10.0)
    t1 = clk.host_time(500, 10.001)  # wrapped after 1000 us
    assert t0 == 10.0 and t1 == pytest.approx(10.001)
    t2 = clk.host_time(1500, 10.0015)  # USB jitter: arrives early relative to the device clock
    assert t2 <= 10.0015
    t3 = clk.host_time(2500, 11.0)  # a second of silence: resynchronized
    assert t3 == 11.0
