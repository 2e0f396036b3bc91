"""The Haply Inverse3 (and its VerseGrip handle) through the Haply Inverse Service's WebSocket
simulation channel, as a :class:`~paintapp.haptics.device.HapticDevice`. Needs the optional
``websockets`` package (the ``haply`` extra: ``pip install websockets``), imported only when
opened.

The service answers every message with one state update, so each tick's
:meth:`~HaplyDevice.write` sends one ``set_cursor_force`` and the next :meth:`~HaplyDevice.read`
takes its answer (it arrived while the loop slept). A late answer never holds up a tick: the read
waits :data:`TICK_WAIT_S` for it, then goes on with the last state, and no new force is sent until
it has come (one answer per command; counted in ``late_answers``).

Frame and units: Haply's frame (basis set to ``XYZ`` at connection) is ours
(:mod:`paintapp.haptics.device`): x right, y away from the user, z up; m, N, a unit quaternion.
Only the origin moves: ours = device - ``centre_m`` (:data:`INVERSE3_CENTRE_M`, mid-reach).

Safety: ``set_cursor_force`` lasts one message, so the device idles if ours stop; no update within
``reply_timeout_s``, a closed connection, a missing or not-ready Inverse3 or malformed state raise
:class:`~paintapp.haptics.device.DeviceError`, stopping the loop with zero force.

Setup: docs/guide/devices-vendor.md.
"""

from __future__ import annotations

import json
import math
import os
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from paintapp.haptics.device import DeviceError, DeviceInfo, DeviceNotFoundError, DeviceState
from paintapp.haptics.devices.vendor import limited

#: The service's default simulation channel; ``PAINTAPP_HAPLY_URI`` overrides it.
DEFAULT_URI = "ws://127.0.0.1:10001"
URI_ENV = "PAINTAPP_HAPLY_URI"
INSTALL_HINT = (
    "install the Haply Hub (it runs the Inverse Service) or the haply-inverse-service daemon"
)
#: Roughly the middle of the Inverse3's reach in the service's default frame, m.
INVERSE3_CENTRE_M = (0.0, -0.12, 0.15)
INVERSE3_INFO = DeviceInfo(
    name="Haply Inverse3",
    kind="haply",
    dof_sensed=3,
    dof_actuated=3,
    max_force_n=3.3,
    max_stiffness_n_per_m=3000.0,
    max_damping_ns_per_m=5.0,
    workspace_m=(0.4, 0.3, 0.3),
)
PROFILE = "org.paintapp:haptic-painting"
#: How long a servo tick waits for the service's answer before it goes on with the last state.
TICK_WAIT_S = 2e-4
GRIP_LISTS = ("wireless_verse_grip", "verse_grip")


def service_uri(uri: str | None = None) -> str:
    """The service's URI: ``uri``, else ``$PAINTAPP_HAPLY_URI``, else :data:`DEFAULT_URI`."""
    return uri or os.environ.get(URI_ENV, "").strip() or DEFAULT_URI


def _vec(d: Any, keys: str = "xyz") -> list[float]:
    """Floats from a JSON object's named fields (ValueError if missing or not finite)."""
    if not isinstance(d, dict):
        raise ValueError(f"expected an object with {keys}, got {type(d).__name__}")
    out = [float(d[k]) for k in keys]
    if not all(map(math.isfinite, out)):
        raise ValueError(f"non-finite value in {d}")
    return out


def force_command(device_id: str, force: list[float]) -> dict[str, Any]:
    """The ``set_cursor_force`` message for one Inverse3."""
    vector = {"x": force[0], "y": force[1], "z": force[2]}
    return {
        "inverse3": [{"device_id": device_id, "commands": {"set_cursor_force": {"vector": vector}}}]
    }


