"""The OpenHaptics backend against a fake libHD (``fakes/fake_hd.c``): the HD API's rules (frames,
the scheduler, queued errors, millimetres and the HD frame) at the ctypes boundary, with the
servo loop on a virtual clock (the test steps the HD scheduler each tick); and the device's own
timeout after the process driving it is killed (SIGKILL)."""

from __future__ import annotations

import ctypes
import ctypes.util
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

from paintapp.haptics.clock import RealTimeClock, VirtualClock
from paintapp.haptics.device import DeviceError, DeviceNotFoundError
from paintapp.haptics.devices import openhaptics as oh
from paintapp.haptics.servo import ServoLoop
from tests.paintapp.haptics.devices.conftest import HD_RECORD, record

REPO = Path(__file__).resolve().parents[4]


def hd_record(lib: ctypes.CDLL) -> dict[str, float]:
    return record(lib, HD_RECORD, "fakeHdRecord")


def output(lib: ctypes.CDLL) -> tuple[np.ndarray, float]:
    """What the fake device's motors give now (HD frame, N; its timeout applied) and the seconds
    since the last servo frame ended."""
    buf = (ctypes.c_double * 4)()
    lib.fakeHdOutput(buf)
    return np.array(buf[:3]), float(buf[3])


def run_loop(lib: ctypes.CDLL, ticks: int, on_tick=None) -> tuple[ServoLoop, VirtualClock]:
    clock = VirtualClock()
    device = oh.OpenHapticsDevice(clock.now_s)
    loop = ServoLoop(device)
    loop.open()

    def tick(i: int, t: float) -> bool:
        if on_tick is not None:
            on_tick(i)
        lib.fakeHdRunScheduler(1)
        return loop.tick(t)

    clock.run(tick, ticks)
    return loop, clock


def test_axes_map_the_hd_frame_onto_ours() -> None:
    # HD: x right, y up, z toward the user; ours: x right, y away from the user, z up
    assert oh.HD_AXES.to_ours([1.0, 2.0, 3.0]) == [1.0, -3.0, 2.0]
    assert oh.HD_AXES.to_device(oh.HD_AXES.to_ours([1.0, 2.0, 3.0])) == [1.0, 2.0, 3.0]
    assert np.linalg.det(oh.HD_AXES.matrix) == pytest.approx(1.0)


def test_limits_come_from_the_device_and_its_safety_switches_are_on(fake_hd) -> None:
    device = oh.OpenHapticsDevice()
    device.open()
    try:
        info = device.info
        assert info.kind == "openhaptics" and info.name == "Touch (fake)"
        assert info.max_force_n == pytest.approx(0.88)  # continuous, not the 3.3 N peak
        assert info.max_stiffness_n_per_m == pytest.approx(1260.0)  # 1.26 N/mm
        assert info.max_damping_ns_per_m == pytest.approx(5.0)
        assert info.workspace_m == pytest.approx((0.16, 0.07, 0.12))  # HD z depth -> our y
        assert (info.dof_sensed, info.dof_actuated) == (6, 3)
        caps = int(hd_record(fake_hd)["caps"])
        for bit in (0, 1, 2, 3, 8, 9):  # output, clamping, ramping, force, velocity, impulse
            assert caps >> bit & 1, f"capability bit {bit} not enabled"
        assert hd_record(fake_hd)["running"] == 1
    finally:
        device.close()


def test_servo_loop_feels_the_canvas_and_writes_nothing_unsafe(fake_hd) -> None:
    loop, _ = run_loop(fake_hd, 1500)
    report = loop.report()
    assert report.stopped_by == "limit" and report.device_fault is None
    log = loop.log.arrays()
    assert np.max(log["force_n"][:, 2]) > 0.2  # the canvas pushed back
    assert np.all(np.isfinite(log["force_n"]))
    # HD y (up, mm) became our z (m): the stroke dipped 2 mm below the canvas and stayed near it
    assert -0.0025 < np.min(log["position_m"][:, 2]) < 0.0
    rec = hd_record(fake_hd)
    assert rec["writes"] == rec["frames"] == 1500
    assert rec["nonfinite"] == 0 and rec["over_limit"] == 0
    assert rec["max_output_n"] <= 0.88 + 1e-9
    assert rec["frames_outside_scheduler"] == 0
    loop.close()


