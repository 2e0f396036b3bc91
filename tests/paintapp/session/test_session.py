"""The painting session: forces from the paint, the brush in the air, stroke events."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from brushes import StylusSample
from common.errors import InputError
from paintapp.canvas.model import Canvas
from paintapp.haptics.channel import ForceChannel
from paintapp.paint.paint_scene import load_paint_scene
from paintapp.session.painting import PaintingSession
from paintapp.strokes.files import CleanBrush, LoadPigment, SwitchBrush
from tests.support.demo_strokes import StrokeSpec, stroke_samples

BLUE = "ultramarine_blue"


def covered(thickness_m: float) -> Canvas:
    """A 24 mm canvas evenly covered with wet blue paint."""
    paint = np.full((1, 96, 96), thickness_m, np.float32)
    return Canvas((96, 96), (0.024, 0.024), (BLUE,), paint, np.ones((96, 96), np.float32))


def drag_force(thickness_m: float, scene_name: str = "default") -> tuple[np.ndarray, np.ndarray]:
    """Mean force (N) over the second half of a clean square probe dragged along +x at 5 cm/s,
    and the stroke's direction."""
    scene = load_paint_scene(scene_name)
    cells = (20, 20, 8) if scene.fluid_model == "grid3d" else (24, 24, 1)
    scene = dataclasses.replace(scene, cells=cells, margin_cells=6)
    session = PaintingSession(covered(thickness_m), "square_probe", scene)
    spec = StrokeSpec((0.006, 0.012), (0.018, 0.012), 0.24, 1.0, ramp_s=0.03)
    steps = [session.sample(s) for s in stroke_samples(spec, 0.0)]
    forces = np.array([s.force_n for s in steps if s.in_contact])
    assert len(forces) > 8
    return forces[len(forces) // 2 :].mean(axis=0), np.array([1.0, 0.0, 0.0])


@pytest.mark.parametrize(("scene_name", "ratio"), [("default", 2.5), ("thin_glaze", 1.2)])
def test_thick_paint_pushes_back_harder_than_thin_paint_against_the_motion(scene_name, ratio):
    """4x the paint: in the 3D grid the drag grows nearly in proportion (more of the tip is in
    viscous paint); the depth-averaged grid's grows less (its tip spans the whole layer)."""
    thin, direction = drag_force(0.1e-3, scene_name)
    thick, _ = drag_force(0.4e-3, scene_name)
    assert thin @ direction < 0.0 and thick @ direction < 0.0  # drag opposes the motion
    assert thick @ direction < ratio * (thin @ direction)  # and thick paint drags harder
    assert abs(thick[1]) < 0.5 * abs(thick[0])  # mostly along the stroke


def test_a_brush_in_the_air_takes_no_steps_and_feels_nothing():
    for kind, sample in (
        ("tablet", lambda t, x: StylusSample(t, np.array([x, 0.012, 0.0]), 0.0)),
        ("haptic", lambda t, x: StylusSample(t, np.array([x, 0.012, 0.003]), 0.0)),
    ):
        canvas = covered(0.3e-3)
        before = canvas.paint_m.copy()
        channel = ForceChannel()
        session = PaintingSession(canvas, "round_small", input_kind=kind, forces=channel)
        steps = [session.sample(sample(0.02 * i, 0.006 + 0.001 * i)) for i in range(10)]
        assert not any(s.in_contact for s in steps)
        assert session.stats.solver_steps == 0 and session.stats.paint_steps == 0
        seq, last = channel.latest()
        assert seq == 10 and last is not None
        assert not last.force.any() and not last.torque.any()
        assert np.array_equal(canvas.paint_m, before)


def test_stroke_events_load_switch_and_clean_the_brush():
    canvas = Canvas((64, 64), (0.016, 0.016))
    session = PaintingSession(canvas, "round_small")
    session.handle(LoadPigment(0.0, BLUE, 1.0))  # far more than fits
    assert canvas.pigment_names == (BLUE,)
    assert session.reservoir.total_m3 == pytest.approx(session.preset.capacity_m3)
    assert session.loaded_m3[BLUE] == pytest.approx(session.preset.capacity_m3)
    session.handle(SwitchBrush(0.1, "flat_wide"))
    assert session.preset.name == "flat_wide" and session.reservoir.is_empty
    assert session.removed_m3[BLUE] == pytest.approx(session.loaded_m3[BLUE])
    session.handle(LoadPigment(0.2, BLUE, 1e-8))
    session.handle(CleanBrush(0.3))
    assert session.reservoir.is_empty
    with pytest.raises(InputError, match="unknown brush preset"):
        session.handle(SwitchBrush(0.4, "no_such_brush"))


def test_step_times_are_kept_for_the_most_recent_steps_only():
    from paintapp.session.painting import STEP_TIMES_KEPT, SessionStats

    stats = SessionStats()
    for i in range(STEP_TIMES_KEPT + 500):
        stats.step_ms.append(float(i))
    assert len(stats.step_ms) == STEP_TIMES_KEPT
    assert stats.step_ms[0] == 500.0 and stats.step_ms[-1] == STEP_TIMES_KEPT + 499.0
