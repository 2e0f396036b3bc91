"""The app's parts that need no window: undo history, journal, recovery, device and CLI parsing."""

from __future__ import annotations

import json
import os

import numpy as np
import pytest

from common.errors import InputError
from paintapp.app.haptic_link import parse_device, sample_from_state
from paintapp.app.history import UndoHistory
from paintapp.app.journal import Journal, make_header
from paintapp.app.options import PaintOptions
from paintapp.app.recovery import Recovery
from paintapp.app.settings import PaintSettings, make_preset, make_scene, scaled_preset
from paintapp.canvas.model import Canvas
from paintapp.cli import main
from paintapp.haptics.device import DeviceState
from paintapp.paint.columns import cell_texels
from paintapp.paint.fit import fit_grid
from paintapp.paint.paint_model import brush_width_m
from paintapp.paint.paint_scene import load_paint_scene, parse_paint_scene
from paintapp.strokes.files import read_strokes
from paintapp.strokes.records import Marker


def _dab(canvas: Canvas, x0: int, y0: int, size: int = 8, value: float = 1e-4) -> None:
    block = np.zeros((len(canvas.pigment_names), size, size), np.float32)
    block[-1] = value
    canvas.write_region(x0, y0, block, np.ones((size, size), np.float32))


def test_history_undo_redo_and_new_pigments() -> None:
    canvas = Canvas((64, 48), (0.016, 0.012), ("ultramarine_blue",))
    history = UndoHistory(canvas)
    _dab(canvas, 4, 4)
    assert history.commit(canvas, (0, 0, 64, 48)) == (4, 4, 12, 12)
    first = canvas.paint_m.copy()
    canvas.add_pigment("cadmium_red")
    _dab(canvas, 30, 20)
    history.commit(canvas, (28, 18, 40, 30))
    assert history.undo(canvas) == (30, 20, 38, 28)
    assert canvas.paint_m[1].max() == 0 and np.array_equal(canvas.paint_m[:1], first)
    assert history.undo(canvas) == (4, 4, 12, 12)
    assert canvas.paint_m.max() == 0
    assert history.undo(canvas) is None
    history.redo(canvas)
    history.redo(canvas)
    assert canvas.paint_m[0].max() > 0 and canvas.paint_m[1].max() > 0
    assert history.commit(canvas, (0, 0, 64, 48)) is None  # nothing changed


def test_history_is_bounded_by_steps_and_bytes() -> None:
    canvas = Canvas((64, 64), (0.016, 0.016), ("titanium_white",))
    history = UndoHistory(canvas, max_steps=60)
    for i in range(70):
        _dab(canvas, (i * 7) % 56, (i * 3) % 56, 8, 1e-5 * (i + 1))
        history.commit(canvas, (0, 0, 64, 64))
    assert history.undo_count == 60
    small = UndoHistory(canvas, max_steps=100, max_bytes=4000)
    for i in range(10):
        _dab(canvas, i * 5, i * 5, 8, 2e-4 + 1e-5 * i)
        small.commit(canvas, (0, 0, 64, 64))
    assert 1 <= small.undo_count < 10 and small.nbytes <= 4000 + 8 * 8 * 4 * 4


def test_journal_rotates_per_canvas(tmp_path) -> None:
    canvas = Canvas((32, 32), (0.01, 0.01))
    header = make_header(canvas, "round_small", ("ultramarine_blue",), "default", "tablet")
    journal = Journal(tmp_path / "s.jsonl")
    journal.start(header)
    journal.marker(0.5, "undo")
    journal.start(header)
    journal.marker(1.0, "redo")
    journal.close()
    assert [r.label for r in read_strokes(tmp_path / "s.jsonl").records] == ["undo"]
    assert isinstance(read_strokes(tmp_path / "s-2.jsonl").records[0], Marker)
    with pytest.raises(InputError):
        Journal(tmp_path / "s.jsonl").start(header)  # never clobbers the first file


def test_recovery_round_trip(tmp_path) -> None:
    from paintapp.app.launch import starting_canvas
    from paintapp.pigments.library import load_pigment_library

    canvas = Canvas((32, 24), (0.008, 0.006), ("ultramarine_blue",))
    _dab(canvas, 2, 2)
    recovery = Recovery(tmp_path / "rec")
    recovery.save(canvas, 3, "/some/picture.exr", "/some/strokes.jsonl")
    assert recovery.pending() is None  # our own autosave is not a crash
    note = json.loads(recovery.note_path.read_text())
    note["pid"] = os.getpid() + 1  # as if written by a run that died
    recovery.note_path.write_text(json.dumps(note))
    assert "did not close" in recovery.pending().describe()
    options = PaintOptions(recovery_dir=tmp_path / "rec", recover="yes")
    got, document, _ = starting_canvas(options, load_pigment_library())
    assert got.pixels == (32, 24) and str(document) == "/some/picture.exr"
    assert np.allclose(got.paint_m, canvas.paint_m, rtol=1e-3)
    assert recovery.pending() is None and not recovery.canvas_path.exists()


