"""The simulation worker in a process of its own, without a window: what crosses the pipes."""

from __future__ import annotations

import pickle
import time

import numpy as np
import pytest

from brushes import StylusSample
from common.errors import InputError
from paintapp.app import actions
from paintapp.app.history import copy_canvas
from paintapp.app.settings import PaintSettings
from paintapp.app.shared import SharedCanvas
from paintapp.app.sim_process import SimulationProcess, simulation_mode
from paintapp.canvas.model import Canvas
from paintapp.strokes.files import read_strokes
from tests.support.waiting import wait_for


def test_every_command_pickles_and_runs_as_the_same_function() -> None:
    """A command crosses to the child pickled: each is a partial of a module-level function."""
    commands = [
        actions.load_pigment("ultramarine_blue"), actions.clean_brush(),
        actions.apply_settings(PaintSettings()), actions.undo(), actions.redo(),
        actions.replace_canvas(Canvas((8, 8), (0.001, 0.001)), "new canvas"),
        actions.slab_put("cadmium_red"), actions.slab_dab(0.01, 0.02), actions.slab_mix(),
        actions.slab_clear(),
    ]  # fmt: skip
    for command in commands:
        again = pickle.loads(pickle.dumps(command))
        assert again.func is command.func and len(again.args) == len(command.args)


def test_the_mode_is_checked_and_a_servo_thread_keeps_the_simulation_a_thread() -> None:
    class ThreadLink:
        process = None

    class ProcessLink:
        process = object()

    assert simulation_mode("process", None) == "process"
    assert simulation_mode("process", ProcessLink()) == "process"
    assert simulation_mode("process", ThreadLink()) == "thread"
    assert simulation_mode("thread", ProcessLink()) == "thread"
    with pytest.raises(InputError, match="simulation"):
        simulation_mode("fork", None)


def test_a_stroke_in_the_child_reaches_the_display_canvas_and_its_journal(tmp_path) -> None:
    """Paint lands in the window's display canvas where the stroke went; the child's journal
    holds the stroke; undo crosses back; closing the window's end of the pipe (the window
    died) makes the child commit the stroke, close the journal and exit."""
    canvas = Canvas((480, 480), (0.048, 0.048))
    shared = SharedCanvas(copy_canvas(canvas))
    record = tmp_path / "s.jsonl"
    sim = SimulationProcess(
        canvas, shared, PaintSettings(brush="round_small"), ("ultramarine_blue",), record
    )
    sim.start()
    try:
        sim.submit(actions.load_pigment("ultramarine_blue"))
        assert wait_for(lambda: "loaded" in sim.status.get().message, 60.0)
        for i in range(60):
            x = 0.012 + 0.024 * i / 59
            sim.push(StylusSample(0.0, np.array([x, 0.024, 0.0]), 0.8))
            time.sleep(0.02)
        sim.push(StylusSample(0.0, np.array([0.036, 0.024, 0.01]), 0.0))
        assert wait_for(lambda: sim.status.get().strokes == 1 and sim.idle.is_set(), 60.0)
        status = sim.status.get()
        assert status.paint_steps > 5 and status.fault is None, status
        with shared.lock:
            painted = shared.canvas.paint_m.sum(axis=0).copy()
        ys, xs = np.nonzero(painted > 1e-7)
        assert len(xs) > 100, status
        dx = shared.canvas.texel_size_m[0]
        assert np.all(np.abs((ys + 0.5) * dx - 0.024) < 2.0 * status.brush_radius_m + 0.002)
        sim.submit(actions.undo())
        assert wait_for(lambda: sim.status.get().undo == 0, 60.0), sim.status.get()
        assert wait_for(lambda: float(shared.canvas.paint_m.sum()) == 0.0, 10.0), (
            float(shared.canvas.paint_m.sum()),
            sim.status.get(),
        )
    finally:
        sim._down.close()  # the window's end goes away without a word
        code = sim.wait_exit(30.0)
    assert code == 0, code
    strokes = read_strokes(record)
    assert sum(1 for s in strokes.samples if s.pressure > 0) >= 5


def test_a_region_that_does_not_fit_the_display_canvas_is_dropped() -> None:
    shared = SharedCanvas(Canvas((10, 10), (0.001, 0.001)))
    block = np.ones((1, 4, 4), np.float32)
    shared.apply_region((8, 8, 12, 12), ("ultramarine_blue",), block, np.ones((4, 4), np.float32))
    shared.apply_region((0, 0, 4, 4), ("ultramarine_blue",), block, np.ones((3, 3), np.float32))
    assert shared.version == 0 and shared.canvas.pigment_names == ()
    shared.apply_region((0, 0, 4, 4), ("ultramarine_blue",), block, np.ones((4, 4), np.float32))
    assert shared.version == 1 and float(shared.canvas.paint_m.sum()) == 16.0
