"""What the app's threads share: the display copy of the canvas, the latest worker status, the
paint settings, and a monotonic clock.

Exchange rules (none of the threads waits on another's work):

- The simulation worker owns the *live* canvas. After each step it copies the region that
  changed into the *display* canvas, holding :attr:`SharedCanvas.lock` only for that copy.
- The render loop (GUI thread) holds the same lock only while it uploads the display canvas's
  dirty region to the GPU, and saving/autosave hold it only while copying the display canvas.
- The worker publishes a :class:`WorkerStatus` snapshot (a latest-value slot) after each step;
  the HUD reads the newest one.
- Stylus samples go from the GUI to the worker through a deque (append/popleft are atomic).
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field

import numpy as np

from paintapp.app.history import copy_canvas, copy_region, match_pigments
from paintapp.canvas.model import Canvas
from paintapp.canvas.regions import Box
from paintapp.haptics.channel import LatestValue


class AppClock:
    """Seconds since the app started (``time.perf_counter`` based)."""

    def __init__(self) -> None:
        self.t0 = time.perf_counter()

    def now_s(self) -> float:
        """Seconds since start."""
        return time.perf_counter() - self.t0


class SharedCanvas:
    """The display copy of the canvas and the lock guarding it.

    Attributes:
        canvas: the display canvas (replace only under :attr:`lock`).
        version: increments whenever the display canvas changes (autosave compares it).
    """

    def __init__(self, canvas: Canvas) -> None:
        self.lock = threading.Lock()
        self.canvas = canvas
        self.version = 0

    def publish_region(self, live: Canvas, box: Box) -> None:
        """Copy ``box`` of ``live`` into the display canvas and mark it dirty there."""
        with self.lock:
            copy_region(live, self.canvas, box)
            self.canvas.mark_dirty(*box)
            self.version += 1

    def apply_region(
        self, box: Box, names: tuple[str, ...], paint: np.ndarray, wetness: np.ndarray
    ) -> None:
        """Write a region a simulation process sent: ``paint`` (one layer per pigment of
        ``names``) and ``wetness`` into ``box`` of the display canvas, marked dirty there. A
        region that does not fit the display canvas (sent before a canvas that replaced it) is
        dropped."""
        x0, y0, x1, y1 = box
        with self.lock:
            canvas = self.canvas
            if not (0 <= x0 <= x1 <= canvas.width and 0 <= y0 <= y1 <= canvas.height):
                return
            if paint.shape != (len(names), y1 - y0, x1 - x0) or wetness.shape != paint.shape[1:]:
                return
            match_pigments(canvas, names)
            for i, name in enumerate(names):
                canvas.paint_m[canvas.pigment_index(name), y0:y1, x0:x1] = paint[i]
            canvas.wetness[y0:y1, x0:x1] = wetness
            canvas.mark_dirty(*box)
            self.version += 1

    def apply_wetness(self, box: Box, wetness: np.ndarray) -> None:
        """Write the wetness a simulation process sent for ``box`` (drying)."""
        x0, y0, x1, y1 = box
        with self.lock:
            canvas = self.canvas
            if not (0 <= x0 <= x1 <= canvas.width and 0 <= y0 <= y1 <= canvas.height):
                return
            if wetness.shape != (y1 - y0, x1 - x0):
                return
            canvas.wetness[y0:y1, x0:x1] = wetness
            canvas.mark_wet_dirty(*box)
            self.version += 1

    def publish_wetness(self, live: Canvas, box: Box) -> None:
        """Copy only the wetness in ``box`` of ``live`` (drying) and mark it wetness-dirty."""
        x0, y0, x1, y1 = box
        with self.lock:
            self.canvas.wetness[y0:y1, x0:x1] = live.wetness[y0:y1, x0:x1]
            self.canvas.mark_wet_dirty(*box)
            self.version += 1

    def replace(self, canvas: Canvas) -> None:
        """Show another canvas (all of it is uploaded on the next frame)."""
        canvas.mark_all_dirty()
        with self.lock:
            self.canvas = canvas
            self.version += 1

    def snapshot(self) -> tuple[Canvas, int]:
        """A deep copy of the display canvas and its version (for saving)."""
        with self.lock:
            return copy_canvas(self.canvas), self.version


@dataclass(frozen=True)
class WorkerStatus:
    """A snapshot of the simulation worker for the HUD.

    Attributes:
        sim_hz: paint steps per second over the last second.
        step_ms: wall time of the last paint step, ms.
        tip_m: (x, y) of the tip, m, or None before any sample.
        in_contact: whether the brush is in the paint.
        brush_radius_m: footprint radius of the brush, m.
        grid_m: the paint grid's (x0, y0, x1, y1) on the canvas, m, while in contact.
        force_n, torque_nm: (3,) the last published force and torque on the tip.
        reservoir_m3: paint in the brush, m^3.
        strokes, undo, redo: strokes committed so far; undo and redo depth.
        fault: a device failure message, or None.
        message: a short note for the status line ("" for none).
        paint_steps: paint steps so far.
        viscosity_pa_s: the paint's viscosity in the session's scene, Pa s.
        journal: the journal file being written ("" for none).
        ready: the worker has prepared the simulation (:mod:`paintapp.app.warmup`).
    """

    sim_hz: float = 0.0
    step_ms: float = 0.0
    tip_m: tuple[float, float] | None = None
    in_contact: bool = False
    brush_radius_m: float = 0.0
    grid_m: tuple[float, float, float, float] | None = None
    force_n: np.ndarray = field(default_factory=lambda: np.zeros(3))
    torque_nm: np.ndarray = field(default_factory=lambda: np.zeros(3))
    reservoir_m3: float = 0.0
    strokes: int = 0
    undo: int = 0
    redo: int = 0
    fault: str | None = None
    message: str = ""
    paint_steps: int = 0
    viscosity_pa_s: float = 0.0
    journal: str = ""
    ready: bool = False


class StatusSlot(LatestValue[WorkerStatus]):
    """Where the worker publishes its :class:`WorkerStatus`."""

    def get(self) -> WorkerStatus:
        """The newest status (a default one before the first)."""
        return self.latest()[1] or WorkerStatus()


class RateMeter:
    """Events per second over a sliding window of ``window_s`` seconds."""

    def __init__(self, window_s: float = 1.0) -> None:
        self.window_s = window_s
        self._times: list[float] = []

    def tick(self, now_s: float | None = None) -> None:
        """Count one event now."""
        now = time.perf_counter() if now_s is None else now_s
        self._times.append(now)
        cut = now - self.window_s
        if self._times[0] < cut:
            self._times = [t for t in self._times if t >= cut]

    def rate(self, now_s: float | None = None) -> float:
        """Events per second over the window ending now."""
        now = time.perf_counter() if now_s is None else now_s
        recent = [t for t in self._times if t >= now - self.window_s]
        return len(recent) / self.window_s
