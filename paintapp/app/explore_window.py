"""The exploration window: a slice of a stored flow, the probe in it and the force it feels.

The slice is a colour map of speed or pressure (S toggles) with velocity arrows; in 3D it is the
plane through the probe's centre normal to z (the mouse wheel moves the probe in z). An
unstructured mesh is shown resampled onto a uniform grid once, when the window opens (grey
outside the mesh); its force is taken on local grids resampled around the probe on a worker
thread, never in the window's tick. The probe
follows the mouse, or the haptic device when one is used (the device's workspace is mapped onto
the data set's extent). Frames of a time series play in real time and loop (space pauses). The
force is evaluated about 60 times a second and published to the servo loop, which filters it to
1 kHz as in painting; the HUD shows it with an arrow.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import numpy as np
from PySide6.QtCore import QPointF, QRectF, Qt, QTimer
from PySide6.QtGui import (
    QCloseEvent,
    QColor,
    QImage,
    QKeyEvent,
    QMouseEvent,
    QPainter,
    QPen,
    QWheelEvent,
)
from PySide6.QtWidgets import QWidget

from paintapp.explore.exploration import Exploration, Workspace
from paintapp.explore.local_resample import display_grid
from paintapp.explore.unstructured import UnstructuredFlow
from solver import Ball, FieldForce, frame_pair

#: Device workspace edge the data set's extent is mapped onto, m.
DEVICE_SPAN_M = 0.2
FRAME_MS = 16


class ExploreWindow(QWidget):
    """A window on ``exploration``; ``publish(t, force, torque)`` sends the felt force on (to the
    servo loop), ``device_position()`` gives the device's position (None: follow the mouse)."""

    def __init__(
        self,
        exploration: Exploration,
        publish: Callable[[float, np.ndarray, np.ndarray], None] | None = None,
        device_position: Callable[[], np.ndarray | None] | None = None,
        aim_device: Callable[[np.ndarray], None] | None = None,
    ) -> None:
        super().__init__()
        self.exploration = exploration
        flow = exploration.flow
        self.flow = display_grid(flow) if isinstance(flow, UnstructuredFlow) else flow
        exploration.use_background_resampling()
        self.publish = publish
        self.device_position = device_position
        self.aim_device = aim_device
        lo, hi = self.flow.extent_m
        self.lo, self.hi = lo, hi
        centre = 0.5 * (lo + hi)
        self.workspace = Workspace(centre, float((hi - lo)[:2].max()) / DEVICE_SPAN_M)
        self.probe_m = centre.copy()
        self.angle = 0.0
        self.show_pressure = False
        self.playing = True
        self.t_s = float(self.flow.times_s[0])
        self._clock = time.perf_counter()
        self.last: FieldForce | None = None
        self.felt_n = np.zeros(3)
        self.evaluations = 0
        self._image: QImage | None = None
        self._image_key: tuple | None = None
        self.setWindowTitle("paintapp explore")
        self.setMouseTracking(True)
        self.setFocusPolicy(Qt.FocusPolicy.StrongFocus)
        self.resize(960, max(240, int(960 * (hi[1] - lo[1]) / max(hi[0] - lo[0], 1e-12)) + 80))
        self.timer = QTimer(self)
        self.timer.timeout.connect(self.tick)
        self.timer.start(FRAME_MS)

    # --- geometry -----------------------------------------------------------------------------
    def _view(self) -> QRectF:
        w, h = self.width(), self.height() - 60
        span = self.hi[:2] - self.lo[:2]
        scale = min(w / span[0], h / span[1])
        return QRectF(
            (w - span[0] * scale) / 2,
            60 + (h - span[1] * scale) / 2,
            span[0] * scale,
            span[1] * scale,
        )

    def to_screen(self, p: np.ndarray) -> QPointF:
        v = self._view()
        s = (p[:2] - self.lo[:2]) / (self.hi[:2] - self.lo[:2])
        return QPointF(v.left() + s[0] * v.width(), v.bottom() - s[1] * v.height())

    def to_data(self, x: float, y: float) -> np.ndarray:
        v = self._view()
        s = np.array([(x - v.left()) / v.width(), (v.bottom() - y) / v.height()])
        out = self.probe_m.copy()
        out[:2] = self.lo[:2] + np.clip(s, 0.0, 1.0) * (self.hi[:2] - self.lo[:2])
        return out

    # --- the loop -----------------------------------------------------------------------------
    def tick(self) -> None:
        """Advance time, move the probe, evaluate and publish the force, repaint."""
        now = time.perf_counter()
        if self.playing and len(self.flow.times_s) > 1:
            t0, t1 = float(self.flow.times_s[0]), float(self.flow.times_s[-1])
            span = self.flow.period_s or max(t1 - t0, 1e-9)
            self.t_s = t0 + ((self.t_s - t0) + (now - self._clock)) % span
        self._clock = now
        if self.device_position is not None:
            pos = self.device_position()
            if pos is not None and np.all(np.isfinite(pos)):
                dim = self.flow.dim
                self.probe_m = self.workspace.offset_m + self.workspace.scale * pos[:dim]
        self.evaluate()
        self.update()

    def evaluate(self) -> FieldForce:
        orientation = self.angle if self.flow.dim == 2 else np.array([1.0, 0.0, 0.0, 0.0])
        result = self.exploration.force_at(self.t_s, self.probe_m, orientation)
        force, torque = self.exploration.felt(result)
        self.last, self.evaluations = result, self.evaluations + 1
        if np.all(np.isfinite(force)) and np.all(np.isfinite(torque)):
            self.felt_n = force
            if self.publish is not None:
                self.publish(self.t_s, force, torque)
        return result

    # --- input --------------------------------------------------------------------------------
    def mouseMoveEvent(self, event: QMouseEvent) -> None:
        target = self.to_data(event.position().x(), event.position().y())
        if self.device_position is None:
            self.probe_m = target
        elif self.aim_device is not None:
            self.aim_device((target - self.workspace.offset_m) / self.workspace.scale)

    def wheelEvent(self, event: QWheelEvent) -> None:
        step = event.angleDelta().y() / 120.0
        if self.flow.dim == 3:
            dz = step * float(self.flow.spacing_m[2])
            self.probe_m[2] = float(np.clip(self.probe_m[2] + dz, self.lo[2], self.hi[2]))
        else:
            self.angle += step * math.radians(5.0)

    def keyPressEvent(self, event: QKeyEvent) -> None:
        if event.key() == Qt.Key.Key_S:
            self.show_pressure = not self.show_pressure
        elif event.key() == Qt.Key.Key_Space:
            self.playing = not self.playing
        elif event.key() in (Qt.Key.Key_Q, Qt.Key.Key_Escape):
            self.close()
        else:
            super().keyPressEvent(event)

    def closeEvent(self, event: QCloseEvent) -> None:
        """Stop evaluating (and publishing) once the window closes."""
        self.timer.stop()
        self.exploration.close()
        super().closeEvent(event)

    # --- drawing ------------------------------------------------------------------------------
    def slice_index(self) -> int | None:
        """The z node of the slice through the probe (3D), or None (2D)."""
        if self.flow.dim == 2:
            return None
        k = round(float(self.probe_m[2] - self.lo[2]) / float(self.flow.spacing_m[2]))
        return min(max(k, 0), self.flow.nodes[2] - 1)

    def slice_rgb(self) -> np.ndarray:
        """(ny, nx, 3) uint8 colour map of the slice (rows top to bottom)."""
        from matplotlib import colormaps

        i0, i1, a = frame_pair(self.flow.times_s, self.t_s, self.flow.period_s)
        k = self.slice_index()

        def field(i: int) -> np.ndarray:
            if self.show_pressure:
                q = self.flow.pressure_pa[i]
            else:
                q = np.linalg.norm(self.flow.velocity_m_s[i], axis=0)
            return q if k is None else q[:, :, k]

        q = (1 - a) * field(i0) + a * field(i1) if a > 0 else field(i0)
        if self.flow.fluid is not None:
            mask = self.flow.fluid if k is None else self.flow.fluid[:, :, k]
            q = np.where(mask, q, np.nan)
        finite = q[np.isfinite(q)]
        lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
        s = np.clip((q - lo) / max(hi - lo, 1e-12), 0.0, 1.0)
        rgba = colormaps["coolwarm" if self.show_pressure else "viridis"](np.nan_to_num(s))
        rgba[~np.isfinite(q)] = (0.25, 0.25, 0.25, 1.0)
        return np.ascontiguousarray((255 * rgba[..., :3]).astype(np.uint8).transpose(1, 0, 2)[::-1])

    def paintEvent(self, _event: object) -> None:
        painter = QPainter(self)
        painter.fillRect(self.rect(), QColor(24, 24, 28))
        key = (round(self.t_s, 3), self.show_pressure, round(float(self.probe_m[-1]), 6))
        if key != self._image_key or self._image is None:
            rgb = self.slice_rgb()
            self._rgb = rgb  # keep the buffer alive while the image uses it
            h, w, _ = rgb.shape
            self._image = QImage(rgb.data, w, h, 3 * w, QImage.Format.Format_RGB888)
            self._image_key = key
        painter.drawImage(self._view(), self._image)
        self._draw_arrows(painter)
        self._draw_probe(painter)
        self._draw_hud(painter)
        painter.end()

    def _draw_arrows(self, painter: QPainter) -> None:
        step = max(1, max(self.flow.nodes[:2]) // 24)
        i0, _, _ = frame_pair(self.flow.times_s, self.t_s, self.flow.period_s)
        u = self.flow.velocity_m_s[i0]
        k = self.slice_index()
        if k is not None:
            u = u[:2, :, :, k]
        speed = float(np.nanmax(np.linalg.norm(u, axis=0))) or 1.0
        painter.setPen(QPen(QColor(255, 255, 255, 150), 1))
        length = 0.8 * step * self._view().width() / self.flow.nodes[0]
        for i in range(0, self.flow.nodes[0], step):
            for j in range(0, self.flow.nodes[1], step):
                vx, vy = float(u[0, i, j]), float(u[1, i, j])
                if not (math.isfinite(vx) and math.isfinite(vy)):
                    continue
                p = self.to_screen(
                    self.lo + self.flow.spacing_m * np.array([i, j, 0][: self.flow.dim])
                )
                painter.drawLine(p, p + QPointF(vx, -vy) * (length / speed))

    def _draw_probe(self, painter: QPainter) -> None:
        painter.setPen(QPen(QColor(255, 220, 80), 2))
        shape = self.exploration.shape
        v = self._view()
        px_per_m = v.width() / float(self.hi[0] - self.lo[0])
        c = self.to_screen(self.probe_m)
        if isinstance(shape, Ball):
            r = shape.radius_m * px_per_m
            painter.drawEllipse(c, r, r)
        else:
            sx, sy = (0.5 * s * px_per_m for s in shape.size_m[:2])
            painter.save()
            painter.translate(c)
            painter.rotate(-math.degrees(self.angle))
            painter.drawRect(QRectF(-sx, -sy, 2 * sx, 2 * sy))
            painter.restore()
        f = self.felt_n[:2]
        norm = float(np.linalg.norm(f))
        if norm > 0:
            painter.setPen(QPen(QColor(255, 90, 60), 3))
            painter.drawLine(c, c + QPointF(f[0], -f[1]) * (60.0 / norm))

    def _draw_hud(self, painter: QPainter) -> None:
        painter.setPen(QColor(230, 230, 230))
        r = self.last
        unit = "N" if self.flow.dim == 3 else f"N (x {self.exploration.depth_m:g} m depth)"
        force = ", ".join(f"{v:+.4g}" for v in self.felt_n)
        lines = [
            f"t {self.t_s:.3f} s   probe {np.round(self.probe_m, 4).tolist()} m   "
            f"{'pressure (Pa)' if self.show_pressure else 'speed (m/s)'}   S: toggle  space: pause",
            f"force [{force}] {unit}"
            + (
                f"   {100 * r.outside_fraction:.0f} % outside the data"
                if r and r.outside_fraction
                else ""
            ),
        ]
        for n, text in enumerate(lines):
            painter.drawText(10, 20 + 18 * n, text)
