"""``paintapp devices`` and ``paintapp haptics-check``."""

from __future__ import annotations

import re

import pytest

from paintapp.bench import servo_check as check
from paintapp.cli import main
from paintapp.haptics.clock import VirtualClock
from paintapp.haptics.devices import catalog
from paintapp.haptics.devices.hid_transport import HidDeviceEntry
from paintapp.haptics.devices.simulated import SimulatedDevice
from tests.support.hid_models import PidJoystickModel, StylusDeviceModel


def test_devices_lists_builtins_and_says_when_no_hid_device_is_attached(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    monkeypatch.setattr(catalog, "enumerate_hid", lambda: [])
    assert main(["devices"]) == 0
    out = capsys.readouterr().out
    assert "simulated 6-DOF stylus" in out and "6-DOF force+torque" in out
    assert "replay" in out and "none found" in out


def test_devices_lists_hid_interfaces_with_their_role(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    stick = HidDeviceEntry(b"/dev/hidraw2", 0x046D, 0xC294, "", "Logitech", "Wheel", 1, 4, 0)
    monkeypatch.setattr(catalog, "enumerate_hid", lambda: [stick])
    assert main(["devices"]) == 0
    out = capsys.readouterr().out
    assert "046d:c294  Logitech Wheel" in out and "joystick" in out and "/dev/hidraw2" in out


def test_probing_a_missing_device_is_a_message_not_a_traceback(
    capsys: pytest.CaptureFixture,
) -> None:
    assert main(["devices", "--probe", "1234:5678"]) == 2
    err = capsys.readouterr().err
    assert "no HID device 1234:5678 is attached" in err and "Traceback" not in err


@pytest.mark.parametrize("kind", ["stylus", "pid"])
def test_probe_reports_the_protocol_a_device_speaks(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture, kind: str
) -> None:
    clock = VirtualClock()
    if kind == "stylus":
        model = StylusDeviceModel(SimulatedDevice(clock.now_s))
    else:
        model = PidJoystickModel(clock.now_s)
    model.description = f"model {kind}"
    monkeypatch.setattr(catalog, "open_hid", lambda vid, pid, path: model)
    assert main(["devices", "--probe", "1234:5678"]) == 0
    out = capsys.readouterr().out
    if kind == "stylus":
        assert "6-DOF stylus protocol: yes" in out and "max 8 N" in out
        assert "HID PID force feedback: no" in out
    else:
        assert "HID PID force feedback: yes" in out and "input axes: X, Y" in out


def test_haptics_check_prints_idle_and_loaded_figures_side_by_side(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    workload = (check.synthetic_workload(cells=24, sweeps=2), "synthetic 3D numpy workload")
    monkeypatch.setattr(check, "load_simulation", lambda: workload)
    assert main(["haptics-check", "--seconds", "0.3"]) == 0
    out = capsys.readouterr().out
    header = next(line for line in out.splitlines() if "idle" in line)
    assert "beside 3D simulation" in header
    for row in (
        "achieved rate (Hz)",
        "lateness p99 (ms)",
        "lateness p99.9 (ms)",
        "missed deadlines",
        "tick cost p50 (us)",
    ):
        assert row in out
    assert "ticks" in out and "verdict:" in out
    assert "machine floor: bare 1 kHz loop" in out  # the process form's floor, after the table


def test_haptics_check_rejects_a_bad_duration(capsys: pytest.CaptureFixture) -> None:
    assert main(["haptics-check", "--seconds", "0"]) == 2
    assert "--seconds" in capsys.readouterr().err


def test_run_once_with_the_synthetic_fluid_engages_and_publishes() -> None:
    from paintapp.haptics.servo import ServoConfig

    run = check.run_once(1.0, ServoConfig())
    assert run.report.timing is not None and run.report.timing.ticks > 500
    assert run.samples_published > 20 and run.report.fluid["fresh_samples"] > 0
    assert run.max_force_n > 0.0  # the stroke reached the canvas and the wall pushed back
    assert run.report.device_fault is None


def test_haptics_check_runs_the_process_form(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    workload = (check.synthetic_workload(cells=24, sweeps=2), "synthetic 3D numpy workload")
    monkeypatch.setattr(check, "load_simulation", lambda: workload)
    assert main(["haptics-check", "--seconds", "0.5", "--form", "process"]) == 0
    out = capsys.readouterr().out
    header = next(line for line in out.splitlines() if "process, idle" in line)
    assert "process, beside 3D" in header
    assert "servo process: " in out and "GC off" in out  # what the OS granted it
    bad = next(line for line in out.splitlines() if line.startswith("bad device writes"))
    assert bad.split()[-2:] == ["0", "0"]
    steal = next(line for line in out.splitlines() if line.startswith("host CPU steal"))
    cells = re.findall(r"\d+\.\d % \(peak \d+\.\d %\)", steal)  # per run, or - where unknown
    assert len(cells) == 2 or steal.split()[-2:] == ["-", "-"]
    assert "verdict: process" in out


def test_run_process_once_publishes_through_shared_memory() -> None:
    from paintapp.haptics.servo import ServoConfig

    run = check.run_process_once(1.0, ServoConfig(record=False))
    assert run.report.timing is not None and run.report.timing.ticks > 500
    assert run.samples_published > 20 and run.report.fluid["fresh_samples"] > 0
    assert run.bad_writes == 0 and run.report.device_fault is None
