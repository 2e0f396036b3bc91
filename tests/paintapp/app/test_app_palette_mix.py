"""The mixing slab: blue and yellow put on the slab and mixed there load the brush with green,
which paints green on the canvas; the pick-up is journalled as a clean and load_pigment events."""

from __future__ import annotations

import math
import threading
from pathlib import Path

import numpy as np
import pytest

from brushes import PaintReservoir
from paintapp.app.options import PaintOptions
from paintapp.app.slab import PUT_VOLUME_M3, MixingSlab
from paintapp.canvas.exr import unlit_rgba
from paintapp.session.playback import replay
from paintapp.strokes.files import read_strokes
from paintapp.strokes.records import CleanBrush, LoadPigment, Marker

BLUE, YELLOW = "ultramarine_blue", "cadmium_yellow"
START_M, END_M = (0.05, 0.08), (0.13, 0.08)


def test_slab_conserves_paint_and_mixes():
    slab = MixingSlab()
    slab.put(BLUE)
    slab.put(YELLOW)
    assert slab.total_m3 == pytest.approx(2 * PUT_VOLUME_M3, rel=1e-5)
    brush = PaintReservoir(2e-8, {"cadmium_red": 1e-8})
    before = slab.total_m3 + brush.total_m3
    (bx, by), (yx, yy) = slab.spots[BLUE], slab.spots[YELLOW]
    for i in range(21):  # drag from the blue blob to the yellow one and back
        f = 1 - abs(i / 10 - 1)
        slab.dab(brush, bx + f * (yx - bx), by + f * (yy - by))
    assert slab.total_m3 + brush.total_m3 == pytest.approx(before, rel=1e-5)
    assert brush.total_m3 == pytest.approx(2e-8)
    assert set(brush.fractions()) >= {BLUE, YELLOW}
    slab.clear()
    assert slab.total_m3 == 0 and not slab.spots


@pytest.fixture
def window(qapp, pump, tmp_path: Path):
    from paintapp.app.launch import create_window

    options = PaintOptions(
        record=tmp_path / "strokes.jsonl",
        recovery_dir=tmp_path / "recovery",
        autosave_s=0,
        recover="no",
    )
    _, win = create_window(options, interactive=False)
    assert pump(5.0, lambda: win.canvas_widget.frame_count > 0), "the canvas never rendered"
    yield win
    win.close()
    pump(0.1)


def _mouse(widget, kind, x: float, y: float, held: bool) -> None:
    from PySide6.QtCore import QPointF, Qt
    from PySide6.QtGui import QMouseEvent
    from PySide6.QtWidgets import QApplication

    left, none = Qt.MouseButton.LeftButton, Qt.MouseButton.NoButton
    pos = QPointF(x, y)
    event = QMouseEvent(
        kind, pos, widget.mapToGlobal(pos), left, left if held else none,
        Qt.KeyboardModifier.NoModifier,
    )  # fmt: skip
    QApplication.sendEvent(widget, event)


def test_mix_blue_and_yellow_on_the_slab_paints_green(window, pump, stroke, tmp_path):
    from PySide6.QtCore import QEvent, Qt
    from PySide6.QtTest import QTest

    win = window
    for name in (BLUE, YELLOW):  # Shift+click on the swatches puts them on the slab
        QTest.mouseClick(
            win.controls.swatches[name],
            Qt.MouseButton.LeftButton,
            Qt.KeyboardModifier.ShiftModifier,
        )
    assert pump(5.0, lambda: win.worker.slab.canvas.pigment_names == (BLUE, YELLOW))
    assert win.worker.session.reservoir.is_empty, "a Shift+click must not load the brush"

    # Drag the brush on the slab widget from the blue blob to the yellow one and back.
    slab_widget = win.controls.slab
    (bx, by), (yx, yy) = (slab_widget.to_widget(*win.worker.slab.spots[n]) for n in (BLUE, YELLOW))
    T = QEvent.Type
    _mouse(slab_widget, T.MouseButtonPress, bx, by, True)
    for i in range(1, 41):
        f = 1 - abs(i / 20 - 1)
        _mouse(slab_widget, T.MouseMove, bx + f * (yx - bx), by + f * (yy - by), True)
    _mouse(slab_widget, T.MouseButtonRelease, bx, by, False)
    win.actions_by_name["slab_mix"].trigger()  # X: knife it together, load the brush
    done = threading.Event()  # commands run in order: once this one has, the mix has too
    win.worker.submit(lambda _worker: done.set())
    assert pump(20.0, done.is_set), "the worker never ran the queued slab commands"
    assert win.worker.status.get().message.startswith("brush:")
    load = win.worker.session.reservoir.fractions()
    load_m3 = win.worker.session.reservoir.total_m3
    assert 0.25 < load.get(BLUE, 0) < 0.75 and 0.25 < load.get(YELLOW, 0) < 0.75, load

    # The slab on screen shows the paint (not the bare ground everywhere).
    pump(0.2)
    pixels = slab_widget.pixels.reshape(-1, 3).astype(int)
    assert np.ptp(pixels, axis=0).max() > 60

    # Paint on the canvas: the stroke is green, unlike either pigment.
    stroke(win, START_M, END_M)
    assert pump(20.0, lambda: win.worker.status.get().strokes >= 1 and win.worker.idle.is_set()), (
        "the stroke did not finish"
    )
    with win.shared.lock:
        canvas = win.shared.canvas
        painted = canvas.paint_m.sum(axis=0).copy()
        ix, iy = (int(v) for v in canvas.metres_to_texel(0.09, START_M[1]))
        colour = unlit_rgba(canvas, win.library)[iy - 2 : iy + 3, ix - 2 : ix + 3, :3]
        colour = colour.reshape(-1, 3).mean(axis=0)
    assert painted[iy, ix] > 1e-6, "no paint in the middle of the stroke"
    r, g, b = colour
    assert g > 1.15 * r and g > 1.15 * b, f"not green: {colour}"
    for name in (BLUE, YELLOW):
        rgb = win.library[name].masstone_linear_rgb()
        assert np.argmax(rgb) != 1, f"{name} is green by itself: {rgb}"

    # The journal holds the pick-up as a clean and loads of both pigments, and replays.
    strokes = read_strokes(tmp_path / "strokes.jsonl")
    records = strokes.records
    labels = [r.label for r in records if isinstance(r, Marker)]
    assert "slab put ultramarine_blue" in labels and "slab mix" in labels
    last_mix = max(
        i for i, r in enumerate(records) if isinstance(r, Marker) and r.label == "slab mix"
    )
    assert isinstance(records[last_mix + 1], CleanBrush)
    loads = {}
    for r in records[last_mix + 2 :]:
        if not isinstance(r, LoadPigment):
            break
        loads[r.pigment] = r.volume_m3
    assert set(loads) == {BLUE, YELLOW}
    assert math.fsum(loads.values()) == pytest.approx(load_m3)
    again = replay(strokes).canvas
    assert np.allclose(again.paint_m.sum(axis=0), painted, atol=1e-9)
