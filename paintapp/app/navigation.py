"""Zoom, pan and turn the canvas in its widget: the view's state and the gestures that change it.

The view (:class:`~paintapp.render.view_transform.CanvasView`) fits the canvas to the widget
until the artist zooms, pans or turns it:

- zoom: the wheel or Ctrl+wheel (about the pointer), a touchpad pinch, the window's +/- keys
  (:data:`KEY_ZOOM` a press, :data:`WHEEL_ZOOM` a notch); 5 % to 1600 % (device pixels per canvas
  texel);
- pan: Space+drag (mouse or pen), a middle-button drag, a two-finger scroll on a touchpad (wheel
  events that carry a pixel distance and no Ctrl);
- turn: R+drag or Shift+Space+drag (about the widget's centre: the canvas follows the pointer's
  angle round it), a touchpad's rotate gesture.

A fitted canvas stays fitted when the widget or the canvas changes size; a zoomed or panned one
keeps its centre and scale when the widget is resized, and is fitted again for a canvas of
another size.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from PySide6.QtCore import QEvent, QPointF, Qt
from PySide6.QtGui import QCursor, QKeyEvent, QNativeGestureEvent, QWheelEvent
from PySide6.QtWidgets import QWidget

from paintapp.render.view_transform import CanvasView

#: Zoom per wheel notch (120 eighths of a degree) and per +/- key press.
WHEEL_ZOOM = 1.25
KEY_ZOOM = 1.25
#: The keys held for a view drag: Space pans (with Shift, turns), R turns.
DRAG_KEYS = (Qt.Key.Key_Space, Qt.Key.Key_R)


class ViewNavigation:
    """The view of the canvas in ``widget`` and the gestures that change it.

    Args:
        widget: the canvas widget (its size, device pixel ratio and cursor).
        canvas_size_m: returns the canvas's (w, h), m.
        texel_m: returns the canvas texel's side, m.
    """

    def __init__(
        self,
        widget: QWidget,
        canvas_size_m: Callable[[], tuple[float, float]],
        texel_m: Callable[[], float],
    ) -> None:
        self.widget = widget
        self.canvas_size_m = canvas_size_m
        self.texel_m = texel_m
        #: called after the view changed (the window's status bar)
        self.on_view: Callable[[], None] | None = None
        # the artist's view (None: the canvas fitted, turned by _fit_angle) and the canvas
        # size it was made for (another size fits the canvas again)
        self._view: CanvasView | None = None
        self._view_size_m: tuple[float, float] | None = None
        self._fit_angle = 0.0
        self._space = False  # Space held: a drag pans (with Shift, turns)
        self._turn_key = False  # R held: a drag turns
        self._drag: tuple[str, QPointF, CanvasView] | None = None  # mode, start, view then

    # --- the view ------------------------------------------------------------------------------
    def view(self) -> CanvasView:
        """Where the canvas sits in the widget now."""
        size_m = self.canvas_size_m()
        widget = (max(self.widget.width(), 1), max(self.widget.height(), 1))
        if self._view is None or self._view_size_m != size_m:
            self._view = None
            return CanvasView.fit(size_m, widget, self._fit_angle)
        return self._view.resized(widget)

    def set_view(self, view: CanvasView) -> None:
        """Show the canvas through ``view`` (its zoom held within 5 % to 1600 %)."""
        self._view = view.clamped(self.texel_m(), self._ratio())
        self._view_size_m = self.canvas_size_m()
        self._fit_angle = self._view.angle_rad
        self._changed()

    def fit_to_window(self) -> None:
        """Show the whole canvas (at its present turn) fitted to the widget."""
        self._fit_angle = self.view().angle_rad
        self._view = None
        self._changed()

    def zoom_by(self, factor: float, anchor_px: tuple[float, float] | None = None) -> None:
        """Zoom ``factor`` times about widget point ``anchor_px`` (default the pointer when it
        is over the widget, else the centre)."""
        self.set_view(self.view().zoomed(factor, anchor_px or self._pointer()))

    def zoom_to(self, zoom: float, anchor_px: tuple[float, float] | None = None) -> None:
        """Zoom to ``zoom`` device pixels per canvas texel (1.0: 100 %) about ``anchor_px``
        (default the centre)."""
        self.set_view(self.view().with_zoom(zoom, self.texel_m(), self._ratio(), anchor_px))

    def pan_by(self, dx_px: float, dy_px: float) -> None:
        """Move the canvas on screen by (dx, dy) widget pixels."""
        self.set_view(self.view().panned(dx_px, dy_px))

    def rotate_by(self, delta_rad: float, anchor_px: tuple[float, float] | None = None) -> None:
        """Turn the canvas ``delta_rad`` counter-clockwise about ``anchor_px`` (default the
        widget's centre); a fitted canvas stays fitted as it turns."""
        if self._view is None:
            self._fit_angle = math.remainder(self._fit_angle + delta_rad, 2.0 * math.pi)
            self._changed()
            return
        self.set_view(self.view().rotated(delta_rad, anchor_px))

    def reset_rotation(self) -> None:
        """Turn the canvas upright again (about the widget's centre)."""
        self.rotate_by(-self.view().angle_rad)

    def zoom_percent(self) -> float:
        """The zoom, % (100: one canvas texel per device pixel)."""
        return 100.0 * self.view().zoom(self.texel_m(), self._ratio())

    def angle_deg(self) -> float:
        """The canvas's turn on screen, degrees counter-clockwise, in [-180, 180]."""
        return math.degrees(self.view().angle_rad)

    # --- gestures ------------------------------------------------------------------------------
    def drag(
        self,
        kind: QEvent.Type,
        pos: QPointF,
        mods: Qt.KeyboardModifier,
        button: Qt.MouseButton,
    ) -> bool:
        """Start, follow or end a view drag (pan or turn) from a mouse or tablet event; True
        when the event was one (then it must not reach the brush)."""
        T = QEvent.Type
        if kind in (T.MouseButtonPress, T.TabletPress) and self._drag is None:
            middle = button == Qt.MouseButton.MiddleButton
            if not (middle or self._space or self._turn_key):
                return False
            shift = bool(mods & Qt.KeyboardModifier.ShiftModifier)
            turn = not middle and (self._turn_key or (self._space and shift))
            self._drag = ("turn" if turn else "pan", QPointF(pos), self.view())
            self.widget.setCursor(Qt.CursorShape.ClosedHandCursor)
            return True
        if self._drag is None:
            return False
        mode, start, view = self._drag
        if mode == "pan":
            self.set_view(view.panned(pos.x() - start.x(), pos.y() - start.y()))
        else:
            cx, cy = 0.5 * self.widget.width(), 0.5 * self.widget.height()
            then = math.atan2(cy - start.y(), start.x() - cx)  # y up: counter-clockwise
            now = math.atan2(cy - pos.y(), pos.x() - cx)
            self.set_view(view.rotated(now - then, (cx, cy)))
        if kind in (T.MouseButtonRelease, T.TabletRelease):
            self._drag = None
            self._show_cursor()
        return True

    def key(self, event: QKeyEvent, pressed: bool) -> bool:
        """Note Space or R going down or up; True when the event was one of them."""
        key = event.key()
        if key not in DRAG_KEYS:
            return False
        if not event.isAutoRepeat():
            if key == Qt.Key.Key_Space:
                self._space = pressed
            else:
                self._turn_key = pressed
            self._show_cursor()
        event.accept()
        return True

    def release_keys(self) -> None:
        """Forget the held keys (the widget lost the focus: their release goes elsewhere)."""
        self._space = self._turn_key = False
        self._show_cursor()

    def wheel(self, event: QWheelEvent) -> None:
        """A wheel zooms about the pointer; a touchpad's two-finger scroll (a pixel distance,
        no Ctrl) pans; Ctrl makes any scroll a zoom."""
        ctrl = bool(event.modifiers() & Qt.KeyboardModifier.ControlModifier)
        pixels, angle = event.pixelDelta(), event.angleDelta()
        pos = event.position()
        if not ctrl and not pixels.isNull():
            self.pan_by(float(pixels.x()), float(pixels.y()))
        else:
            notches = (angle.y() or angle.x()) / 120.0
            if notches:
                self.zoom_by(WHEEL_ZOOM**notches, (pos.x(), pos.y()))
        event.accept()

    def gesture(self, event: QNativeGestureEvent) -> None:
        """A touchpad or tablet gesture: a pinch zooms about the fingers, a twist turns the
        canvas (Qt's angle is clockwise on screen), a smart zoom fits the canvas."""
        kind = event.gestureType()
        pos = event.position()
        anchor = (pos.x(), pos.y())
        value = float(event.value())
        if math.isfinite(value):
            if kind == Qt.NativeGestureType.ZoomNativeGesture:
                self.zoom_by(max(1.0 + value, 0.1), anchor)
            elif kind == Qt.NativeGestureType.RotateNativeGesture:
                self.rotate_by(-math.radians(value), anchor)
            elif kind == Qt.NativeGestureType.SmartZoomNativeGesture:
                self.fit_to_window()
        event.accept()

    # --- helpers -------------------------------------------------------------------------------
    def _ratio(self) -> float:
        return float(self.widget.devicePixelRatioF())

    def _pointer(self) -> tuple[float, float] | None:
        """The pointer in widget pixels, or None when it is not over the widget."""
        pos = self.widget.mapFromGlobal(QCursor.pos())
        return (float(pos.x()), float(pos.y())) if self.widget.rect().contains(pos) else None

    def _changed(self) -> None:
        # the render loop redraws the whole widget: the view is part of what it is drawn for
        if self.on_view is not None:
            self.on_view()

    def _show_cursor(self) -> None:
        if self._drag is not None:
            return
        if self._space or self._turn_key:
            self.widget.setCursor(Qt.CursorShape.OpenHandCursor)
        else:
            self.widget.unsetCursor()
