"""The heads-up display over the canvas: rates, force and torque, and the paint grid outline.

It is a transparent widget laid over the canvas widget (mouse events pass through). It shows:

- the simulation rate (paint steps per second) and the last step's time;
- the servo loop's rate and jitter (99th percentile of |tick interval - 1 ms|), live from its
  clock (the servo process's shared timing ring), or "off" without a haptic device; and where it
  runs with what the OS granted it (priority, core, GC);
- the display frame rate;
- the force and torque on the brush tip, as numbers and as an arrow in a gauge (the in-plane
  force; the felt force is this times the force scale);
- on request (G) the outline of the paint grid riding with the brush, through the canvas view
  (turned with the canvas).

It is off by default (H shows it): the status bar carries what an artist needs while painting
(brush, pigment, zoom and turn).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from PySide6.QtCore import QPointF, QRect, QRectF, Qt
from PySide6.QtGui import QColor, QFont, QFontMetrics, QImage, QPainter, QPen, QPolygonF
from PySide6.QtWidgets import QWidget

from paintapp.app.shared import WorkerStatus
from paintapp.render.view_transform import CanvasView

GAUGE_PX = 70
#: Newtons at the gauge's rim (the in-plane fluid force, before the force scale).
GAUGE_FULL_N = 0.02
#: Room, px, the panel's repaint leaves it to grow right and down between two repaints.
PANEL_SLACK_PX = 48
#: The grid outline's colour and dash pattern (px on, px off).
GRID_COLOUR = QColor(80, 220, 255, 220)
GRID_DASH = (4, 2)


@dataclass(frozen=True)
class HudData:
    """Everything the HUD shows besides the worker status."""

    frame_hz: float = 0.0
    servo: tuple[float, float] | None = None
    device: str = "tablet/mouse"
    servo_where: str = ""
    brush: str = ""
    model: str = ""
    force_scale: float = 0.0
    journal: str = ""


def hud_lines(status: WorkerStatus, data: HudData) -> list[str]:
    """The HUD's text lines."""
    f, t = status.force_n, status.torque_nm
    servo = (
        "off"
        if data.servo is None
        else f"{data.servo[0]:6.1f} Hz  jitter p99 {data.servo[1]:.3f} ms"
    )
    lines = [
        f"sim    {status.sim_hz:6.1f} Hz  step {status.step_ms:5.1f} ms",
        f"servo  {servo}",
        *([f"       {data.servo_where}"] if data.servo_where else []),
        f"frame  {data.frame_hz:6.1f} Hz",
        f"force  {float(np.linalg.norm(f)):.4f} N  ({f[0]:+.3f}, {f[1]:+.3f}, {f[2]:+.3f})",
        f"torque {float(np.linalg.norm(t)):.2e} N m   felt x{data.force_scale:g}",
        f"brush  {data.brush}   paint {status.reservoir_m3 * 1e9:.1f} mm3",
        f"fluid  {data.model}",
        f"input  {data.device}",
        f"strokes {status.strokes}  undo {status.undo}  redo {status.redo}",
    ]
    if data.journal:
        lines.append(f"rec    {data.journal}")
    if status.fault:
        lines.append(f"DEVICE FAULT: {status.fault}")
    if status.message:
        lines.append(status.message)
    lines.append("F1 / ?  help")
    return lines


