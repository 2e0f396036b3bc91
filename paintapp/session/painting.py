"""The painting session: stylus samples in, paint on the canvas and force samples out.

For each stylus sample (a tablet, a replayed stroke file, or the servo loop's published device
state): the canvas dries for the time that passed; the :class:`~brushes.TipTracker` turns the
sample into a tip pose over the wet paint surface; while the tip is in contact, the paint model
(:mod:`paintapp.paint`) drives the tip probe through the local paint grid, trades paint with the
brush's reservoir and writes it back to the canvas; the force and torque on the tip are published
to the :class:`~paintapp.haptics.channel.ForceChannel`. A brush in the air takes no solver steps
and publishes zero force; a non-finite step is dropped and counted, never published.

Frames: the paint grid, the force channel and the haptic device all use the canvas frame (x
right, y up the canvas, z toward the painter): forces need no rotation, only units (N, N m).

The session models only what the scene requires (:mod:`paintapp.paint.choice`); its decisions and
counts are :attr:`PaintingSession.decisions` and :attr:`PaintingSession.choices`. Events:
``load_pigment`` dips the brush, ``brush`` switches preset with a clean brush, ``clean`` empties
it; every volume entering or leaving the brush is booked in ``loaded_m3`` / ``removed_m3``, so
``canvas + brush == loaded - removed`` per pigment (:func:`paint_inventory`).
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from brushes import BrushPreset, PaintReservoir, StylusSample, TipPose, TipTracker
from brushes.presets import load_preset_named
from paintapp.canvas.model import Canvas
from paintapp.haptics.channel import ForceChannel
from paintapp.paint.choice import ChoiceStats, TimedDecision, needs_for_device
from paintapp.paint.paint_model import PaintModel, PaintStep
from paintapp.paint.paint_scene import PaintScene, load_paint_scene
from paintapp.paint.selector import ModelSelector
from paintapp.resources import asset_path
from paintapp.strokes.records import CleanBrush, LoadPigment, Marker, StrokeRecord, SwitchBrush

if TYPE_CHECKING:
    from paintapp.haptics.device import DeviceInfo

#: Samples closer together than this (s) do not advance the paint.
MIN_DT_S = 1e-6
#: A touch-down continues from the previous (air) pose if it was this recent (s).
TOUCH_DOWN_GAP_S = 0.2
#: Paint-step wall times kept for medians (about 4 minutes of painting at 40 steps/s).
STEP_TIMES_KEPT = 10_000


@dataclass(frozen=True)
class SessionStep:
    """What one stylus sample did.

    Attributes:
        t_s: the sample's time, s.
        pose: the tip pose.
        in_contact: whether the tip was in the paint.
        force_n: (3,) published force on the tip, canvas frame, N.
        torque_nm: (3,) published torque about the apex, N m.
        paint: the paint model's step, None when it took none (in the air, repeated time).
    """

    t_s: float
    pose: TipPose
    in_contact: bool
    force_n: np.ndarray
    torque_nm: np.ndarray
    paint: PaintStep | None = None


@dataclass
class SessionStats:
    """Counts over a session: samples, paint steps, solver steps, dropped non-finite forces,
    the wall time (ms) spent in paint steps, samples in the air and steps of a dry brush (no
    fluid; not counted in ``paint_steps``). ``step_ms`` keeps the wall times of the most recent
    :data:`STEP_TIMES_KEPT` paint steps (a live session runs for hours). ``pauses`` counts the
    records that came after a pause longer than the session's ``max_gap_s``."""

    samples: int = 0
    paint_steps: int = 0
    solver_steps: int = 0
    nonfinite_forces: int = 0
    paint_ms: float = 0.0
    step_ms: deque[float] = field(default_factory=lambda: deque(maxlen=STEP_TIMES_KEPT))
    air_samples: int = 0
    dry_steps: int = 0
    pauses: int = 0


def wet_height_m(canvas: Canvas, x_m: float, y_m: float) -> float:
    """Mean wet paint thickness (m) over the 3 x 3 texels around (x, y); 0 off the canvas."""
    fx, fy = canvas.metres_to_texel(x_m, y_m)
    ix, iy = math.floor(float(fx)), math.floor(float(fy))
    x0, x1 = max(ix - 1, 0), min(ix + 2, canvas.width)
    y0, y1 = max(iy - 1, 0), min(iy + 2, canvas.height)
    if x1 <= x0 or y1 <= y0:
        return 0.0
    paint = canvas.paint_m[:, y0:y1, x0:x1].sum(axis=0, dtype=np.float64)
    return float(np.mean(paint * canvas.wetness[y0:y1, x0:x1]))


