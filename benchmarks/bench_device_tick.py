"""Each vendor backend's per-tick overhead: what one servo tick spends in the device's
``read`` and ``write`` (the ctypes calls, or the WebSocket round trip).

    python benchmarks/bench_device_tick.py [--backend all|openhaptics|dhd|haply] [--ticks 5000]
                                           [--sleep-us 800] [--real]

Without ``--real`` it measures against the test fakes: it compiles ``fake_hd.c`` and
``fake_dhd.c`` from ``tests/paintapp/haptics/devices/fakes/`` (``cc -shared -fPIC``) and starts
the fake Inverse Service on 127.0.0.1, so the figures are the backend's own cost plus a trivial
library or server (the fake service is Python, in this process: its share is in the Haply
figure). With ``--real`` it opens the installed library or the running service and the device
attached to it (``PAINTAPP_LIBHD``, ``PAINTAPP_LIBDHD``, ``PAINTAPP_HAPLY_URI`` as for the app).

Each tick is ``read()`` then ``write()`` of a small force, timed with ``perf_counter``, with
``--sleep-us`` of sleep after each (as the servo process sleeps to its deadlines). For
OpenHaptics, whose device calls run in the HD scheduler's callback, it also times the callback
itself (one scheduler frame: a ctypes call into Python and the frame's HD calls) when the fake's
scheduler is stepped by hand. Prints median, p99 and max in microseconds per backend.

Run it on a quiet machine: on a shared one the figures say more about the neighbours.
"""

from __future__ import annotations

import argparse
import ctypes
import os
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
FAKES = ROOT / "tests" / "paintapp" / "haptics" / "devices" / "fakes"
sys.path.insert(0, str(ROOT))

from paintapp.haptics.device import HapticDevice  # noqa: E402
from paintapp.haptics.devices.backends import build_vendor_device  # noqa: E402


def compile_fake(name: str, out_dir: Path) -> Path:
    """``fakes/<name>.c`` -> ``out_dir/lib<name>.so``."""
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        raise SystemExit("the fake libraries need a C compiler (cc); or use --real")
    out = out_dir / f"lib{name}.so"
    src = str(FAKES / f"{name}.c")
    subprocess.run(
        [cc, "-shared", "-fPIC", "-O2", "-o", str(out), src, "-lm", "-lpthread"], check=True
    )
    return out


def percentiles(samples_s: list[float]) -> str:
    us = np.asarray(samples_s) * 1e6
    p50, p99 = np.percentile(us, [50, 99])
    return f"median {p50:7.1f} us, p99 {p99:7.1f} us, max {us.max():7.1f} us ({len(us)} ticks)"


def time_ticks(
    device: HapticDevice, ticks: int, sleep_s: float, before: Callable[[], None] | None = None
) -> list[float]:
    """Seconds each ``read() + write()`` took."""
    force, torque = np.array([0.0, 0.0, 0.2]), np.zeros(3)
    out = []
    for _ in range(ticks):
        if before is not None:
            before()
        t0 = time.perf_counter()
        device.read()
        device.write(force, torque)
        out.append(time.perf_counter() - t0)
        if sleep_s > 0:
            time.sleep(sleep_s)
    return out


def bench_openhaptics(ticks: int, sleep_s: float, real: bool, lib_dir: Path | None) -> None:
    fake = None
    if not real:
        assert lib_dir is not None
        path = compile_fake("fake_hd", lib_dir)
        os.environ["PAINTAPP_LIBHD"] = str(path)
        fake = ctypes.CDLL(str(path))
        fake.fakeHdSetManual(1)  # the benchmark steps the scheduler: the callback can be timed
    device = build_vendor_device("openhaptics")
    device.open()
    try:
        frames: list[float] = []

        def frame() -> None:
            if fake is not None:
                t0 = time.perf_counter()
                fake.fakeHdRunScheduler(1)
                frames.append(time.perf_counter() - t0)

        if real:
            time.sleep(0.1)  # the scheduler's own thread fills the buffers
        samples = time_ticks(device, ticks, sleep_s, frame)
    finally:
        device.close()
    print(f"openhaptics  read+write (buffer exchange): {percentiles(samples)}")
    if frames:
        print(f"openhaptics  scheduler callback (1 frame): {percentiles(frames)}")


def bench_dhd(ticks: int, sleep_s: float, real: bool, lib_dir: Path | None) -> None:
    if not real:
        assert lib_dir is not None
        os.environ["PAINTAPP_LIBDHD"] = str(compile_fake("fake_dhd", lib_dir))
    device = build_vendor_device("dhd")
    device.open()
    try:
        samples = time_ticks(device, ticks, sleep_s)
    finally:
        device.close()
    print(f"dhd          read+write (ctypes calls):    {percentiles(samples)}")


def bench_haply(ticks: int, sleep_s: float, real: bool) -> None:
    if real:
        device = build_vendor_device("haply")
        device.open()
        try:
            samples = time_ticks(device, ticks, sleep_s)
        finally:
            device.close()
    else:
        from tests.paintapp.haptics.devices.fakes.inverse_service import FakeInverseService

        with FakeInverseService(lifetime_s=600.0) as service:
            os.environ["PAINTAPP_HAPLY_URI"] = service.uri
            device = build_vendor_device("haply")
            device.open()
            try:
                samples = time_ticks(device, ticks, sleep_s)
            finally:
                device.close()
    print(f"haply        read+write (WebSocket trip):  {percentiles(samples)}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--backend", choices=("all", "openhaptics", "dhd", "haply"), default="all")
    parser.add_argument("--ticks", type=int, default=5000)
    parser.add_argument("--sleep-us", type=float, default=800.0)
    parser.add_argument("--real", action="store_true", help="the installed library and device")
    args = parser.parse_args()
    if args.ticks < 1 or not 0 <= args.sleep_us <= 1e5:
        parser.error("--ticks must be >= 1 and --sleep-us in [0, 100000]")
    sleep_s = args.sleep_us * 1e-6
    chosen = ("openhaptics", "dhd", "haply") if args.backend == "all" else (args.backend,)
    print(
        f"{args.ticks} ticks each, {args.sleep_us:g} us sleep after each, {'real' if args.real else 'fake'} devices"
    )
    with tempfile.TemporaryDirectory() as tmp:
        lib_dir = None if args.real else Path(tmp)
        if "openhaptics" in chosen:
            bench_openhaptics(args.ticks, sleep_s, args.real, lib_dir)
        if "dhd" in chosen:
            bench_dhd(args.ticks, sleep_s, args.real, lib_dir)
        if "haply" in chosen:
            bench_haply(args.ticks, sleep_s, args.real)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
