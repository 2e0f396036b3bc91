"""The real painting window under Xvfb: a tablet stroke paints where it went, is journalled,
undoes and redoes, and the window shows the canvas and the HUD."""

from __future__ import annotations

import numpy as np
import pytest

from paintapp.app.haptic_link import parse_device
from paintapp.session.playback import replay
from paintapp.strokes.files import read_strokes
from paintapp.strokes.records import LoadPigment, Marker
from tests.paintapp.app.conftest import FAST_CANVAS, window_options

START_M, END_M = (0.05, 0.06), (0.13, 0.06)


def _idle(win, pump, strokes: int) -> None:
    done = pump(
        20.0, lambda: win.worker.status.get().strokes >= strokes and win.worker.idle.is_set()
    )
    assert done, f"the worker did not finish the stroke: {win.worker.status.get()}"


def _paint(win) -> np.ndarray:
    with win.shared.lock:
        return win.shared.canvas.paint_m.sum(axis=0).copy()


def test_stroke_paints_journals_undoes_and_shows(window, pump, stroke, tmp_path):
    win = window
    win.load_pigment("ultramarine_blue")
    stroke(win, START_M, END_M)
    _idle(win, pump, 1)
    painted = _paint(win)
    canvas = win.shared.canvas
    dx = canvas.texel_size_m[0]

    # Paint lies along the stroke, and nowhere else.
    ys, xs = np.nonzero(painted > 1e-7)
    assert len(xs) > 200
    x_m, y_m = (xs + 0.5) * dx, (ys + 0.5) * dx
    reach = 2.0 * win.worker.status.get().brush_radius_m + 0.005
    assert np.all(np.abs(y_m - START_M[1]) < reach)
    assert x_m.min() > START_M[0] - reach and x_m.max() < END_M[0] + reach
    mid = canvas.metres_to_texel(0.5 * (START_M[0] + END_M[0]), START_M[1])
    assert painted[int(mid[1]), int(mid[0])] > 1e-6, "no paint in the middle of the stroke"
    assert painted[:, :100].max() == 0 and painted[:150].max() == 0

    # The journal holds the dip and the stroke, and replays to the same canvas.
    strokes = read_strokes(tmp_path / "strokes.jsonl")
    assert any(isinstance(r, LoadPigment) for r in strokes.records)
    down = [s for s in strokes.samples if s.pressure > 0]
    assert len(down) >= 5
    xs_rec = [float(s.position_m[0]) for s in down]
    assert min(xs_rec) == pytest.approx(START_M[0], abs=1e-3)
    assert max(xs_rec) == pytest.approx(END_M[0], abs=1e-3)
    again = replay(strokes).canvas
    assert np.allclose(again.paint_m.sum(axis=0), painted, atol=1e-9)

    # Screenshot: canvas with the stroke and the HUD (off by default: H shows it).
    assert not win.hud.show_text
    win.hud.show_text = True
    win.hud.refresh()
    pump(0.2)
    shot = win.grab().toImage()
    widget = win.canvas_widget
    px, py = widget.mapping().to_widget(0.5 * (START_M[0] + END_M[0]), START_M[1])
    origin = widget.mapTo(win, widget.rect().topLeft())
    colour = shot.pixelColor(origin.x() + int(px), origin.y() + int(py))
    assert colour.blue() > colour.red() + 40, f"no blue paint on screen: {colour.name()}"
    hud_box = _region(shot, origin.x() + 10, origin.y() + 10, 220, 90)
    win.hud.show_text = False
    win.hud.refresh()  # what the render loop calls: the panel is erased
    pump(0.2)
    bare = _region(win.grab().toImage(), origin.x() + 10, origin.y() + 10, 220, 90)
    assert np.mean(np.abs(hud_box - bare)) > 10, "the HUD is not on screen"

    # Undo removes the stroke, redo brings it back.
    win.undo()
    assert pump(5.0, lambda: win.worker.status.get().undo == 0)
    pump(0.1)
    assert _paint(win).max() == 0
    win.redo()
    assert pump(5.0, lambda: win.worker.status.get().redo == 0)
    pump(0.1)
    assert np.array_equal(_paint(win), painted)
    labels = [
        r.label for r in read_strokes(tmp_path / "strokes.jsonl").records if isinstance(r, Marker)
    ]
    assert labels == ["undo", "redo"]


