"""No holes: a lifted tip's footprint closes over, and the transfer leaves no pinholes."""

from __future__ import annotations

import numpy as np
import pytest

from brushes import PaintReservoir
from paintapp.canvas.lattice import count_holes
from paintapp.canvas.model import FILM_FLOOR_M, Canvas
from paintapp.paint.paint_model import PaintModel
from paintapp.paint.texel_transfer import close_pinholes
from paintapp.session.painting import PaintingSession, paint_inventory
from tests.paintapp.paint.test_paint_transfer import paint, small_scene
from tests.support.demo_strokes import StrokeSpec

RED = "cadmium_red"


def wet_layer() -> Canvas:
    """A 0.5 mm layer of wet red over the middle of a 3 cm canvas, a bare margin round it."""
    layer = np.zeros((1, 120, 120), np.float32)
    layer[0, 20:100, 20:100] = 5e-4
    wet = np.zeros((120, 120), np.float32)
    wet[20:100, 20:100] = 1.0
    return Canvas((120, 120), (0.03, 0.03), (RED,), layer, wet)


def drag_probe(canvas: Canvas, scene: str = "default") -> PaintingSession:
    session = PaintingSession(canvas, "square_probe", small_scene(scene))
    paint(session, StrokeSpec((0.009, 0.015), (0.019, 0.016), 0.5, 1.0), 0.0)
    return session


def pit_m(canvas: Canvas) -> float:
    """The thinnest paint where the probe was lifted (within 1.5 mm of the stroke's end)."""
    y, x = (np.mgrid[0:120, 0:120] + 0.5) * canvas.texel_size_m[0]
    near = np.hypot(x - 0.019, y - 0.016) < 0.0015
    return float(canvas.height_m[near].min())


@pytest.mark.parametrize("scene", ["default", "thin_glaze"])
def test_a_lifted_probe_leaves_no_hole_in_wet_paint(scene, monkeypatch):
    canvas = wet_layer()
    before = paint_inventory(canvas, PaintReservoir(1e-6))[RED]
    session = drag_probe(canvas, scene)
    assert count_holes(canvas.height_m) == (0, 0)
    assert pit_m(canvas) > 0.1 * 5e-4  # the paint closed over the footprint
    assert canvas.paint_m.min() >= 0.0
    after = paint_inventory(canvas, session.reservoir)[RED]  # canvas and brush
    np.testing.assert_allclose(after, before, rtol=1e-6)
    # Without the paint closing in at lift-off, the probe's print stays a pit to the canvas.
    monkeypatch.setattr(PaintModel, "settles_on_lift", False)
    print_left = wet_layer()
    drag_probe(print_left, scene)
    assert pit_m(print_left) < 0.02 * 5e-4


def test_lift_off_moves_no_dry_paint_and_conserves_the_wet():
    canvas = wet_layer()
    canvas.wetness[20:100, 20:60] = 0.0  # the left half is dry
    before = canvas.paint_m.astype(np.float64)
    start = paint_inventory(canvas, PaintReservoir(1e-6))[RED]
    session = drag_probe(canvas)
    # Wet paint may be pushed over the dry half, but none of the dry paint leaves it.
    dry_before = before[:, :, :60].sum(axis=0)
    assert np.all(canvas.height_m[:, :60] >= dry_before.astype(np.float32) * (1 - 1e-6))
    assert not np.array_equal(canvas.paint_m, before.astype(np.float32))  # the wet half moved
    after = paint_inventory(canvas, session.reservoir)[RED]
    np.testing.assert_allclose(after, start, rtol=1e-6)


def test_a_pinhole_is_filled_from_its_neighbours_conserving_each_pigment():
    rng = np.random.default_rng(3)
    mobile = rng.uniform(1e-6, 1e-5, (2, 9, 9))
    mobile[:, 4, 4] = 1e-9  # a pinhole
    mobile[:, 0, 0] = 0.0  # on the box's edge: left alone
    total = mobile.sum(axis=0)  # no dry paint under the texels
    out, changed = mobile.copy(), np.ones((9, 9), bool)
    assert close_pinholes(out, changed, total, FILM_FLOOR_M) == 1
    np.testing.assert_allclose(out.sum(axis=(1, 2)), mobile.sum(axis=(1, 2)), rtol=1e-12)
    assert out.min() >= 0.0 and out[:, 4, 4].sum() > FILM_FLOOR_M
    neighbours = mobile[:, 3:6, 3:6].sum(axis=(1, 2)) - mobile[:, 4, 4]
    np.testing.assert_allclose(out[:, 4, 4], mobile[:, 4, 4] + neighbours / 9.0)
    assert out[:, 0, 0].sum() == 0.0
    assert changed[4, 4] and changed[3:6, 3:6].all()
    same, untouched = mobile.copy(), np.zeros((9, 9), bool)  # unchanged texels are no pinholes
    assert close_pinholes(same, untouched, total, FILM_FLOOR_M) == 0
    assert np.array_equal(same, mobile) and not untouched.any()
    under_dry = total + 1e-5  # dry paint under the hole: not a hole
    same, changed = mobile.copy(), np.ones((9, 9), bool)
    assert close_pinholes(same, changed, under_dry, FILM_FLOOR_M) == 0
    assert np.array_equal(same, mobile)


def test_settle_on_lift_is_a_scene_switch_and_a_bad_value_names_the_key():
    from common.errors import InputError
    from paintapp.paint.paint_scene import parse_paint_scene

    assert parse_paint_scene({}, "s").settle_on_lift is True
    assert parse_paint_scene({"paint": {"settle_on_lift": False}}, "s").settle_on_lift is False
    with pytest.raises(InputError) as err:
        parse_paint_scene({"paint": {"settle_on_lift": "no"}}, "s", "my_scene.toml")
    assert err.value.key == "paint.settle_on_lift" and "my_scene.toml" in str(err.value)
