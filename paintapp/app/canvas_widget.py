"""The canvas widget: renders the display canvas with moderngl and turns pointer events into
stylus samples.

It is a :class:`QOpenGLWidget`; ``initializeGL`` wraps Qt's context with
``moderngl.create_context()`` and ``paintGL`` draws into Qt's framebuffer object
(``ctx.detect_framebuffer(self.defaultFramebufferObject())``; framebuffer 0 is not the widget's).
Each frame uploads only the display canvas's dirty region, under the shared lock, re-shades only
that region of the cached lit picture (:meth:`CanvasRenderer.render_cached`), draws the picture,
and the brush outline and the force arrow over it. The render loop is a Qt timer at the display
rate that calls ``update()``.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import moderngl
from PySide6.QtCore import QEvent, Qt
from PySide6.QtGui import QMouseEvent, QTabletEvent
from PySide6.QtOpenGLWidgets import QOpenGLWidget
from PySide6.QtWidgets import QWidget

from paintapp.app.input import (
    PenState,
    ViewMapping,
    pen_from_mouse,
    pen_from_tablet,
)
from paintapp.app.shared import RateMeter, SharedCanvas, WorkerStatus
from paintapp.pigments.library import PigmentLibrary
from paintapp.render import BrushOutline, CanvasRenderer, ForceArrow, Lighting

#: Force arrow length on the canvas per newton of (unscaled) fluid force, in canvas widths
#: (the paint's forces are millinewtons to a few tenths of a newton: 10 mN is a tenth).
ARROW_WIDTH_PER_N = 10.0


class CanvasWidget(QOpenGLWidget):
    """Shows the shared display canvas; reports pen states to ``on_pen``.

    Args:
        shared: the display canvas and its lock.
        library: the pigments.
        status: returns the newest worker status (for the overlays).
        on_pen: called with each :class:`PenState` from a tablet or the mouse.
        parent: the parent widget.
    """

    def __init__(
        self,
        shared: SharedCanvas,
        library: PigmentLibrary,
        status: Callable[[], WorkerStatus],
        on_pen: Callable[[PenState], None],
        parent: QWidget | None = None,
    ) -> None:
        super().__init__(parent)
        self.shared = shared
        self.library = library
        self.status = status
        self.on_pen = on_pen
        self.mouse_pressure = 0.6
        self.lighting = Lighting()
        self.show_brush = True
        self.ctx: moderngl.Context | None = None
        self.renderer: CanvasRenderer | None = None
        self.frames = RateMeter()
        self.frame_count = 0
        self.gl_error: str | None = None
        self._tablet_down = False
        self.setMouseTracking(True)
        self.setFocusPolicy(Qt.FocusPolicy.StrongFocus)
        self.setAttribute(Qt.WidgetAttribute.WA_TabletTracking, True)
        self.setMinimumSize(320, 240)

    # --- geometry ------------------------------------------------------------------------------
    def mapping(self) -> ViewMapping:
        """Where the canvas sits in the widget now."""
        return ViewMapping(self.shared.canvas.size_m, (self.width(), self.height()))

    # --- GL ------------------------------------------------------------------------------------
    def initializeGL(self) -> None:
        try:
            self.ctx = moderngl.create_context()
            self.renderer = CanvasRenderer(self.ctx, self.library, lighting=self.lighting)
        except Exception as exc:  # no usable GL: the window stays up and says so
            self.gl_error = f"OpenGL unavailable: {exc}"
            self.ctx = self.renderer = None

    def paintGL(self) -> None:
        if self.ctx is None or self.renderer is None:
            return
        renderer = self.renderer
        renderer.lighting = self.lighting
        with self.shared.lock:
            renderer.update(self.shared.canvas)
            size_m = self.shared.canvas.size_m
        ratio = self.devicePixelRatioF()
        size = (max(1, round(self.width() * ratio)), max(1, round(self.height() * ratio)))
        fbo = self.ctx.detect_framebuffer(self.defaultFramebufferObject())
        mapping = ViewMapping(size_m, (self.width(), self.height()))
        outlines, arrows = self._overlays(size_m)
        renderer.render_cached(size, mapping.view, outlines, arrows, framebuffer=fbo)
        self.frames.tick()
        self.frame_count += 1

    def _overlays(self, size_m: tuple[float, float]) -> tuple[list, list]:
        status = self.status()
        if not self.show_brush or status.tip_m is None:
            return [], []
        r = max(status.brush_radius_m, 1e-4)
        colour = (1.0, 1.0, 1.0, 0.9) if status.in_contact else (0.8, 0.8, 0.8, 0.5)
        outlines = [BrushOutline(status.tip_m, (r, r), 0.0, colour)]
        force = tuple(float(v) for v in status.force_n[:2])
        if not all(math.isfinite(v) for v in force):
            return outlines, []
        arrow = ForceArrow(status.tip_m, (*force, 0.0), ARROW_WIDTH_PER_N * size_m[0])
        return outlines, [arrow]

    def resizeEvent(self, event) -> None:
        super().resizeEvent(event)
        for child in self.findChildren(QWidget, options=Qt.FindChildOption.FindDirectChildrenOnly):
            child.setGeometry(self.rect())  # overlays (HUD, help) cover the canvas

    # --- input ---------------------------------------------------------------------------------
    def tabletEvent(self, event: QTabletEvent) -> None:
        kind = event.type()
        if kind == QEvent.Type.TabletPress:
            self._tablet_down = True
        elif kind == QEvent.Type.TabletRelease:
            self._tablet_down = False
        pen = pen_from_tablet(event)
        if not self._tablet_down:
            pen = PenState(pen.x_px, pen.y_px, 0.0, pen.tilt_deg, pen.rotation_deg, 0, "tablet")
        self.on_pen(pen)
        event.accept()

    def _mouse(self, event: QMouseEvent) -> None:
        if self._tablet_down:
            return  # the tablet's own events already carry this stroke
        self.on_pen(pen_from_mouse(event, self.mouse_pressure))
        event.accept()

    def mousePressEvent(self, event: QMouseEvent) -> None:
        self._mouse(event)

    def mouseMoveEvent(self, event: QMouseEvent) -> None:
        self._mouse(event)

    def mouseReleaseEvent(self, event: QMouseEvent) -> None:
        self._mouse(event)

    # --- pictures ------------------------------------------------------------------------------
    def render_picture(self):
        """The lit canvas at one pixel per texel, linear RGBA (H, W, 4), row 0 = bottom; None
        without OpenGL."""
        if self.renderer is None:
            return None
        self.makeCurrent()
        try:
            with self.shared.lock:
                self.renderer.update(self.shared.canvas)
            self.renderer.render()
            return self.renderer.read_linear_rgba()
        finally:
            self.doneCurrent()
