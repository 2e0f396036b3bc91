"""The servo loop: force composition, published states, device failure, device kinds."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from paintapp.haptics.clock import VirtualClock
from paintapp.haptics.contact import ContactConfig
from paintapp.haptics.device import DeviceError, DeviceInfo, DeviceState
from paintapp.haptics.devices.simulated import SIMULATED_INFO, SimulatedDevice, hold_at
from paintapp.haptics.fluid import FluidConfig
from paintapp.haptics.servo import ServoConfig, ServoLoop


class ScriptedDevice:
    """Reports a fixed position; records writes; can fail after a number of reads."""

    def __init__(
        self,
        clock: VirtualClock,
        info: DeviceInfo,
        z_m: float = 0.01,
        fail_after: int | None = None,
    ) -> None:
        self.clock, self._info, self.z_m, self.fail_after = clock, info, z_m, fail_after
        self.reads, self.writes, self.closed = 0, [], False

    @property
    def info(self) -> DeviceInfo:
        return self._info

    def open(self) -> None: ...

    def close(self) -> None:
        self.closed = True

    def read(self) -> DeviceState:
        self.reads += 1
        if self.fail_after is not None and self.reads > self.fail_after:
            raise DeviceError("unplugged")
        return DeviceState(self.clock.now_s(), np.array([0.0, 0.0, self.z_m]), pressure=0.3)

    def write(self, force_n: np.ndarray, torque_nm: np.ndarray) -> None:
        self.writes.append((force_n.copy(), torque_nm.copy()))


def run_publishing(loop: ServoLoop, clock: VirtualClock, seconds: float, force, torque=None):
    """Run the loop while a 'simulation' publishes the same sample every 10 ticks."""

    def tick(i: int, t: float) -> bool:
        if i % 10 == 0:
            loop.forces.publish_force(t, force, torque)
        return loop.tick(t)

    loop.open()
    clock.run(tick, round(seconds / clock.period_s))


def fast_engage(scale: float = 2.0) -> ServoConfig:
    from paintapp.haptics.safety import SafetyConfig

    return ServoConfig(safety=SafetyConfig(ramp_time_s=0.01), fluid=FluidConfig(force_scale=scale))


def test_force_is_contact_plus_scaled_filtered_fluid_and_torque() -> None:
    clock = VirtualClock()
    dev = ScriptedDevice(clock, SIMULATED_INFO, z_m=-0.0005)  # 0.5 mm into the canvas
    loop = ServoLoop(dev, config=fast_engage(scale=2.0))
    run_publishing(loop, clock, 0.5, [0.1, -0.2, 0.0], [0.0, 0.01, 0.0])
    f, t = dev.writes[-1]
    k = 0.5 * SIMULATED_INFO.max_stiffness_n_per_m
    np.testing.assert_allclose(f, [0.2, -0.4, k * 0.0005], rtol=1e-9)
    np.testing.assert_allclose(t, [0.0, 0.02, 0.0], rtol=1e-9)
    log = loop.log.arrays()
    assert len(log["t_s"]) == 500
    np.testing.assert_allclose(log["force_n"][-1], f)
    np.testing.assert_allclose(log["contact_force_n"][-1], [0, 0, k * 0.0005])


def test_a_large_force_at_start_waits_until_it_is_small() -> None:
    """Pressing 3 mm into the canvas when the loop starts: nothing is output (chai3d-style)."""
    clock = VirtualClock()
    dev = ScriptedDevice(clock, SIMULATED_INFO, z_m=-0.003)
    loop = ServoLoop(dev, config=fast_engage())
    loop.run(clock, 0.5)
    assert all(np.all(f == 0) for f, _ in dev.writes)
    dev.z_m = 0.001  # lifted
    loop.run(clock, 0.1)
    dev.z_m = -0.003  # pressing again: now the wall pushes back
    loop.run(clock, 0.1)
    assert dev.writes[-1][0][2] == pytest.approx(3.0)


def test_published_state_is_in_the_canvas_frame_with_velocity_and_pressure() -> None:
    clock = VirtualClock()
    dev = SimulatedDevice(clock.now_s, target=hold_at((0.01, 0.02, 0.0495)))
    cfg = replace(fast_engage(), contact=ContactConfig(height_m=0.05))
    loop = ServoLoop(dev, config=cfg)
    loop.run(clock, 1.0)
    seq, state = loop.states.latest()
    assert seq == 1000
    assert state.position_m[2] < 0  # below the canvas, held up by the wall
    assert state.position_m[2] == pytest.approx(-0.0005 * 300 / 1300, rel=1e-3)  # hand vs wall
    np.testing.assert_allclose(state.position_m[:2], [0.01, 0.02], atol=1e-9)
    assert state.pressure > 0.0
    assert np.linalg.norm(state.velocity_m_per_s) < 1e-3


def test_device_failure_stops_the_loop_cleanly_and_keeps_the_log() -> None:
    clock = VirtualClock()
    dev = ScriptedDevice(clock, SIMULATED_INFO, fail_after=300)
    with ServoLoop(dev, config=fast_engage()) as loop:
        report = loop.run(clock, 1.0)
        assert report.stopped_by == "device fault"
        assert "unplugged" in (report.device_fault or "")
        assert report.ticks == 300 and len(loop.log) == 300
        assert np.all(dev.writes[-1][0] == 0)  # zero force sent on the way out
        assert not loop.tick(clock.now_s())  # stays stopped
    assert dev.closed


def test_input_only_device_gets_zero_force() -> None:
    clock = VirtualClock()
    tablet = DeviceInfo("tablet", "test", 3, 0)
    dev = ScriptedDevice(clock, tablet, z_m=-0.002)
    loop = ServoLoop(dev, config=fast_engage())
    loop.forces.publish_force(0.0, [1.0, 1.0, 1.0])
    loop.run(clock, 0.2)
    assert all(np.all(f == 0) and np.all(t == 0) for f, t in dev.writes)
    assert loop.states.latest()[1].pressure == pytest.approx(0.3)  # the tablet's own pressure


def test_two_dof_device_gets_no_z_force() -> None:
    clock = VirtualClock()
    joystick = DeviceInfo("stick", "test", 2, 2, max_force_n=2.0, max_stiffness_n_per_m=400.0)
    dev = ScriptedDevice(clock, joystick, z_m=-0.002)
    loop = ServoLoop(dev, config=fast_engage())
    run_publishing(loop, clock, 0.3, [0.3, 0.0, 0.5])
    f, _ = dev.writes[-1]
    np.testing.assert_allclose(f, [0.6, 0.0, 0.0])


def test_a_virtual_clock_run_is_exactly_repeatable(closed_loop) -> None:
    runs = []
    for _ in range(2):
        cl = closed_loop(config=fast_engage(scale=8.0))
        cl.run(1.0)
        runs.append(cl.loop.log.table())
    np.testing.assert_array_equal(runs[0][:, 1:], runs[1][:, 1:])


def test_an_unexpected_driver_error_also_stops_the_loop_with_zero_force() -> None:
    clock = VirtualClock()
    dev = ScriptedDevice(clock, SIMULATED_INFO)
    loop = ServoLoop(dev, config=fast_engage())
    loop.open()

    def broken_read() -> DeviceState:
        raise ValueError("malformed report")

    loop.run(clock, 0.1)
    dev.read = broken_read
    report = loop.run(clock, 0.1)
    assert report.stopped_by == "device fault" and "ValueError" in report.device_fault
    assert np.all(dev.writes[-1][0] == 0) and report.ticks == 100


def test_force_scale_can_change_while_the_loop_runs() -> None:
    clock = VirtualClock()
    dev = ScriptedDevice(clock, SIMULATED_INFO, z_m=0.01)  # above the canvas: fluid force only
    loop = ServoLoop(dev, config=fast_engage(scale=2.0))
    run_publishing(loop, clock, 0.3, [0.1, 0.0, 0.0], [0.0, 0.0, 0.01])
    np.testing.assert_allclose(dev.writes[-1][0], [0.2, 0.0, 0.0], rtol=1e-9)
    loop.set_force_scale(5.0)
    assert loop.config.fluid.force_scale == 5.0

    def tick(i: int, t: float) -> bool:
        if i % 10 == 0:
            loop.forces.publish_force(t, [0.1, 0.0, 0.0], [0.0, 0.0, 0.01])
        return loop.tick(t)

    clock.run(tick, 300)
    force, torque = dev.writes[-1]
    np.testing.assert_allclose(force, [0.5, 0.0, 0.0], rtol=1e-9)
    np.testing.assert_allclose(torque, [0.0, 0.0, 0.05], rtol=1e-9)


def test_the_simulated_stroke_starts_at_its_first_read_whatever_the_setup_time() -> None:
    """A loop may spend a while after opening the device (building its filter); the simulated
    hand must still start at the stroke's hover point, or it would already press into the canvas
    and the safety stage would never engage (a servo process then wrote no force at all)."""
    now = [1000.0]  # a clock that does not start at 0
    device = SimulatedDevice(lambda: now[0])
    device.open()
    now[0] += 2.0  # setup time: longer than the stroke's approach
    first = device.read()
    assert first.position_m[2] > 0.009  # at the hover height, above the canvas
    for _ in range(400):
        now[0] += 1e-3
        last = device.read()
    assert last.position_m[2] < 0.0  # the approach then brings it down into the paint


def test_a_loop_on_the_simulated_stroke_engages_and_writes_force() -> None:
    now = [50.0]
    device = SimulatedDevice(lambda: now[0])
    loop = ServoLoop(device)
    loop.open()
    now[0] += 1.5  # a slow start
    for _ in range(2000):
        loop.tick(now[0])
        now[0] += 1e-3
    assert loop.safety.state.value == "engaged"
    assert device.max_force_written_n > 0.2  # the canvas pushes back on the pressed tip
