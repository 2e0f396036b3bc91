"""The servo loop in its own process: it starts light, runs, takes commands, and fails safe when
the app dies, stops beating, or when it is killed itself. Every device write stays finite and
within the device's limits.

No test asserts timing: each waits for a condition with a generous bound (the machines these
run on are shared and loaded).
"""

from __future__ import annotations

import contextlib
import multiprocessing as mp
import os
import signal
import time

import pytest

from common.errors import InputError
from paintapp.haptics.device import DeviceNotFoundError
from paintapp.haptics.process import (
    HEAVY_MODULES,
    NORMAL_SPIN_S,
    REALTIME_SPIN_S,
    ProcessOptions,
    ServoProcess,
    spin_for,
)
from paintapp.haptics.realtime import Granted
from paintapp.haptics.shared_state import PHASE_EXITED, SharedBlock
from tests.support.servo_harness import app_stand_in
from tests.support.waiting import wait_for


def assert_clean_writes(audit: dict[str, float]) -> None:
    assert audit["writes"] > 0
    assert audit["nonfinite_writes"] == 0 and audit["over_limit_writes"] == 0, audit


def gone(pid: int) -> bool:
    """The process has exited (a zombie left for a reaper that is not there counts as gone)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] in ("Z", "X")
    except FileNotFoundError:
        return True


def test_servo_process_runs_light_takes_commands_and_stops_at_zero():
    servo = ServoProcess(ProcessOptions(device="sim", start_m=(0.03, 0.03, 0.005)))
    try:
        servo.start()
        assert servo.heavy_modules == [] and set(servo.heavy_modules) <= set(HEAVY_MODULES)
        assert servo.granted and servo.granted != "not started"
        assert "us before each tick" in servo.granted  # the clock's spin, as granted
        for i in range(3000):  # hovering: the safety stage engages, the fluid force comes in
            servo.forces.publish_force(0.01 * i, [0.02, 0.0, 0.0])
            if servo.audit()["last_force_n"] > 0:
                break
            time.sleep(0.01)
        servo.target.set_position((0.03, 0.03, -0.001))  # press into the canvas
        for i in range(3000):
            servo.forces.publish_force(0.01 * i, [0.02, 0.0, 0.0])
            if servo.states.latest()[1].position_m[2] < 0 and servo.audit()["max_force_n"] > 0.5:
                break
            time.sleep(0.01)
        _, state = servo.states.latest()
        assert state is not None and state.position_m[2] < 0.002  # the hand went down
        assert servo.audit()["max_force_n"] > 0.5  # the canvas wall pushes back
        servo.set_force_scale(2.0)
        servo.engage(False)
        assert wait_for(lambda: servo.audit()["last_force_n"] == 0.0, 10.0), servo.audit()
        servo.engage(True)
        rate, _, seen = servo.live()
        assert seen > 100 and rate > 0
        assert servo.fault is None
    finally:
        report = servo.stop()
    assert report is not None and report.ticks > 500 and report.device_fault is None
    assert servo.left_because == "stopped by the app"
    audit = servo.audit()
    assert_clean_writes(audit)
    assert audit["last_force_n"] == 0.0 and audit["last_torque_nm"] == 0.0


def test_a_missing_device_is_reported_by_start():
    servo = ServoProcess(ProcessOptions(device="hid:dead:beef"))
    with pytest.raises(DeviceNotFoundError):
        servo.start()
    assert not servo.alive


def test_no_heartbeat_fades_out_and_exits(monkeypatch):
    options = ProcessOptions(device="sim:stroke", heartbeat_timeout_s=0.3)
    servo = ServoProcess(options, heartbeat=False)
    try:
        servo.start()
        servo.beat()
        assert wait_for(lambda: not servo.alive, 30.0), "the servo process kept running"
        assert "no heartbeat" in (servo.fault or "")
    finally:
        servo.stop()
    assert_clean_writes(servo.audit())
    assert servo.audit()["last_force_n"] == 0.0


def test_the_heartbeat_watchdog_waits_for_the_app_to_arm_it():
    """A start-up that holds the interpreter lock (and so the heartbeat) for longer than the
    timeout does not end the child; once armed, the same silence does, and the audit keeps the
    longest silence it saw after arming."""
    options = ProcessOptions(device="sim:stroke", heartbeat_timeout_s=0.3, arm_at_start=False)
    servo = ServoProcess(options, heartbeat=False)
    try:
        servo.start()
        silent_from = time.monotonic()
        assert not wait_for(lambda: not servo.alive, 1.5), "ended before it was armed"
        assert time.monotonic() - silent_from > 1.0  # over three timeouts without a beat
        assert servo.fault is None and servo.audit()["longest_app_silence_s"] == 0.0
        servo.arm()
        assert wait_for(lambda: not servo.alive, 30.0), "the armed servo process kept running"
        assert "no heartbeat" in (servo.fault or "")
    finally:
        servo.stop()
    audit = servo.audit()
    assert_clean_writes(audit)
    assert 0.3 <= audit["longest_app_silence_s"] < 1.0  # the armed silence, not the start-up's
    assert audit["last_force_n"] == 0.0


def test_an_app_that_never_arms_the_watchdog_counts_as_gone():
    options = ProcessOptions(device="sim:stroke", arm_at_start=False, arm_timeout_s=0.5)
    servo = ServoProcess(options)  # beating all along, but never armed
    try:
        servo.start()
        assert wait_for(lambda: not servo.alive, 30.0), "the servo process kept running"
        assert "did not finish starting within 0.5 s" in (servo.fault or ""), servo.fault
    finally:
        servo.stop()
    assert_clean_writes(servo.audit())
    assert servo.audit()["last_force_n"] == 0.0


def test_sigkill_of_the_app_fades_to_zero_and_exits():
    """The app (a stand-in process) presses the hand into the canvas and publishes a fluid force,
    then is SIGKILLed: the orphaned servo process fades out, writes zero and exits."""
    ctx = mp.get_context("spawn")
    ours, theirs = ctx.Pipe()
    app = ctx.Process(target=app_stand_in, args=(theirs,))  # not daemonic: it has a child
    app.start()
    block = None
    try:
        started = wait_for(lambda: ours.poll() or not app.is_alive(), 60.0)
        assert started and app.is_alive(), "the stand-in app did not start its servo process"
        name, servo_pid = ours.recv()
        block = SharedBlock(name)
        pressing = wait_for(lambda: block.audit_counts()["last_force_n"] > 0.05, 30.0)
        assert pressing, block.audit_counts()
        os.kill(app.pid, signal.SIGKILL)
        app.join(10.0)
        assert wait_for(lambda: block.phase == PHASE_EXITED, 30.0), "the servo kept running"
        assert wait_for(lambda: gone(servo_pid), 10.0)
        audit = block.audit_counts()
        assert_clean_writes(audit)
        assert audit["last_force_n"] == 0.0 and audit["last_torque_nm"] == 0.0
    finally:
        if app.is_alive():
            app.kill()
        if block is not None:
            if block.phase != PHASE_EXITED and block.pid and not gone(block.pid):
                os.kill(block.pid, signal.SIGKILL)
            with contextlib.suppress(FileNotFoundError):
                block.shm.unlink()  # its owner was killed


def test_sigkill_of_the_servo_process_is_noticed():
    servo = ServoProcess(ProcessOptions(device="sim:stroke"))
    try:
        servo.start()
        assert wait_for(lambda: servo.audit()["writes"] > 100, 30.0)
        assert servo.fault is None
        os.kill(servo.pid, signal.SIGKILL)
        assert wait_for(lambda: servo.fault is not None, 10.0)
        assert "servo process stopped" in servo.fault and "-9" in servo.fault
        servo.forces.publish_force(0.0, [0.01, 0, 0])  # publishing on is harmless
    finally:
        servo.stop()
    assert_clean_writes(servo.audit())


def test_the_clock_spins_only_without_real_time_priority_unless_told():
    """With a real-time class the wake-up is precise and the spin's core time goes to the
    simulation; without one the clock keeps spinning; an explicit spin wins either way."""
    fifo, rr = Granted("SCHED_FIFO 40"), Granted("SCHED_RR 40")
    assert fifo.realtime and rr.realtime
    assert not Granted("nice -10").realtime and not Granted("normal").realtime
    assert spin_for(fifo) == spin_for(rr) == REALTIME_SPIN_S
    assert spin_for(Granted("nice -10")) == spin_for(Granted()) == NORMAL_SPIN_S
    assert REALTIME_SPIN_S < NORMAL_SPIN_S
    assert spin_for(fifo, 1e-4) == spin_for(Granted(), 1e-4) == 1e-4
    for bad in (-1e-4, float("nan"), float("inf"), 2e-3):  # more than a whole 1 ms tick
        with pytest.raises(InputError, match="spin_s"):
            ProcessOptions(spin_s=bad)
    assert ProcessOptions(spin_s=0.0).spin_s == 0.0 and ProcessOptions().spin_s is None
