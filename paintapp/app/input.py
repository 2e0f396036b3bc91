"""Pointer input: tablet and mouse events to stylus samples, through the view to canvas metres.

A pen tablet's :class:`QTabletEvent` gives the pressure, the tilt (``xTilt``, ``yTilt`` in
degrees, positive toward the right and toward the user) and the barrel rotation (degrees,
clockwise seen from above). In the canvas frame (x right, y up, twist counter-clockwise seen from
the handle) that is ``tilt = (radians(xTilt), -radians(yTilt))`` and ``twist = -radians(rotation)``.

With the canvas turned on screen (:class:`~paintapp.render.view_transform.CanvasView`, angle
``a`` counter-clockwise), the pen's position goes through the view, and its tilt and twist, read
in the screen's frame, are turned by ``-a`` into the canvas's.

The mouse is a stylus without pressure: the left button presses with the set mouse pressure;
holding Shift presses fully (1.0), holding Alt lightly (a quarter of the set pressure).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from PySide6.QtCore import QEvent, Qt
from PySide6.QtGui import QMouseEvent, QTabletEvent

from brushes import StylusSample
from paintapp.render.view_transform import CanvasView

MAX_TILT_RAD = 0.5 * math.pi - 1e-3


@dataclass(frozen=True)
class PenState:
    """One pointer reading in widget pixels (y down), before mapping to the canvas.

    Attributes:
        x_px, y_px: position in the widget, logical pixels.
        pressure: 0..1 (0 with the pen up).
        tilt_deg: (xTilt, yTilt) as Qt reports them, degrees.
        rotation_deg: barrel rotation, degrees clockwise.
        buttons: button bit mask.
        source: ``"tablet"`` or ``"mouse"``.
    """

    x_px: float
    y_px: float
    pressure: float
    tilt_deg: tuple[float, float] = (0.0, 0.0)
    rotation_deg: float = 0.0
    buttons: int = 0
    source: str = "mouse"

    @property
    def down(self) -> bool:
        """Whether the pen presses on the canvas."""
        return self.pressure > 0.0


def pen_from_tablet(event: QTabletEvent) -> PenState:
    """The pen state of a tablet event (pressure 0 on release)."""
    pos = event.position()
    released = event.type() == QEvent.Type.TabletRelease
    pressure = 0.0 if released else float(event.pressure())
    return PenState(
        float(pos.x()),
        float(pos.y()),
        min(max(pressure, 0.0), 1.0) if math.isfinite(pressure) else 0.0,
        (float(event.xTilt()), float(event.yTilt())),
        float(event.rotation()),
        int(event.buttons().value) & 0xFF,
        "tablet",
    )


def pen_from_mouse(event: QMouseEvent, mouse_pressure: float) -> PenState:
    """The pen state of a mouse event: the left button presses (see the module docstring)."""
    pos = event.position()
    down = bool(event.buttons() & Qt.MouseButton.LeftButton)
    pressure = 0.0
    if down:
        mods = event.modifiers()
        pressure = mouse_pressure
        if mods & Qt.KeyboardModifier.ShiftModifier:
            pressure = 1.0
        elif mods & Qt.KeyboardModifier.AltModifier:
            pressure = 0.25 * mouse_pressure
    return PenState(float(pos.x()), float(pos.y()), pressure, buttons=1 if down else 0)


def sample_from_pen(pen: PenState, view: CanvasView) -> StylusSample | None:
    """The stylus sample (time 0: the worker stamps it) of a pen state seen through ``view``;
    None if unusable."""
    x_m, y_m = view.to_canvas(pen.x_px, pen.y_px)
    tx, ty = (math.radians(a) for a in pen.tilt_deg)
    twist = -math.radians(pen.rotation_deg)
    values = (x_m, y_m, pen.pressure, tx, ty, twist)
    if not all(math.isfinite(v) for v in values):
        return None
    tilt = np.clip(_on_canvas(tx, -ty, view.angle_rad), -MAX_TILT_RAD, MAX_TILT_RAD)
    if view.angle_rad != 0.0:
        twist = math.remainder(twist - view.angle_rad, 2.0 * math.pi)
    pressure = min(max(pen.pressure, 0.0), 1.0)
    return StylusSample(0.0, np.array([x_m, y_m, 0.0]), pressure, tilt, twist, pen.buttons)


def _on_canvas(tx: float, ty: float, angle_rad: float) -> np.ndarray:
    """A tilt (x, y) read in the screen's frame (y up), in the frame of a canvas shown turned by
    ``angle_rad`` counter-clockwise."""
    if angle_rad == 0.0:
        return np.array([tx, ty])
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([c * tx + s * ty, -s * tx + c * ty])
