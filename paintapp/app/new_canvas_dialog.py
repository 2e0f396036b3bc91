"""The New Canvas dialog: the size (a paper name or W x H mm), the texel and the surface.

The same choices as ``paintapp paint --canvas-size --texel-mm --surface``
(:func:`paintapp.canvas.sizes.canvas_size`, :mod:`paintapp.canvas.surfaces`); the dialog opens on
the current canvas's, shows the texel count as it changes, and refuses a size the canvas cannot
hold (over :data:`paintapp.canvas.model.MAX_PIXELS` texels a side) with the reason.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from PySide6.QtCore import Qt
from PySide6.QtWidgets import (
    QComboBox,
    QDialog,
    QDialogButtonBox,
    QDoubleSpinBox,
    QFormLayout,
    QLabel,
    QWidget,
)

from common.errors import InputError
from paintapp.canvas.model import Canvas
from paintapp.canvas.sizes import PAPER_MM, canvas_size
from paintapp.canvas.surfaces import SURFACES, surface_spec

if TYPE_CHECKING:
    from paintapp.app.haptic_link import HapticLink

#: The sizes the size box offers (it also takes any ``WxH`` in millimetres).
SIZE_CHOICES = tuple(n for p in PAPER_MM for n in (p, f"{p}-landscape"))


@dataclass(frozen=True)
class NewCanvasChoice:
    """What the dialog chose: ``size`` (a paper name or ``WxH`` mm), ``texel_mm``, ``surface``."""

    size: str
    texel_mm: float
    surface: str

    def resolve(self) -> tuple[tuple[int, int], tuple[float, float]]:
        """(pixels, metres) of the canvas; InputError for a size it cannot be."""
        surface_spec(self.surface)
        return canvas_size(self.size, self.texel_mm)

    def describe(self) -> str:
        """``2100 x 2970 texels, 210 x 297 mm, cotton duck`` (or why it cannot be)."""
        try:
            (w, h), (w_m, h_m) = self.resolve()
        except InputError as exc:
            return exc.message
        label = surface_spec(self.surface).label
        return f"{w} x {h} texels, {w_m * 1e3:g} x {h_m * 1e3:g} mm, {label}"


def current_choice(canvas: Canvas) -> NewCanvasChoice:
    """The choice that remakes ``canvas``'s size, texel and surface."""
    w_m, h_m = canvas.size_m
    texel_mm = round(canvas.texel_size_m[0] * 1e3, 4)
    size = f"{w_m * 1e3:g}x{h_m * 1e3:g}"
    for name in SIZE_CHOICES:
        try:
            pixels, metres = canvas_size(name, texel_mm)
        except InputError:
            continue
        if pixels == canvas.pixels and all(
            abs(a - b) <= 1e-6 * b for a, b in zip(metres, canvas.size_m, strict=True)
        ):
            size = name
            break
    return NewCanvasChoice(size, texel_mm, canvas.surface)


class NewCanvasDialog(QDialog):
    """Size, texel and surface of a new canvas; :meth:`choice` after it is accepted."""

    def __init__(self, parent: QWidget | None, initial: NewCanvasChoice) -> None:
        super().__init__(parent)
        self.setWindowTitle("New canvas")
        form = QFormLayout(self)
        self.size_box = QComboBox()
        self.size_box.setEditable(True)
        self.size_box.addItems(list(SIZE_CHOICES))
        self.size_box.setEditText(initial.size)
        self.size_box.setToolTip("a paper size, or width x height in millimetres (300x200)")
        self.texel_box = QDoubleSpinBox()
        self.texel_box.setRange(0.01, 5.0)
        self.texel_box.setDecimals(3)
        self.texel_box.setSingleStep(0.05)
        self.texel_box.setSuffix(" mm")
        self.texel_box.setValue(initial.texel_mm)
        self.surface_box = QComboBox()
        for spec in SURFACES.values():
            self.surface_box.addItem(spec.label, spec.name)
            index = self.surface_box.count() - 1
            self.surface_box.setItemData(index, spec.describe(), Qt.ItemDataRole.ToolTipRole)
        self.surface_box.setCurrentIndex(list(SURFACES).index(initial.surface))
        self.summary = QLabel()
        form.addRow("Size", self.size_box)
        form.addRow("Texel", self.texel_box)
        form.addRow("Surface", self.surface_box)
        form.addRow(self.summary)
        self.buttons = QDialogButtonBox(
            QDialogButtonBox.StandardButton.Ok | QDialogButtonBox.StandardButton.Cancel
        )
        self.buttons.accepted.connect(self.accept)
        self.buttons.rejected.connect(self.reject)
        form.addRow(self.buttons)
        self.size_box.editTextChanged.connect(self._refresh)
        self.texel_box.valueChanged.connect(self._refresh)
        self.surface_box.currentIndexChanged.connect(self._refresh)
        self._refresh()

    def choice(self) -> NewCanvasChoice:
        """The choice as the dialog shows it now."""
        surface = str(self.surface_box.currentData())
        return NewCanvasChoice(self.size_box.currentText(), self.texel_box.value(), surface)

    def _refresh(self, *_: Any) -> None:
        choice = self.choice()
        try:
            choice.resolve()
            ok = True
        except InputError:
            ok = False
        self.summary.setText(choice.describe())
        self.buttons.button(QDialogButtonBox.StandardButton.Ok).setEnabled(ok)


def ask_new_canvas(window: Any) -> bool:
    """File > New in the painting window: ask for the size and surface (a window that is not
    interactive, as in tests, starts a blank canvas like the current one), then start it. True
    when a new canvas was started."""
    if not getattr(window, "interactive", False):
        window.document.new()
        return True
    dialog = NewCanvasDialog(window, current_choice(window.shared.canvas))
    if dialog.exec() != QDialog.DialogCode.Accepted:
        return False
    choice = dialog.choice()
    try:
        pixels, size_m = choice.resolve()
    except InputError as exc:
        window.document.dialogs.warn("Cannot make the canvas", exc)
        return False
    window.document.new(pixels, size_m, choice.surface)
    return True


def follow_surface(link: HapticLink | None) -> Callable[[str], None]:
    """A :class:`~paintapp.app.document.Document`'s ``on_surface``: the haptic link's canvas
    contact follows the surface of each new or opened canvas."""

    def follow(surface: str) -> None:
        if link is not None:
            link.set_surface(surface)

    return follow
