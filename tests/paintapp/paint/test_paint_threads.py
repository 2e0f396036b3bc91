"""The paint grid's step on two threads (the probes' geometry beside the advection, the brush's
exchange beside the pressure solve, the canvas read beside the re-centring, the pigments'
transport in groups): the same paint, brush and forces, bit for bit, as on one."""

from __future__ import annotations

import dataclasses

import numpy as np

from paintapp.canvas.model import Canvas
from paintapp.paint.grid3d import PaintGrid3D
from paintapp.paint.paint_scene import load_paint_scene
from paintapp.session.painting import PaintingSession
from tests.support.demo_strokes import StrokeSpec, stroke_samples

PIGMENTS = ("ultramarine_blue", "cadmium_yellow", "titanium_white")


def wet_session(threads: int) -> PaintingSession:
    """The default scene (solver on ``threads`` threads) over 5 x 2.5 cm of three wet pigments
    at 0.2 mm texels, a brush loaded with blue."""
    base = load_paint_scene("default")
    scene = dataclasses.replace(base, solver=dataclasses.replace(base.solver, threads=threads))
    y, x = np.mgrid[0:128, 0:256] / 256.0
    paint = np.stack([(1e-4 * (1.0 + np.sin(9.0 * x * (p + 1) + 4.0 * y * p))).astype(np.float32)
                      for p in range(len(PIGMENTS))])  # fmt: skip
    canvas = Canvas((256, 128), (0.05, 0.025), PIGMENTS, paint, np.ones((128, 256), np.float32))
    session = PaintingSession(canvas, "round_small", scene)
    session.load_pigment(PIGMENTS[0], 1e-8)
    return session


def test_a_stroke_on_two_threads_lays_the_same_paint_and_feels_the_same_force():
    runs = []
    for threads in (1, 2):
        session = wet_session(threads)
        spec = StrokeSpec((0.01, 0.012), (0.04, 0.014), 0.4, 0.8, (0.2, 0.0))
        forces, steps = [], 0
        for sample in stroke_samples(spec, 0.0):
            step = session.sample(sample).paint
            if step is not None:
                forces.append(step.force_n.copy())
                steps += step.solver_steps
        model = session.model
        assert isinstance(model, PaintGrid3D) and model.sim is not None
        assert model.sim.component_threads() == threads
        runs.append((session.canvas.paint_m.copy(), session.reservoir.volumes_m3, forces, steps))
    (paint_1, brush_1, forces_1, steps_1), (paint_2, brush_2, forces_2, steps_2) = runs
    assert steps_1 == steps_2 > 10
    assert np.array_equal(paint_1, paint_2)
    assert brush_1 == brush_2
    assert np.array_equal(np.array(forces_1), np.array(forces_2))
    assert np.abs(np.array(forces_1)).max() > 0.0  # the brush felt the paint


def test_the_canvas_read_beside_a_re_centring_serves_only_the_window_it_was_read_for():
    session = wet_session(2)
    spec = StrokeSpec((0.01, 0.012), (0.02, 0.013), 0.1, 0.8, (0.2, 0.0))
    for sample in stroke_samples(spec, 0.0):
        session.sample(sample)
    model = session.model
    assert isinstance(model, PaintGrid3D)
    assert model._read_ahead is None  # each step took the columns read for it
    model.window.shift(0.5, 0.0)
    model._shifted(0.5, 0.0)
    assert model._read_ahead is not None
    fresh = model.band_columns()
    np.testing.assert_array_equal(model._columns(), fresh)  # the same window: read ahead
    model.window.shift(1.0, 0.0)
    model._shifted(1.0, 0.0)
    ahead = model._read_ahead[1]
    model.window.shift(3.0, 0.0)  # moved again without its own read: the columns read afresh
    columns = model._columns()
    assert not np.array_equal(columns, ahead)
    np.testing.assert_array_equal(columns, model.band_columns())