def test_the_simulation_in_a_process_of_its_own_paints_journals_undoes_and_dies_safely(
    qapp, pump, stroke, tmp_path
):
    """``--simulation process``: the same stroke paints the display canvas through the regions
    the child sends, the child's journal replays to that canvas, undo and redo cross the pipe,
    and SIGKILL of the child is reported with the paint kept."""
    import os
    import signal

    from paintapp.app.launch import create_window
    from paintapp.app.sim_process import SimulationProcess

    _, win = create_window(
        window_options(tmp_path, simulation="process", **FAST_CANVAS), interactive=False
    )
    try:
        assert isinstance(win.worker, SimulationProcess)
        assert pump(5.0, lambda: win.canvas_widget.frame_count > 0), "the canvas never rendered"
        win.load_pigment("ultramarine_blue")
        assert pump(60.0, lambda: "loaded" in win.worker.status.get().message), "no child"
        stroke(win, START_M, END_M)
        _idle(win, pump, 1)
        painted = _paint(win)
        ys, xs = np.nonzero(painted > 1e-7)
        assert len(xs) > 200
        dx = win.shared.canvas.texel_size_m[0]
        reach = 2.0 * win.worker.status.get().brush_radius_m + 0.005
        assert np.all(np.abs((ys + 0.5) * dx - START_M[1]) < reach)
        strokes = read_strokes(tmp_path / "strokes.jsonl")
        assert any(isinstance(r, LoadPigment) for r in strokes.records)
        again = replay(strokes).canvas
        assert np.allclose(again.paint_m.sum(axis=0), painted, atol=1e-9)
        assert win.worker.status.get().journal == str(tmp_path / "strokes.jsonl")

        win.undo()
        assert pump(10.0, lambda: win.worker.status.get().undo == 0)
        assert pump(5.0, lambda: _paint(win).max() == 0)
        win.redo()
        assert pump(10.0, lambda: win.worker.status.get().redo == 0)
        assert pump(5.0, lambda: np.array_equal(_paint(win), painted))

        os.kill(win.worker.pid, signal.SIGKILL)
        assert pump(10.0, lambda: win.worker.status.get().fault is not None)
        assert "simulation process stopped" in win.worker.status.get().fault
        assert np.array_equal(_paint(win), painted)  # nothing painted is lost
    finally:
        win.close()
        pump(0.1)


def _region(image, x: int, y: int, w: int, h: int) -> np.ndarray:
    return np.array(
        [
            [image.pixelColor(x + i, y + j).lightness() for i in range(0, w, 2)]
            for j in range(0, h, 2)
        ],
        dtype=np.float64,
    )


def test_the_default_canvas_is_a4_and_a_stroke_paints_where_it_went(qapp, pump, stroke, tmp_path):
    from paintapp.app.launch import create_window

    _, win = create_window(window_options(tmp_path), interactive=False)
    try:
        assert pump(10.0, lambda: win.canvas_widget.frame_count > 0), "the canvas never rendered"
        canvas = win.shared.canvas
        assert canvas.pixels == (2100, 2970) and canvas.texel_size_m[0] == pytest.approx(1e-4)
        win.load_pigment("ultramarine_blue")
        stroke(win, START_M, END_M)
        _idle(win, pump, 1)
        painted = _paint(win)
        ys, xs = np.nonzero(painted > 1e-7)
        assert len(xs) > 2000
        dx = canvas.texel_size_m[0]
        reach = 2.0 * win.worker.status.get().brush_radius_m + 0.005
        assert np.all(np.abs((ys + 0.5) * dx - START_M[1]) < reach)
        assert (xs + 0.5).min() * dx > START_M[0] - reach
        assert (xs + 0.5).max() * dx < END_M[0] + reach
        assert pump(5.0, lambda: win.canvas_widget.frame_count > 2)
    finally:
        win.close()
        pump(0.1)


def test_palette_swatches_name_their_pigment(window):
    for name, button in window.controls.swatches.items():
        label = window.library[name].label or name.replace("_", " ")
        assert label in button.text() and label in button.toolTip()


