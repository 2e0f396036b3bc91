"""Replaying a stroke file: the same path as live painting, on a virtual clock.

Stylus samples go from the file to the :class:`~paintapp.session.painting.PaintingSession` (as a
tablet's would). The force path is the haptic servo loop
(:class:`~paintapp.haptics.servo.ServoLoop`) driving a
:class:`~paintapp.haptics.devices.stroke_player.ReplayDevice` at 1 kHz on a
:class:`~paintapp.haptics.clock.VirtualClock`: after the session handles the sample at ``t_k`` the
loop runs every tick in ``[t_k, t_k+1)``, so each tick sees exactly the force samples published
before it, and the same file gives the same canvas and the same force trace. The trace is the
loop's tick log: per tick, the force and torque *written to the device* (filtered, scaled, made
safe), canvas frame. ``device`` names the replay device (a 6-DOF stylus by default,
:data:`~paintapp.session.replay_devices.REPLAY_DEVICES`); ``fidelity`` applies a preset's fluid
settings (:mod:`paintapp.paint.fidelity`).

A pause longer than :data:`MAX_GAP_S` (``StrokeFile.gaps``) counts as a lift (the canvas still
dries through it); the servo loop runs its first :data:`MAX_GAP_S` and skips the rest
(``ReplayResult.skipped_ticks``). The brush presets and pigments a file names are checked before
any work (:func:`check_stroke_names`), each error naming the file and the line.
"""

from __future__ import annotations

import contextlib
import math
import time
from collections.abc import Callable, Collection, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from brushes import StylusSample
from brushes.presets import list_presets
from common.errors import InputError
from paintapp.canvas.model import Canvas
from paintapp.haptics.channel import ForceChannel
from paintapp.haptics.clock import VirtualClock
from paintapp.haptics.device import DeviceInfo
from paintapp.haptics.devices.stroke_player import ReplayDevice
from paintapp.haptics.force_csv import DEVICE_COLUMNS
from paintapp.haptics.servo import ServoConfig, ServoLoop, ServoReport
from paintapp.paint.fidelity import apply_fidelity
from paintapp.paint.paint_scene import PaintScene, load_paint_scene
from paintapp.resources import asset_path
from paintapp.session.painting import PaintingSession
from paintapp.session.replay_devices import replay_device
from paintapp.strokes.files import MAX_GAP_S, StrokeFile, StrokeHeader
from paintapp.strokes.records import SwitchBrush

#: Columns of a force trace (and of the forces CSV).
FORCE_COLUMNS = DEVICE_COLUMNS


class ServoForcePath:
    """The replay's force path: a servo loop on a virtual clock playing the stroke's samples.

    Args:
        samples: the stroke's stylus samples (at least one).
        channel: the force channel the session publishes into.
        config: servo configuration (tick, filter, force scale, safety).
        source: the stroke file's name, for messages.
        info: the capabilities the replayed device claims (default: a simulated 6-DOF stylus).
    """

    def __init__(
        self,
        samples: Sequence[StylusSample],
        channel: ForceChannel,
        config: ServoConfig | None = None,
        source: str | None = None,
        info: DeviceInfo | None = None,
    ) -> None:
        self.config = config or ServoConfig()
        self.t0_s = float(samples[0].t_s)
        self.clock = VirtualClock(self.config.tick_s, start_s=self.t0_s)
        self.device = ReplayDevice(samples, self.clock.now_s, source=source, info=info)
        self.servo = ServoLoop(self.device, channel, self.config)
        self.servo.open()
        #: Most ticks run through one pause; the rest of it is skipped.
        self.max_gap_ticks = max(1, round(MAX_GAP_S / self.config.tick_s))
        self.skipped_ticks = 0

    @property
    def ticks(self) -> int:
        """Ticks run so far."""
        return len(self.servo.log)

    def run_until(self, t_s: float | None) -> None:
        """Run every tick before ``t_s`` (None: to the end of the stroke's playback); of a pause
        longer than :data:`MAX_GAP_S`, only the first :data:`MAX_GAP_S` is run, the rest skipped."""
        if self.servo.finished or self.servo.device_fault is not None:
            return
        tick = self.config.tick_s
        if t_s is None:
            target = math.ceil(self.device.duration_s / tick) + 1
        else:
            target = math.ceil((t_s - self.t0_s) / tick - 1e-9)
        pending = target - self.clock.next_index
        if pending <= 0:
            return
        self.servo.run(self.clock, max_ticks=min(pending, self.max_gap_ticks))
        left = target - self.clock.next_index
        if left > 0 and not (self.servo.finished or self.servo.device_fault is not None):
            self.clock.skip(left)
            self.skipped_ticks += left

    def close(self) -> ServoReport:
        """Close the loop (zero force to the device) and return its report."""
        report = self.servo.report()
        self.servo.close()
        return report

    def trace(self) -> np.ndarray:
        """(ticks, 7): time (s), force (N) and torque (N m) written to the device each tick."""
        log = self.servo.log.arrays()
        return np.column_stack([log["t_s"], log["force_n"], log["torque_nm"]])