def paint_inventory(canvas: Canvas, reservoir: PaintReservoir) -> dict[str, float]:
    """Paint volume (m^3) per pigment on the canvas plus in the brush."""
    dx, dy = canvas.texel_size_m
    totals = canvas.paint_m.sum(axis=(1, 2), dtype=np.float64) * dx * dy
    out = {name: float(v) for name, v in zip(canvas.pigment_names, totals, strict=True)}
    for name, v in reservoir.volumes_m3.items():
        out[name] = out.get(name, 0.0) + v
    return out


class PaintingSession:
    """Paints stylus samples onto ``canvas`` with brush ``brush`` in painting scene ``scene``.

    Args:
        canvas: the canvas (square texels).
        brush: a preset, or a preset name looked up in ``brush_dir``.
        scene: the painting scene (default: the bundled ``default``).
        input_kind: ``"tablet"`` (pressure sets the depth) or ``"haptic"`` (z does).
        forces: where force samples go; a new channel if None.
        brush_dir: where named presets are found (default: the bundled presets).
        device: the force-feedback device's capabilities; no force work when it outputs no
            force, no torque when it outputs none (None: force and torque are both read).
        max_gap_s: a record more than this after the one before (s) follows a pause: the pen
            counts as lifted through it, and a sample after it only places the brush, so no paint
            step spans the pause (its cost would grow with its length). None: no limit.
    """

    def __init__(
        self,
        canvas: Canvas,
        brush: BrushPreset | str,
        scene: PaintScene | None = None,
        *,
        input_kind: str = "tablet",
        forces: ForceChannel | None = None,
        brush_dir: str | Path | None = None,
        device: DeviceInfo | None = None,
        max_gap_s: float | None = None,
    ) -> None:
        self.canvas = canvas
        self.max_gap_s = max_gap_s
        self.scene = scene or load_paint_scene()
        self.forces = forces if forces is not None else ForceChannel()
        self.brush_dir = Path(brush_dir) if brush_dir else asset_path("brushes")
        preset = brush if isinstance(brush, BrushPreset) else self._preset(brush)
        self.tracker = TipTracker(preset, input_kind)  # type: ignore[arg-type]
        self.reservoir = PaintReservoir(preset.capacity_m3)
        self.needs = needs_for_device(device)
        self.selector = ModelSelector(self.scene, canvas, preset, self.needs)
        self.time_s: float | None = None
        self.in_contact = False
        self.stats = SessionStats()
        self.loaded_m3: dict[str, float] = {}
        self.removed_m3: dict[str, float] = {}
        self._force = (np.zeros(3), np.zeros(3))

    @property
    def model(self) -> PaintModel:
        """The paint model in use (or next to run, while the brush is in the air or dry)."""
        return self.selector.model

    @property
    def decisions(self) -> list[TimedDecision]:
        """Every modelling decision so far, with its reason (for ``--explain``)."""
        return self.selector.decisions

    @property
    def choices(self) -> ChoiceStats:
        """Counts of what ran: steps per model and per grid, switches, pigment channels."""
        return self.selector.stats

    @property
    def preset(self) -> BrushPreset:
        """The brush in use."""
        return self.tracker.preset

    def _preset(self, name: str) -> BrushPreset:
        return load_preset_named(name, self.brush_dir)

    # --- records ----------------------------------------------------------------------------
    def handle(self, record: StrokeRecord) -> SessionStep | None:
        """Process one stroke-file record: a sample (returns its step) or an event (None)."""
        if isinstance(record, StylusSample):
            return self.sample(record)
        if self._paused(self.advance_time(record.t_s)):
            self.forces.publish_force(record.t_s, np.zeros(3), np.zeros(3))
        if isinstance(record, LoadPigment):
            self.load_pigment(record.pigment, record.volume_m3)
        elif isinstance(record, SwitchBrush):
            self.switch_brush(record.preset)
        elif isinstance(record, CleanBrush):
            self.clean()
        elif not isinstance(record, Marker):
            raise TypeError(f"not a stroke record: {record!r}")
        return None

    def advance_time(self, t_s: float) -> float:
        """Let the canvas dry up to ``t_s``; returns the time that passed (s, >= 0)."""
        dt = 0.0 if self.time_s is None else max(t_s - self.time_s, 0.0)
        if dt > 0.0:
            self.canvas.dry(dt, self.scene.drying_rate_per_s)
        self.time_s = t_s if self.time_s is None else max(self.time_s, t_s)
        return dt

    # --- events -----------------------------------------------------------------------------
    def load_pigment(self, pigment: str, volume_m3: float) -> float:
        """Dip the brush in ``pigment``; returns the volume it took (m^3, up to its free room)."""
        self.canvas.add_pigment(pigment)
        taken = self.reservoir.load(pigment, volume_m3)
        self.loaded_m3[pigment] = self.loaded_m3.get(pigment, 0.0) + taken
        return taken

    def clean(self) -> dict[str, float]:
        """Wipe the brush; returns the paint removed (m^3 per pigment)."""
        removed = self.reservoir.clean()
        self._book_removed(removed)
        return removed

    def switch_brush(self, name: str | BrushPreset) -> None:
        """Paint on with another preset (its brush is clean; the old one's paint is removed)."""
        preset = name if isinstance(name, BrushPreset) else self._preset(name)
        self._lift()
        self.clean()
        self.tracker.preset = preset
        self.tracker.reset()
        self.reservoir = PaintReservoir(preset.capacity_m3)
        self.selector.set_preset(preset)

    def _book_removed(self, volumes: Mapping[str, float]) -> None:
        for name, v in volumes.items():
            self.removed_m3[name] = self.removed_m3.get(name, 0.0) + v

    # --- samples ----------------------------------------------------------------------------
    def sample(self, sample: StylusSample) -> SessionStep:
        """Process one stylus sample (see the module docstring)."""
        self.stats.samples += 1
        previous = self.tracker.last
        dt = self.advance_time(sample.t_s)
        surface = wet_height_m(
            self.canvas, float(sample.position_m[0]), float(sample.position_m[1])
        )
        pose = self.tracker.update(sample, surface)
        if self._paused(dt):  # the sample after a long pause only places the brush
            return self._publish(pose, None)
        if not pose.in_contact:
            self._lift()
            self.stats.air_samples += 1
            return self._publish(pose, None)
        entry = previous if self.in_contact and previous is not None else pose
        if not self.in_contact:
            entry = self._touch_down_pose(previous, pose)
        plan = self.selector.engage(pose, self.reservoir, entry)
        self.in_contact = True
        if dt < MIN_DT_S:
            return SessionStep(pose.t_s, pose, True, *self._force)
        step = PaintStep() if plan.dry else self.model.step(pose, dt, self.reservoir)
        self.selector.record(plan, step, pose.t_s, dt)
        if plan.dry:
            self.stats.dry_steps += 1
            return self._publish(pose, step)
        self.stats.paint_steps += 1
        self.stats.solver_steps += step.solver_steps
        self.stats.paint_ms += step.step_ms
        self.stats.step_ms.append(step.step_ms)
        return self._publish(pose, step)

    def _touch_down_pose(self, previous: TipPose | None, pose: TipPose) -> TipPose:
        """Where the tip enters: the last air pose if it is recent and near, else ``pose``."""
        if previous is None or not 0.0 <= pose.t_s - previous.t_s <= TOUCH_DOWN_GAP_S:
            return pose
        near = (
            np.linalg.norm(pose.position_m - previous.position_m)
            < 0.25 * self.model.window.cells[0] * self.model.cell_size_m
        )
        return previous if near else pose

    def _paused(self, dt: float) -> bool:
        """Whether ``dt`` is a pause longer than ``max_gap_s``; if so the pen is lifted."""
        if self.max_gap_s is None or dt <= self.max_gap_s:
            return False
        self._lift()
        self.stats.pauses += 1
        return True

    def _lift(self) -> None:
        if self.in_contact:
            self.selector.lift()
            self.in_contact = False

    def _publish(self, pose: TipPose, step: PaintStep | None) -> SessionStep:
        force, torque = (
            (np.zeros(3), np.zeros(3)) if step is None else (step.force_n, step.torque_nm)
        )
        if not (np.all(np.isfinite(force)) and np.all(np.isfinite(torque))):
            self.stats.nonfinite_forces += 1
            force, torque = np.zeros(3), np.zeros(3)
        self._force = (force, torque)
        self.forces.publish_force(pose.t_s, force, torque)
        return SessionStep(pose.t_s, pose, step is not None, force, torque, step)