def test_help_overlay_and_shortcut_actions(window, pump):
    win = window
    assert not win.help.isVisible()
    win.actions_by_name["help"].trigger()
    pump(0.1)
    assert win.help.isVisible()
    win.actions_by_name["model"].trigger()
    assert win.settings.fluid_model == "depth_averaged"
    win.actions_by_name["larger"].trigger()
    assert win.settings.brush_scale == pytest.approx(1.25)
    assert pump(5.0, lambda: win.worker.session.scene.fluid_model == "depth_averaged")


def test_simulated_device_paints_and_survives_a_fault(qapp, pump, stroke, tmp_path):
    """With --device sim the servo loop (the thread form, so the test can reach the device)
    steers the brush; a device failure mid-stroke keeps the stroke (undoable, journalled) and
    hands the brush back to the pointer."""
    from paintapp.app.launch import create_window
    from paintapp.haptics.device import DeviceError

    options = window_options(tmp_path, device=parse_device("sim"), servo="thread")
    _, win = create_window(options, interactive=False)
    try:
        win.load_pigment("cadmium_red")
        device = win.link.loop.device
        real_read = device.read
        calls = {"n": 0, "fail_after": None}

        def flaky_read():
            calls["n"] += 1
            if calls["fail_after"] is not None and calls["n"] > calls["fail_after"]:
                raise DeviceError("unplugged")
            return real_read()

        device.read = flaky_read
        win.link.target.set(START_M[0], START_M[1], 0.0, False)
        pump(0.5)
        rate, jitter, seen = win.link.live()
        assert seen > 100 and rate > 0, (rate, jitter)  # it runs (a thread's rate is not asserted)
        win.link.target.set(START_M[0], START_M[1], 1.0, True)
        assert pump(30.0, lambda: win.worker.status.get().in_contact), "the hand never touched"
        for i in range(30):
            x = START_M[0] + (END_M[0] - START_M[0]) * i / 29
            win.link.target.set(x, START_M[1], 1.0, True)
            pump(0.03)
        calls["fail_after"] = calls["n"]  # unplug mid-stroke
        assert pump(20.0, lambda: win.worker.status.get().fault is not None)
        status = win.worker.status.get()
        assert status.strokes >= 1 and status.undo == status.strokes and not status.in_contact
        assert _paint(win).max() > 0
        first = read_strokes(tmp_path / "strokes.jsonl")
        assert any(isinstance(r, Marker) and "device fault" in r.label for r in first.records)
        assert (tmp_path / "strokes-2.jsonl").is_file()
        stroke(win, START_M, END_M)  # the pointer paints on
        _idle(win, pump, status.strokes + 1)
    finally:
        win.close()
        pump(0.1)


@pytest.mark.parametrize("simulation", ["thread", "process"])
def test_servo_process_steers_the_brush_and_its_death_is_survived(
    qapp, pump, stroke, tmp_path, simulation
):
    """The default servo form is a process of its own: it steers the brush through shared
    memory; SIGKILL of it mid-stroke is noticed, journalled, and the pointer paints on. The
    device never got a non-finite or over-limit write. With the simulation in a process of its
    own too, that process reads the stylus and publishes the force through the servo's shared
    memory, and learns of the servo's death from the window."""
    import os
    import signal

    from paintapp.app.launch import create_window

    options = window_options(tmp_path, device=parse_device("sim"), simulation=simulation)
    _, win = create_window(options, interactive=False)
    try:
        link = win.link
        assert link.mode == "process" and link.process.heavy_modules == []
        # the heartbeat watchdog counts once the first frame (its shader compiles) is drawn and
        # the simulation prepared (its warm-up)
        assert pump(120.0, lambda: link.process.block.armed), win.worker.status.get()
        assert win.canvas_widget.frame_count > 0 and win.worker.status.get().ready
        win.load_pigment("cadmium_red")
        link.target.set(START_M[0], START_M[1], 0.0, False)
        assert pump(10.0, lambda: link.live()[2] > 100), link.live()
        assert "process" in win._servo_where()
        pump(0.5)  # the worker steps the hovering hand: nothing painted, nothing to save
        assert not win.document.unsaved and win.shared.version == 0
        link.target.set(START_M[0], START_M[1], 1.0, True)
        assert pump(30.0, lambda: win.worker.status.get().in_contact), "the hand never touched"
        for i in range(30):
            x = START_M[0] + (END_M[0] - START_M[0]) * i / 29
            link.target.set(x, START_M[1], 1.0, True)
            pump(0.03)
        audit = link.process.audit()
        os.kill(link.process.pid, signal.SIGKILL)  # the servo process dies mid-stroke
        assert pump(20.0, lambda: win.worker.status.get().fault is not None)
        status = win.worker.status.get()
        assert "servo process stopped" in status.fault and not status.in_contact
        assert status.strokes >= 1 and _paint(win).max() > 0
        first = read_strokes(tmp_path / "strokes.jsonl")
        assert any(isinstance(r, Marker) and "servo process" in r.label for r in first.records)
        assert audit["nonfinite_writes"] == 0 and audit["over_limit_writes"] == 0, audit
        stroke(win, START_M, END_M)  # the pointer paints on
        _idle(win, pump, status.strokes + 1)
    finally:
        win.close()
        pump(0.1)


