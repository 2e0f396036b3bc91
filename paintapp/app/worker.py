"""The simulation worker: a thread that steps the painting session as fast as it can.

Each pass of its loop:

1. runs the commands the GUI queued; the worker owns the brush's paint and the mixing slab's;
2. takes the latest input: with a tablet or mouse, the samples pushed since the last pass
   (pen transitions, the newest sample, and while the pen is down one sample every half brush
   radius of travel, so a slow pass never breaks the stroke; a pen held still repeats its last
   sample, so the paint keeps flowing); with a haptic device, the servo loop's newest pose;
3. stamps each sample with the session clock, hands it to the session and journals it;
4. copies the changed canvas region into the display canvas (under the shared lock), commits the
   stroke to the undo history when the brush leaves the paint, and publishes a
   :class:`~paintapp.app.shared.WorkerStatus`.

The session clock advances with wall time but by at most ``MAX_STEP_S`` per sample: a slow step
slows the simulation instead of making the next step longer. A failing device or a dead servo
process ends the stroke (kept, undoable, journalled), lifts the brush and switches the input back
to the tablet or mouse.
"""

from __future__ import annotations

import collections
import queue
import sys
import threading
import time
import traceback
from collections.abc import Callable

import numpy as np

from brushes import StylusSample
from common.errors import InputError
from paintapp.app.haptic_link import HapticLink, sample_from_state
from paintapp.app.history import UndoHistory, copy_canvas, grow
from paintapp.app.journal import Journal, make_header
from paintapp.app.settings import (
    PaintSettings,
    brush_radius_m,
    make_preset,
    make_scene,
    rebuild_session,
)
from paintapp.app.shared import AppClock, RateMeter, SharedCanvas, StatusSlot, WorkerStatus
from paintapp.app.slab import MixingSlab
from paintapp.app.warmup import warm_up
from paintapp.canvas.model import Canvas
from paintapp.canvas.regions import Box
from paintapp.compile_ahead import compiling_ahead
from paintapp.haptics.channel import ForceChannel, LatestValue
from paintapp.paint.paint_scene import PaintScene
from paintapp.strokes.records import StrokeHeader

#: Longest session time one sample may advance, s.
MAX_STEP_S = 0.05
#: Longest gap, in brush radii, that the samples a busy worker keeps of a stroke may leave: a
#: slow step (the first one loads the kernels) must not turn the rest of the stroke into a jump.
TRAIL_SPACING = 0.5
#: Most samples of travel a pass keeps (the spacing widens beyond that): after a long stall the
#: brush catches up with the pen in a bounded number of steps.
MAX_TRAIL_STEPS = 16
#: Pause between passes with nothing to do, s.
IDLE_S = 0.004
#: A warm-up that took this long (s: the kernels were compiled, not loaded) stays in the HUD.
PREPARE_NOTE_S = 5.0
#: Pause between haptic samples while the brush is in the air, s.
AIR_S = 0.01
#: A stroke ends once the brush has been out of the paint this long (wall time, s), so a
#: haptic tip bouncing on the canvas makes one stroke, not many.
STROKE_GAP_S = 0.15

Command = Callable[["SimulationWorker"], None]


