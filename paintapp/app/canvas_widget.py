"""The canvas widget: renders the display canvas with moderngl offscreen and shows it as an image,
and turns pointer events into stylus samples.

A plain raster :class:`QWidget`: the GL work happens in a standalone (EGL) context the widget
owns, into an offscreen 8-bit framebuffer the widget's size. Each pass of the render loop
(:meth:`CanvasWidget.refresh`, a Qt timer at the display rate):

1. uploads the display canvas's dirty region, under the shared lock (only for the upload);
2. finds the widget rectangle that changed: that region on screen, and where the brush outline
   and the force arrow were and are now (all of it after a resize, a new view, light or canvas);
3. draws only that rectangle (a GL scissor): minified, the Kubelka-Munk mixing and lighting per
   window pixel (:meth:`CanvasRenderer.render`); magnified, the cached lit picture, each texel
   drawn sharp (:meth:`CanvasRenderer.render_cached`, which shades each changed texel in sight
   at most once);
4. reads that rectangle back (sRGB-encoded, as in ``preview.png``) into the widget's image and
   asks Qt to repaint just that rectangle.

Qt's raster backing store then puts only the changed pixels on the screen, where a GL widget
would compose and redraw the whole window every frame (costly on a software rasterizer).

The view (:class:`~paintapp.render.view_transform.CanvasView`: zoom, pan, turn; the gestures
that change it are :mod:`paintapp.app.navigation`'s) is one object: the pen's position, the drawn
canvas, the brush outline, the force arrow and the HUD's grid outline all go through it.

A new view redraws the whole widget: the per-pixel path shades each window pixel once, the
cached path shades only the stale texels in sight, so a frame costs what the screen holds, not
what the canvas holds.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import moderngl
import numpy as np
from PySide6.QtCore import QEvent, QRect, Qt
from PySide6.QtGui import (
    QColor,
    QFocusEvent,
    QImage,
    QKeyEvent,
    QMouseEvent,
    QNativeGestureEvent,
    QPainter,
    QPaintEvent,
    QTabletEvent,
    QWheelEvent,
)
from PySide6.QtWidgets import QWidget

from paintapp.app.input import PenState, pen_from_mouse, pen_from_tablet
from paintapp.app.navigation import ViewNavigation
from paintapp.app.shared import RateMeter, SharedCanvas, WorkerStatus
from paintapp.canvas.regions import Box, union_box
from paintapp.pigments.library import PigmentLibrary
from paintapp.render import BrushOutline, CanvasRenderer, ForceArrow, Lighting
from paintapp.render.context import RenderUnavailable, create_headless_context
from paintapp.render.finish import gl_finish
from paintapp.render.headless import render_canvas_rgba
from paintapp.render.overlays import arrow_triangles, outline_triangles
from paintapp.render.view_transform import CanvasView

#: Force arrow length on the canvas per newton of (unscaled) fluid force, in canvas widths
#: (the paint's forces are millinewtons to a few tenths of a newton: 10 mN is a tenth).
ARROW_WIDTH_PER_N = 10.0
#: Pixels added around a changed rectangle (filtering, line widths, rounding), device pixels.
PAD_PX = 3
#: Coarsest texture reduction for a minified view (canvas texels per texture texel, a side):
#: at the 5 % zoom floor (20 texels per device pixel) a pixel still spans at most two texels.
MAX_REDUCTION = 16
#: OpenGL enums moderngl has no names for: an sRGB-encoded colour format, and its switch.
GL_SRGB8_ALPHA8 = 0x8C43
GL_FRAMEBUFFER_SRGB = 0x8DB9
#: RGBA bytes to the byte order of ``QImage.Format_RGB32``.
BGRA = [2, 1, 0, 3]
#: Colour of the widget while no picture exists (no GL, or before the first frame).
BLANK = QColor(5, 5, 5)


class CanvasWidget(QWidget):
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
        #: passes of the render loop that left the screen up to date, and how many drew
        self.frames = RateMeter()
        self.frame_count = 0
        self.drawn_count = 0
        self.gl_error: str | None = None
        self._tablet_down = False
        self._fbo: moderngl.Framebuffer | None = None
        self._pixels = np.zeros((1, 1, 4), np.uint8)  # device pixels, row 0 = top
        self._image: QImage | None = None
        self._drawn: tuple | None = None  # what the whole picture was last drawn for
        self._overlay_box: Box | None = None  # device pixels, y down
        self._overlays_drawn: tuple[list, list] = ([], [])
        #: the artist's view: zoom, pan and turn, and the gestures that change it
        self.nav = ViewNavigation(
            self,
            lambda: self.shared.canvas.size_m,
            lambda: float(min(self.shared.canvas.texel_size_m)),
        )
        self.setMouseTracking(True)
        self.setFocusPolicy(Qt.FocusPolicy.StrongFocus)
        self.setAttribute(Qt.WidgetAttribute.WA_TabletTracking, True)
        self.setAttribute(Qt.WidgetAttribute.WA_OpaquePaintEvent, True)
        self.setMinimumSize(320, 240)

    # --- the view ------------------------------------------------------------------------------
    def view(self) -> CanvasView:
        """Where the canvas sits in the widget now (the one widget-to-canvas mapping)."""
        return self.nav.view()

    def mapping(self) -> CanvasView:
        """The view (see :meth:`view`)."""
        return self.nav.view()

    # --- geometry ------------------------------------------------------------------------------

    def _device_size(self) -> tuple[int, int]:
        ratio = self.devicePixelRatioF()
        return max(1, round(self.width() * ratio)), max(1, round(self.height() * ratio))

    # --- GL ------------------------------------------------------------------------------------
    def _start_gl(self) -> bool:
        """Create the context and renderer once; False (and ``gl_error`` set) without GL."""
        if self.renderer is not None:
            return True
        if self.gl_error is not None:
            return False
        try:
            self.ctx = create_headless_context()
            with self.ctx:
                self.renderer = CanvasRenderer(self.ctx, self.library, lighting=self.lighting)
        except Exception as exc:  # no usable GL: the window stays up and says so
            self.gl_error = f"OpenGL unavailable: {exc}"
            self.ctx = self.renderer = None
            self.update()
            return False
        return True

    def refresh(self) -> None:
        """One pass of the render loop (see the module docstring)."""
        if not self._start_gl():
            return
        assert self.ctx is not None and self.renderer is not None
        renderer = self.renderer
        renderer.lighting = self.lighting
        size = self._device_size()
        key = self._view_key(size)
        if self._up_to_date(key):
            self.frames.tick()
            self.frame_count += 1
            return
        renderer.reduction = key[3]
        with self.ctx:
            with self.shared.lock:
                table = renderer.table
                uploaded = renderer.update(self.shared.canvas)
                size_m = self.shared.canvas.size_m
                texel_m = self.shared.canvas.texel_size_m
            mapping = key[4]
            ratio = size[0] / max(1, self.width())
            outlines, arrows = self._overlays(size_m)
            overlay_box = self._overlay_extent(outlines, arrows, mapping, ratio, size)
            if key != self._drawn or renderer.table is not table or self._fbo is None:
                box: Box | None = (0, 0, *size)
                self._resize_target(size)
                self._drawn = key
            else:
                moved = (outlines, arrows) != self._overlays_drawn
                box = union_box(self._overlay_box, overlay_box) if moved else None
                if uploaded is not None:
                    # the lighting's slopes and the filtering reach two texture texels round
                    grow = 2 * renderer.reduction
                    changed = _texel_box_px(uploaded, texel_m, grow, mapping, ratio, size)
                    box = union_box(box, changed)
            self._overlay_box = overlay_box
            self._overlays_drawn = (outlines, arrows)
            if box is not None:
                # magnified: a texture texel covers more than a pixel
                cached = mapping.metres_per_px < min(texel_m) * renderer.reduction * ratio
                self._draw(box, size, mapping, outlines, arrows, cached)
                self.drawn_count += 1
        self.frames.tick()
        self.frame_count += 1

    def _view_key(self, size: tuple[int, int]) -> tuple:
        """What the whole picture depends on: its size, the canvas's, the light, the texture
        reduction (the largest power of two, at most :data:`MAX_REDUCTION`, of canvas texels per
        device pixel: a box filter for minified views) and the view."""
        canvas = self.shared.canvas
        view = self.view()
        texels = view.metres_per_px * self.width() / size[0] / min(canvas.texel_size_m)
        reduction = 1
        while reduction < MAX_REDUCTION and 2 * reduction <= texels:
            reduction *= 2
        return size, canvas.size_m, self.lighting, reduction, view

    def _up_to_date(self, key: tuple) -> bool:
        """Whether the picture already shows the canvas, the light and the overlays of now."""
        assert self.renderer is not None
        if self._drawn != key:
            return False
        if self._overlays(self.shared.canvas.size_m) != self._overlays_drawn:
            return False
        table = self.renderer.table
        with self.shared.lock:
            canvas = self.shared.canvas
            return (
                canvas.peek_dirty() is None
                and canvas.peek_wet_dirty() is None
                and table is not None
                and table.names == canvas.pigment_names
            )

    def invalidate(self) -> None:
        """Make the next pass of the render loop redraw the whole widget."""
        self._drawn = None

    def shown_pixels(self) -> np.ndarray:
        """A copy of what the widget shows, (H, W, 3) uint8 RGB in device pixels, row 0 = top."""
        return self._pixels[..., [2, 1, 0]].copy()

    def _resize_target(self, size: tuple[int, int]) -> None:
        assert self.ctx is not None
        if self._fbo is not None and self._fbo.size == size:
            return
        if self._fbo is not None:
            for attachment in self._fbo.color_attachments:
                attachment.release()
            self._fbo.release()
        # An sRGB target: the renderer's linear colour is encoded as it is written (blending
        # stays linear), so the window shows what preview.png does.
        target = self.ctx.texture(size, 4, internal_format=GL_SRGB8_ALPHA8)
        self._fbo = self.ctx.framebuffer(color_attachments=[target])
        self.ctx.enable_direct(GL_FRAMEBUFFER_SRGB)
        w, h = size
        # The image owns its memory and the array views it (an image made over a Python
        # buffer upsets PySide6's reference counts at exit).
        image = QImage(w, h, QImage.Format.Format_RGB32)  # the backing store's own format
        image.fill(BLANK)
        image.setDevicePixelRatio(w / max(1, self.width()))
        rows = np.frombuffer(image.bits(), np.uint8).reshape(h, image.bytesPerLine())
        self._pixels = rows[:, : 4 * w].reshape(h, w, 4)
        self._image = image

    def _draw(
        self,
        box: Box,
        size: tuple[int, int],
        mapping: CanvasView,
        outlines: list,
        arrows: list,
        cached: bool,
    ) -> None:
        """Draw device-pixel rectangle ``box`` (y down) offscreen, read it back, show it."""
        assert self.ctx is not None and self.renderer is not None and self._fbo is not None
        x0, y0, x1, y1 = box
        w, h = x1 - x0, y1 - y0
        gl_box = (x0, size[1] - y1, w, h)  # GL rows count up from the bottom
        fbo = self._fbo
        fbo.use()
        self.ctx.scissor = gl_box
        try:
            draw = self.renderer.render_cached if cached else self.renderer.render
            draw(size, mapping, outlines, arrows, framebuffer=fbo)
            gl_finish()  # the rasterizer's wait without the interpreter lock
            data = fbo.read(viewport=gl_box, components=4)
        finally:
            fbo.use()
            self.ctx.scissor = None
        rgba = np.frombuffer(data, np.uint8).reshape(h, w, 4)
        self._pixels[y0:y1, x0:x1] = rgba[::-1, :, BGRA]  # RGB32 is B, G, R, 255 in memory
        ratio = size[0] / max(1, self.width())
        self.update(_logical_rect(box, ratio))

    def paintEvent(self, event: QPaintEvent) -> None:
        painter = QPainter(self)
        try:
            area = event.rect()
            if self._image is None:
                painter.fillRect(area, BLANK)
                if self.gl_error:
                    painter.setPen(QColor(230, 230, 230))
                    painter.drawText(self.rect(), Qt.AlignmentFlag.AlignCenter, self.gl_error)
                return
            painter.drawImage(area, self._image, _device_rect(area, self._image))
        finally:
            painter.end()

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

    @staticmethod
    def _overlay_extent(
        outlines: list,
        arrows: list,
        mapping: CanvasView,
        ratio: float,
        size: tuple[int, int],
    ) -> Box | None:
        """Device-pixel box (y down) covering the overlays, or None without any."""
        pixel_m = mapping.metres_per_px / ratio
        shapes = [outline_triangles(o, pixel_m) for o in outlines]
        shapes += [arrow_triangles(a, pixel_m) for a in arrows]
        points = [s for s in shapes if len(s)]
        if not points:
            return None
        xy = np.concatenate(points)
        lo, hi = xy.min(axis=0), xy.max(axis=0)
        if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))):
            return (0, 0, *size)
        return _metres_box_px((lo[0], lo[1], hi[0], hi[1]), mapping, ratio, size)

    def resizeEvent(self, event) -> None:
        super().resizeEvent(event)
        for child in self.findChildren(QWidget, options=Qt.FindChildOption.FindDirectChildrenOnly):
            child.setGeometry(self.rect())  # overlays (HUD, help) cover the canvas

    # --- input ---------------------------------------------------------------------------------
    def tabletEvent(self, event: QTabletEvent) -> None:
        kind = event.type()
        if self.nav.drag(kind, event.position(), event.modifiers(), event.button()):
            event.accept()
            return
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
        if self.nav.drag(event.type(), event.position(), event.modifiers(), event.button()):
            event.accept()
            return
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

    def keyPressEvent(self, event: QKeyEvent) -> None:
        if not self.nav.key(event, pressed=True):
            super().keyPressEvent(event)

    def keyReleaseEvent(self, event: QKeyEvent) -> None:
        if not self.nav.key(event, pressed=False):
            super().keyReleaseEvent(event)

    def focusOutEvent(self, event: QFocusEvent) -> None:
        self.nav.release_keys()  # a key released elsewhere is never seen here
        super().focusOutEvent(event)

    def wheelEvent(self, event: QWheelEvent) -> None:
        self.nav.wheel(event)

    def event(self, event: QEvent) -> bool:
        if event.type() == QEvent.Type.NativeGesture and isinstance(event, QNativeGestureEvent):
            self.nav.gesture(event)
            return True
        return super().event(event)

    # --- pictures ------------------------------------------------------------------------------
    def render_picture(self):
        """The lit canvas at one pixel per texel, linear RGBA (H, W, 4), row 0 = bottom; None
        without OpenGL. Drawn from a copy of the display canvas at full resolution in a context
        of its own (the widget's textures may be reduced)."""
        if not self._start_gl():
            return None
        canvas, _ = self.shared.snapshot()
        try:
            return render_canvas_rgba(canvas, self.library, self.lighting)
        except RenderUnavailable:
            return None


def _metres_box_px(
    box_m: tuple[float, float, float, float],
    mapping: CanvasView,
    ratio: float,
    size: tuple[int, int],
) -> Box | None:
    """Device-pixel box (y down, padded, clipped to ``size``) bounding a canvas box in metres
    (turned with the view)."""
    left, top, right, bottom = mapping.widget_box(box_m)
    if not all(math.isfinite(v) and abs(v) < 1e7 for v in (left, top, right, bottom)):
        return (0, 0, *size)
    x0 = max(0, math.floor(left * ratio) - PAD_PX)
    y0 = max(0, math.floor(top * ratio) - PAD_PX)
    x1 = min(size[0], math.ceil(right * ratio) + PAD_PX)
    y1 = min(size[1], math.ceil(bottom * ratio) + PAD_PX)
    if x1 <= x0 or y1 <= y0:
        return None
    return x0, y0, x1, y1


def _texel_box_px(
    box: Box, texel_m: tuple[float, float], grow: int, mapping: CanvasView, ratio: float, size
) -> Box | None:
    """Device-pixel box of a canvas texel box grown by ``grow`` texels each way."""
    dx, dy = texel_m
    x0, y0, x1, y1 = box
    box_m = ((x0 - grow) * dx, (y0 - grow) * dy, (x1 + grow) * dx, (y1 + grow) * dy)
    return _metres_box_px(box_m, mapping, ratio, size)


def _logical_rect(box: Box, ratio: float) -> QRect:
    x0, y0, x1, y1 = box
    left, top = math.floor(x0 / ratio), math.floor(y0 / ratio)
    return QRect(left, top, math.ceil(x1 / ratio) - left, math.ceil(y1 / ratio) - top)


def _device_rect(area: QRect, image: QImage) -> QRect:
    """The image's device pixels behind widget rectangle ``area``."""
    ratio = image.devicePixelRatio()
    x0, y0 = math.floor(area.x() * ratio), math.floor(area.y() * ratio)
    x1 = math.ceil((area.x() + area.width()) * ratio)
    y1 = math.ceil((area.y() + area.height()) * ratio)
    return QRect(x0, y0, x1 - x0, y1 - y0)
