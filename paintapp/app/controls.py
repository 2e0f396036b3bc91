"""The controls panel: palette, brush, paint, force, fluid model and light.

The panel does not act itself; it calls the window's handlers:

- ``on_pigment(name)``: a palette swatch was clicked (dip the brush);
- ``on_slab_put(name)``: a swatch was Shift+clicked, or clicked with "put on slab" down (put a
  blob of the pigment on the mixing slab);
- ``on_slab_dab(x_m, y_m)``, ``on_slab_mix()``, ``on_slab_clear()``: the mixing slab (dab the
  brush on it, knife it all together and load the brush, scrape it clean);
- ``on_clean()``: the clean-brush button;
- ``on_settings(settings)``: brush preset or size, load, viscosity, fluid model, force scale;
- ``on_view(lighting, mouse_pressure)``: light direction, relief, mouse pressure.

:meth:`ControlsPanel.show_settings` puts values changed elsewhere (shortcuts) back on the
controls without re-triggering the handlers.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
from PySide6.QtCore import Qt
from PySide6.QtGui import QMouseEvent
from PySide6.QtWidgets import (
    QComboBox,
    QFormLayout,
    QGridLayout,
    QGroupBox,
    QLabel,
    QPushButton,
    QSlider,
    QVBoxLayout,
    QWidget,
)

from paintapp.app.settings import MODEL_LABELS, PaintSettings, brush_names
from paintapp.app.slab_widget import SlabWidget
from paintapp.pigments.library import PigmentLibrary
from paintapp.pigments.spectra import srgb_encode
from paintapp.render import Lighting


def swatch_colour(library: PigmentLibrary, name: str) -> str:
    """The pigment's masstone as ``#rrggbb``."""
    rgb = np.clip(srgb_encode(library[name].masstone_linear_rgb()), 0.0, 1.0)
    r, g, b = (round(255 * float(v)) for v in rgb)
    return f"#{r:02x}{g:02x}{b:02x}"


def text_colour(background: str) -> str:
    """Black or white, whichever reads better on ``#rrggbb``."""
    r, g, b = (int(background[i : i + 2], 16) for i in (1, 3, 5))
    return "black" if 0.299 * r + 0.587 * g + 0.114 * b > 150 else "white"


def _slider(lo: int, hi: int, value: int) -> QSlider:
    slider = QSlider(Qt.Orientation.Horizontal)
    slider.setRange(lo, hi)
    slider.setValue(value)
    return slider


def viscosity_to_slider(v: float) -> int:
    """0.1..1000 Pa s on a log scale to 0..400."""
    return round(100 * (math.log10(v) + 1))


def slider_to_viscosity(s: int) -> float:
    """Inverse of :func:`viscosity_to_slider`."""
    return float(10 ** (s / 100 - 1))


class SwatchButton(QPushButton):
    """A palette swatch that remembers the keyboard modifiers of its last click."""

    def __init__(self, text: str) -> None:
        super().__init__(text)
        self.modifiers = Qt.KeyboardModifier.NoModifier

    def mousePressEvent(self, event: QMouseEvent) -> None:
        self.modifiers = event.modifiers()
        super().mousePressEvent(event)

    def mouseReleaseEvent(self, event: QMouseEvent) -> None:
        self.modifiers |= event.modifiers()
        super().mouseReleaseEvent(event)

    def take_modifiers(self) -> Qt.KeyboardModifier:
        """The modifiers of the click just made (cleared for the next one)."""
        mods, self.modifiers = self.modifiers, Qt.KeyboardModifier.NoModifier
        return mods