def test_close_zeroes_the_force_within_one_tick(fake_hd) -> None:
    loop, _ = run_loop(fake_hd, 800)
    assert hd_record(fake_hd)["out_y"] > 0.05  # pressing on the canvas when closed
    loop.close()
    rec = hd_record(fake_hd)
    assert (rec["out_x"], rec["out_y"], rec["out_z"]) == (0.0, 0.0, 0.0)
    assert rec["running"] == 0 and rec["initialised"] == 0
    loop.close()  # twice is fine


def test_an_hd_error_is_a_safe_stop_with_its_message(fake_hd) -> None:
    fake_hd.fakeHdInjectError(0x0203, 400)  # HD_EXCEEDED_MAX_VELOCITY at frame 400
    loop, _ = run_loop(fake_hd, 1000)
    report = loop.report()
    assert report.stopped_by == "device fault"
    assert "Maximum velocity exceeded" in report.device_fault
    assert 395 <= report.ticks <= 402
    rec = hd_record(fake_hd)
    assert (rec["out_x"], rec["out_y"], rec["out_z"]) == (0.0, 0.0, 0.0)
    loop.close()


def test_non_finite_writes_never_reach_the_device(fake_hd) -> None:
    device = oh.OpenHapticsDevice()
    device.open()
    try:
        device.write(np.array([np.nan, 0.0, 1.0]), np.zeros(3))
        fake_hd.fakeHdRunScheduler(5)
        device.write(np.array([0.0, 0.0, 50.0]), np.zeros(3))  # far over the limit
        fake_hd.fakeHdRunScheduler(100)  # past the ramp
        rec = hd_record(fake_hd)
        assert rec["nonfinite"] == 0 and rec["over_limit"] == 0
        assert rec["max_output_n"] <= 0.88 + 1e-9
    finally:
        device.close()


def test_a_stalled_servo_loop_drops_the_force(fake_hd) -> None:
    device = oh.OpenHapticsDevice()
    device.open()
    try:
        for _ in range(60):  # past the device's force ramp
            device.write(np.array([0.0, 0.0, 0.5]), np.zeros(3))
            fake_hd.fakeHdRunScheduler(1)
        assert hd_record(fake_hd)["out_y"] == pytest.approx(0.5)  # our z is HD y
        fake_hd.fakeHdRunScheduler(oh.HOLD_FRAMES - 1)  # no write from the loop since
        assert hd_record(fake_hd)["out_y"] == pytest.approx(0.5)
        fake_hd.fakeHdRunScheduler(1)
        assert hd_record(fake_hd)["out_y"] == 0.0
    finally:
        device.close()


def test_missing_library_says_what_to_install_and_the_variable(monkeypatch, tmp_path) -> None:
    monkeypatch.setenv("PAINTAPP_LIBHD", str(tmp_path / "libHD.so"))
    with pytest.raises(DeviceNotFoundError) as err:
        oh.OpenHapticsDevice().open()
    text = str(err.value)
    assert "OpenHaptics" in text and "PAINTAPP_LIBHD" in text and "does not exist" in text
    assert "\n" not in text


def test_a_library_without_the_hd_calls_is_refused(monkeypatch) -> None:
    libm = ctypes.util.find_library("m")
    if libm is None:
        pytest.skip("no libm to stand in for a wrong library")
    monkeypatch.setenv("PAINTAPP_LIBHD", libm)
    with pytest.raises(DeviceNotFoundError, match="has no hd"):
        oh.OpenHapticsDevice().open()


def test_no_device_attached_is_a_clear_message(fake_hd) -> None:
    fake_hd.fakeHdSetNoDevice(1)
    with pytest.raises(DeviceNotFoundError, match="did not initialise: Communication error"):
        oh.OpenHapticsDevice().open()
    device = oh.OpenHapticsDevice()
    with pytest.raises(DeviceError):
        device.read()


def test_real_clock_run_with_the_fake_scheduler_thread(fake_hd) -> None:
    """Behaviour only (no rates): the scheduler's own thread and the servo loop side by side."""
    fake_hd.fakeHdSetManual(0)
    clock = RealTimeClock(1e-3)
    device = oh.OpenHapticsDevice(clock.now_s)
    loop = ServoLoop(device)
    loop.open()
    loop.start(clock, 0.3)
    deadline = time.monotonic() + 30.0
    while clock.running and time.monotonic() < deadline:
        time.sleep(0.02)
    loop.stop()
    assert loop.report().device_fault is None and loop.ticks > 0
    loop.close()
    rec = hd_record(fake_hd)
    assert rec["frames"] > 0 and rec["nonfinite"] == 0 and rec["over_limit"] == 0
    assert (rec["out_x"], rec["out_y"], rec["out_z"]) == (0.0, 0.0, 0.0)
    assert rec["running"] == 0


