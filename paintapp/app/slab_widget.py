"""The mixing slab on screen: its unlit Kubelka-Munk colour drawn with QPainter (computed on the
CPU, no second OpenGL context), and left-button dabs and drags that mix with the brush.

The widget only shows copies of the slab the simulation worker publishes
(:meth:`SlabWidget.show_canvas`) and reports where the brush touched it through ``on_dab(x_m,
y_m)``; a drag dabs again each time the pointer has moved ``DAB_STEP_M`` on the slab.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from PySide6.QtCore import QRectF, QSize, Qt
from PySide6.QtGui import QColor, QImage, QMouseEvent, QPainter, QPen
from PySide6.QtWidgets import QSizePolicy, QWidget

from paintapp.app.slab import SLAB_PIXELS, SLAB_SIZE_M
from paintapp.canvas.exr import unlit_rgba
from paintapp.canvas.model import Canvas
from paintapp.pigments.library import PigmentLibrary
from paintapp.pigments.spectra import srgb_encode

#: Pointer travel on the slab between two dabs of a drag, m.
DAB_STEP_M = 0.0015
#: Side of the widget, px.
SIDE_PX = 180


def slab_image(canvas: Canvas, library: PigmentLibrary) -> np.ndarray:
    """(H, W, 3) uint8 sRGB of the slab's unlit colour, rows top first."""
    rgb = unlit_rgba(canvas, library)[::-1, :, :3]
    encoded = np.clip(srgb_encode(rgb), 0.0, 1.0)
    return np.ascontiguousarray(np.round(255 * encoded).astype(np.uint8))


class SlabWidget(QWidget):
    """See the module docstring."""

    def __init__(
        self,
        library: PigmentLibrary,
        on_dab: Callable[[float, float], None],
        parent: QWidget | None = None,
    ) -> None:
        super().__init__(parent)
        self.library = library
        self.on_dab = on_dab
        self.pixels: np.ndarray | None = None
        self._image: QImage | None = None
        self._last_dab: tuple[float, float] | None = None
        self.show_canvas(Canvas(SLAB_PIXELS, SLAB_SIZE_M))
        self.setSizePolicy(QSizePolicy.Policy.Fixed, QSizePolicy.Policy.Fixed)
        self.setFixedSize(SIDE_PX, SIDE_PX)
        self.setCursor(Qt.CursorShape.CrossCursor)
        self.setToolTip("Mixing slab: drag the brush here to mix and pick up paint")

    def sizeHint(self) -> QSize:
        return QSize(SIDE_PX, SIDE_PX)

    def show_canvas(self, canvas: Canvas) -> None:
        """Show a copy of the slab."""
        self.pixels = slab_image(canvas, self.library)
        h, w = self.pixels.shape[:2]
        self._image = QImage(self.pixels.data, w, h, 3 * w, QImage.Format.Format_RGB888)
        self.update()

    def to_slab(self, x_px: float, y_px: float) -> tuple[float, float]:
        """Widget pixels to slab metres (origin bottom-left, y up)."""
        x = min(max(x_px / max(self.width(), 1), 0.0), 1.0) * SLAB_SIZE_M[0]
        y = (1.0 - min(max(y_px / max(self.height(), 1), 0.0), 1.0)) * SLAB_SIZE_M[1]
        return x, y

    def to_widget(self, x_m: float, y_m: float) -> tuple[float, float]:
        """Slab metres to widget pixels."""
        return x_m / SLAB_SIZE_M[0] * self.width(), (1.0 - y_m / SLAB_SIZE_M[1]) * self.height()

    # --- events ---------------------------------------------------------------------------------
    def paintEvent(self, _event) -> None:
        painter = QPainter(self)
        painter.setRenderHint(QPainter.RenderHint.SmoothPixmapTransform, True)
        if self._image is not None:
            painter.drawImage(QRectF(self.rect()), self._image)
        painter.setPen(QPen(QColor(90, 90, 90), 1))
        painter.setBrush(Qt.BrushStyle.NoBrush)
        painter.drawRect(self.rect().adjusted(0, 0, -1, -1))
        painter.end()

    def mousePressEvent(self, event: QMouseEvent) -> None:
        if event.button() == Qt.MouseButton.LeftButton:
            self._last_dab = None
            self._dab(event)

    def mouseMoveEvent(self, event: QMouseEvent) -> None:
        if event.buttons() & Qt.MouseButton.LeftButton:
            self._dab(event)

    def mouseReleaseEvent(self, event: QMouseEvent) -> None:
        self._last_dab = None

    def _dab(self, event: QMouseEvent) -> None:
        pos = event.position()
        x, y = self.to_slab(pos.x(), pos.y())
        last = self._last_dab
        if last is not None and math.hypot(x - last[0], y - last[1]) < DAB_STEP_M:
            return
        self._last_dab = (x, y)
        self.on_dab(x, y)