@pytest.mark.parametrize(
    ("window_px", "reduction"),
    [((1180, 760), 1), ((900, 620), 1), ((400, 300), 2)],
    ids=["magnified", "minified", "reduced"],
)
def test_the_canvas_redraws_only_what_changed_and_matches_a_full_redraw(
    window, pump, stroke, window_px, reduction
):
    """The widget redraws only the rectangles that changed (paint, brush outline, force arrow);
    what it shows then equals a redraw of everything. A 720x480 canvas in the default window
    shows each texel on more than one pixel (the cached picture path), in a smaller window on
    less than one (the per-pixel path), in a small one on less than half (drawn from textures
    averaged over 2 x 2 texels)."""
    win, widget = window, window.canvas_widget
    win.resize(*window_px)
    assert pump(5.0, lambda: widget.size().width() < window_px[0])
    pump(0.3)
    texel_m = win.shared.canvas.texel_size_m[0]
    magnified = widget.mapping().metres_per_px < texel_m
    assert magnified == (window_px[0] > 1000)
    assert widget.renderer.reduction == reduction
    drawn = widget.drawn_count
    pump(0.3)
    assert widget.drawn_count == drawn, "an idle canvas was redrawn"
    win.load_pigment("cadmium_red")
    stroke(win, START_M, END_M)
    _idle(win, pump, 1)
    pump(0.3)
    assert widget.drawn_count > drawn
    shown = widget.shown_pixels()
    assert shown.shape[:2] == (widget.height(), widget.width())
    red = shown[..., 0].astype(int) - shown[..., 2]
    assert (red > 40).sum() > 50, "no red paint on screen"
    widget.invalidate()
    widget.refresh()
    assert np.array_equal(widget.shown_pixels(), shown)


def test_the_hud_outlines_the_paint_grid_on_request(window, pump, pen):
    win = window
    win.load_pigment("ultramarine_blue")
    pen(win, "press", START_M)
    try:
        # the pen is held down: the brush stays in the paint and the grid rides with it
        assert pump(10.0, lambda: win.worker.status.get().grid_m is not None)

        def outline_pixels() -> int:
            win.hud.refresh()
            pump(0.3)
            shot = win.grab().toImage()
            rgb = np.array(
                [
                    [shot.pixelColor(i, j).getRgb()[:3] for i in range(0, shot.width(), 2)]
                    for j in range(0, shot.height(), 2)
                ]
            )
            cyan = (rgb[..., 2] > 200) & (rgb[..., 1] > 170) & (rgb[..., 0] < 140)
            return int(cyan.sum())

        assert outline_pixels() < 5
        win.hud.show_grid = True
        assert outline_pixels() > 20, "no grid outline on screen"
        win.hud.show_grid = False
        assert outline_pixels() < 5, "the outline stayed after it was turned off"
    finally:
        pen(win, "release", START_M)
        pump(0.2)


