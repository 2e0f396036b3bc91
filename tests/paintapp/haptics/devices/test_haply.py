"""The Haply backend against a fake Inverse Service (``fakes/inverse_service.py``): the
simulation channel's messages (inventory, one update per message, ``set_cursor_force``), the
service closing mid-stroke, the device unplugged, with the servo loop on a virtual clock; and the
service idling the device after the client's process is killed (SIGKILL)."""

from __future__ import annotations

import math
import os
import signal
import socket
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("websockets")

from paintapp.haptics.clock import RealTimeClock, VirtualClock
from paintapp.haptics.device import DeviceError, DeviceNotFoundError
from paintapp.haptics.devices import haply
from paintapp.haptics.servo import ServoLoop
from tests.paintapp.haptics.devices.fakes.inverse_service import (
    ARM_ID,
    CHECK_INTERVAL_S,
    FakeInverseService,
)

REPO = Path(__file__).resolve().parents[4]


def run_loop(service: FakeInverseService, ticks: int) -> ServoLoop:
    clock = VirtualClock()
    # on a virtual clock the ticks do not wait for real time: the device answers in lockstep
    loop = ServoLoop(haply.HaplyDevice(clock.now_s, uri=service.uri, tick_wait_s=None))
    loop.open()
    clock.run(lambda i, t: loop.tick(t), ticks)
    return loop


def test_a_late_answer_does_not_hold_up_the_tick_and_a_silent_service_stops_the_loop() -> None:
    with FakeInverseService(mute_after=3, lifetime_s=30) as service:
        # lockstep for the answered commands (a busy machine must not make them late)
        device = haply.HaplyDevice(uri=service.uri, reply_timeout_s=0.2, tick_wait_s=None)
        device.open()
        push = np.array([0.0, 0.0, 1.0])
        for _ in range(2):  # the opening's zero force and the first push are answered
            state = device.read()
            device.write(push, np.zeros(3))
        device.tick_wait_s = 1e-3
        sent = service.record.forces
        begin = time.monotonic()
        stale = 0
        with pytest.raises(DeviceError, match="no state update"):
            while time.monotonic() - begin < 10.0:
                again = device.read()
                device.write(push, np.zeros(3))
                assert np.array_equal(again.position_m, state.position_m)
                stale += 1
        elapsed = time.monotonic() - begin
        assert stale > 1  # ticks went on with the last state, not held up until the timeout
        assert device.late_answers >= stale - 1
        assert service.record.forces <= sent + 1  # no new force while unanswered
        assert elapsed >= 0.15  # given up only after reply_timeout_s of silence
        device.close()


def closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def test_servo_loop_feels_the_canvas_through_the_service() -> None:
    with FakeInverseService(lifetime_s=30) as service:
        loop = run_loop(service, 1500)
        assert loop.report().stopped_by == "limit"
        info = loop.device.info
        assert info.kind == "haply" and info.dof_sensed == 6 and "VerseGrip" in info.name
        log = loop.log.arrays()
        assert np.max(log["force_n"][:, 2]) > 0.3
        # Haply's axes are ours; the origin moved to the middle of reach
        # the fake's stroke starts 30 mm right of the centre, 10 mm above the canvas
        np.testing.assert_allclose(log["position_m"][0], [0.03, 0.0, 0.010], atol=1e-3)
        _, state = loop.states.latest()
        assert state is not None
        np.testing.assert_allclose(
            state.orientation_wxyz, [math.cos(0.15), math.sin(0.15), 0, 0], atol=1e-12
        )
        assert state.buttons == 1  # the grip's "a" is held in the fake's second half-second
        rec = service.record
        assert rec.forces >= 1500 and rec.messages >= 1500  # one command per tick, one update each
        assert rec.nonfinite == 0 and rec.over_limit == 0 and rec.probes == 0
        assert rec.session["configure"]["basis"] == {"permutation": "XYZ"}
        loop.close()
        assert service.record.last_force == [0.0, 0.0, 0.0]


def test_close_sends_zero_force_and_leaves() -> None:
    with FakeInverseService(lifetime_s=30) as service:
        loop = run_loop(service, 700)
        assert np.linalg.norm(service.record.last_force) > 0.05
        loop.close()
        assert service.record.last_force == [0.0, 0.0, 0.0]
        loop.close()


def test_service_closing_mid_stroke_stops_the_loop_safely() -> None:
    with FakeInverseService(close_after=500, lifetime_s=30) as service:
        loop = run_loop(service, 1500)
        report = loop.report()
        assert report.stopped_by == "device fault"
        assert "closed the connection" in report.device_fault
        assert report.ticks == 499
        loop.close()  # no exception from a service that is gone


def test_unplugged_inverse3_stops_the_loop_safely() -> None:
    with FakeInverseService(unplug_after=300, lifetime_s=30) as service:
        loop = run_loop(service, 1500)
        report = loop.report()
        assert report.stopped_by == "device fault" and "unplugged" in report.device_fault
        assert report.ticks == 299
        loop.close()