class SimulationWorker(threading.Thread):
    """Owns the live canvas and the painting session (see the module docstring).

    Args:
        canvas: the live canvas (the worker's from now on).
        shared: the display canvas it publishes to.
        settings: the initial paint settings.
        pigments: the pigments the palette offers (the journal header lists them).
        journal: where records go.
        user_scene: the scene given on the command line, if any.
        link: the haptic device link, or None for tablet/mouse input.
        clock: the app clock.
    """

    def __init__(
        self,
        canvas: Canvas,
        shared: SharedCanvas,
        settings: PaintSettings,
        pigments: tuple[str, ...],
        journal: Journal,
        user_scene: PaintScene | None = None,
        link: HapticLink | None = None,
        clock: AppClock | None = None,
    ) -> None:
        super().__init__(name="paint-simulation", daemon=True)
        self.live = canvas
        canvas.take_dirty()  # the display canvas starts as a copy: nothing to publish yet (else
        canvas.take_wet_dirty()  # a device's first step copies it all, and it counts as unsaved)
        self.shared = shared
        self.settings = settings
        self.pigments = pigments
        self.journal = journal
        self.user_scene = user_scene
        self.link = link
        self.clock = clock or AppClock()
        self.forces = link.forces if link is not None else ForceChannel()
        self.input_kind = "haptic" if link is not None else "tablet"
        self.status = StatusSlot()
        self.slab = MixingSlab()
        #: Copies of the slab's canvas for the controls panel (published after each change).
        self.slab_view: LatestValue[Canvas] = LatestValue()
        self.history = UndoHistory(canvas)
        self.session = rebuild_session(
            None,
            canvas,
            make_preset(settings),
            make_scene(settings, user_scene),
            self.input_kind,
            self.forces,
        )
        self._commands: queue.SimpleQueue[Command] = queue.SimpleQueue()
        self._inputs: collections.deque[StylusSample] = collections.deque(maxlen=4096)
        self._stop_event = threading.Event()
        self._wake = threading.Event()
        self._last_input: StylusSample | None = None
        self._sim_t = 0.0
        self._last_real: float | None = None
        self._stroke: Box | None = None
        self._stroking = False
        self._lifted_at: float | None = None
        self._strokes = 0
        self._steps = RateMeter()
        self._step_ms = 0.0
        self.message = ""
        self._fault: str | None = None
        self._ready = False
        self._radius = brush_radius_m(self.session.preset)
        self.journal.start(self.header())
        self.idle = threading.Event()

    # --- called from other threads -----------------------------------------------------------
    def push(self, sample: StylusSample) -> None:
        """A tablet or mouse sample (its time is replaced by the session clock)."""
        self._inputs.append(sample)
        self._wake.set()

    def submit(self, command: Command) -> None:
        """Run ``command(worker)`` in the worker thread before its next step."""
        self._commands.put(command)
        self._wake.set()

    def stop(self, timeout_s: float = 10.0) -> None:
        """Stop the thread (the current stroke is committed) and close the journal."""
        self._stop_event.set()
        self._wake.set()
        if self.is_alive():
            self.join(timeout_s)

    # --- the loop ------------------------------------------------------------------------------
    def run(self) -> None:
        try:
            self._prepare()
            while not self._stop_event.is_set():
                self._run_commands()
                self._end_stroke_after_gap()
                if not self._pass():
                    self.idle.set()
                    self._wake.wait(IDLE_S)
                    self._wake.clear()
        finally:
            self.end_stroke()
            self._publish_status()
            self.journal.close()

    def _prepare(self) -> None:
        """Paint the warm-up stroke (:mod:`paintapp.app.warmup`) before the first real one;
        the HUD says so while it runs, and how long it took when that was long."""
        if self.pigments:
            self.message = "preparing the simulation..."
            self._publish_status()
            try:
                with compiling_ahead():  # a cold cache: a second process compiles from the end
                    took = warm_up(
                        self.session.preset,
                        self.session.scene,
                        self.live.texel_size_m,
                        self.pigments[0],
                        self.input_kind,
                    )
            except Exception as exc:  # the real strokes will say what is wrong, or work
                self.message = f"could not prepare the simulation: {type(exc).__name__}: {exc}"
            else:
                long = took >= PREPARE_NOTE_S
                self.message = f"simulation prepared in {took:.0f} s" if long else ""
        self._ready = True
        self._publish_status()

    def _pass(self) -> bool:
        """One pass over the newest input; False when there was nothing to do."""
        self._check_device()
        samples = self._take_samples()
        if not samples:
            return False
        self.idle.clear()
        for sample in samples:
            self._step(sample)
        if self.link is not None and self._fault is None and not self.session.in_contact:
            time.sleep(AIR_S)
        return True

    def _run_commands(self) -> None:
        while True:
            try:
                command = self._commands.get_nowait()
            except queue.Empty:
                return
            self.idle.clear()
            try:
                command(self)
            except (InputError, ValueError, OSError) as exc:
                self.message = str(exc)
            self._sync_display()
            self._publish_status()

    # --- input ---------------------------------------------------------------------------------
    def session_time(self) -> float:
        """The session clock for the next record, s (see the module docstring)."""
        real = time.perf_counter()
        if self._last_real is not None:
            self._sim_t += min(max(real - self._last_real, 0.0), MAX_STEP_S)
        self._last_real = real
        return self._sim_t

    def _take_samples(self) -> list[StylusSample]:
        if self.link is not None and self._fault is None:
            _, state = self.link.states.latest()
            sample = None if state is None else sample_from_state(state, 0.0)
            return [] if sample is None else [sample]
        batch: list[StylusSample] = []
        while self._inputs:
            batch.append(self._inputs.popleft())
        if not batch:
            held = self._last_input is not None and self._last_input.pressure > 0
            return [self._last_input] if held and self._last_input is not None else []
        keep = keep_samples(batch, self._last_input, TRAIL_SPACING * self._radius)
        self._last_input = batch[-1]
        return keep

    def _step(self, raw: StylusSample) -> None:
        sample = StylusSample(
            self.session_time(),
            raw.position_m,
            raw.pressure,
            raw.tilt_rad,
            raw.twist_rad,
            raw.buttons,
        )
        begin = time.perf_counter()
        try:
            step = self.session.sample(sample)
        except (InputError, ValueError, FloatingPointError) as exc:
            self.message = f"step skipped: {exc}"
            return
        except Exception as exc:  # keep painting possible; the stroke so far is kept
            traceback.print_exc(file=sys.stderr)
            self.message = f"simulation error: {type(exc).__name__}: {exc}"
            self.end_stroke()
            return
        self.journal.write(sample)
        if step.paint is not None:
            self._steps.tick()
            self._step_ms = 1e3 * (time.perf_counter() - begin)
        self._after_step()

    def _after_step(self) -> None:
        in_contact = self.session.in_contact
        if in_contact:
            self._lifted_at = None
            if not self._stroking:
                self._stroking, self._stroke = True, None
        elif self._stroking and self._lifted_at is None:
            self._lifted_at = time.perf_counter()
        self._sync_display()
        self._publish_status()

    def _end_stroke_after_gap(self) -> None:
        lifted = self._lifted_at
        if lifted is not None and time.perf_counter() - lifted >= STROKE_GAP_S:
            self.end_stroke()
            self._publish_status()

    def _sync_display(self) -> None:
        wet = self.live.take_wet_dirty()  # drying: the wetness alone changed there
        if wet is not None:
            self.shared.publish_wetness(self.live, wet)
        box = self.live.take_dirty()
        if box is None:
            return
        if self._stroking:
            self._stroke = grow(self._stroke, box)
        self.shared.publish_region(self.live, box)

    def end_stroke(self) -> None:
        """Commit the current stroke (if any) to the undo history."""
        if not self._stroking:
            return
        self._sync_display()
        self._stroking = False
        self._lifted_at = None
        if self.history.commit(self.live, self._stroke) is not None:
            self._strokes += 1
        self._stroke = None

    # --- device --------------------------------------------------------------------------------
    def _check_device(self) -> None:
        if self.link is None or self._fault is not None or self.link.fault is None:
            return
        fault = self.link.fault
        t = self.session_time()
        self.journal.marker(t, f"device fault: {fault}")
        last = self.session.tracker.last
        xy = last.position_m[:2] if last is not None else np.zeros(2)
        self._step(StylusSample(t, np.array([xy[0], xy[1], 0.01]), 0.0))  # lift the brush
        self.end_stroke()
        # The status shows the fault only now, with the stroke it cut short already committed
        # (on a large canvas the commit takes a while; a status in between showed neither).
        self._fault = fault
        self.input_kind = "tablet"
        self.rebuild()
        self.journal.start(self.header())
        self.message = f"device stopped ({self._fault}); painting continues with the pointer"
        self._publish_status()

    # --- helpers for commands ------------------------------------------------------------------
    def header(self) -> StrokeHeader:
        """The journal header for the current canvas, brush, scene and input."""
        kind = "haptic" if self.input_kind == "haptic" else "tablet"
        return make_header(
            self.live, self.settings.brush, self.pigments, self.session.scene.name, kind
        )

    def publish_slab(self) -> None:
        """Show the mixing slab's paint as it is now."""
        self.slab_view.publish(copy_canvas(self.slab.canvas))

    def rebuild(self) -> None:
        """A new session for the current settings (after a brush, scene or canvas change)."""
        preset = make_preset(self.settings)
        scene = make_scene(self.settings, self.user_scene)
        self.session = rebuild_session(
            self.session, self.live, preset, scene, self.input_kind, self.forces
        )
        self._radius = brush_radius_m(preset)

    def _publish_status(self) -> None:
        last = self.session.tracker.last
        grid = None
        if self.session.in_contact:
            window = self.session.model.window
            x0, y0 = window.origin_m
            size = window.cell_size_m
            grid = (x0, y0, x0 + window.cells[0] * size, y0 + window.cells[1] * size)
        _, sample = self.forces.latest()
        status = WorkerStatus(
            sim_hz=self._steps.rate(),
            step_ms=self._step_ms,
            tip_m=None if last is None else (float(last.position_m[0]), float(last.position_m[1])),
            in_contact=self.session.in_contact,
            brush_radius_m=self._radius * (last.splay if last is not None else 1.0),
            grid_m=grid,
            force_n=np.zeros(3) if sample is None else sample.force,
            torque_nm=np.zeros(3) if sample is None else sample.torque,
            reservoir_m3=self.session.reservoir.total_m3,
            strokes=self._strokes,
            undo=self.history.undo_count,
            redo=self.history.redo_count,
            fault=self._fault,
            message=self.journal.error or self.message,
            paint_steps=self.session.stats.paint_steps,
            viscosity_pa_s=self.session.scene.viscosity_pa_s,
            ready=self._ready,
            journal=str(self.journal.path or ""),
        )
        self.status.publish(status)