def test_device_parsing_and_samples() -> None:
    assert parse_device("none").kind == "none" and parse_device("sim").kind == "sim"
    spec = parse_device("hid:046d:c294:pid")
    assert (spec.vendor_id, spec.product_id, spec.protocol) == (0x046D, 0xC294, "pid")
    for bad in ("hid", "hid:zz:1", "joystick", "hid:1:2:foo"):
        with pytest.raises(InputError):
            parse_device(bad)
    state = DeviceState(0.0, np.array([0.01, 0.02, -0.001]), pressure=0.5, buttons=1)
    sample = sample_from_state(state, 2.0)
    assert sample.t_s == 2.0 and sample.pressure == 0.5
    assert sample_from_state(DeviceState(0.0, np.array([np.nan, 0, 0])), 0.0) is None


def test_settings_validate_and_scale() -> None:
    with pytest.raises(InputError):
        PaintSettings(brush_scale=5.0)
    with pytest.raises(InputError):
        PaintSettings(viscosity_pa_s=float("nan"))
    base = make_preset(PaintSettings())
    big = scaled_preset(base, 2.0)
    assert big.length_m == pytest.approx(2 * base.length_m)
    assert big.capacity_m3 == pytest.approx(4 * base.capacity_m3)


def test_paint_without_display_says_so(monkeypatch, capsys) -> None:
    for key in ("DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM"):
        monkeypatch.delenv(key, raising=False)
    monkeypatch.setattr("sys.platform", "linux")
    assert main(["paint"]) == 2
    err = capsys.readouterr().err
    assert "no display" in err and "paintapp demo" in err and "paintapp replay" in err
    assert "Traceback" not in err


def test_the_start_up_heap_is_frozen_out_of_the_collector_s_passes():
    import gc

    from paintapp.app.launch import freeze_startup_heap

    before = [object() for _ in range(10)], {"a": [1, 2]}
    try:
        frozen = freeze_startup_heap()
        assert frozen > 1000
        tracked = {id(o) for o in gc.get_objects()}
        assert id(before) not in tracked and id(before[1]) not in tracked
        after = {"b": [3]}
        assert id(after) in {id(o) for o in gc.get_objects()}
    finally:
        gc.unfreeze()


@pytest.mark.parametrize("release", [False, True])
def test_releasing_the_frozen_heap_lets_the_process_exit_without_leak_reports(release):
    """Objects frozen at start-up outlive the interpreter's last collection: OpenImageIO's
    bindings then report every instance, type and function of theirs as leaked at exit. The
    window releases the heap when it closes."""
    import subprocess
    import sys

    code = (
        "import OpenImageIO\n"
        "from paintapp.app.launch import freeze_startup_heap, release_startup_heap\n"
        "freeze_startup_heap()\n" + ("release_startup_heap()\n" if release else "")
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True
    )
    assert ("leaked" in done.stderr) is not release, done.stderr[-400:]


def test_the_window_steps_the_velocity_components_on_one_thread_unless_a_scene_asks():
    settings = PaintSettings()
    assert make_scene(settings, None).solver.threads == 1  # auto: the other core draws
    two = parse_paint_scene({"solver": {"threads": 2}}, "x")
    assert make_scene(settings, two).solver.threads == 2  # the scene's own choice stands


def test_the_window_paints_live_the_default_paint_on_a_grid_fitted_to_the_brush():
    settings = PaintSettings()
    live, default = make_scene(settings, None), load_paint_scene("default")
    assert live.name == "live" and live.fluid_model == "grid3d"
    same = ("viscosity_pa_s", "density_kg_m3", "cells", "follow", "sides", "push")
    assert [getattr(live, k) for k in same] == [getattr(default, k) for k in same]
    assert live.choose.fit_grid and live.choose.stokes_below_re > 0.0
    assert not default.choose.fit_grid and default.choose.stokes_below_re == 0.0
    # the window's brush on its A4 canvas at 0.1 mm: fewer cells than the scene's, and finer
    # than the default's (the same cells over a narrower span)
    preset = make_preset(settings)
    fitted = fit_grid(live, preset, 1e-4, "grid3d", 0.3).cells
    assert fitted[0] < live.cells[0] and fitted[1] < live.cells[1] and fitted[2] < live.cells[2]
    width = brush_width_m(preset)
    cell = cell_texels(width, 1e-4, live.cells[0], live.span)
    assert cell < cell_texels(width, 1e-4, default.cells[0], default.span)


def test_the_window_takes_the_auto_scene_and_its_model_control_offers_it():
    """``paintapp paint --scene auto`` (the 3D or the 2D grid per sample) starts the window in
    that scene; ``--model auto`` without a scene takes the bundled one."""
    from paintapp.app.settings import MODEL_LABELS
    from paintapp.cli import build_parser
    from paintapp.commands.paint import options_from_args

    options = options_from_args(build_parser().parse_args(["paint", "--scene", "auto"]))
    assert options.settings.fluid_model == "auto"
    assert make_scene(options.settings, options.scene).fluid_model == "auto"
    by_model = options_from_args(build_parser().parse_args(["paint", "--model", "auto"]))
    assert make_scene(by_model.settings, None).name == "auto"
    assert "auto" in MODEL_LABELS
    with pytest.raises(InputError, match="fluid_model"):
        PaintSettings(fluid_model="stamp")