def test_without_opengl_the_window_says_so_and_keeps_painting(
    qapp, pump, stroke, tmp_path, monkeypatch
):
    """No EGL on the machine: the canvas shows why instead of a picture, and the brush still
    paints (and the canvas can still be saved, without a lit picture)."""
    from paintapp.app import canvas_widget
    from paintapp.app.launch import create_window
    from paintapp.render import RenderUnavailable

    def no_gl():
        raise RenderUnavailable("cannot create a headless EGL OpenGL context: no display")

    monkeypatch.setattr(canvas_widget, "create_headless_context", no_gl)
    _, win = create_window(window_options(tmp_path, **FAST_CANVAS), interactive=False)
    try:
        pump(0.5)
        widget = win.canvas_widget
        assert widget.gl_error is not None and "OpenGL unavailable" in widget.gl_error
        assert widget.render_picture() is None
        shot = win.grab().toImage()  # paints the message, no exception
        assert shot.width() > 0
        win.load_pigment("ultramarine_blue")
        stroke(win, START_M, END_M)
        _idle(win, pump, 1)
        assert _paint(win).max() > 1e-6
    finally:
        win.close()
        pump(0.1)


def test_the_window_shows_the_colours_of_the_preview(window, pump):
    """The canvas on screen is sRGB-encoded like ``preview.png``: a flat patch of paint shows
    the colour the exported preview gives it."""
    from paintapp.app.history import copy_canvas
    from paintapp.canvas.preview import encode_preview
    from paintapp.render.headless import render_canvas_rgba

    win, widget = window, window.canvas_widget
    with win.shared.lock:
        canvas = win.shared.canvas
        red = canvas.add_pigment("cadmium_red")
        patch = np.zeros((len(canvas.pigment_names), 200, 300), np.float32)
        patch[red] = 2e-4
        canvas.write_region(200, 140, patch, np.zeros((200, 300), np.float32))
        snapshot = copy_canvas(canvas)
    pump(0.5)
    expected = encode_preview(render_canvas_rgba(snapshot, win.library, widget.lighting))
    x_m, y_m = snapshot.texel_to_metres(350, 240)  # the patch's middle
    px, py = widget.mapping().to_widget(x_m, y_m)
    ratio = widget.devicePixelRatioF()
    shown = widget.shown_pixels()[round(py * ratio), round(px * ratio)].astype(int)
    preview = expected[snapshot.height - 1 - 240, 350].astype(int)
    assert np.abs(shown - preview).max() <= 3, (shown, preview)


def test_the_grid_outline_drawn_in_pieces_is_the_outline_drawn_whole(qapp):
    """The canvas beneath repaints changed rectangles, and the HUD redraws its grid outline
    only where each meets it: any split into rectangles gives the same dashed outline."""
    from PySide6.QtCore import QRect
    from PySide6.QtGui import QImage, QPainter
    from PySide6.QtWidgets import QWidget

    from paintapp.app.hud import GRID_DASH, HudData, HudOverlay
    from paintapp.app.shared import WorkerStatus
    from paintapp.render.view_transform import CanvasView

    parent = QWidget()
    parent.resize(300, 200)
    status = WorkerStatus(grid_m=(0.031, 0.042, 0.113, 0.094))
    hud = HudOverlay(
        lambda: status, HudData, lambda: CanvasView.fit((0.3, 0.2), (300, 200)), parent
    )
    hud.show_grid = True
    outline = hud._outline(status)
    assert outline is not None and hud._grid_rect(status) == outline.adjusted(-3, -3, 3, 3)

    def drawn(areas: list[QRect]) -> np.ndarray:
        image = QImage(300, 200, QImage.Format.Format_ARGB32_Premultiplied)
        image.fill(0)
        painter = QPainter(image)
        for area in areas:
            hud._draw_grid(painter, outline, area)
        painter.end()
        return np.frombuffer(image.constBits(), np.uint8).reshape(200, 300, 4).copy()

    whole = drawn([QRect(0, 0, 300, 200)])
    pieces = drawn([QRect(x, y, 37, 29) for x in range(0, 300, 37) for y in range(0, 200, 29)])
    np.testing.assert_array_equal(pieces, whole)
    lit = whole[..., 3] > 0
    x, y, w, h = outline.x(), outline.y(), outline.width(), outline.height()
    on_edges = np.zeros_like(lit)
    on_edges[[y, y + h], x : x + w + 1] = True
    on_edges[y : y + h + 1, [x, x + w]] = True
    assert lit.any() and not (lit & ~on_edges).any()  # nothing off the outline
    on, off = GRID_DASH
    top = lit[y, x : x + w + 1]
    assert list(top[: 2 * (on + off)]) == ([True] * on + [False] * off) * 2
    assert not drawn([QRect(x + 2, y + 2, w - 3, h - 3)]).any()  # nothing inside it
