"""A fake Haply Inverse Service for tests: a WebSocket server on 127.0.0.1 speaking the
simulation channel's documented messages over a simulated Inverse3 (a stylus in a simulated
hand) and, optionally, a Wireless VerseGrip.

As the service does: on connect it sends the full inventory (config, state, status of every
device); then exactly one state update per message received. ``set_cursor_force`` acts for one
tick; every force received is recorded (count, non-finite, over the 3.3 N limit, the largest,
the last). Each message advances the simulated hand by 1 ms.

The device side is kept apart from the channel: ``Record.device_force`` is the force the service
applies to the Inverse3 now. When the connection is lost (closed by the client, or its process
dying) the service commands zero force at once; while a connection stays silent it commands zero
once every ``check_interval_s`` (its own check), so the arm never keeps a stale force.

Bounded: it serves at most ``max_messages`` messages and stops by itself after ``lifetime_s``.
Faults on demand: close the connection after ``close_after`` messages (the service stopping
mid-stroke), drop the Inverse3 from the updates after ``unplug_after`` (unplugged).
"""

from __future__ import annotations

import json
import math
import threading
import time
from dataclasses import dataclass, field
from typing import Any

from websockets.exceptions import ConnectionClosed
from websockets.sync.server import Server, ServerConnection, serve

ARM_ID = "049D"
GRIP_ID = "C3A1"
CENTRE = (0.0, -0.12, 0.15)
MAX_FORCE_N = 3.3
#: How often the service checks a silent connection and idles the device, s.
CHECK_INTERVAL_S = 0.1


@dataclass
class Record:
    """What the fake saw."""

    messages: int = 0
    forces: int = 0
    nonfinite: int = 0
    over_limit: int = 0
    max_force_n: float = 0.0
    last_force: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    session: dict[str, Any] = field(default_factory=dict)
    probes: int = 0
    connections: int = 0
    #: the force the service applies to the Inverse3 now
    device_force: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    #: time.monotonic() of the last message received
    last_message_s: float | None = None
    #: time.monotonic() when the service saw the connection end, and when it then commanded zero
    connection_lost_s: float | None = None
    zeroed_after_loss_s: float | None = None
    #: times a silent connection's check found a force applied and commanded zero
    idle_stops: int = 0


