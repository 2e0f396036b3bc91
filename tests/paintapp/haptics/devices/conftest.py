"""Fixtures for the vendor backends: the fake ``libHD`` and ``libdhd`` compiled from the C files
in ``fakes/`` (once per test session, with ``cc -shared -fPIC``) and pointed to by the
environment variables the backends honour, and the fake Haply Inverse Service."""

from __future__ import annotations

import ctypes
import shutil
import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest

FAKES = Path(__file__).parent / "fakes"

HD_RECORD = (
    "frames",
    "writes",
    "nonfinite",
    "over_limit",
    "max_output_n",
    "out_x",
    "out_y",
    "out_z",
    "caps",
    "running",
    "initialised",
    "frames_outside_scheduler",
    "timeout_s",
    "timeouts",
)
DHD_RECORD = (
    "writes",
    "nonfinite",
    "over_limit",
    "watchdog_trips",
    "watchdog_s",
    "max_force_seen_n",
    "open",
    "forces_on",
    "brakes",
    "closed",
    "force_x",
    "force_y",
    "force_z",
    "since_last_call_s",
    "max_force_limit_n",
)


def compile_fake(name: str, out_dir: Path) -> Path:
    """Compile ``fakes/<name>.c`` into ``out_dir/lib<name>.so``; skip without a compiler."""
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        pytest.skip("the fake vendor libraries need a C compiler (Debian: build-essential)")
    out = out_dir / f"lib{name}.so"
    cmd = [cc, "-shared", "-fPIC", "-O1", "-o", str(out), str(FAKES / f"{name}.c"), "-lm"]
    result = subprocess.run([*cmd, "-lpthread"], capture_output=True, text=True, timeout=120)
    if result.returncode != 0:
        raise RuntimeError(f"compiling {name}.c failed:\n{result.stderr}")
    return out


@pytest.fixture(scope="session")
def fake_lib_dir(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    out = tmp_path_factory.mktemp("fake_vendor_libs")
    return {name: compile_fake(name, out) for name in ("fake_hd", "fake_dhd")}


def record(lib: ctypes.CDLL, fields: tuple[str, ...], fn: str) -> dict[str, float]:
    """A fake library's record as a dict."""
    buf = (ctypes.c_double * len(fields))()
    getattr(lib, fn)(buf)
    return dict(zip(fields, buf, strict=True))


@pytest.fixture
def fake_hd(
    fake_lib_dir: dict[str, Path], monkeypatch: pytest.MonkeyPatch
) -> Iterator[ctypes.CDLL]:
    """The fake libHD, reset (device state in this process's memory), its scheduler stepped by
    the test (``fakeHdRunScheduler``)."""
    path = fake_lib_dir["fake_hd"]
    monkeypatch.setenv("PAINTAPP_LIBHD", str(path))
    monkeypatch.delenv("PAINTAPP_FAKE_HD_STATE", raising=False)
    lib = ctypes.CDLL(str(path))
    lib.fakeHdReset()
    lib.fakeHdSetManual(1)
    yield lib
    lib.fakeHdReset()
    lib.fakeHdSetManual(0)


@pytest.fixture
def fake_dhd(
    fake_lib_dir: dict[str, Path], monkeypatch: pytest.MonkeyPatch
) -> Iterator[ctypes.CDLL]:
    """The fake libdhd, reset (device state in this process's memory), its watchdog stretched
    100 times for runs on a virtual clock (a test of the watchdog sets it back to 1)."""
    path = fake_lib_dir["fake_dhd"]
    monkeypatch.setenv("PAINTAPP_LIBDHD", str(path))
    monkeypatch.delenv("PAINTAPP_FAKE_DHD_STATE", raising=False)
    lib = ctypes.CDLL(str(path))
    lib.fakeDhdReset()
    lib.fakeDhdWatchdogScale(ctypes.c_double(100.0))
    yield lib
    lib.fakeDhdReset()
