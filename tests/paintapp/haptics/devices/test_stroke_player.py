"""Replaying strokes through the servo loop and recording the output forces."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

from common.errors import InputError
from paintapp.haptics.clock import VirtualClock
from paintapp.haptics.device import DeviceInfo
from paintapp.haptics.devices.stroke_player import ReplayDevice
from paintapp.haptics.orientation import tilt_twist_from_quat
from paintapp.haptics.safety import SafetyConfig
from paintapp.haptics.servo import ServoConfig, ServoLoop


@dataclass
class Sample:
    t_s: float
    position_m: np.ndarray
    pressure: float = 0.5
    tilt_rad: np.ndarray = field(default_factory=lambda: np.zeros(2))
    twist_rad: float = 0.0
    buttons: int = 1


def press_stroke() -> list[Sample]:
    """Hover, press 0.5 mm into the canvas while moving along x, lift."""
    ts = np.linspace(0.0, 1.0, 61)
    z = np.where((ts > 0.3) & (ts < 0.7), -0.0005, 0.005)
    return [
        Sample(
            t,
            np.array([0.1 * t, 0.0, zi]),
            tilt_rad=np.array([0.2 * t, 0.0]),
            twist_rad=t,
            buttons=int(t > 0.5),
        )
        for t, zi in zip(ts, z, strict=True)
    ]


def test_replay_interpolates_between_samples() -> None:
    clock = VirtualClock()
    dev = ReplayDevice(press_stroke(), clock.now_s)
    dev.open()
    clock.run(lambda i, t: True, 25)  # now at 24 ms: between samples at 16.7 and 33.3 ms
    state = dev.read()
    assert state.position_m[0] == pytest.approx(0.1 * 0.024)
    tilt, twist = tilt_twist_from_quat(state.orientation_wxyz)
    assert tilt[0] == pytest.approx(0.2 * 0.024) and twist == pytest.approx(0.024)
    assert state.buttons == 0


def test_replay_reads_any_time_in_any_order() -> None:
    """A read reuses the last read's pair of samples while the time stays between them; a time
    before it, past the end or on a held tilt reads the same as a search from scratch."""
    now = [0.0]
    curved = press_stroke()
    for s in curved:
        s.position_m[0] = s.t_s**2  # not a line: a wrong pair of samples reads another value
    ts = np.array([s.t_s for s in curved])
    dev = ReplayDevice(curved, lambda: now[0])
    held = press_stroke()
    for s in held:
        s.tilt_rad = np.array([0.1, -0.2])  # held: the orientation is computed once
    steady = ReplayDevice(held, lambda: now[0])
    dev.open()
    steady.open()
    for t in (0.024, 0.030, 0.5001, 0.2, 0.2, 0.0, 0.99, 1.5, 0.024):
        now[0] = t
        state = dev.read()
        assert state.position_m[0] == pytest.approx(np.interp(t, ts, ts**2), abs=1e-15)
        tilt, twist = tilt_twist_from_quat(state.orientation_wxyz)
        u = min(t, 1.0)
        assert tilt[0] == pytest.approx(0.2 * u, abs=1e-12) and twist == pytest.approx(u)
        tilt, _ = tilt_twist_from_quat(steady.read().orientation_wxyz)
        np.testing.assert_allclose(tilt, [0.1, -0.2], atol=1e-12)


def test_replay_through_the_loop_records_the_forces_felt() -> None:
    clock = VirtualClock()
    dev = ReplayDevice(press_stroke(), clock.now_s)
    loop = ServoLoop(dev, config=ServoConfig(safety=SafetyConfig(ramp_time_s=0.05)))
    report = loop.run(clock, 5.0)
    assert report.stopped_by == "device finished"
    rec = dev.recorded()
    assert len(rec["t_s"]) == report.ticks == 1001
    fz = rec["force_n"][:, 2]
    pressing = (rec["t_s"] > 0.35) & (rec["t_s"] < 0.65)
    k = 0.5 * dev.info.max_stiffness_n_per_m
    # the canvas pushes back (plus a fading damping term from the estimated velocity)
    np.testing.assert_allclose(fz[pressing], k * 0.0005, rtol=0.01)
    assert np.all(fz[rec["t_s"] < 0.29] == 0) and np.all(fz[rec["t_s"] > 0.71] == 0)


def test_recorded_forces_survive_a_save(tmp_path: Path) -> None:
    clock = VirtualClock()
    dev = ReplayDevice(press_stroke(), clock.now_s)
    ServoLoop(dev).run(clock, 0.5)
    dev.save_forces(tmp_path / "f.npz")
    with np.load(tmp_path / "f.npz", allow_pickle=False) as data:
        np.testing.assert_array_equal(data["force_n"], dev.recorded()["force_n"])


def test_bad_strokes_are_input_errors() -> None:
    clock = VirtualClock()
    with pytest.raises(InputError, match="no samples"):
        ReplayDevice([], clock.now_s, source="empty.jsonl")
    backwards = [Sample(0.1, np.zeros(3)), Sample(0.05, np.zeros(3))]
    with pytest.raises(InputError, match="backwards"):
        ReplayDevice(backwards, clock.now_s)
    with pytest.raises(InputError, match="non-finite"):
        ReplayDevice([Sample(0.0, np.array([0.0, np.nan, 0.0]))], clock.now_s)
    with pytest.raises(InputError, match="malformed"):
        ReplayDevice([object()], clock.now_s)


def test_replay_of_a_shipped_stroke_file() -> None:
    strokes = pytest.importorskip("paintapp.strokes.files")
    from paintapp.resources import asset_path

    stroke_file = strokes.read_strokes(asset_path("strokes", "example_short.jsonl"))
    clock = VirtualClock()
    tablet = DeviceInfo("tablet replay", "replay", 6, 0)
    dev = ReplayDevice(stroke_file.samples, clock.now_s, info=tablet)
    loop = ServoLoop(dev)
    report = loop.run(clock, dev.duration_s + 1.0)
    assert report.stopped_by == "device finished"
    positions = loop.log.arrays()["position_m"]
    first = stroke_file.samples[0].position_m
    np.testing.assert_allclose(positions[0], first)
    assert np.all(dev.recorded()["force_n"] == 0)  # input only: nothing to feel
