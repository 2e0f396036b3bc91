"""The painting window's view under Xvfb: zoom, pan and turn keep the stroke under the pen.

The pen's events go the real way: QTabletEvents to the canvas widget, through the window's
pen handler and the one view mapping (:class:`paintapp.render.view_transform.CanvasView`), to
the samples the simulation worker receives."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.paintapp.app.conftest import tablet_event

#: The scripted stroke, canvas metres: a gentle S across 24 mm.
STROKE_M = [(0.06 + 0.024 * i / 40, 0.05 + 0.004 * math.sin(i / 6.0)) for i in range(41)]


@pytest.fixture
def samples(window):
    """The stylus samples the window hands the simulation worker, as they arrive."""
    got: list = []
    push = window.worker.push

    def record(sample) -> None:
        got.append(sample)
        push(sample)

    window.worker.push = record
    return got


def _set_view(win, pump, zoom: float, angle_deg: float, centre_m) -> None:
    """Show the canvas at ``zoom`` (device pixels per texel) turned ``angle_deg``, centred on
    ``centre_m``, and let the window draw it."""
    from paintapp.render.view_transform import CanvasView

    widget = win.canvas_widget
    texel = min(win.shared.canvas.texel_size_m)
    ratio = widget.devicePixelRatioF()
    size = (widget.width(), widget.height())
    widget.nav.set_view(CanvasView(centre_m, texel * ratio / zoom, math.radians(angle_deg), size))
    drawn = widget.drawn_count
    assert pump(5.0, lambda: widget.drawn_count > drawn)
    pump(0.1)
    assert widget.nav.zoom_percent() == pytest.approx(100.0 * zoom)


def _send_stroke(win, pump, points_m) -> None:
    """Press, move and lift the pen along ``points_m`` where the window shows them."""
    from PySide6.QtCore import QEvent
    from PySide6.QtWidgets import QApplication

    widget = win.canvas_widget
    view = widget.view()
    pixels = [view.to_widget(*p) for p in points_m]
    T = QEvent.Type
    kinds = [T.TabletPress] + [T.TabletMove] * (len(pixels) - 2) + [T.TabletRelease]
    for kind, (x, y) in zip(kinds, pixels, strict=True):
        pressure = 0.0 if kind == T.TabletRelease else 0.8
        QApplication.sendEvent(widget, tablet_event(widget, kind, x, y, pressure))
        pump(0.01)


def _texels(win, got) -> np.ndarray:
    """The canvas texels (continuous, (N, 2)) of the pressed samples."""
    canvas = win.shared.canvas
    down = [s for s in got if s.pressure > 0]
    xy = np.array([[float(s.position_m[0]), float(s.position_m[1])] for s in down])
    return np.stack(canvas.metres_to_texel(xy[:, 0], xy[:, 1]), axis=1)


def test_a_stroke_at_400_percent_turned_30_degrees_lands_on_the_texels_of_100_percent(
    window, pump, samples
):
    """The request's target: the same scripted tablet stroke, painted at 100 % upright and at
    400 % turned 30 degrees, reaches the canvas on the same texels (within a texel)."""
    win = window
    win.load_pigment("ultramarine_blue")
    _set_view(win, pump, 1.0, 0.0, (0.072, 0.05))
    _send_stroke(win, pump, STROKE_M)
    upright = _texels(win, samples)
    samples.clear()
    _set_view(win, pump, 4.0, 30.0, (0.072, 0.05))
    _send_stroke(win, pump, STROKE_M)
    turned = _texels(win, samples)
    assert len(upright) == len(turned) == len(STROKE_M) - 1
    assert np.abs(turned - upright).max() < 1.0, np.abs(turned - upright).max()
    canvas = win.shared.canvas
    planned = np.stack(canvas.metres_to_texel(*np.array(STROKE_M[:-1]).T), axis=1)
    assert np.abs(turned - planned).max() < 1.0
    assert win.canvas_widget.nav.angle_deg() == pytest.approx(30.0)


@pytest.mark.parametrize(("zoom", "angle_deg"), [(1.0, 0.0), (4.0, 30.0), (0.6, -117.0)])
def test_the_pen_reaches_the_canvas_where_the_window_shows_it(
    window, pump, samples, zoom, angle_deg
):
    """A red square painted on the canvas is found on screen (in the widget's own pixels), the
    pen is put there, and the sample it gives lies on the square (within a texel)."""
    from PySide6.QtCore import QEvent
    from PySide6.QtWidgets import QApplication

    win, widget = window, window.canvas_widget
    with win.shared.lock:
        canvas = win.shared.canvas
        red = canvas.add_pigment("cadmium_red")
        patch = np.zeros((len(canvas.pigment_names), 6, 6), np.float32)
        patch[red] = 5e-4
        canvas.write_region(300, 200, patch, np.zeros((6, 6), np.float32))  # texels 300-305
    _set_view(win, pump, zoom, angle_deg, (0.0731, 0.0517))
    shown = widget.shown_pixels().astype(int)
    is_red = (shown[..., 0] - shown[..., 2] > 60) & (shown[..., 0] > 90)
    ys, xs = np.nonzero(is_red)
    assert len(xs) > 0, "the square is not on screen"
    ratio = widget.devicePixelRatioF()
    x_px, y_px = (xs.mean() + 0.5) / ratio, (ys.mean() + 0.5) / ratio
    QApplication.sendEvent(widget, tablet_event(widget, QEvent.Type.TabletMove, x_px, y_px, 0.0))
    pump(0.05)
    sample = samples[-1]
    tx, ty = canvas.metres_to_texel(float(sample.position_m[0]), float(sample.position_m[1]))
    assert float(tx) == pytest.approx(303.0, abs=1.0)
    assert float(ty) == pytest.approx(203.0, abs=1.0)


def test_wheel_pinch_scroll_drags_and_keys_move_the_view(window, pump, samples):
    from PySide6.QtCore import QEvent, QPoint, QPointF, Qt
    from PySide6.QtGui import (
        QKeyEvent,
        QMouseEvent,
        QNativeGestureEvent,
        QPointingDevice,
        QWheelEvent,
    )
    from PySide6.QtWidgets import QApplication

    win, widget = window, window.canvas_widget
    send = QApplication.sendEvent
    none = Qt.KeyboardModifier.NoModifier
    at = QPointF(200.5, 150.25)
    held = widget.view().to_canvas(at.x(), at.y())
    zoom = widget.nav.zoom_percent()

    # the wheel zooms about the pointer: what is under it stays there
    wheel = QWheelEvent(at, widget.mapToGlobal(at), QPoint(), QPoint(0, 120),
                        Qt.MouseButton.NoButton, none, Qt.ScrollPhase.NoScrollPhase, False)  # fmt: skip
    send(widget, wheel)
    assert widget.nav.zoom_percent() == pytest.approx(1.25 * zoom)
    assert widget.view().to_canvas(at.x(), at.y()) == pytest.approx(held, abs=1e-9)
    # a pinch too
    device = QPointingDevice.primaryPointingDevice()
    pinch = QNativeGestureEvent(Qt.NativeGestureType.ZoomNativeGesture, device, 2, at, at,
                                widget.mapToGlobal(at), 0.5, QPointF())  # fmt: skip
    send(widget, pinch)
    assert widget.nav.zoom_percent() == pytest.approx(1.875 * zoom)
    assert widget.view().to_canvas(at.x(), at.y()) == pytest.approx(held, abs=1e-9)
    # a two-finger scroll (pixel distances, no Ctrl) pans: the canvas follows the fingers
    scroll = QWheelEvent(at, widget.mapToGlobal(at), QPoint(15, -8), QPoint(0, -24),
                         Qt.MouseButton.NoButton, none, Qt.ScrollPhase.ScrollUpdate, False)  # fmt: skip
    send(widget, scroll)
    assert widget.nav.zoom_percent() == pytest.approx(1.875 * zoom)
    assert widget.view().to_canvas(at.x() + 15, at.y() - 8) == pytest.approx(held, abs=1e-9)

    def mouse(kind, pos, button, buttons):
        return QMouseEvent(kind, pos, widget.mapToGlobal(pos), button, buttons, none)

    T, B = QEvent.Type, Qt.MouseButton
    # a middle-button drag pans and paints nothing
    pushed = len(samples)
    before = widget.view().to_canvas(100, 100)
    send(widget, mouse(T.MouseButtonPress, QPointF(100, 100), B.MiddleButton, B.MiddleButton))
    send(widget, mouse(T.MouseMove, QPointF(130, 90), B.NoButton, B.MiddleButton))
    send(widget, mouse(T.MouseButtonRelease, QPointF(140, 80), B.MiddleButton, B.NoButton))
    assert widget.view().to_canvas(140, 80) == pytest.approx(before, abs=1e-9)
    assert len(samples) == pushed, "a pan reached the brush"
    # R + drag turns the canvas about the widget's centre: a quarter turn of the pointer
    cx, cy = 0.5 * widget.width(), 0.5 * widget.height()
    send(widget, QKeyEvent(T.KeyPress, Qt.Key.Key_R, none))
    send(widget, mouse(T.MouseButtonPress, QPointF(cx + 100, cy), B.LeftButton, B.LeftButton))
    send(widget, mouse(T.MouseMove, QPointF(cx, cy - 100), B.NoButton, B.LeftButton))
    send(widget, mouse(T.MouseButtonRelease, QPointF(cx, cy - 100), B.LeftButton, B.NoButton))
    send(widget, QKeyEvent(T.KeyRelease, Qt.Key.Key_R, none))
    assert widget.nav.angle_deg() == pytest.approx(90.0)
    assert len(samples) == pushed
    # Space + drag pans with the pen too
    before = widget.view().to_canvas(300, 200)
    send(widget, QKeyEvent(T.KeyPress, Qt.Key.Key_Space, none))
    send(widget, tablet_event(widget, T.TabletPress, 300, 200, 0.7))
    send(widget, tablet_event(widget, T.TabletMove, 260, 230, 0.7))
    send(widget, tablet_event(widget, T.TabletRelease, 250, 240, 0.0))
    send(widget, QKeyEvent(T.KeyRelease, Qt.Key.Key_Space, none))
    assert widget.view().to_canvas(250, 240) == pytest.approx(before, abs=1e-9)
    assert len(samples) == pushed

    # the keys' actions: 100 %, zoom in and out, upright, fit; the status bar follows
    actions = win.actions_by_name
    actions["actual"].trigger()
    assert widget.nav.zoom_percent() == pytest.approx(100.0)
    win.show_view_status()
    assert "zoom 100 %" in win.view_label.text() and "turn 90" in win.view_label.text()
    actions["zoom_in"].trigger()
    assert widget.nav.zoom_percent() == pytest.approx(125.0)
    actions["zoom_out"].trigger()
    assert widget.nav.zoom_percent() == pytest.approx(100.0)
    for _ in range(40):
        actions["zoom_in"].trigger()
    assert widget.nav.zoom_percent() == pytest.approx(1600.0)
    actions["upright"].trigger()
    assert widget.nav.angle_deg() == pytest.approx(0.0, abs=1e-9)
    actions["turn"].trigger()
    assert widget.nav.angle_deg() == pytest.approx(15.0)
    actions["turn_back"].trigger()
    actions["fit"].trigger()
    from paintapp.render.view_transform import CanvasView

    fitted = CanvasView.fit(win.shared.canvas.size_m, (widget.width(), widget.height()))
    assert widget.view().metres_per_px == pytest.approx(fitted.metres_per_px)
    win.load_pigment("cadmium_red")
    win.show_view_status()
    assert "pigment cadmium_red" in win.view_label.text()


def test_the_hud_is_off_until_its_key(window, pump):
    win = window
    assert not win.hud.show_text
    win.actions_by_name["hud"].trigger()
    assert win.hud.show_text


def test_the_grid_outline_turns_with_the_canvas(qapp):
    """Turned 30 degrees, the paint grid's outline is drawn as the turned rectangle: dashes lie
    along its four edges and its bounds cover its corners."""
    from PySide6.QtGui import QImage, QPainter
    from PySide6.QtWidgets import QWidget

    from paintapp.app.hud import HudData, HudOverlay
    from paintapp.app.shared import WorkerStatus
    from paintapp.render.view_transform import CanvasView

    parent = QWidget()
    parent.resize(300, 200)
    status = WorkerStatus(grid_m=(0.031, 0.042, 0.113, 0.094))
    view = CanvasView((0.07, 0.07), 6e-4, math.radians(30.0), (300, 200))
    hud = HudOverlay(lambda: status, HudData, lambda: view, parent)
    hud.show_grid = True
    assert hud._outline(status) is None  # not an upright rectangle
    corners = hud._corners(status)
    assert corners is not None
    bounds = hud._grid_rect(status)
    for x, y in corners:
        assert bounds.contains(round(x), round(y))
    image = QImage(300, 200, QImage.Format.Format_ARGB32_Premultiplied)
    image.fill(0)
    painter = QPainter(image)
    hud._draw_turned_grid(painter, corners, image.rect())
    painter.end()
    alpha = np.frombuffer(image.constBits(), np.uint8).reshape(200, 300, 4)[..., 3]
    ys, xs = np.nonzero(alpha > 0)
    assert len(xs) > 100
    for a, b in zip(corners, np.roll(corners, -1, axis=0), strict=True):
        mid = 0.5 * (a + b)  # dashes near the middle of each edge
        near = np.hypot(xs - mid[0], ys - mid[1]) < 6
        assert near.any(), f"no outline near the edge's middle {mid}"


def test_a_tablet_s_tilt_and_twist_turn_with_the_canvas():
    """On a canvas turned a quarter turn counter-clockwise, a pen leaning to the screen's right
    leans toward the canvas's -y, and its barrel's zero turns with the canvas."""
    from paintapp.app.input import PenState, sample_from_pen
    from paintapp.render.view_transform import CanvasView

    upright = CanvasView((0.05, 0.05), 1e-4, 0.0, (400, 300))
    turned = CanvasView((0.05, 0.05), 1e-4, 0.5 * math.pi, (400, 300))
    pen = PenState(250.0, 120.0, 0.5, (30.0, 0.0), 0.0, 1, "tablet")
    a, b = sample_from_pen(pen, upright), sample_from_pen(pen, turned)
    assert a is not None and b is not None
    np.testing.assert_allclose(a.tilt_rad, [math.radians(30.0), 0.0], atol=1e-12)
    np.testing.assert_allclose(b.tilt_rad, [0.0, -math.radians(30.0)], atol=1e-12)
    assert b.twist_rad == pytest.approx(-0.5 * math.pi)
    assert (b.position_m[0], b.position_m[1]) == pytest.approx(turned.to_canvas(250.0, 120.0))
