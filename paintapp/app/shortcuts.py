"""Keyboard shortcuts (one table, used for the actions and for the help overlay) and the help
overlay itself (F1 or ?)."""

from __future__ import annotations

from PySide6.QtCore import QPointF, QRectF, Qt
from PySide6.QtGui import QColor, QFont, QPainter
from PySide6.QtWidgets import QWidget

#: (action name, key sequences, description). The window binds every name to a handler.
SHORTCUTS: tuple[tuple[str, tuple[str, ...], str], ...] = (
    ("help", ("F1", "?"), "show or hide this help"),
    ("undo", ("Ctrl+Z",), "undo the last stroke"),
    ("redo", ("Ctrl+Shift+Z", "Ctrl+Y"), "redo"),
    ("new", ("Ctrl+N",), "new canvas: size, texel and surface"),
    ("open", ("Ctrl+O",), "open a canvas (.exr)"),
    ("save", ("Ctrl+S",), "save the canvas (.exr)"),
    ("save_as", ("Ctrl+Shift+S",), "save the canvas as ..."),
    ("export", ("Ctrl+E",), "export a picture (.png or .exr)"),
    ("clean", ("C",), "clean the brush"),
    (
        "pigment",
        ("1", "2", "3", "4", "5", "6", "7", "8", "9", "0"),
        "dip the brush in pigment 1-10",
    ),
    ("slab_mix", ("X",), "mix the paint on the slab and load the brush from it"),
    ("slab_clear", ("Shift+X",), "clear the mixing slab"),
    ("next_brush", ("B",), "next brush preset"),
    ("prev_brush", ("Shift+B",), "previous brush preset"),
    ("smaller", ("[",), "smaller brush"),
    ("larger", ("]",), "larger brush"),
    ("weaker", (",",), "lower the force scale"),
    ("stronger", (".",), "raise the force scale"),
    ("zoom_in", ("+", "=", "Ctrl+="), "zoom in (about the pointer), up to 1600 %"),
    ("zoom_out", ("-", "Ctrl+-"), "zoom out (about the pointer), down to 5 %"),
    ("fit", ("F", "Ctrl+0"), "fit the canvas to the window"),
    ("actual", ("Ctrl+1",), "100 %: one canvas texel per screen pixel"),
    ("turn", ("Ctrl+R",), "turn the canvas 15 degrees counter-clockwise"),
    ("turn_back", ("Ctrl+Shift+R",), "turn the canvas 15 degrees clockwise"),
    ("upright", ("Shift+R",), "turn the canvas upright again"),
    ("model", ("M",), "next fluid model (3D grid, 2D depth-averaged, none)"),
    ("grid", ("G",), "show the paint grid around the brush"),
    ("hud", ("H",), "show or hide the HUD"),
    ("light", ("L",), "turn the light 15 degrees"),
    ("light_back", ("Shift+L",), "turn the light back 15 degrees"),
    ("controls", ("Tab",), "show or hide the controls"),
    ("quit", ("Ctrl+Q",), "quit"),
)

MOUSE_HELP = (
    ("left drag", "paint (mouse pressure from the controls)"),
    ("wheel / Ctrl + wheel", "zoom about the pointer"),
    ("pinch", "zoom (touchpad); a two-finger twist turns the canvas"),
    ("two-finger scroll", "pan (touchpad)"),
    ("Space + drag", "pan (mouse or pen)"),
    ("middle drag", "pan"),
    ("R + drag", "turn the canvas (also Shift + Space + drag)"),
    ("Shift + drag", "paint at full pressure"),
    ("Alt + drag", "paint lightly"),
    ("pen tablet", "pressure, tilt and twist shape the brush"),
    ("Shift + swatch", "put the pigment on the mixing slab"),
    ("drag on the slab", "mix there and pick up the mixture"),
)


def help_rows() -> list[tuple[str, str]]:
    """(keys, what) rows of the help overlay."""
    rows = [
        (f"{keys[0]} .. {keys[-1]}" if name == "pigment" else " / ".join(keys), text)
        for name, keys, text in SHORTCUTS
    ]
    return rows + list(MOUSE_HELP)


class HelpOverlay(QWidget):
    """A panel listing the shortcuts, drawn over the canvas while shown."""

    def __init__(self, parent: QWidget) -> None:
        super().__init__(parent)
        self.setAttribute(Qt.WidgetAttribute.WA_TransparentForMouseEvents, True)
        self.setGeometry(parent.rect())
        self.hide()

    def paintEvent(self, _event) -> None:
        rows = help_rows()
        painter = QPainter(self)
        font = QFont("monospace")
        font.setStyleHint(QFont.StyleHint.Monospace)
        font.setPointSize(10)
        painter.setFont(font)
        metrics = painter.fontMetrics()
        line = metrics.height() + 2
        key_w = max(metrics.horizontalAdvance(k) for k, _ in rows) + 24
        text_w = max(metrics.horizontalAdvance(t) for _, t in rows)
        width, height = key_w + text_w + 40, line * (len(rows) + 2) + 20
        box = QRectF((self.width() - width) / 2, (self.height() - height) / 2, width, height)
        painter.setPen(Qt.PenStyle.NoPen)
        painter.setBrush(QColor(10, 10, 14, 225))
        painter.drawRoundedRect(box, 10, 10)
        painter.setPen(QColor(255, 255, 255))
        x0, y = box.left() + 20, box.top() + 14 + metrics.ascent()
        painter.drawText(QPointF(x0, y), "Keyboard shortcuts")
        y += 2 * line
        for keys, text in rows:
            painter.setPen(QColor(255, 210, 120))
            painter.drawText(QPointF(x0, y), keys)
            painter.setPen(QColor(230, 230, 230))
            painter.drawText(QPointF(x0 + key_w, y), text)
            y += line
        painter.end()
