"""The main window: canvas, HUD, help overlay, controls, menus, shortcuts, timers.

Threads (none waits on another; they exchange the latest state):

- the GUI thread: Qt events (tablet, mouse, keys, controls) and the render loop, a timer at the
  display rate that repaints the canvas widget and the HUD;
- the simulation worker (:mod:`paintapp.app.worker`): steps the painting session with the
  latest input as fast as it can;
- with a haptic device, the 1 kHz servo loop (:mod:`paintapp.app.haptic_link`), by default in a
  process of its own that owns the device (shared memory carries forces, poses and timing);
- an autosave thread now and then (:mod:`paintapp.app.recovery`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from PySide6.QtCore import Qt, QTimer
from PySide6.QtGui import QAction, QCloseEvent, QKeySequence
from PySide6.QtWidgets import (
    QDockWidget,
    QFileDialog,
    QLabel,
    QMainWindow,
    QMessageBox,
    QScrollArea,
)

from paintapp.app import actions
from paintapp.app.canvas_widget import CanvasWidget
from paintapp.app.controls import ControlsPanel
from paintapp.app.document import Document
from paintapp.app.haptic_link import HapticLink
from paintapp.app.history import copy_canvas
from paintapp.app.hud import HudData, HudOverlay
from paintapp.app.input import PenState, sample_from_pen
from paintapp.app.journal import Journal
from paintapp.app.navigation import KEY_ZOOM
from paintapp.app.new_canvas_dialog import ask_new_canvas, follow_surface
from paintapp.app.options import PaintOptions
from paintapp.app.recovery import Recovery
from paintapp.app.settings import (
    MAX_SCALE,
    MIN_SCALE,
    MODEL_LABELS,
    PaintSettings,
    brush_names,
    make_scene,
)
from paintapp.app.shared import SharedCanvas
from paintapp.app.shortcuts import SHORTCUTS, HelpOverlay
from paintapp.app.sim_process import SimulationProcess, simulation_mode
from paintapp.app.view_status import view_status_text
from paintapp.app.worker import SimulationWorker
from paintapp.canvas.model import Canvas
from paintapp.pigments.library import PigmentLibrary
from paintapp.render import Lighting

#: The HUD repaints every this many frames (10 times a second at the default frame period):
#: its figures are read, not watched, and its painting holds the interpreter lock.
HUD_EVERY_FRAMES = 6
#: Turn of the canvas per key press (Ctrl+R, Ctrl+Shift+R), radians.
TURN_STEP_RAD = math.radians(15.0)


class PaintWindow(QMainWindow):
    """The painting window.

    Args:
        canvas: the canvas to paint on.
        library: the pigments (the palette shows all of them, at most 16).
        options: the command-line options.
        link: the started haptic link, or None.
        document: the file the canvas came from, if any.
        interactive: False suppresses message boxes (tests, benchmarks).
    """

    def __init__(
        self,
        canvas: Canvas,
        library: PigmentLibrary,
        options: PaintOptions,
        link: HapticLink | None = None,
        document: Path | None = None,
        interactive: bool = True,
    ) -> None:
        super().__init__()
        self.library = library
        self.options = options
        self.link = link
        self.interactive = interactive
        self.settings: PaintSettings = options.settings
        self.pigments = tuple(sorted(library))[:16]
        self.shared = SharedCanvas(copy_canvas(canvas))
        self.journal = Journal(options.record, options.overwrite_record)
        self.simulation = simulation_mode(options.simulation, link)
        self.worker: SimulationWorker | SimulationProcess
        if self.simulation == "process":
            block = None if link is None or link.process is None else link.process.block.name
            self.worker = SimulationProcess(
                canvas,
                self.shared,
                self.settings,
                self.pigments,
                options.record,
                options.overwrite_record,
                options.scene,
                block,
            )
        else:
            self.worker = SimulationWorker(
                canvas, self.shared, self.settings, self.pigments, self.journal, options.scene, link
            )
        self._scene_viscosity = make_scene(self.settings, options.scene).viscosity_pa_s
        self._fault_sent = False
        self.recovery = Recovery(options.recovery_dir, library)
        self.pen_events = 0
        self._frame = 0
        self._armed = False
        self._fault_seen = False
        self._slab_seq = 0
        self.pigment_label = "none"  # what the brush was last loaded with (the status bar)
        self._build_widgets()
        self.document = Document(
            self.shared, library, self.worker.submit, self.picture_for, _WindowDialogs(self)
        )
        self.document.on_surface = follow_surface(link)
        self._build_actions()
        self._start_timers()
        self.document.set_path(document)
        self.resize(1180, 760)
        self.worker.start()

    # --- construction ---------------------------------------------------------------------------
    def _build_widgets(self) -> None:
        self.canvas_widget = CanvasWidget(
            self.shared, self.library, self.worker.status.get, self.on_pen
        )
        self.setCentralWidget(self.canvas_widget)
        self.view_label = QLabel()
        self.statusBar().addPermanentWidget(self.view_label)
        self.canvas_widget.nav.on_view = self.show_view_status
        self.canvas_widget.setFocus()  # Space and R (held for a pan or a turn) reach the canvas
        self.hud = HudOverlay(
            self.worker.status.get, self.hud_data, self.canvas_widget.mapping, self.canvas_widget
        )
        self.help = HelpOverlay(self.canvas_widget)
        handlers: dict[str, Callable[..., Any]] = {
            "pigment": self.load_pigment,
            "clean": self.clean_brush,
            "slab_put": self.slab_put,
            "slab_dab": self.slab_dab,
            "slab_mix": self.slab_mix,
            "slab_clear": self.slab_clear,
            "settings": self.apply_settings,
            "view": self.set_view,
        }
        self.controls = ControlsPanel(
            self.library,
            self.pigments,
            self.settings,
            self._scene_viscosity,
            handlers,
        )
        scroll = QScrollArea()
        scroll.setWidget(self.controls)
        scroll.setWidgetResizable(True)
        self.dock = QDockWidget("Controls", self)
        self.dock.setWidget(scroll)
        self.dock.setFeatures(QDockWidget.DockWidgetFeature.DockWidgetMovable)
        self.addDockWidget(Qt.DockWidgetArea.RightDockWidgetArea, self.dock)

    def _handlers(self) -> dict:
        return {
            "help": lambda: self.help.setVisible(not self.help.isVisible()),
            "undo": self.undo,
            "redo": self.redo,
            "new": lambda: ask_new_canvas(self),
            "open": self.document.open,
            "save": self.document.save,
            "save_as": lambda: self.document.save(ask=True),
            "export": self.document.export,
            "clean": self.clean_brush,
            "slab_mix": self.slab_mix,
            "slab_clear": self.slab_clear,
            "next_brush": lambda: self.step_brush(1),
            "prev_brush": lambda: self.step_brush(-1),
            "smaller": lambda: self.scale_brush(1 / 1.25),
            "larger": lambda: self.scale_brush(1.25),
            "weaker": lambda: self.change_force(-0.5),
            "stronger": lambda: self.change_force(0.5),
            "model": self.next_model,
            "grid": lambda: setattr(self.hud, "show_grid", not self.hud.show_grid),
            "hud": lambda: setattr(self.hud, "show_text", not self.hud.show_text),
            "light": lambda: self.turn_light(15.0),
            "light_back": lambda: self.turn_light(-15.0),
            "controls": lambda: self.dock.setVisible(not self.dock.isVisible()),
            "zoom_in": lambda: self.canvas_widget.nav.zoom_by(KEY_ZOOM),
            "zoom_out": lambda: self.canvas_widget.nav.zoom_by(1 / KEY_ZOOM),
            "fit": self.canvas_widget.nav.fit_to_window,
            "actual": lambda: self.canvas_widget.nav.zoom_to(1.0),
            "turn": lambda: self.canvas_widget.nav.rotate_by(TURN_STEP_RAD),
            "turn_back": lambda: self.canvas_widget.nav.rotate_by(-TURN_STEP_RAD),
            "upright": self.canvas_widget.nav.reset_rotation,
            "quit": self.close,
        }

    def _build_actions(self) -> None:
        handlers = self._handlers()
        self.actions_by_name: dict[str, QAction] = {}
        menus = {"file": self.menuBar().addMenu("&File"), "edit": self.menuBar().addMenu("&Edit")}
        menus["brush"] = self.menuBar().addMenu("&Brush")
        menus["view"] = self.menuBar().addMenu("&View")
        where = {"new": "file", "open": "file", "save": "file", "save_as": "file"}
        where |= {"export": "file", "quit": "file", "undo": "edit", "redo": "edit"}
        where |= {"clean": "brush", "next_brush": "brush", "prev_brush": "brush"}
        where |= {"slab_mix": "brush", "slab_clear": "brush"}
        where |= {"smaller": "brush", "larger": "brush", "model": "brush"}
        for name, keys, text in SHORTCUTS:
            if name == "pigment":
                self._pigment_shortcuts(keys)
                continue
            action = QAction(text[:1].upper() + text[1:], self)
            action.setShortcuts([QKeySequence(k) for k in keys])
            action.setShortcutContext(Qt.ShortcutContext.ApplicationShortcut)
            action.triggered.connect(lambda _=False, f=handlers[name]: f())
            menus[where.get(name, "view")].addAction(action)
            self.addAction(action)
            self.actions_by_name[name] = action

    def _pigment_shortcuts(self, keys: tuple[str, ...]) -> None:
        for key, name in zip(keys, self.pigments, strict=False):
            action = QAction(f"Load {name}", self)
            action.setShortcut(QKeySequence(key))
            action.setShortcutContext(Qt.ShortcutContext.ApplicationShortcut)
            action.triggered.connect(lambda _=False, n=name: self.load_pigment(n))
            self.addAction(action)

    def _start_timers(self) -> None:
        self.render_timer = QTimer(self)
        self.render_timer.timeout.connect(self._frame_tick)
        self.render_timer.start(self.options.frame_ms)
        self.autosave_timer = QTimer(self)
        self.autosave_timer.timeout.connect(self.autosave)
        if self.options.autosave_s > 0:
            self.autosave_timer.start(round(1000 * self.options.autosave_s))

    # --- the render loop ------------------------------------------------------------------------
    def _frame_tick(self) -> None:
        self.canvas_widget.refresh()
        self._frame += 1
        if not self._armed and self.link is not None and self.worker.status.get().ready:
            # start-up is over: the first frame's shader compiles, the worker's warm-up (which
            # compiles the kernels on a new installation) -- both hold the interpreter lock
            self._armed = True
            self.link.arm()
        if self._frame % HUD_EVERY_FRAMES == 0:
            self.show_view_status()
            self.hud.refresh()
            if self.help.isVisible():
                self.help.update()
            self._show_slab()
        status = self.worker.status.get()
        link = self.link
        if (
            isinstance(self.worker, SimulationProcess)
            and link is not None
            and link.fault is not None
            and not self._fault_sent
        ):
            self._fault_sent = True  # the worker in the child cannot see the link's fault
            self.worker.device_fault(link.fault)
        if status.fault and not self._fault_seen:
            self._fault_seen = True  # keep the work: autosave at once
            self.autosave(force=True)
            self.statusBar().showMessage(status.message, 15000)

    def _show_slab(self) -> None:
        seq, slab = self.worker.slab_view.latest()
        if seq != self._slab_seq and slab is not None:
            self._slab_seq = seq
            self.controls.slab.show_canvas(slab)

    def show_view_status(self) -> None:
        """The status bar's permanent part: brush, pigment, zoom and turn."""
        nav = self.canvas_widget.nav
        s = self.settings
        text = view_status_text(
            s.brush, s.brush_scale, self.pigment_label, nav.zoom_percent(), nav.angle_deg()
        )
        if self.view_label.text() != text:
            self.view_label.setText(text)

    def hud_data(self) -> HudData:
        """The HUD's figures besides the worker's."""
        servo = None
        if self.link is not None and self.link.fault is None:
            rate, jitter, _ = self.link.live()
            servo = (rate, jitter)
        s = self.settings
        return HudData(
            frame_hz=self.canvas_widget.frames.rate(),
            servo=servo,
            device=self.options.device.label,
            servo_where=self._servo_where(),
            brush=f"{s.brush} x{s.brush_scale:.2g} load {100 * s.load_fraction:.0f}%",
            model=f"{MODEL_LABELS[s.fluid_model]}, {self._viscosity():.3g} Pa s",
            force_scale=s.force_scale,
            journal=self.worker.status.get().journal,
        )

    def _viscosity(self) -> float:
        """The paint's viscosity in the session's scene, Pa s (the worker's, once it has said)."""
        return self.worker.status.get().viscosity_pa_s or self._scene_viscosity

    def _servo_where(self) -> str:
        link = self.link
        if link is None:
            return ""
        if link.mode == "process":
            return f"process: {link.granted}"
        return "thread in the app"

    # --- input ----------------------------------------------------------------------------------
    def on_pen(self, pen: PenState) -> None:
        """A tablet or mouse reading: to the simulated hand, or straight to the worker."""
        sample = sample_from_pen(pen, self.canvas_widget.mapping())
        if sample is None:
            return
        self.pen_events += 1
        link = self.link
        if link is not None and link.fault is None:
            if link.spec.kind == "sim":
                x, y = float(sample.position_m[0]), float(sample.position_m[1])
                link.target.set(x, y, sample.pressure, pen.down)
            return
        self.worker.push(sample)

    # --- controls -------------------------------------------------------------------------------
    def load_pigment(self, name: str) -> None:
        """Dip the brush in ``name``."""
        self.pigment_label = name
        self.worker.submit(actions.load_pigment(name))

    def clean_brush(self) -> None:
        """Wipe the brush."""
        self.pigment_label = "none"
        self.worker.submit(actions.clean_brush())

    def slab_put(self, name: str) -> None:
        """Put a blob of ``name`` on the mixing slab."""
        self.worker.submit(actions.slab_put(name))

    def slab_dab(self, x_m: float, y_m: float) -> None:
        """Dab the brush on the mixing slab at (x_m, y_m) (slab metres)."""
        self.pigment_label = "slab mixture"
        self.worker.submit(actions.slab_dab(x_m, y_m))

    def slab_mix(self) -> None:
        """Knife the slab's paint together and load the brush from it."""
        self.pigment_label = "slab mixture"
        self.worker.submit(actions.slab_mix())

    def slab_clear(self) -> None:
        """Scrape the mixing slab clean."""
        self.worker.submit(actions.slab_clear())

    def apply_settings(self, settings: PaintSettings) -> None:
        """Paint on with ``settings``."""
        self.settings = settings
        if self.link is not None:
            self.link.set_force_scale(settings.force_scale)
        self.worker.submit(actions.apply_settings(settings))
        self.controls.show_settings(settings, self.canvas_widget.lighting)

    def set_view(self, lighting: Lighting, mouse_pressure: float) -> None:
        """Light and mouse pressure."""
        self.canvas_widget.lighting = lighting
        self.canvas_widget.mouse_pressure = mouse_pressure

    def step_brush(self, step: int) -> None:
        """Next (+1) or previous (-1) brush preset."""
        names = brush_names()
        i = names.index(self.settings.brush) if self.settings.brush in names else 0
        self.apply_settings(replace(self.settings, brush=names[(i + step) % len(names)]))

    def scale_brush(self, factor: float) -> None:
        """Brush size times ``factor`` (within the allowed range)."""
        scale = float(np.clip(self.settings.brush_scale * factor, MIN_SCALE, MAX_SCALE))
        self.apply_settings(replace(self.settings, brush_scale=round(scale, 3)))

    def change_force(self, delta: float) -> None:
        """Force scale plus ``delta`` (0 to 10)."""
        scale = float(np.clip(self.settings.force_scale + delta, 0.0, 10.0))
        self.apply_settings(replace(self.settings, force_scale=scale))

    def next_model(self) -> None:
        """Cycle the fluid model."""
        models = list(MODEL_LABELS)
        i = (models.index(self.settings.fluid_model) + 1) % len(models)
        self.apply_settings(replace(self.settings, fluid_model=models[i]))

    def turn_light(self, degrees: float) -> None:
        """Turn the light's azimuth."""
        light = self.canvas_widget.lighting
        lighting = replace(light, azimuth_deg=(light.azimuth_deg + degrees) % 360.0)
        self.canvas_widget.lighting = lighting
        self.controls.show_settings(self.settings, lighting)

    def undo(self) -> None:
        """Undo the last stroke."""
        self.worker.submit(actions.undo())

    def redo(self) -> None:
        """Redo."""
        self.worker.submit(actions.redo())

    # --- documents ------------------------------------------------------------------------------
    def picture_for(self, canvas: Canvas) -> np.ndarray | None:
        """The lit picture of the display canvas, if it matches ``canvas``'s size."""
        rgba = self.canvas_widget.render_picture()
        if rgba is None or rgba.shape[:2] != (canvas.height, canvas.width):
            return None
        return rgba

    def autosave(self, force: bool = False) -> None:
        """Write the recovery file if the canvas changed since the last one."""
        if not force and self.shared.version == self.recovery.saved_version:
            return
        canvas, version = self.shared.snapshot()
        document = str(self.document.path) if self.document.path else None
        journal = self.worker.status.get().journal or None
        self.recovery.save_async(canvas, version, document, journal)

    def closeEvent(self, event: QCloseEvent) -> None:
        """Offer to save unsaved paint, stop the threads; a clean exit removes the autosave."""
        if self.interactive and self.document.unsaved:
            buttons = QMessageBox.StandardButton
            answer = QMessageBox.question(
                self,
                "Unsaved paint",
                "Save the canvas before closing?",
                buttons.Save | buttons.Discard | buttons.Cancel,
            )
            if answer == buttons.Cancel or (answer == buttons.Save and not self.document.save()):
                event.ignore()
                return
        self.render_timer.stop()
        self.autosave_timer.stop()
        self.worker.stop()
        if self.link is not None:
            self.link.stop()
        self.recovery.discard()
        event.accept()


class _WindowDialogs:
    """The window's file dialogs and messages, for its :class:`Document`."""

    def __init__(self, window: PaintWindow) -> None:
        self.window = window

    def ask_open(self, title: str, filter_text: str) -> str | None:
        path, _ = QFileDialog.getOpenFileName(self.window, title, "", filter_text)
        return path or None

    def ask_save(self, title: str, filter_text: str) -> str | None:
        path, _ = QFileDialog.getSaveFileName(self.window, title, "", filter_text)
        return path or None

    def warn(self, title: str, exc: Exception) -> None:
        if self.window.interactive:
            QMessageBox.warning(self.window, title, str(exc))
        self.window.statusBar().showMessage(f"{title}: {exc}", 10000)

    def status(self, message: str) -> None:
        self.window.statusBar().showMessage(message, 5000)

    def titled(self, path: Path | None) -> None:
        self.window.setWindowTitle(f"paintapp paint - {path.name if path else 'untitled'}")
