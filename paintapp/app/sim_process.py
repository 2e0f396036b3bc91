"""The simulation worker in a process of its own (``paintapp paint --simulation process``).

In a thread, each of the worker's many kernel calls a paint step waits for the interpreter lock
while the GUI holds it. Here the :class:`~paintapp.app.worker.SimulationWorker` runs in a
``spawn``-started child behind :class:`SimulationProcess`, which offers the worker's interface:

- down a pipe: stylus samples, commands (each a picklable :func:`functools.partial` of a function
  of :mod:`paintapp.app.actions`), a device fault the window noticed, and stop;
- up another: the changed canvas regions, which a receiver thread copies into the window's
  display canvas under its lock (:meth:`SharedCanvas.apply_region`), a replacing canvas, the
  worker's status and the mixing slab's picture;
- with a haptic device the child reads the stylus and publishes the force through the servo
  process's shared memory itself (:class:`ChildLink`; the servo loop then runs in a process).

The child owns the live canvas, the undo history and the journal; the window's display canvas is
the live one up to the last region sent, so autosave and save work from it. If the child dies,
the status's ``fault`` says so (the window autosaves at once) and the paint sent so far is kept;
if the window dies, the child commits the stroke, closes the journal and exits.
"""

from __future__ import annotations

import contextlib
import multiprocessing as mp
import signal
import threading
from dataclasses import dataclass, replace
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any

from brushes import StylusSample
from common.errors import InputError
from paintapp.app.journal import Journal
from paintapp.app.shared import SharedCanvas, StatusSlot, WorkerStatus
from paintapp.app.worker import SimulationWorker
from paintapp.canvas.model import Canvas
from paintapp.canvas.regions import Box
from paintapp.haptics.channel import LatestValue
from paintapp.haptics.shared_state import SharedBlock, SharedForceChannel, SharedStateChannel
from paintapp.paint.paint_scene import PaintScene

#: The ways the window's simulation worker can run.
SIMULATION_MODES = ("thread", "process")


def simulation_mode(asked: str, link: Any) -> str:
    """Where the simulation worker runs: ``asked`` ("thread" or "process"), except that a
    haptic device whose servo loop is a thread of the app keeps it a thread (its force channel
    lives in the app's memory)."""
    if asked not in SIMULATION_MODES:
        raise InputError(
            f"expected simulation mode thread or process, got {asked!r}", key="simulation"
        )
    if asked == "process" and link is not None and getattr(link, "process", None) is None:
        return "thread"
    return asked


@dataclass(frozen=True)
class SimulationSpec:
    """What the child needs to build the worker (picklable).

    Attributes:
        canvas: the live canvas to paint on.
        settings: the initial paint settings (a :class:`~paintapp.app.settings.PaintSettings`).
        pigments: the palette.
        record, overwrite_record: the journal file and whether it may replace one.
        user_scene: the painting scene given on the command line, if any.
        servo_block: the servo process's shared-memory block (haptic input), or None.
    """

    canvas: Canvas
    settings: Any
    pigments: tuple[str, ...]
    record: Path | None
    overwrite_record: bool
    user_scene: PaintScene | None
    servo_block: str | None


class _Sender:
    """One end of a pipe shared by the child's threads (a send is not thread-safe)."""

    def __init__(self, conn: Connection) -> None:
        self.conn = conn
        self.lock = threading.Lock()
        self.broken = False

    def send(self, message: tuple) -> None:
        if self.broken:
            return
        with self.lock:
            try:
                self.conn.send(message)
            except (OSError, ValueError):  # the window is gone: the child is stopping anyway
                self.broken = True


class RemoteDisplay:
    """The worker's display canvas in the child: each change goes up the pipe."""

    def __init__(self, sender: _Sender) -> None:
        self.sender = sender

    def publish_region(self, live: Canvas, box: Box) -> None:
        x0, y0, x1, y1 = box
        paint = live.paint_m[:, y0:y1, x0:x1].copy()
        wetness = live.wetness[y0:y1, x0:x1].copy()
        self.sender.send(("region", box, tuple(live.pigment_names), paint, wetness))

    def publish_wetness(self, live: Canvas, box: Box) -> None:
        x0, y0, x1, y1 = box
        self.sender.send(("wetness", box, live.wetness[y0:y1, x0:x1].copy()))

    def replace(self, canvas: Canvas) -> None:
        self.sender.send(("replace", canvas))


class _RemoteSlot:
    """A latest-value slot whose publications go up the pipe as ``(kind, value)``."""

    def __init__(self, sender: _Sender, kind: str) -> None:
        self.sender, self.kind = sender, kind
        self._last: Any = None

    def publish(self, value: Any) -> int:
        self._last = value
        self.sender.send((self.kind, value))
        return 0

    def get(self) -> Any:
        return self._last if self._last is not None else WorkerStatus()

    def latest(self) -> tuple[int, Any]:
        return 0, self._last


class _RemoteEvent:
    """The worker's idle flag in the child: each change goes up the pipe as ``("idle", bool)``."""

    def __init__(self, sender: _Sender) -> None:
        self.sender = sender
        self._event = threading.Event()

    def set(self) -> None:
        if not self._event.is_set():
            self._event.set()
            self.sender.send(("idle", True))

    def clear(self) -> None:
        if self._event.is_set():
            self._event.clear()
            self.sender.send(("idle", False))

    def is_set(self) -> bool:
        return self._event.is_set()

    def wait(self, timeout: float | None = None) -> bool:
        return self._event.wait(timeout)


class ChildLink:
    """The haptic device as the child sees it: the servo process's shared channels, attached by
    name, and the fault the window tells it of."""

    def __init__(self, block_name: str) -> None:
        self.block = SharedBlock(block_name)
        self.forces = SharedForceChannel(self.block.force)
        self.states = SharedStateChannel(self.block.state)
        self.fault: str | None = None


