"""Paint that holds still: a column changing by less than a share of its paint keeps it."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.ndimage import distance_transform_edt

from brushes import PaintReservoir
from common.errors import InputError
from paintapp.canvas.model import Canvas
from paintapp.paint.paint_scene import parse_paint_scene
from paintapp.paint.still import keep_still
from paintapp.session.painting import PaintingSession, paint_inventory
from tests.paintapp.paint.test_paint_transfer import paint, small_scene
from tests.support.demo_strokes import StrokeSpec

RED = "cadmium_red"


def random_step(seed: int, pigments: int) -> tuple[np.ndarray, np.ndarray]:
    """Columns' paint (P, 12, 12), some empty, and a change that leaves none negative: large
    near one corner, falling off as exp(-distance) from it (as the transport's tails do)."""
    rng = np.random.default_rng(seed)
    owned = rng.uniform(0.0, 1.0, (pigments, 12, 12)) * (rng.uniform(size=(1, 12, 12)) > 0.2)
    i, j = np.mgrid[0:12, 0:12]
    size = np.exp(-0.8 * np.hypot(i - 2.0, j - 3.0))
    change = rng.uniform(-1.0, 1.0, owned.shape) * size[None]
    change = np.maximum(change, -owned)
    return owned, change


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 3), st.sampled_from([1e-3, 1e-2, 0.1]))
def test_still_columns_keep_their_paint_and_the_step_s_paint_is_conserved(seed, pigments, share):
    owned, change = random_step(seed, pigments)
    out = keep_still(owned, change, share)
    held = owned.sum(axis=0)
    moving = np.any(change != 0.0, axis=0)
    still = moving & (held > 0.0) & np.all(np.abs(change) < share * held, axis=0)
    if out is change:  # nothing still, or the net change could not be placed
        return
    assert still.any()
    assert not out[:, still].any()  # a still column keeps its paint exactly
    np.testing.assert_allclose(out.sum(axis=(1, 2)), change.sum(axis=(1, 2)), atol=1e-12)
    assert (owned + out).min() >= -1e-12  # no column asked for more than it holds
    assert not out[:, ~moving].any()  # nothing lands on a column the step left alone


def test_a_column_without_paint_is_never_still():
    owned = np.zeros((1, 3, 1))
    owned[0, 0, 0] = 1.0
    change = np.array([[[0.5], [1e-9], [0.0]]])
    out = keep_still(owned, change, 0.1)
    np.testing.assert_array_equal(out, change)  # the bare column's tiny gain is kept


def test_a_still_column_s_gain_goes_to_the_gaining_columns_and_its_loss_to_the_losing_ones():
    owned = np.ones((1, 4, 1))
    change = np.array([[[0.3], [0.1], [-0.4], [0.001]]])
    out = keep_still(owned, change, 0.01)
    assert out[0, 3, 0] == 0.0
    np.testing.assert_allclose(out[0, :3, 0], [0.3 + 0.00075, 0.1 + 0.00025, -0.4])
    change = np.array([[[0.3], [0.1], [-0.4], [-0.001]]])
    out = keep_still(owned, change, 0.01)
    np.testing.assert_allclose(out[0, :3, 0], [0.3 - 0.00075, 0.1 - 0.00025, -0.4])


def test_a_net_loss_no_column_can_give_leaves_the_change_as_it_is():
    owned = np.array([[[1.0], [0.5], [1.0]]])
    change = np.array([[[-0.009], [-0.5], [0.0]]])  # the loser is emptied; nothing gains
    np.testing.assert_array_equal(keep_still(owned, change, 0.01), change)


def test_a_scene_s_still_rate_is_read_and_a_bad_one_named():
    assert parse_paint_scene({}, "x").still_rate_per_s == 0.3
    assert parse_paint_scene({"paint": {"still_rate_per_s": 0}}, "x").still_rate_per_s == 0.0
    for bad in (-0.1, 11.0, float("nan"), "fast"):
        with pytest.raises(InputError, match=r"paint\.still_rate_per_s"):
            parse_paint_scene({"paint": {"still_rate_per_s": bad}}, "x")


def test_a_share_of_zero_keeps_every_change():
    owned, change = random_step(3, 2)
    assert keep_still(owned, change, 0.0) is change


def wet_layer() -> Canvas:
    """A 0.5 mm layer of wet red over a 3 x 2 cm canvas."""
    layer = np.full((1, 80, 120), 5e-4, np.float32)
    return Canvas((120, 80), (0.03, 0.02), (RED,), layer, np.ones((80, 120), np.float32))


def drag(still_rate_per_s: float) -> tuple[Canvas, PaintingSession]:
    scene = dataclasses.replace(small_scene("default"), still_rate_per_s=still_rate_per_s)
    canvas = wet_layer()
    session = PaintingSession(canvas, "round_small", scene)
    paint(session, StrokeSpec((0.008, 0.010), (0.022, 0.010), 0.5, 1.0), 0.0)
    return canvas, session


def test_the_paint_far_from_the_brush_holds_still_and_the_stroke_is_the_same():
    """The grid's Newtonian flow reaches its sides: without a still rate every column the grid
    ever covered creeps a little (measured: texels up to 11.5 mm from the tip's path moved,
    3 100 of them beyond 6 mm); with the default rate none beyond 5.3 mm did (the brush's ridges
    reach 4-5 mm), and the stroke's cross-section barely changes."""
    canvas, session = drag(0.3)
    creeping, _ = drag(0.0)
    y, x = (np.mgrid[0:80, 0:120] + 0.5) * canvas.texel_size_m[0]
    on_path = (np.abs(y - 0.010) < 2e-4) & (x > 0.008) & (x < 0.022)
    far = distance_transform_edt(~on_path) * canvas.texel_size_m[0] > 6e-3
    start = wet_layer().height_m
    moved_far = far & (canvas.height_m != start)
    crept_far = far & (creeping.height_m != start)
    assert not moved_far.any()
    assert crept_far.sum() > 100
    # the stroke's cross-section (its middle stretch, averaged along it): 2.7 % of the layer
    # apart at most (measured), the paint the still columns leave out going to the moving ones
    held, crept = (c.height_m[:, 48:72].mean(axis=1) for c in (canvas, creeping))
    assert np.abs(held - crept).max() < 0.05 * 5e-4
    before = paint_inventory(wet_layer(), PaintReservoir(1e-6))[RED]
    after = paint_inventory(canvas, session.reservoir)[RED]
    np.testing.assert_allclose(after, before, rtol=1e-6)