class FakeInverseService:
    """The fake service; use as a context manager (``with FakeInverseService() as svc``)."""

    def __init__(
        self,
        grip: bool = True,
        close_after: int | None = None,
        unplug_after: int | None = None,
        mute_after: int | None = None,
        max_messages: int = 100_000,
        lifetime_s: float = 60.0,
        check_interval_s: float = CHECK_INTERVAL_S,
    ) -> None:
        self.grip = grip
        self.close_after = close_after
        self.unplug_after = unplug_after
        self.mute_after = mute_after
        self.max_messages = max_messages
        self.lifetime_s = lifetime_s
        self.check_interval_s = check_interval_s
        self.record = Record()
        self._stopping = threading.Event()
        self._server: Server | None = None
        self._thread: threading.Thread | None = None
        self._timer: threading.Timer | None = None
        self._x = [0.0, 0.0, 0.0]
        self._v = [0.0, 0.0, 0.0]
        self._force = [0.0, 0.0, 0.0]
        self._steps = 0

    @property
    def uri(self) -> str:
        assert self._server is not None
        port = self._server.socket.getsockname()[1]
        return f"ws://127.0.0.1:{port}"

    def __enter__(self) -> FakeInverseService:
        self._server = serve(self._handle, "127.0.0.1", 0, compression=None)
        self._thread = threading.Thread(target=self._server.serve_forever, daemon=True)
        self._thread.start()
        self._timer = threading.Timer(self.lifetime_s, self.stop)
        self._timer.daemon = True
        self._timer.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()

    def stop(self) -> None:
        self._stopping.set()
        if self._timer is not None:
            self._timer.cancel()
        if self._server is not None:
            self._server.shutdown()
        if self._thread is not None:
            self._thread.join(5.0)

    def _target(self, t: float) -> tuple[list[float], list[float]]:
        w, r = 2.0 * math.pi, 0.03
        c = CENTRE
        p = [c[0] + r * math.cos(w * t), c[1] + r * math.sin(w * t), c[2] - 0.002]
        v = [-r * w * math.sin(w * t), r * w * math.cos(w * t), 0.0]
        if t < 0.3:
            ph = math.pi * t / 0.3
            p[2] += 0.012 * 0.5 * (1.0 + math.cos(ph))
            v[2] = -0.012 * 0.5 * math.sin(ph) * math.pi / 0.3
        return p, v

    def _step(self) -> None:
        p, v = self._target(self._steps * 1e-3)
        h, k, c, m = 1e-3, 300.0, 3.0, 0.25
        for i in range(3):
            self._v[i] += (
                h * (k * (p[i] - self._x[i]) + c * (v[i] - self._v[i]) + self._force[i]) / m
            )
            self._x[i] += h * self._v[i]
        self._steps += 1

    def _message(self, full: bool) -> dict[str, Any]:
        x, v = self._x, self._v
        arm: dict[str, Any] = {
            "device_id": ARM_ID,
            "state": {
                "cursor_position": {"x": x[0], "y": x[1], "z": x[2]},
                "cursor_velocity": {"x": v[0], "y": v[1], "z": v[2]},
                "current_cursor_force": dict(zip("xyz", self._force, strict=True)),
                "mode": "cartesian",
            },
            "status": {"calibrated": True, "in_use": True, "power_supply": True, "ready": True},
        }
        if full:
            arm["config"] = {
                "type": "inverse3",
                "handedness": "right",
                "basis": {"permutation": "XYZ"},
            }
        out: dict[str, Any] = {"session_id": 1}
        unplugged = self.unplug_after is not None and self.record.messages >= self.unplug_after
        out["inverse3"] = [] if unplugged else [arm]
        if self.grip:
            down = (self._steps // 500) % 2 == 1
            grip: dict[str, Any] = {
                "device_id": GRIP_ID,
                "state": {
                    "orientation": {"w": math.cos(0.15), "x": math.sin(0.15), "y": 0.0, "z": 0.0},
                    "buttons": {"a": down, "b": False},
                    "hall": 0,
                },
                "status": {"connected": True},
            }
            if full:
                grip["config"] = {"type": "wireless_verse_grip"}
            out["wireless_verse_grip"] = [grip]
        return out

    def _apply(self, message: dict[str, Any]) -> None:
        if "session" in message:
            self.record.session = message["session"]
        self._force = [0.0, 0.0, 0.0]  # a force command lasts one tick
        for arm in message.get("inverse3") or []:
            commands = arm.get("commands") or {}
            if "probe_position" in commands:
                self.record.probes += 1
            cmd = commands.get("set_cursor_force")
            if cmd is None:
                continue
            vec = cmd["vector"]
            f = [float(vec[k]) for k in "xyz"]
            self.record.forces += 1
            if not all(map(math.isfinite, f)):
                self.record.nonfinite += 1
                continue
            n = math.sqrt(sum(c * c for c in f))
            if n > MAX_FORCE_N * (1 + 1e-9):
                self.record.over_limit += 1
            self.record.max_force_n = max(self.record.max_force_n, n)
            self.record.last_force = f
            self._force = f
        self.record.device_force = list(self._force)

    def _receive(self, ws: ServerConnection) -> str | bytes | None:
        """The next message; None once the connection stayed silent for ``lifetime_s`` or the
        service stops. Each ``check_interval_s`` without one, the device is commanded zero."""
        silent_since = time.monotonic()
        while not self._stopping.is_set():
            try:
                return ws.recv(timeout=self.check_interval_s)
            except TimeoutError:
                if any(self.record.device_force):
                    self.record.idle_stops += 1
                self.record.device_force = [0.0, 0.0, 0.0]
                if time.monotonic() - silent_since > self.lifetime_s:
                    return None
        return None

    def _handle(self, ws: ServerConnection) -> None:
        self.record.connections += 1
        p, _ = self._target(0.0)
        self._x, self._v, self._steps = list(p), [0.0, 0.0, 0.0], 0
        try:
            ws.send(json.dumps(self._message(full=True)))
            while self.record.messages < self.max_messages:
                raw = self._receive(ws)
                if raw is None:
                    return
                self.record.last_message_s = time.monotonic()
                self._apply(json.loads(raw))
                self.record.messages += 1
                if self.close_after is not None and self.record.messages >= self.close_after:
                    ws.close()
                    return
                self._step()
                if self.mute_after is not None and self.record.messages >= self.mute_after:
                    continue  # a service that stalls: it reads on but answers no more
                ws.send(json.dumps(self._message(full=False)))
        except ConnectionClosed:
            return
        finally:
            # the connection is gone (or given up): the device gets zero force
            self.record.connection_lost_s = time.monotonic()
            self.record.device_force = [0.0, 0.0, 0.0]
            self.record.zeroed_after_loss_s = time.monotonic()
