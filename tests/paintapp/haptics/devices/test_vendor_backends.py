"""The vendor backends wired in: ``--device NAME[:ARG]`` parsing, the servo process building
them by name, ``paintapp devices`` without any vendor library, ``paintapp haptics-check
--device``, and that importing them loads nothing of the vendors'."""

from __future__ import annotations

import socket
import subprocess
import sys
import time

import numpy as np
import pytest

from common.errors import InputError
from paintapp.app.haptic_link import device_text, parse_device
from paintapp.cli import main
from paintapp.haptics.device import DeviceNotFoundError
from paintapp.haptics.devices.backends import VENDOR_NAMES, split_device
from paintapp.haptics.devices.forcedimension import ForceDimensionDevice
from paintapp.haptics.devices.haply import HaplyDevice
from paintapp.haptics.devices.openhaptics import OpenHapticsDevice
from paintapp.haptics.devices.vendor import AxisMap, quat_from_matrix
from paintapp.haptics.process import ProcessOptions, ServoProcess, build_device
from tests.paintapp.haptics.devices.conftest import DHD_RECORD, record


def test_device_names_parse_and_round_trip() -> None:
    for text, kind, arg in (
        ("openhaptics", "openhaptics", ""),
        ("openhaptics:Left Touch", "openhaptics", "Left Touch"),
        ("dhd", "dhd", ""),
        ("haply:049D", "haply", "049D"),
    ):
        spec = parse_device(text)
        assert (spec.kind, spec.arg) == (kind, arg)
        assert device_text(spec) == text
        assert split_device(device_text(spec)) == (kind, arg)
    with pytest.raises(InputError, match="dhd takes no argument"):
        parse_device("dhd:1")
    with pytest.raises(InputError, match="openhaptics"):
        parse_device("phantom")


def test_the_servo_process_builds_each_backend_by_name_without_opening_it() -> None:
    assert isinstance(
        build_device("openhaptics:Default", time.perf_counter, None), OpenHapticsDevice
    )
    assert isinstance(build_device("dhd", time.perf_counter, None), ForceDimensionDevice)
    device = build_device("haply:049D", time.perf_counter, None)
    assert isinstance(device, HaplyDevice) and device.device_id == "049D"
    with pytest.raises(DeviceNotFoundError, match="openhaptics"):
        build_device("falcon", time.perf_counter, None)


def test_importing_the_backends_loads_no_vendor_code() -> None:
    code = (
        "import sys\n"
        "import paintapp.haptics.devices.backends, paintapp.haptics.devices.openhaptics\n"
        "import paintapp.haptics.devices.forcedimension, paintapp.haptics.devices.haply\n"
        "import paintapp.haptics.process\n"
        "assert 'websockets' not in sys.modules, 'websockets imported'\n"
        "maps = open('/proc/self/maps').read() if sys.platform == 'linux' else ''\n"
        "assert 'libHD' not in maps and 'libdhd' not in maps, 'a vendor library is loaded'\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def test_devices_without_vendor_libraries_says_what_to_install(
    monkeypatch, tmp_path, capsys
) -> None:
    monkeypatch.setenv("PAINTAPP_LIBHD", str(tmp_path / "none" / "libHD.so"))
    monkeypatch.setenv("PAINTAPP_LIBDHD", str(tmp_path / "none" / "libdhd.so"))
    monkeypatch.setenv("PAINTAPP_HAPLY_URI", f"ws://127.0.0.1:{free_port()}")
    assert main(["devices"]) == 0
    out = capsys.readouterr().out
    lines = [line.strip() for line in out.splitlines() if line.strip().startswith(VENDOR_NAMES)]
    assert len(lines) == 3 and all("not found" in line for line in lines), out
    assert "OpenHaptics" in lines[0] and "PAINTAPP_LIBHD" in lines[0]
    assert "Force Dimension" in lines[1] and "PAINTAPP_LIBDHD" in lines[1]
    assert "Haply Hub" in lines[2] and "PAINTAPP_HAPLY_URI" in lines[2]


def test_devices_lists_a_library_it_finds(fake_dhd, capsys) -> None:
    assert main(["devices"]) == 0
    out = capsys.readouterr().out
    assert "Force Dimension DHD (libdhd) found" in out


def test_haptics_check_runs_a_vendor_device(fake_dhd, capsys) -> None:
    """Behaviour only (a short real-clock run; no rates asserted)."""
    assert main(["haptics-check", "--device", "dhd", "--seconds", "0.2", "--form", "thread"]) == 0
    out = capsys.readouterr().out
    assert "haptics-check: dhd" in out
    bad = [line for line in out.splitlines() if line.startswith("bad device writes")]
    assert bad and bad[0].split()[-1] == "0"
    rec = record(fake_dhd, DHD_RECORD, "fakeDhdRecord")
    assert rec["closed"] == 1 and rec["nonfinite"] == 0 and rec["over_limit"] == 0


def test_a_missing_vendor_library_is_one_line_from_haptics_check(
    monkeypatch, tmp_path, capsys
) -> None:
    monkeypatch.setenv("PAINTAPP_LIBHD", str(tmp_path / "libHD.so"))
    assert main(["haptics-check", "--device", "openhaptics", "--seconds", "0.2"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "PAINTAPP_LIBHD" in err[0]


def test_the_servo_process_drives_a_vendor_device(fake_dhd) -> None:
    """The window's form: the servo process builds the device from its name and closes it with
    zero force (behaviour only)."""
    servo = ServoProcess(ProcessOptions(device="dhd", realtime=False))
    servo.start()
    try:
        time.sleep(0.3)
    finally:
        report = servo.stop()
    assert report is not None and report.device_fault is None and report.ticks > 0
    audit = servo.audit()
    assert audit.get("nonfinite_writes", 0) == 0 and audit.get("over_limit_writes", 0) == 0


def test_axis_maps_keep_handedness_and_quaternions_are_unit() -> None:
    with pytest.raises(ValueError, match="handedness"):
        AxisMap(axes=(0, 2, 1), signs=(1.0, 1.0, 1.0))
    c, s = np.cos(0.4), np.sin(0.4)
    q = quat_from_matrix(np.array([[1, 0, 0], [0, c, -s], [0, s, c]]))
    np.testing.assert_allclose(q, [np.cos(0.2), np.sin(0.2), 0, 0], atol=1e-12)
    q = quat_from_matrix(np.diag([-1.0, -1.0, 1.0]))  # half a turn about z
    np.testing.assert_allclose(np.abs(q), [0, 0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(quat_from_matrix(np.full((3, 3), np.nan)), [1, 0, 0, 0])
