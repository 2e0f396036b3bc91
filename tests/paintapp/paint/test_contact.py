"""The pressed tip's contact radius, and the sweep's start measured by it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from brushes import RoundCone
from paintapp.canvas.model import Canvas
from paintapp.paint.contact import RAY_SAMPLES, contact_radius_m
from paintapp.paint.paint_scene import load_paint_scene
from paintapp.session.painting import PaintingSession
from tests.support.demo_strokes import StrokeSpec, stroke_samples

#: A round cone: tip sphere 1 mm, belly sphere 4 mm, 20 mm long. The cone's side leaves the tip
#: sphere where its normal tilts by ``asin((4 - 1) / (16 - 1))`` below the horizontal.
CONE = RoundCone(1e-3, 4e-3, 20e-3)
SIN_A = 3.0 / 15.0
COS_A = math.sqrt(1.0 - SIN_A**2)


def cone_radius_m(height_m: float) -> float:
    """The round cone's cut at ``height_m`` above its apex, exactly: the tip sphere's circle
    below the side's tangent point, the side's straight line above it."""
    r1 = 1e-3
    z_touch = r1 * (1.0 - SIN_A)
    if height_m <= z_touch:
        return math.sqrt(r1**2 - (r1 - height_m) ** 2)
    return r1 * COS_A + (height_m - z_touch) * SIN_A / COS_A


@pytest.mark.parametrize("height_m", [0.2e-3, 0.5e-3, 2e-3, 5e-3])
def test_the_contact_radius_bounds_the_cut_from_above_within_one_sample(height_m):
    reach = 4e-3
    exact = cone_radius_m(height_m)
    measured = contact_radius_m(CONE, height_m, reach)
    assert exact <= measured <= exact + reach / (RAY_SAMPLES - 1) + 1e-12


def test_a_tip_cut_below_its_apex_or_with_no_reach_has_no_contact():
    assert contact_radius_m(CONE, -1e-3, 4e-3) == 0.0
    assert contact_radius_m(CONE, 1e-3, 0.0) == 0.0


def fast_stroke_sweeps() -> tuple[list[bool], float, float]:
    """The large round brush dragged at 0.3 m/s (5 mm a sample) across a blank canvas: whether
    each step was laid along its path, the distance the sweep waited for (m) and twice the
    body's reach (m), both at full pressure."""
    texel = 1e-4
    w, h = 900, 300
    paint = np.zeros((1, h, w), np.float32)
    canvas = Canvas((w, h), (w * texel, h * texel), ("ultramarine_blue",), paint, paint[0].copy())
    session = PaintingSession(canvas, "round_large", load_paint_scene("live"))
    session.load_pigment("ultramarine_blue", 1.2e-7)
    spec = StrokeSpec((0.01, 0.015), (0.08, 0.015), 0.07 / 0.3, 0.8, (0.2, 0.0), ramp_s=0.01)
    swept, pose = [], None
    for sample in stroke_samples(spec, 0.0):
        if session.sample(sample).paint is not None:
            swept.append(bool(np.any(session.model.travel_m != 0.0)))
            pose = session.model.pose or pose  # the last pose in the paint, at full pressure
    model = session.model
    assert pose is not None
    model.travelled_m = 0.0  # as at a touch-down here
    return swept, model.sweep_start_m(pose), 2.0 * model.footprint_radius_m(pose)


def test_a_fast_stroke_is_laid_along_its_path_once_clear_of_its_touch_down_print():
    """The sweep waits until the tip has left the print of its touch-down (twice the contact's
    reach and a cell: sweeping that print moved it behind the stroke's start), and no longer.
    Measured by the body's whole width (the large round brush's belly), the first 23 mm of a
    stroke were left unswept: a row of dabs along a fast stroke's start."""
    swept, start, body = fast_stroke_sweeps()
    assert 0.0 < start < 0.4 * body
    assert swept[0] is False  # the touch-down's own step
    # 4.7 mm a step in two sub-steps, the first step without travel: the second move's second
    # sub-step starts 7.0 mm out (the body's width waited for the sixth move)
    assert swept.index(True) <= 2
    assert all(swept[swept.index(True) :])
