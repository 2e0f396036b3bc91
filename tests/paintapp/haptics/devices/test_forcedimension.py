"""The Force Dimension DHD backend against a fake libdhd (``fakes/fake_dhd.c``): return codes,
brakes and forces, the controller's watchdog, metres and the DHD frame at the ctypes boundary,
with the servo loop on a virtual clock; and the watchdog after the process holding the device
is killed (SIGKILL)."""

from __future__ import annotations

import ctypes
import math
import os
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

from paintapp.haptics.clock import VirtualClock
from paintapp.haptics.device import DeviceError, DeviceNotFoundError
from paintapp.haptics.devices import forcedimension as fd
from paintapp.haptics.servo import ServoLoop
from tests.paintapp.haptics.devices.conftest import DHD_RECORD, record

REPO = Path(__file__).resolve().parents[4]


def dhd_record(lib: ctypes.CDLL) -> dict[str, float]:
    return record(lib, DHD_RECORD, "fakeDhdRecord")


def output(lib: ctypes.CDLL) -> np.ndarray:
    """What the fake device's motors give now (its watchdog rule applied)."""
    buf = (ctypes.c_double * 6)()
    lib.fakeDhdOutput(buf)
    return np.array(buf[:])


def run_loop(ticks: int) -> ServoLoop:
    clock = VirtualClock()
    loop = ServoLoop(fd.ForceDimensionDevice(clock.now_s))
    loop.open()
    clock.run(lambda i, t: loop.tick(t), ticks)
    return loop


def test_axes_map_the_dhd_frame_onto_ours() -> None:
    # DHD: x toward the user, y right, z up; ours: x right, y away from the user, z up
    assert fd.DHD_AXES.to_ours([1.0, 2.0, 3.0]) == [2.0, -1.0, 3.0]
    assert fd.DHD_AXES.to_device([2.0, -1.0, 3.0]) == [1.0, 2.0, 3.0]
    assert np.linalg.det(fd.DHD_AXES.matrix) == pytest.approx(1.0)


def test_open_arms_the_watchdog_and_limits_before_forces(fake_dhd) -> None:
    device = fd.ForceDimensionDevice()
    device.open()
    try:
        rec = dhd_record(fake_dhd)
        assert rec["watchdog_s"] == pytest.approx(fd.WATCHDOG_S)
        assert rec["max_force_limit_n"] == pytest.approx(20.0)  # delta.3
        assert rec["forces_on"] == 0 and rec["brakes"] == 1  # not until the first write
        device.write(np.zeros(3), np.zeros(3))
        rec = dhd_record(fake_dhd)
        assert rec["forces_on"] == 1 and rec["brakes"] == 0
        assert device.info.kind == "forcedimension" and device.info.name == "delta.3 (fake)"
        assert (device.info.dof_sensed, device.info.dof_actuated) == (3, 3)
    finally:
        device.close()


def test_servo_loop_feels_the_canvas_and_writes_nothing_unsafe(fake_dhd) -> None:
    loop = run_loop(1500)
    assert loop.report().stopped_by == "limit"
    log = loop.log.arrays()
    assert np.max(log["force_n"][:, 2]) > 0.3
    # the fake's circle starts at DHD x = +30 mm (toward the user): our y = -30 mm
    assert log["position_m"][0, 1] == pytest.approx(-0.03, abs=1e-3)
    assert log["position_m"][0, 2] > 0.005  # coming down from above the canvas
    rec = dhd_record(fake_dhd)
    assert rec["writes"] >= 1500 and rec["nonfinite"] == 0 and rec["over_limit"] == 0
    loop.close()


def test_close_zeroes_the_force_and_puts_the_brakes_on(fake_dhd) -> None:
    loop = run_loop(800)
    assert np.linalg.norm(output(fake_dhd)) > 0.1  # pressing on the canvas when closed
    loop.close()
    rec = dhd_record(fake_dhd)
    assert rec["closed"] == 1 and rec["forces_on"] == 0 and rec["brakes"] == 1
    assert np.all(output(fake_dhd) == 0.0)


def test_a_library_error_is_a_safe_stop_and_the_watchdog_backs_it(fake_dhd) -> None:
    fake_dhd.fakeDhdWatchdogScale(ctypes.c_double(1.0))
    fake_dhd.fakeDhdFailAfter(900)  # every call fails from then on: the device is unplugged
    loop = run_loop(1500)
    report = loop.report()
    assert report.stopped_by == "device fault"
    assert "communication error" in report.device_fault
    # the loop's own zero write failed too; the device's watchdog ends the last force
    time.sleep(3 * fd.WATCHDOG_S)
    assert np.all(output(fake_dhd) == 0.0)
    assert dhd_record(fake_dhd)["watchdog_trips"] == 1
    loop.close()  # no exception from a device that is gone