@dataclass
class ReplayResult:
    """A finished replay: the painted canvas, the session, the force trace and the servo report."""

    canvas: Canvas
    session: PaintingSession
    forces: np.ndarray
    servo: ServoReport | None
    wall_s: float
    skipped_ticks: int = 0


@contextlib.contextmanager
def _from_file(strokes: StrokeFile, line: int | None = None) -> Iterator[None]:
    """Re-raise an :class:`InputError` caused by the file's content naming the file."""
    try:
        yield
    except InputError as exc:
        if exc.source:
            raise
        raise InputError(exc.message, strokes.source, exc.key, exc.line or line) from None


def check_stroke_names(
    strokes: StrokeFile,
    brush_dir: str | Path | None = None,
    pigments: Collection[str] | None = None,
) -> None:
    """Raise :class:`InputError` (file, line, field) for a brush preset the stroke file names
    that does not exist in ``brush_dir`` (default: the bundled presets): the header's ``brush``
    (line 1) and each ``brush`` event's ``preset``; with ``pigments`` (the names a pigment library
    knows), also a header pigment not among them (line 1, ``pigments``). Run before any work, so
    a typo does not cost a replay."""
    presets = list_presets(brush_dir or asset_path("brushes"))
    header = strokes.header

    def unknown_brush(name: str, key: str, line: int | None) -> InputError:
        known = ", ".join(presets) or "none"
        return InputError(
            f"unknown brush preset {name!r}; known presets: {known}", strokes.source, key, line
        )

    if header.brush not in presets:
        raise unknown_brush(header.brush, "brush", 1)
    for i, record in enumerate(strokes.records):
        if isinstance(record, SwitchBrush) and record.preset not in presets:
            raise unknown_brush(record.preset, "preset", strokes.line_of(i))
    unknown = [name for name in header.pigments if pigments is not None and name not in pigments]
    if unknown:
        known = ", ".join(sorted(pigments or ())) or "none"
        raise InputError(
            f"unknown pigment {unknown[0]!r}; known pigments: {known}",
            strokes.source,
            "pigments",
            1,
        )


def new_canvas(header: StrokeHeader) -> Canvas:
    """The blank canvas a stroke file's header describes (its pigments as empty channels)."""
    return Canvas(header.canvas.pixels, header.canvas.size_m, header.pigments)


def replay(
    strokes: StrokeFile,
    scene: PaintScene | None = None,
    *,
    canvas: Canvas | None = None,
    servo_config: ServoConfig | None = None,
    progress: Callable[[int], object] | None = None,
    brush_dir: str | Path | None = None,
    fidelity: str | None = None,
    device: str | DeviceInfo | None = None,
) -> ReplayResult:
    """Replay ``strokes`` (see the module docstring).

    Args:
        strokes: a loaded stroke file.
        scene: the painting scene; default the one the header names.
        canvas: paint on this canvas instead of a blank one (its size must match the header's).
        servo_config: the force path's configuration (default: 1 kHz, the paper's FIR filter).
        progress: called with 1 after each record (a progress bar's ``update``).
        brush_dir: where the named brush presets are (default: the bundled ones).
        fidelity: ``draft``, ``standard`` or ``high`` on top of the scene (None: as written).
        device: the device played on, by name (:data:`~paintapp.session.replay_devices.REPLAY_DEVICES`) or capabilities
            (default: a simulated 6-DOF stylus).
    """
    start = time.perf_counter()
    header = strokes.header
    check_stroke_names(strokes, brush_dir)
    info = replay_device(device) if isinstance(device, str) else device
    channel = ForceChannel()
    with _from_file(strokes, line=1):
        scene = scene or load_paint_scene(header.scene)
    scene = apply_fidelity(scene, fidelity) if fidelity is not None else scene
    with _from_file(strokes, line=1):
        canvas = canvas if canvas is not None else new_canvas(header)
        session = PaintingSession(
            canvas,
            header.brush,
            scene,
            input_kind=header.input_kind,
            forces=channel,
            brush_dir=brush_dir,
            device=info,
            max_gap_s=MAX_GAP_S,
        )
    samples = strokes.samples
    path = ServoForcePath(samples, channel, servo_config, strokes.source, info) if samples else None
    records = strokes.records
    for i, record in enumerate(records):
        with _from_file(strokes, line=strokes.line_of(i)):
            session.handle(record)
        if path is not None and isinstance(record, StylusSample):
            path.run_until(records[i + 1].t_s if i + 1 < len(records) else None)
        if progress is not None:
            progress(1)
    report = path.close() if path is not None else None
    forces = path.trace() if path is not None else np.zeros((0, len(FORCE_COLUMNS)))
    skipped = path.skipped_ticks if path is not None else 0
    return ReplayResult(canvas, session, forces, report, time.perf_counter() - start, skipped)