class HudOverlay(QWidget):
    """Draws the HUD (see the module docstring) from ``source()``.

    Args:
        status: returns the newest worker status.
        data: returns the rest of the HUD's figures.
        mapping: returns the canvas view (the canvas-to-widget mapping).
        parent: the canvas widget.
    """

    def __init__(
        self,
        status: Callable[[], WorkerStatus],
        data: Callable[[], HudData],
        mapping: Callable[[], CanvasView],
        parent: QWidget,
    ) -> None:
        super().__init__(parent)
        self.status, self.data, self.mapping = status, data, mapping
        self.show_grid = False
        self.show_text = False
        self.setAttribute(Qt.WidgetAttribute.WA_TransparentForMouseEvents, True)
        self.setAttribute(Qt.WidgetAttribute.WA_NoSystemBackground, True)
        self.setGeometry(parent.rect())
        self._panel = QRect()  # what the last paint covered (empty: nothing yet)
        self._grid = QRect()  # where the grid outline was drawn since the last refresh
        self._font = QFont("monospace")
        self._font.setStyleHint(QFont.StyleHint.Monospace)
        self._font.setPointSize(9)
        self._metrics = QFontMetrics(self._font, self)
        self._image: QImage | None = None  # the panel, drawn once per refresh
        self._dashes: tuple[int, QImage, QImage] | None = None  # the outline's strips

    def paintEvent(self, event) -> None:
        # The canvas beneath repaints its changed rectangles every frame, and Qt repaints this
        # overlay over each: draw only the parts that meet the rectangle repainted.
        area = event.rect()
        status = self.status()
        grid = self._grid_rect(status)
        draw_grid = not grid.isEmpty() and area.intersects(grid)
        draw_text = self.show_text and (self._panel.isEmpty() or area.intersects(self._panel))
        if draw_grid:
            self._grid = self._grid.united(grid)
        if not (draw_grid or draw_text):
            return
        painter = QPainter(self)
        outline = self._outline(status) if draw_grid else None
        if outline is not None:
            self._draw_grid(painter, outline, area)
        elif draw_grid:
            corners = self._corners(status)
            if corners is not None:
                self._draw_turned_grid(painter, corners, area)
        if draw_text:
            if self._image is None:
                self._image, self._panel = self._draw_panel(status)
            painter.drawImage(self._panel.topLeft(), self._image)
            if not area.contains(self._panel):
                self.update(self._panel)  # the panel grew past what was repainted
        painter.end()

    def _draw_panel(self, status: WorkerStatus) -> tuple[QImage, QRect]:
        """The text panel and the force gauge, drawn into an image, and where it goes: the
        canvas beneath repaints every frame and Qt repaints this overlay over each repainted
        rectangle, so the panel is drawn once per :meth:`refresh` and copied in between."""
        lines = hud_lines(status, self.data())
        text = self._text_box(lines)
        gauge = self._gauge_area(text.bottom() + 8)
        panel = text.united(gauge).toAlignedRect().adjusted(-2, -2, 2, 2)
        ratio = self.devicePixelRatioF()
        image = QImage(panel.size() * ratio, QImage.Format.Format_ARGB32_Premultiplied)
        image.setDevicePixelRatio(ratio)
        image.fill(Qt.GlobalColor.transparent)
        painter = QPainter(image)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing)
        painter.translate(-panel.topLeft())
        self._draw_text(painter, lines, text)
        self._draw_gauge(painter, status, gauge)
        painter.end()
        return image, panel

    def refresh(self) -> None:
        """Repaint what the HUD covers: its panel (with room to grow; once more after it was
        turned off) and the grid outline, where it was drawn and where it is now."""
        self._image = None
        if self.show_text and self._panel.isEmpty():
            self.update()
            return
        panel = QRect()
        if not self._panel.isEmpty():
            panel = self._panel.adjusted(0, 0, PANEL_SLACK_PX, PANEL_SLACK_PX)
        if not self.show_text:
            self._panel = QRect()
        grid, self._grid = self._grid.united(self._grid_rect(self.status())), QRect()
        for area in (panel, grid):
            if not area.isEmpty():
                self.update(area)

    def _grid_rect(self, status: WorkerStatus) -> QRect:
        """Where the grid outline is drawn, with a margin (empty when it is not shown; the
        whole widget when the mapping gives no sensible outline)."""
        if not self.show_grid or status.grid_m is None:
            return QRect()
        corners = self._corners(status)
        if corners is None:
            return self.rect()
        return _bounds(corners).adjusted(-3, -3, 3, 3)

    def _corners(self, status: WorkerStatus) -> np.ndarray | None:
        """The grid's corners in widget pixels (4, 2), in order round it (None when it is not
        shown, or off any sensible mapping)."""
        if not self.show_grid or status.grid_m is None:
            return None
        corners = self.mapping().corners_px(status.grid_m)
        if not (np.all(np.isfinite(corners)) and np.abs(corners).max() < 1e7):
            return None
        return corners

    def _outline(self, status: WorkerStatus) -> QRect | None:
        """The grid outline's rectangle on whole pixels while the canvas is upright (or turned
        by a multiple of 90 degrees); None when it is not shown, off any sensible mapping or
        turned otherwise (then drawn as a polygon)."""
        corners = self._corners(status)
        if corners is None or abs(math.sin(2.0 * self.mapping().angle_rad)) > 1e-9:
            return None
        return _bounds(corners)

    def _draw_turned_grid(self, painter: QPainter, corners: np.ndarray, area: QRect) -> None:
        """The grid outline of a turned canvas: a dashed 1-px polygon, clipped to ``area``."""
        pen = QPen(GRID_COLOUR, 1)
        pen.setDashPattern([float(v) for v in GRID_DASH])
        painter.save()
        painter.setClipRect(area)
        painter.setPen(pen)
        painter.setBrush(Qt.BrushStyle.NoBrush)
        painter.drawPolygon(QPolygonF([QPointF(float(x), float(y)) for x, y in corners]))
        painter.restore()

    def _draw_grid(self, painter: QPainter, outline: QRect, area: QRect) -> None:
        """The grid outline where it meets ``area``: a dashed 1-px line along the edges of
        ``outline``, copied from a dashed strip across and one down made once per widget size
        (Qt's dashed stroke redrew the whole outline with every canvas repaint beneath it, and
        the painting holds the interpreter lock the simulation worker waits for)."""
        x, y, w, h = outline.x(), outline.y(), outline.width(), outline.height()
        period = sum(GRID_DASH)
        across, down = self._dash_strips(max(self.width(), self.height()) + period)
        sides = (
            (across, x, y, w + 1),
            (across, x, y + h, w + 1),
            (down, x, y, h + 1),
            (down, x + w, y, h + 1),
        )
        for strip, sx, sy, length in sides:
            flat = strip is across
            side = QRect(sx, sy, length, 1) if flat else QRect(sx, sy, 1, length)
            part = side.intersected(area)
            if part.isEmpty():
                continue
            phase = (part.left() - sx if flat else part.top() - sy) % period
            source = QRect(phase, 0, part.width(), 1) if flat else QRect(0, phase, 1, part.height())
            painter.drawImage(part.topLeft(), strip, source)

    def _dash_strips(self, length: int) -> tuple[QImage, QImage]:
        """A dashed line ``length`` px across and one down, in the outline's colour."""
        if self._dashes is None or self._dashes[0] != length:
            on, off = GRID_DASH
            strips = []
            for shape in ((length, 1), (1, length)):
                image = QImage(*shape, QImage.Format.Format_ARGB32_Premultiplied)
                image.fill(Qt.GlobalColor.transparent)
                painter = QPainter(image)
                for start in range(0, length, on + off):
                    dash = (start, 0, on, 1) if shape[1] == 1 else (0, start, 1, on)
                    painter.fillRect(*dash, GRID_COLOUR)
                painter.end()
                strips.append(image)
            self._dashes = (length, strips[0], strips[1])
        return self._dashes[1], self._dashes[2]

    def _text_box(self, lines: list[str]) -> QRectF:
        """The rectangle the text panel of ``lines`` covers."""
        metrics = self._metrics
        width = max(metrics.horizontalAdvance(line) for line in lines) + 16
        return QRectF(8, 8, width, metrics.height() * len(lines) + 12)

    def _draw_text(self, painter: QPainter, lines: list[str], box: QRectF) -> None:
        painter.setFont(self._font)
        metrics = self._metrics
        height = metrics.height()
        painter.setPen(Qt.PenStyle.NoPen)
        painter.setBrush(QColor(0, 0, 0, 160))
        painter.drawRoundedRect(box, 6, 6)
        painter.setPen(QColor(235, 235, 235))
        for i, line in enumerate(lines):
            painter.drawText(QPointF(16, 14 + metrics.ascent() + i * height), line)

    @staticmethod
    def _gauge_area(top: float) -> QRectF:
        """The rectangle the force gauge below ``top`` covers."""
        rim = GAUGE_PX / 2 + 4
        return QRectF(8 + GAUGE_PX / 2 + 4 - rim, top + GAUGE_PX / 2 + 4 - rim, 2 * rim, 2 * rim)

    def _draw_gauge(self, painter: QPainter, status: WorkerStatus, area: QRectF) -> None:
        """Draw the force gauge in ``area``."""
        centre = area.center()
        painter.setPen(Qt.PenStyle.NoPen)
        painter.setBrush(QColor(0, 0, 0, 160))
        painter.drawEllipse(centre, GAUGE_PX / 2 + 4, GAUGE_PX / 2 + 4)
        painter.setPen(QPen(QColor(160, 160, 160), 1))
        painter.setBrush(Qt.BrushStyle.NoBrush)
        painter.drawEllipse(centre, GAUGE_PX / 2, GAUGE_PX / 2)
        fx, fy = (float(v) for v in status.force_n[:2])
        if not (math.isfinite(fx) and math.isfinite(fy)):
            return
        size = math.hypot(fx, fy)
        if size < 1e-9:
            return
        length = GAUGE_PX / 2 * min(size / GAUGE_FULL_N, 1.0)
        tip = QPointF(centre.x() + length * fx / size, centre.y() - length * fy / size)
        painter.setPen(QPen(QColor(255, 60, 20), 3))
        painter.drawLine(centre, tip)
        painter.setBrush(QColor(255, 60, 20))
        painter.drawEllipse(tip, 3, 3)


def _bounds(corners: np.ndarray) -> QRect:
    """The rectangle on whole pixels bounding widget points ``corners`` (N, 2)."""
    lo, hi = corners.min(axis=0), corners.max(axis=0)
    return QRectF(
        QPointF(float(lo[0]), float(lo[1])), QPointF(float(hi[0]), float(hi[1]))
    ).toAlignedRect()
