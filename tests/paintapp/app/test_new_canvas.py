"""New canvas: the dialog's size, texel and surface; the document makes that canvas."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from common.errors import InputError
from paintapp.app.document import Document
from paintapp.app.history import copy_canvas
from paintapp.app.options import PaintOptions, blank_canvas
from paintapp.app.settings import PaintSettings
from paintapp.app.shared import SharedCanvas
from paintapp.canvas.model import Canvas
from paintapp.pigments.library import load_pigment_library


class Dialogs:
    def __init__(self) -> None:
        self.warnings: list[str] = []

    def ask_open(self, title: str, filter_text: str) -> str | None:
        return None

    def ask_save(self, title: str, filter_text: str) -> str | None:
        return None

    def warn(self, title: str, exc: Exception) -> None:
        self.warnings.append(str(exc))

    def status(self, message: str) -> None: ...

    def titled(self, path: Path | None) -> None: ...


def document(canvas: Canvas):
    """A document whose worker applies nothing: the submitted actions are kept."""
    submitted: list = []
    surfaces: list[str] = []
    doc = Document(
        SharedCanvas(canvas),
        load_pigment_library(),
        submitted.append,
        lambda c: None,
        Dialogs(),
        on_surface=surfaces.append,
    )
    return doc, submitted, surfaces


def new_canvas_of(action) -> Canvas:
    return action.args[0]  # actions.replace_canvas is a partial of (canvas, note)


def test_new_keeps_size_and_surface_or_takes_the_given_ones():
    doc, submitted, surfaces = document(Canvas((40, 30), (0.004, 0.003), surface="gesso"))
    doc.new()
    same = new_canvas_of(submitted[-1])
    assert same.pixels == (40, 30) and same.surface == "gesso"
    doc.new((50, 20), (0.005, 0.002), "cotton_duck")
    other = new_canvas_of(submitted[-1])
    assert other.pixels == (50, 20) and other.surface == "cotton_duck"
    assert surfaces == ["gesso", "cotton_duck"]  # the haptic contact is told each time
    with pytest.raises(InputError, match="unknown surface"):
        doc.new(surface="velvet")


def test_the_surface_survives_copies_and_the_options_blank_canvas():
    canvas = Canvas((30, 20), (0.003, 0.002), ("cadmium_red",), surface="fine_linen")
    assert copy_canvas(canvas).surface == "fine_linen"
    assert blank_canvas(canvas).surface == "fine_linen"
    options = PaintOptions(settings=PaintSettings(surface="cold_press"))
    assert blank_canvas(options=options).surface == "cold_press"
    with pytest.raises(InputError):
        PaintSettings(surface="velvet")


def test_the_paint_command_takes_surface_and_canvas_size():
    from paintapp.cli import build_parser
    from paintapp.commands.paint import options_from_args

    args = build_parser().parse_args(
        ["paint", "--surface", "cotton_duck", "--canvas-size", "a6-landscape", "--texel-mm", "0.2"]
    )
    options = options_from_args(args)
    assert options.settings.surface == "cotton_duck"
    assert options.pixels == (740, 525)
    bad = build_parser().parse_args(["paint", "--surface", "velvet"])
    with pytest.raises(InputError, match="unknown surface"):
        options_from_args(bad)


def test_the_dialog_offers_sizes_texels_and_surfaces(qapp):
    from paintapp.app.new_canvas_dialog import NewCanvasDialog, current_choice

    canvas = Canvas((2100, 2970), (0.21, 0.297), surface="fine_linen")
    initial = current_choice(canvas)
    assert (initial.size, initial.texel_mm, initial.surface) == ("a4", 0.1, "fine_linen")
    dialog = NewCanvasDialog(None, initial)
    ok = dialog.buttons.button(dialog.buttons.StandardButton.Ok)
    assert dialog.choice() == initial and ok.isEnabled()
    dialog.size_box.setEditText("300x200")
    dialog.texel_box.setValue(0.25)
    dialog.surface_box.setCurrentIndex(dialog.surface_box.findData("cold_press"))
    choice = dialog.choice()
    assert choice.resolve() == ((1200, 800), (0.3, 0.2))
    assert "cold-press paper" in dialog.summary.text()
    dialog.size_box.setEditText("a4")
    dialog.texel_box.setValue(0.01)  # 21000 texels across: too many
    assert not ok.isEnabled() and "at most" in dialog.summary.text()
    dialog.size_box.setEditText("nonsense")
    assert not ok.isEnabled()
    dialog.deleteLater()
    assert np.isclose(current_choice(Canvas((300, 200), (0.03, 0.02))).texel_mm, 0.1)


def test_the_haptic_link_feels_the_surface_it_is_given_and_told():
    import time

    from paintapp.app.haptic_link import DeviceSpec, HapticLink
    from paintapp.app.new_canvas_dialog import follow_surface

    link = HapticLink(DeviceSpec("sim"), mode="thread", surface="cotton_duck")
    assert link.loop is not None and link.loop.config.contact.surface == "cotton_duck"
    link.start()
    try:
        assert link.loop.contact.surface == "cotton_duck"
        follow_surface(link)("cold_press")  # a new canvas on paper
        deadline = time.monotonic() + 10.0
        while link.loop.contact.surface != "cold_press" and time.monotonic() < deadline:
            time.sleep(0.01)
        assert link.loop.contact.surface == "cold_press"
    finally:
        link.stop()
    follow_surface(None)("smooth")  # no device: nothing to tell