class ControlsPanel(QWidget):
    """See the module docstring."""

    def __init__(
        self,
        library: PigmentLibrary,
        pigments: tuple[str, ...],
        settings: PaintSettings,
        scene_viscosity: float,
        handlers: dict[str, Callable],
        parent: QWidget | None = None,
    ) -> None:
        super().__init__(parent)
        self.settings = settings
        self.handlers = handlers
        self.lighting = Lighting()
        self.mouse_pressure = 0.6
        layout = QVBoxLayout(self)
        layout.addWidget(self._palette(library, pigments))
        layout.addWidget(self._slab_box(library))
        layout.addWidget(self._brush_box())
        layout.addWidget(self._paint_box(scene_viscosity))
        layout.addWidget(self._view_box())
        layout.addStretch(1)
        self.setMinimumWidth(230)

    # --- building -------------------------------------------------------------------------------
    def _palette(self, library: PigmentLibrary, pigments: tuple[str, ...]) -> QGroupBox:
        box = QGroupBox("Palette (click: load, Shift+click: to slab)")
        grid = QGridLayout(box)
        self.swatches: dict[str, SwatchButton] = {}
        for i, name in enumerate(pigments):
            label = library[name].label or name.replace("_", " ")
            key = f"{(i + 1) % 10}  " if i < 10 else ""
            button = SwatchButton(f"{key}{label}")
            shortcut = f" (key {(i + 1) % 10})" if i < 10 else ""
            button.setToolTip(
                f"{label}{shortcut}: click to load the brush, Shift+click to put it "
                "on the mixing slab"
            )
            colour = swatch_colour(library, name)
            text = text_colour(colour)
            button.setStyleSheet(
                f"background:{colour}; color:{text}; min-height:26px; text-align:left; "
                "padding-left:6px"
            )
            button.clicked.connect(lambda _=False, n=name: self._swatch_clicked(n))
            grid.addWidget(button, i // 2, i % 2)
            self.swatches[name] = button
        clean = QPushButton("Clean brush (C)")
        clean.clicked.connect(lambda: self.handlers["clean"]())
        grid.addWidget(clean, (len(pigments) + 1) // 2, 0, 1, 2)
        return box

    def _slab_box(self, library: PigmentLibrary) -> QGroupBox:
        box = QGroupBox("Mixing slab (drag to mix and pick up)")
        grid = QGridLayout(box)
        self.slab = SlabWidget(library, lambda x, y: self.handlers["slab_dab"](x, y))
        grid.addWidget(self.slab, 0, 0, 1, 2, Qt.AlignmentFlag.AlignHCenter)
        self.put_on_slab = QPushButton("Put on slab")
        self.put_on_slab.setCheckable(True)
        self.put_on_slab.setToolTip("While down, palette clicks put paint on the slab")
        mix = QPushButton("Mix && load (X)")
        mix.setToolTip("Knife all the paint on the slab together and load the brush from it")
        mix.clicked.connect(lambda: self.handlers["slab_mix"]())
        clear = QPushButton("Clear slab (Shift+X)")
        clear.clicked.connect(lambda: self.handlers["slab_clear"]())
        grid.addWidget(self.put_on_slab, 1, 0)
        grid.addWidget(mix, 1, 1)
        grid.addWidget(clear, 2, 0, 1, 2)
        return box

    def _brush_box(self) -> QGroupBox:
        box = QGroupBox("Brush")
        form = QFormLayout(box)
        self.brush = QComboBox()
        self.brush.addItems(brush_names())
        self.brush.setCurrentText(self.settings.brush)
        self.brush.currentTextChanged.connect(lambda t: self._change(brush=t))
        self.brush_size = _slider(50, 200, round(100 * self.settings.brush_scale))
        self.brush_size.valueChanged.connect(lambda v: self._change(brush_scale=v / 100))
        self.load = _slider(5, 100, round(100 * self.settings.load_fraction))
        self.load.valueChanged.connect(lambda v: self._change(load_fraction=v / 100))
        self.pressure = _slider(5, 100, round(100 * self.mouse_pressure))
        self.pressure.valueChanged.connect(self._view_changed)
        form.addRow("preset", self.brush)
        form.addRow("size", self.brush_size)
        form.addRow("paint load", self.load)
        form.addRow("mouse pressure", self.pressure)
        return box

    def _paint_box(self, scene_viscosity: float) -> QGroupBox:
        box = QGroupBox("Paint and force")
        form = QFormLayout(box)
        self.model = QComboBox()
        for key, label in MODEL_LABELS.items():
            self.model.addItem(label, key)
        self.model.setCurrentIndex(list(MODEL_LABELS).index(self.settings.fluid_model))
        self.model.currentIndexChanged.connect(
            lambda i: self._change(fluid_model=self.model.itemData(i))
        )
        viscosity = self.settings.viscosity_pa_s or scene_viscosity
        self.viscosity = _slider(0, 400, viscosity_to_slider(viscosity))
        self.viscosity_label = QLabel(f"{viscosity:.3g} Pa s")
        self.viscosity.valueChanged.connect(self._viscosity_changed)
        self.force = _slider(0, 100, round(10 * self.settings.force_scale))
        self.force_label = QLabel(f"x{self.settings.force_scale:g}")
        self.force.valueChanged.connect(self._force_changed)
        form.addRow("fluid model", self.model)
        form.addRow("viscosity", self.viscosity)
        form.addRow("", self.viscosity_label)
        form.addRow("force scale", self.force)
        form.addRow("", self.force_label)
        return box

    def _view_box(self) -> QGroupBox:
        box = QGroupBox("Light (impasto)")
        form = QFormLayout(box)
        self.azimuth = _slider(0, 359, round(self.lighting.azimuth_deg))
        self.elevation = _slider(5, 90, round(self.lighting.elevation_deg))
        self.relief = _slider(0, 50, round(10 * self.lighting.relief))
        for slider in (self.azimuth, self.elevation, self.relief):
            slider.valueChanged.connect(self._view_changed)
        form.addRow("direction", self.azimuth)
        form.addRow("elevation", self.elevation)
        form.addRow("relief", self.relief)
        return box

    # --- events ---------------------------------------------------------------------------------
    def _swatch_clicked(self, name: str) -> None:
        shift = bool(self.swatches[name].take_modifiers() & Qt.KeyboardModifier.ShiftModifier)
        if shift or self.put_on_slab.isChecked():
            self.handlers["slab_put"](name)
        else:
            self.handlers["pigment"](name)

    def _change(self, **changes: Any) -> None:
        self.settings = replace(self.settings, **changes)
        self.handlers["settings"](self.settings)

    def _viscosity_changed(self, value: int) -> None:
        v = min(max(slider_to_viscosity(value), 0.1), 1000.0)
        self.viscosity_label.setText(f"{v:.3g} Pa s")
        self._change(viscosity_pa_s=v)

    def _force_changed(self, value: int) -> None:
        self.force_label.setText(f"x{value / 10:g}")
        self._change(force_scale=value / 10)

    def _view_changed(self, _value: int = 0) -> None:
        self.lighting = replace(
            self.lighting,
            azimuth_deg=float(self.azimuth.value()),
            elevation_deg=float(self.elevation.value()),
            relief=self.relief.value() / 10,
        )
        self.mouse_pressure = self.pressure.value() / 100
        self.handlers["view"](self.lighting, self.mouse_pressure)

    # --- from elsewhere -------------------------------------------------------------------------
    def show_settings(self, settings: PaintSettings, lighting: Lighting) -> None:
        """Show values changed by shortcuts, without calling the handlers."""
        self.settings, self.lighting = settings, lighting
        widgets = (self.brush, self.brush_size, self.load, self.model, self.force, self.azimuth)
        for w in widgets:
            w.blockSignals(True)
        try:
            self.brush.setCurrentText(settings.brush)
            self.brush_size.setValue(round(100 * settings.brush_scale))
            self.load.setValue(round(100 * settings.load_fraction))
            self.model.setCurrentIndex(list(MODEL_LABELS).index(settings.fluid_model))
            self.force.setValue(round(10 * settings.force_scale))
            self.force_label.setText(f"x{settings.force_scale:g}")
            self.azimuth.setValue(round(lighting.azimuth_deg) % 360)
        finally:
            for w in widgets:
                w.blockSignals(False)