def test_the_watchdog_ends_the_force_when_calls_stop(fake_dhd) -> None:
    fake_dhd.fakeDhdWatchdogScale(ctypes.c_double(1.0))
    device = fd.ForceDimensionDevice()
    device.open()
    device.read()
    device.write(np.array([0.0, 0.0, 1.0]), np.zeros(3))
    assert output(fake_dhd)[2] == pytest.approx(1.0)
    time.sleep(3 * fd.WATCHDOG_S)  # our loop "stalls"
    assert np.all(output(fake_dhd) == 0.0)
    rec = dhd_record(fake_dhd)
    assert rec["watchdog_trips"] == 1 and rec["since_last_call_s"] > fd.WATCHDOG_S
    device.close()


def test_non_finite_and_excessive_forces_are_not_sent(fake_dhd) -> None:
    device = fd.ForceDimensionDevice()
    device.open()
    try:
        device.write(np.array([np.inf, 0.0, 0.0]), np.zeros(3))
        device.write(np.array([0.0, 0.0, 500.0]), np.zeros(3))
        rec = dhd_record(fake_dhd)
        assert rec["nonfinite"] == 0 and rec["over_limit"] == 0
        assert math.isclose(rec["force_z"], 20.0)
    finally:
        device.close()


def test_a_wrist_gives_orientation_and_torque(fake_dhd) -> None:
    fake_dhd.fakeDhdSetType(35)  # omega.7: active wrist
    device = fd.ForceDimensionDevice()
    device.open()
    try:
        assert (device.info.dof_sensed, device.info.dof_actuated) == (6, 6)
        state = device.read()
        # the fake's frame turns 0.2 rad about DHD y, which is our x
        np.testing.assert_allclose(
            state.orientation_wxyz, [math.cos(0.1), math.sin(0.1), 0, 0], atol=1e-9
        )
    finally:
        device.close()


def test_missing_library_and_missing_device_are_clear_messages(
    fake_dhd, monkeypatch, tmp_path
) -> None:
    fake_dhd.fakeDhdSetNoDevice(1)
    with pytest.raises(DeviceNotFoundError, match="no Force Dimension device: no device found"):
        fd.ForceDimensionDevice().open()
    monkeypatch.setenv("PAINTAPP_LIBDHD", str(tmp_path / "libdhd.so"))
    with pytest.raises(DeviceNotFoundError) as err:
        fd.ForceDimensionDevice().open()
    assert "PAINTAPP_LIBDHD" in str(err.value) and "Force Dimension" in str(err.value)
    with pytest.raises(DeviceError):
        fd.ForceDimensionDevice().read()


CHILD = textwrap.dedent(
    """
    import sys, time
    import numpy as np
    from paintapp.haptics.devices.forcedimension import ForceDimensionDevice
    device = ForceDimensionDevice()
    device.open()
    end = time.monotonic() + 30.0  # bounded even if nobody kills it
    i = 0
    while time.monotonic() < end:
        device.read()
        device.write(np.array([0.0, 0.0, 1.5]), np.zeros(3))
        i += 1
        if i == 200:
            print("running", flush=True)
        time.sleep(0.001)
    """
)


def test_the_watchdog_zeroes_the_force_after_the_process_is_killed(fake_lib_dir, tmp_path) -> None:
    """The process holding the device is SIGKILLed mid-stroke: the device (the fake's state in a
    shared file, its watchdog applied from outside the dead process) gives zero force once the
    watchdog time has passed since the last call."""
    state = tmp_path / "device.state"
    env = dict(
        os.environ,
        PAINTAPP_LIBDHD=str(fake_lib_dir["fake_dhd"]),
        PAINTAPP_FAKE_DHD_STATE=str(state),
        PYTHONPATH=str(REPO),
    )
    observer_path = tmp_path / "observer.so"  # a second copy: its own globals, same device file
    shutil.copy(fake_lib_dir["fake_dhd"], observer_path)
    observer = ctypes.CDLL(str(observer_path))
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD], env=env, stdout=subprocess.PIPE, text=True
    )
    try:
        assert child.stdout is not None
        assert child.stdout.readline().strip() == "running"
        observer.fakeDhdMapPath(str(state).encode())
        assert output(observer)[2] == pytest.approx(1.5)  # pressing while alive
        child.send_signal(signal.SIGKILL)
        child.wait(10)
        deadline = time.monotonic() + 10.0
        while np.any(output(observer) != 0.0) and time.monotonic() < deadline:
            time.sleep(fd.WATCHDOG_S / 4)
        rec = dhd_record(observer)
        assert np.all(output(observer) == 0.0)
        assert rec["watchdog_trips"] == 1 and rec["watchdog_s"] == pytest.approx(fd.WATCHDOG_S)
        assert rec["since_last_call_s"] > fd.WATCHDOG_S  # zero exactly by the watchdog's rule
    finally:
        if child.poll() is None:
            child.kill()
            child.wait(10)