def child_main(spec: SimulationSpec, inbox: Connection, outbox: Connection) -> None:
    """The simulation process (see the module docstring)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl+C reaches the window; it stops us
    sender = _Sender(outbox)
    link = ChildLink(spec.servo_block) if spec.servo_block is not None else None
    worker = SimulationWorker(
        spec.canvas,
        RemoteDisplay(sender),  # type: ignore[arg-type]
        spec.settings,
        spec.pigments,
        Journal(spec.record, spec.overwrite_record),
        spec.user_scene,
        link,  # type: ignore[arg-type]
    )
    worker.status = _RemoteSlot(sender, "status")  # type: ignore[assignment]
    worker.slab_view = _RemoteSlot(sender, "slab")  # type: ignore[assignment]
    worker.idle = _RemoteEvent(sender)  # type: ignore[assignment]
    worker.start()
    try:
        while True:
            try:
                message = inbox.recv()
            except (EOFError, OSError):  # the window is gone
                break
            kind = message[0]
            if kind == "sample":
                worker.push(message[1])
            elif kind == "command":
                worker.submit(message[1])
            elif kind == "fault" and link is not None:
                link.fault = message[1]
            elif kind == "stop":
                break
    finally:
        worker.stop()  # the stroke is committed and the journal closed
        sender.send(("stopped",))


class SimulationProcess:
    """The window's side of a simulation process (see the module docstring); it offers the
    simulation worker's interface.

    Args:
        canvas: the live canvas (it crosses to the child).
        shared: the window's display canvas.
        settings, pigments, record, overwrite_record, user_scene: as for the worker.
        servo_block: the servo process's shared block name, or None without a device.
    """

    def __init__(
        self,
        canvas: Canvas,
        shared: SharedCanvas,
        settings: Any,
        pigments: tuple[str, ...],
        record: Path | None = None,
        overwrite_record: bool = False,
        user_scene: PaintScene | None = None,
        servo_block: str | None = None,
    ) -> None:
        self.shared = shared
        self.status = StatusSlot()
        self.slab_view: LatestValue[Canvas] = LatestValue()
        self.idle = threading.Event()
        self.message = ""
        spec = SimulationSpec(
            canvas, settings, pigments, record, overwrite_record, user_scene, servo_block
        )
        ctx = mp.get_context("spawn")
        down_r, self._down = ctx.Pipe(duplex=False)  # window -> child
        self._up, up_w = ctx.Pipe(duplex=False)  # child -> window
        self._child_ends = (down_r, up_w)
        self._proc = ctx.Process(
            target=child_main, args=(spec, down_r, up_w), name="paint-simulation", daemon=True
        )
        self._send_lock = threading.Lock()
        # Every wait on the child goes through this lock: two threads waiting on one process race
        # in multiprocessing (one reaps it, the other's wait fails and reads no exit code).
        self._reap_lock = threading.Lock()
        self._receiver = threading.Thread(target=self._receive, name="simulation-receiver")
        self._receiver.daemon = True
        self._stopping = False
        self.exitcode: int | None = None

    @property
    def pid(self) -> int | None:
        """The child's process id (after :meth:`start`)."""
        return self._proc.pid

    def start(self) -> None:
        """Start the child and the receiver."""
        self._proc.start()
        for end in self._child_ends:
            end.close()
        self._receiver.start()

    def is_alive(self) -> bool:
        with self._reap_lock:
            return self._proc.is_alive()

    def wait_exit(self, timeout_s: float) -> int | None:
        """Wait up to ``timeout_s`` for the child to exit; its exit code, or None if it has not."""
        with self._reap_lock:
            self._proc.join(timeout_s)
            return self._proc.exitcode

    def _send(self, message: tuple) -> None:
        with self._send_lock:
            try:
                self._down.send(message)
            except (OSError, ValueError):  # the child is gone: the receiver says so
                pass

    def push(self, sample: StylusSample) -> None:
        """A tablet or mouse sample."""
        self._send(("sample", sample))

    def submit(self, command: Any) -> None:
        """A command (a picklable callable taking the worker)."""
        self._send(("command", command))

    def device_fault(self, fault: str) -> None:
        """Tell the child the haptic device failed."""
        self._send(("fault", fault))

    def stop(self, timeout_s: float = 10.0) -> None:
        """Stop the child (the stroke is committed and the journal closed) and the receiver."""
        self._stopping = True
        self._send(("stop",))
        if self.wait_exit(timeout_s) is None:
            with self._reap_lock:
                self._proc.kill()
            self.wait_exit(2.0)
        with contextlib.suppress(OSError):
            self._down.close()
        self._receiver.join(timeout_s)

    def _receive(self) -> None:
        while True:
            try:
                message = self._up.recv()
            except (EOFError, OSError):
                break
            kind = message[0]
            if kind == "region":
                _, box, names, paint, wetness = message
                self.shared.apply_region(box, names, paint, wetness)
            elif kind == "wetness":
                self.shared.apply_wetness(message[1], message[2])
            elif kind == "replace":
                self.shared.replace(message[1])
            elif kind == "status":
                self.status.publish(message[1])
                self.message = message[1].message
            elif kind == "slab":
                self.slab_view.publish(message[1])
            elif kind == "idle":
                (self.idle.set if message[1] else self.idle.clear)()
            elif kind == "stopped":
                break
        self.exitcode = self.wait_exit(1.0)
        if not self._stopping:
            code = "unknown" if self.exitcode is None else self.exitcode
            fault = f"simulation process stopped (exit code {code}); the canvas is kept"
            self.status.publish(replace(self.status.get(), fault=fault, message=fault))