def keep_samples(
    batch: list[StylusSample], before: StylusSample | None, spacing_m: float
) -> list[StylusSample]:
    """The samples of ``batch`` (all that arrived since the last pass) worth a step: the last one
    before each pen-down/pen-up change, the touch-down itself, the newest sample, and, while the
    pen is down, a sample wherever the tip has moved ``spacing_m`` since the last one kept (from
    ``before``, the previous pass's newest), so a stroke stays a trail however far behind the
    worker is; the spacing widens so that at most about ``MAX_TRAIL_STEPS`` are kept for travel."""
    travel = 0.0
    prev = before
    for s in batch:
        if prev is not None and s.pressure > 0 and prev.pressure > 0:
            travel += float(np.hypot(*(s.position_m[:2] - prev.position_m[:2])))
        prev = s
    spacing_m = max(spacing_m, travel / MAX_TRAIL_STEPS)  # a long backlog: wider, bounded steps
    keep: list[StylusSample] = []
    last = before
    for i, s in enumerate(batch):
        newest = i == len(batch) - 1
        transition = not newest and (s.pressure > 0) != (batch[i + 1].pressure > 0)
        down = s.pressure > 0
        touch_down = down and (last is None or last.pressure <= 0)
        far = (
            down
            and not touch_down
            and last is not None
            and float(np.hypot(*(s.position_m[:2] - last.position_m[:2]))) >= spacing_m
        )
        if newest or transition or touch_down or far:
            keep.append(s)
            last = s
    return keep