def test_a_six_dof_model_takes_torque_in_millinewton_metres(fake_hd) -> None:
    fake_hd.fakeHdSetOutputDof(6)
    loop, _ = run_loop(fake_hd, 300)
    info = loop.device.info
    assert (info.dof_sensed, info.dof_actuated) == (6, 6)
    assert info.max_torque_nm == pytest.approx(0.15)  # 150 mN m
    assert loop.report().device_fault is None  # HD_CURRENT_TORQUE accepted every frame
    loop.close()


def test_before_the_first_frame_the_pose_is_upright(fake_hd) -> None:
    device = oh.OpenHapticsDevice()
    device.open()
    try:
        np.testing.assert_allclose(device.read().orientation_wxyz, [1.0, 0.0, 0.0, 0.0])
        fake_hd.fakeHdRunScheduler(1)
        # the fake tilts the stylus 0.3 rad about HD x, which is our x
        q = device.read().orientation_wxyz
        np.testing.assert_allclose(q, [np.cos(0.15), np.sin(0.15), 0.0, 0.0], atol=1e-12)
    finally:
        device.close()


CHILD = textwrap.dedent(
    """
    import time
    import numpy as np
    from paintapp.haptics.devices.openhaptics import OpenHapticsDevice
    device = OpenHapticsDevice()
    device.open()  # the HD scheduler's own thread runs the servo frames
    end = time.monotonic() + 30.0  # bounded even if nobody kills it
    i = 0
    while time.monotonic() < end:
        device.read()
        device.write(np.array([0.0, 0.0, 0.5]), np.zeros(3))
        i += 1
        if i == 200:
            print("running", flush=True)
        time.sleep(0.001)
    """
)


def test_the_device_drops_the_force_after_the_process_is_killed(fake_lib_dir, tmp_path) -> None:
    """The process driving the device is SIGKILLed mid-stroke: its HD scheduler dies with it, and
    the device (the fake's state in a shared file, its timeout applied from outside the dead
    process) gives zero force once its timeout has passed since the last servo frame."""
    state = tmp_path / "device.state"
    env = dict(
        os.environ,
        PAINTAPP_LIBHD=str(fake_lib_dir["fake_hd"]),
        PAINTAPP_FAKE_HD_STATE=str(state),
        PYTHONPATH=str(REPO),
    )
    env.pop("PAINTAPP_FAKE_HD_MANUAL", None)  # the scheduler's own thread, on the real clock
    env.pop("PAINTAPP_FAKE_HD_NO_DEVICE", None)
    observer_path = tmp_path / "observer.so"  # a second copy: its own globals, same device file
    shutil.copy(fake_lib_dir["fake_hd"], observer_path)
    observer = ctypes.CDLL(str(observer_path))
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD], env=env, stdout=subprocess.PIPE, text=True
    )
    try:
        assert child.stdout is not None
        assert child.stdout.readline().strip() == "running"
        observer.fakeHdMapPath(str(state).encode())
        # pressing while alive (polled: a busy machine may stall the servo frames a while)
        deadline = time.monotonic() + 10.0
        force, _ = output(observer)
        while force[1] != pytest.approx(0.5) and time.monotonic() < deadline:
            time.sleep(0.001)
            force, _ = output(observer)
        assert force[1] == pytest.approx(0.5)  # our z is HD y
        child.send_signal(signal.SIGKILL)
        child.wait(10)
        rec = hd_record(observer)
        # no close, no zero frame: the process died with its scheduler running, a force commanded
        assert rec["initialised"] == 1 and rec["running"] == 1
        assert rec["out_y"] == pytest.approx(0.5)
        timeout_s = rec["timeout_s"]
        assert 0.0 < timeout_s <= 0.1
        deadline = time.monotonic() + 10.0
        while np.any(output(observer)[0] != 0.0) and time.monotonic() < deadline:
            time.sleep(timeout_s / 4)
        force, since_last_frame_s = output(observer)
        assert np.all(force == 0.0)
        assert since_last_frame_s > timeout_s  # zero exactly by the device's rule
        rec = hd_record(observer)
        assert rec["timeouts"] >= 1 and rec["out_y"] == pytest.approx(0.5)
    finally:
        if child.poll() is None:
            child.kill()
            child.wait(10)