def test_non_finite_force_is_never_sent() -> None:
    with FakeInverseService(lifetime_s=30) as service:
        # lockstep: on a busy machine an answer may miss the 0.2 ms a servo tick waits
        device = haply.HaplyDevice(uri=service.uri, tick_wait_s=None)
        device.open()
        device.read()
        device.write(np.array([np.nan, 0.0, 1.0]), np.zeros(3))
        device.read()
        device.write(np.array([0.0, 0.0, 40.0]), np.zeros(3))
        device.read()
        device.close()
        assert service.record.nonfinite == 0 and service.record.over_limit == 0
        assert service.record.max_force_n == pytest.approx(haply.INVERSE3_INFO.max_force_n)


def test_a_read_with_nothing_outstanding_probes() -> None:
    with FakeInverseService(lifetime_s=30) as service:
        # lockstep: on a busy machine an answer may miss the 0.2 ms a servo tick waits
        device = haply.HaplyDevice(uri=service.uri, tick_wait_s=None)
        device.open()
        device.read()
        device.read()  # no write in between: a probe keeps the channel one-to-one
        device.close()
        assert service.record.probes == 1


def test_service_not_running_is_a_clear_message() -> None:
    uri = f"ws://127.0.0.1:{closed_port()}"
    with pytest.raises(DeviceNotFoundError) as err:
        haply.HaplyDevice(uri=uri, connect_timeout_s=1.0).open()
    text = str(err.value)
    assert uri in text and "Haply Hub" in text and "PAINTAPP_HAPLY_URI" in text
    with pytest.raises(DeviceError):
        haply.HaplyDevice(uri=uri).read()


def test_no_inverse3_listed_is_a_clear_message(monkeypatch) -> None:
    with FakeInverseService(unplug_after=0, lifetime_s=30) as service:
        with pytest.raises(DeviceNotFoundError, match="lists no Inverse3"):
            haply.HaplyDevice(uri=service.uri).open()
    with FakeInverseService(lifetime_s=30) as service:
        with pytest.raises(DeviceNotFoundError, match="no Inverse3 'FFFF'"):
            haply.HaplyDevice(uri=service.uri, device_id="FFFF").open()


def test_without_websockets_the_message_says_what_to_install(monkeypatch) -> None:
    monkeypatch.setitem(sys.modules, "websockets.sync.client", None)
    with pytest.raises(DeviceNotFoundError, match=r"pip install websockets"):
        haply.HaplyDevice(uri="ws://127.0.0.1:1").open()


def test_real_clock_run_through_the_service() -> None:
    """Behaviour only (no rates): the loop on the real clock against the service."""
    with FakeInverseService(lifetime_s=30) as service:
        clock = RealTimeClock(1e-3)
        loop = ServoLoop(haply.HaplyDevice(clock.now_s, uri=service.uri, device_id=ARM_ID))
        loop.open()
        loop.start(clock, 0.3)
        deadline = time.monotonic() + 30.0
        while clock.running and time.monotonic() < deadline:
            time.sleep(0.02)
        loop.stop()
        assert loop.report().device_fault is None and loop.ticks > 0
        loop.close()
        assert service.record.nonfinite == 0 and service.record.over_limit == 0
        assert service.record.last_force == [0.0, 0.0, 0.0]


CHILD = textwrap.dedent(
    """
    import sys, time
    import numpy as np
    from paintapp.haptics.devices.haply import HaplyDevice
    # generous timeouts: a busy machine must not end the stroke before the kill
    device = HaplyDevice(uri=sys.argv[1], reply_timeout_s=5.0, connect_timeout_s=10.0)
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


def test_the_service_zeroes_the_force_after_the_client_is_killed() -> None:
    """The client's process is SIGKILLed mid-stroke: its connection drops, and the service
    commands zero force to the Inverse3 within its check interval of seeing the loss."""
    push = [0.0, 0.0, 1.5]
    with FakeInverseService(lifetime_s=60) as service:
        env = dict(os.environ, PYTHONPATH=str(REPO))
        child = subprocess.Popen(
            [sys.executable, "-c", CHILD, service.uri], env=env, stdout=subprocess.PIPE, text=True
        )
        try:
            assert child.stdout is not None
            assert child.stdout.readline().strip() == "running"
            rec = service.record
            # pushing while alive (polled: a stalled client has the service idle the arm a while)
            deadline = time.monotonic() + 10.0
            while rec.device_force != push and time.monotonic() < deadline:
                time.sleep(0.001)
            assert rec.device_force == push and rec.connection_lost_s is None
            killed_s = time.monotonic()
            child.send_signal(signal.SIGKILL)
            child.wait(10)
            deadline = time.monotonic() + 10.0
            while (rec.connection_lost_s is None or any(rec.device_force)) and (
                time.monotonic() < deadline
            ):
                time.sleep(CHECK_INTERVAL_S / 10)
            assert rec.device_force == [0.0, 0.0, 0.0]
            assert rec.last_force == push  # the client's last word was a push: the zero is ours
            assert rec.connection_lost_s is not None and rec.connection_lost_s >= killed_s
            assert rec.zeroed_after_loss_s is not None
            assert 0.0 <= rec.zeroed_after_loss_s - rec.connection_lost_s <= CHECK_INTERVAL_S
        finally:
            if child.poll() is None:
                child.kill()
                child.wait(10)