class HaplyDevice:
    """An Inverse3 (with a VerseGrip when one is connected) as a :class:`HapticDevice`.

    Args:
        time_source: the servo clock's ``now_s``; readings are stamped with it.
        uri: the service's simulation channel (see :func:`service_uri`).
        device_id: which Inverse3; None: the first the service lists.
        reply_timeout_s: longest wait for a state update.
        connect_timeout_s: longest wait to connect and receive the inventory.
        centre_m: our origin in Haply's frame, m.
        tick_wait_s: how long a tick waits for a late answer before it goes on with the last
            state (:data:`TICK_WAIT_S`); None: wait for every answer, in lockstep (for a servo
            loop on a virtual clock, whose ticks do not wait for real time).
    """

    def __init__(
        self,
        time_source: Callable[[], float] = time.perf_counter,
        uri: str | None = None,
        device_id: str | None = None,
        reply_timeout_s: float = 0.05,
        connect_timeout_s: float = 2.0,
        centre_m: tuple[float, float, float] = INVERSE3_CENTRE_M,
        tick_wait_s: float | None = TICK_WAIT_S,
    ) -> None:
        self.time_source = time_source
        self.uri = service_uri(uri)
        self.device_id = device_id
        self.reply_timeout_s = float(reply_timeout_s)
        self.connect_timeout_s = float(connect_timeout_s)
        self.tick_wait_s = tick_wait_s
        self.centre_m = tuple(float(c) for c in centre_m)
        self._ws: Any = None
        self._info: DeviceInfo | None = None
        self._grip_id: str | None = None
        self._pending = False
        self._sent_at = 0.0
        self._first = True
        self._state: DeviceState | None = None
        #: ticks whose force was not sent because the last command was still unanswered
        self.late_answers = 0

    @property
    def info(self) -> DeviceInfo:
        if self._info is None:
            raise DeviceError("Haply device is not open")
        return self._info

    @property
    def name(self) -> str:
        return f"Haply Inverse3 {self.device_id or ''}".strip()

    def open(self) -> None:
        try:
            from websockets.sync.client import connect
        except ImportError as exc:
            raise DeviceNotFoundError(
                "the Haply backend needs the websockets package: pip install websockets "
                "(the haptic-fluid-paint[haply] extra)"
            ) from exc
        try:
            conn = connect(
                self.uri, open_timeout=self.connect_timeout_s, max_size=2**22, compression=None
            )
            # held open until close() (entering it marks it managed; it closes in _drop)
            self._ws = conn.__enter__()
            inventory = self._receive(self.connect_timeout_s)
        except (OSError, TimeoutError, DeviceError, ValueError) as exc:
            self._drop()
            raise DeviceNotFoundError(
                f"Haply Inverse Service not reachable at {self.uri} ({exc}): {INSTALL_HINT}, and "
                f"start it; set {URI_ENV}=ws://HOST:PORT if it listens elsewhere."
            ) from exc
        except Exception as exc:  # the library's handshake errors
            self._drop()
            raise DeviceNotFoundError(f"Haply Inverse Service at {self.uri}: {exc}") from exc
        try:
            self._choose(inventory)
            self._state = self._parse(inventory)
            self._pending, self._first = False, True
            self._send(force_command(str(self.device_id), [0.0, 0.0, 0.0]))
        except DeviceNotFoundError:
            self._drop()
            raise
        except DeviceError as exc:
            self._drop()
            raise DeviceNotFoundError(str(exc)) from exc

    def _choose(self, inventory: dict[str, Any]) -> None:
        arms = inventory.get("inverse3") or []
        ids = [str(a.get("device_id")) for a in arms if isinstance(a, dict)]
        if not ids:
            raise DeviceNotFoundError(
                f"the Haply Inverse Service at {self.uri} lists no Inverse3 (is it plugged in "
                "and powered?)"
            )
        if self.device_id is None:
            self.device_id = ids[0]
        elif self.device_id not in ids:
            raise DeviceNotFoundError(
                f"no Inverse3 {self.device_id!r} at {self.uri}; it lists {', '.join(ids)}"
            )
        grips = [g for key in GRIP_LISTS for g in inventory.get(key) or [] if isinstance(g, dict)]
        self._grip_id = str(grips[0].get("device_id")) if grips else None
        name = f"Haply Inverse3 {self.device_id}" + (" + VerseGrip" if grips else "")
        self._info = DeviceInfo(
            name=name,
            kind="haply",
            dof_sensed=6 if grips else 3,
            dof_actuated=3,
            max_force_n=INVERSE3_INFO.max_force_n,
            max_stiffness_n_per_m=INVERSE3_INFO.max_stiffness_n_per_m,
            max_damping_ns_per_m=INVERSE3_INFO.max_damping_ns_per_m,
            workspace_m=INVERSE3_INFO.workspace_m,
        )

    def _send(self, message: dict[str, Any]) -> None:
        if self._first:
            message["session"] = {
                "configure": {"profile": {"name": PROFILE}, "basis": {"permutation": "XYZ"}}
            }
            self._first = False
        try:
            self._ws.send(json.dumps(message, separators=(",", ":")))
        except Exception as exc:
            raise DeviceError(f"{self.name}: the Inverse Service connection failed: {exc}") from exc
        self._pending = True
        self._sent_at = time.monotonic()

    def _receive(self, timeout_s: float) -> dict[str, Any]:
        try:
            raw = self._ws.recv(timeout=timeout_s)
        except TimeoutError as exc:
            raise DeviceError(
                f"{self.name}: no state update from the Inverse Service in {timeout_s * 1e3:.0f} ms"
            ) from exc
        except Exception as exc:  # ConnectionClosed and kin
            raise DeviceError(
                f"{self.name}: the Inverse Service closed the connection ({exc})"
            ) from exc
        self._pending = False
        return self._decode(raw)

    def _decode(self, raw: str | bytes) -> dict[str, Any]:
        try:
            message = json.loads(raw)
        except (TypeError, ValueError) as exc:
            raise DeviceError(f"{self.name}: malformed message from the service: {exc}") from exc
        if not isinstance(message, dict):
            raise DeviceError(f"{self.name}: malformed message from the service")
        return message

    def _parse(self, message: dict[str, Any]) -> DeviceState:
        arm = next(
            (
                a
                for a in message.get("inverse3") or []
                if isinstance(a, dict) and str(a.get("device_id")) == self.device_id
            ),
            None,
        )
        if arm is None:
            raise DeviceError(f"{self.name} is gone from the service's update (unplugged?)")
        status = arm.get("status") or {}
        if isinstance(status, dict) and (status.get("error") or status.get("ready") is False):
            raise DeviceError(f"{self.name}: the service reports it not ready ({status})")
        try:
            p = _vec((arm.get("state") or {}).get("cursor_position"))
        except (KeyError, TypeError, ValueError) as exc:
            raise DeviceError(f"{self.name}: bad cursor_position in the update ({exc})") from exc
        c = self.centre_m
        pos = np.array([p[0] - c[0], p[1] - c[1], p[2] - c[2]])
        q, buttons = np.array([1.0, 0.0, 0.0, 0.0]), 0
        grip = self._grip(message)
        if grip is not None:
            q, buttons = grip
        return DeviceState(self.time_source(), pos, q, 0.0, buttons)

    def _grip(self, message: dict[str, Any]) -> tuple[np.ndarray, int] | None:
        if self._grip_id is None:
            return None
        for key in GRIP_LISTS:
            for g in message.get(key) or []:
                if isinstance(g, dict) and str(g.get("device_id")) == self._grip_id:
                    state = g.get("state") or {}
                    try:
                        q = np.array(_vec(state.get("orientation"), "wxyz"))
                    except (KeyError, TypeError, ValueError):
                        return None  # a grip glitch: keep the arm running
                    n = float(np.linalg.norm(q))
                    q = q / n if n > 1e-6 else np.array([1.0, 0.0, 0.0, 0.0])
                    b = state.get("buttons")
                    if isinstance(b, dict):
                        bits = int(bool(b.get("a"))) | (int(bool(b.get("b"))) << 1)
                    else:
                        bits = int(bool(state.get("button")))
                    return (q if q[0] >= 0 else -q), bits
        return None

    def read(self) -> DeviceState:
        """The latest state: the service's answer to the last command if it has come within
        :data:`TICK_WAIT_S`, else the state before it (the servo tick is not held up by a late
        answer); :class:`DeviceError` once no answer has come for ``reply_timeout_s``."""
        if self._ws is None:
            raise DeviceError(f"{self.name} is not open")
        if not self._pending:
            self._send(
                {"inverse3": [{"device_id": self.device_id, "commands": {"probe_position": {}}}]}
            )
        self._take_answer()
        assert self._state is not None
        return self._state

    def write(self, force_n: np.ndarray, torque_nm: np.ndarray) -> None:
        """Command ``force_n`` (limited, finite) unless the last command is still unanswered:
        the channel stays one answer per command, and the service keeps the last force until
        the answer comes (or the connection is given up after ``reply_timeout_s``)."""
        if self._ws is None:
            raise DeviceError(f"{self.name} is not open")
        if self._pending:
            self._take_answer()
        if self._pending:
            self.late_answers += 1
            return
        f = limited([float(v) for v in force_n], self.info.max_force_n)
        self._send(force_command(str(self.device_id), f))

    def _take_answer(self) -> None:
        """Parse the answer to the outstanding command if it comes within :data:`TICK_WAIT_S`;
        raise :class:`DeviceError` when none has come for ``reply_timeout_s`` (or there is no
        state at all yet)."""
        waited = time.monotonic() - self._sent_at
        if self._state is None or self.tick_wait_s is None or waited >= self.reply_timeout_s:
            self._state = self._parse(self._receive(max(self.reply_timeout_s - waited, 1e-4)))
            return
        try:
            raw = self._ws.recv(timeout=self.tick_wait_s)
        except TimeoutError:
            return
        except Exception as exc:  # ConnectionClosed and kin
            raise DeviceError(
                f"{self.name}: the Inverse Service closed the connection ({exc})"
            ) from exc
        self._pending = False
        self._state = self._parse(self._decode(raw))

    def close(self) -> None:
        if self._ws is None:
            return
        try:
            if self._pending:
                self._receive(self.reply_timeout_s)
            self._send(force_command(str(self.device_id), [0.0, 0.0, 0.0]))
            self._receive(self.reply_timeout_s)
        except DeviceError:
            pass  # the service is gone: it idles the device itself
        finally:
            self._drop()

    def _drop(self) -> None:
        ws, self._ws = self._ws, None
        if ws is not None:
            try:
                ws.close()
            except Exception:
                pass
