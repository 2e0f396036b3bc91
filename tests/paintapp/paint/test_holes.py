"""No holes: a lifted tip's footprint closes over, and the transfer leaves no pinholes."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.ndimage import binary_fill_holes, maximum_filter

from brushes import PaintReservoir
from paintapp.canvas.lattice import count_holes
from paintapp.canvas.model import FILM_FLOOR_M, Canvas
from paintapp.paint.columns_kernels import (
    HOLE_FILL,
    _ascending,
    close_pinholes,
    fill_thin_holes,
    gather_fringe_films,
)
from paintapp.paint.paint_model import PaintModel
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
    out, changed, kept = mobile.copy(), np.ones((9, 9), bool), total.copy()
    assert close_pinholes(out, changed, kept, FILM_FLOOR_M) == 1
    np.testing.assert_allclose(kept, out.sum(axis=0), rtol=1e-12)  # the totals follow the move
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


def test_a_thin_hole_is_filled_from_its_thickest_neighbour_and_a_loop_s_inside_is_not():
    floor = FILM_FLOOR_M
    mobile = np.zeros((2, 16, 16))
    mobile[:, 1:15, 1:15] = 0.8 * floor  # 1.6 floors a texel: less than the pinholes ask
    mobile[:, 3, 3:5] = [[3e-8, 1e-8], [2e-8, 0.0]]  # a hole two texels long, under the floor
    mobile[:, 2, 3] = 2.0 * floor  # their thickest neighbour
    mobile[:, 2, 4] = 1.5 * floor
    mobile[:, 6:14, 6:14] = 5e-6  # a thick loop the brush drew
    mobile[:, 7:13, 7:13] = 0.0  # its inside: 36 texels, no paint
    total = mobile.sum(axis=0)
    out, touched = mobile.copy(), np.zeros((16, 16), bool)
    assert fill_thin_holes(out, touched, total, floor) == 2
    np.testing.assert_allclose(out.sum(axis=(1, 2)), mobile.sum(axis=(1, 2)), rtol=1e-12)
    np.testing.assert_allclose(total, out.sum(axis=0), rtol=1e-12)
    np.testing.assert_allclose(total[3, 3:5], HOLE_FILL * floor, rtol=1e-12)
    given = HOLE_FILL * floor - 5e-8  # (3, 3)'s, half of each pigment (the giver's shares)
    np.testing.assert_allclose(out[:, 3, 3], [3e-8 + given / 2, 2e-8 + given / 2], rtol=1e-12)
    assert out.min() >= 0.0 and total[2, 3] > HOLE_FILL * floor
    assert (total[1:15, 1:15] > floor).sum() == 14 * 14 - 36  # all but the loop's inside
    assert not out[:, 7:13, 7:13].any() and touched.sum() == 3  # the two, and their giver


def test_a_hole_in_a_film_too_thin_to_lift_it_shares_its_thickest_neighbour_s_paint():
    """A texel just under the floor in a film just over it (1.1-1.3 floors, the fringe's
    films): its thickest neighbour could not give what lifts it to ``HOLE_FILL`` floors and keep
    that much, so the two share their paint evenly, both clear of the floor; conserved."""
    floor = FILM_FLOOR_M
    mobile = np.zeros((1, 7, 7))
    mobile[0, 1:6, 1:6] = 1.1 * floor
    mobile[0, 2, 3] = 1.3 * floor  # the thickest neighbour
    mobile[0, 3, 3] = 0.99 * floor  # the hole
    total = mobile.sum(axis=0)
    out, touched = mobile.copy(), np.zeros((7, 7), bool)
    assert fill_thin_holes(out, touched, total, floor) == 1
    np.testing.assert_allclose(out[0, 3, 3], 1.145 * floor, rtol=1e-12)
    np.testing.assert_allclose(out[0, 2, 3], 1.145 * floor, rtol=1e-12)
    np.testing.assert_allclose(out.sum(), mobile.sum(), rtol=1e-12)
    np.testing.assert_allclose(total, out.sum(axis=0), rtol=1e-12)
    assert touched.sum() == 2
    level = mobile.copy()
    level[0, 1:6, 1:6] = 1.0005 * floor  # shared, the level would be within float32's reach
    level[0, 3, 3] = 0.9995 * floor  # of the floor: left as it is
    total = level.sum(axis=0)
    assert fill_thin_holes(level.copy(), np.zeros((7, 7), bool), total, floor) == 0


def test_a_fringe_film_goes_to_its_thickest_neighbour_and_an_inner_one_stays():
    floor = 1e-9
    mobile = np.zeros((2, 5, 7))
    mobile[:, 1:4, 1:6] = 1e-6  # a painted block
    mobile[:, 2, 6] = [2e-10, 1e-10]  # a thin film at its edge, beside unpainted texels
    mobile[:, 1, 5] = 4e-6  # the edge texel's thickest neighbour
    mobile[:, 2, 3] = [3e-10, 3e-10]  # a thin film inside the block: no unpainted texel beside it
    mobile[:, 0, 0] = 5e-10  # a thin film at the edge of a texel that did not change
    total = mobile.sum(axis=0)
    out, touched = mobile.copy(), np.ones((5, 7), bool)
    touched[0, 0] = False
    assert gather_fringe_films(out, touched, total, floor) == 1
    np.testing.assert_allclose(out.sum(axis=(1, 2)), mobile.sum(axis=(1, 2)), rtol=1e-12)
    assert out[:, 2, 6].sum() == 0.0 and total[2, 6] == 0.0
    np.testing.assert_array_equal(out[:, 0, 0], [5e-10, 5e-10])
    np.testing.assert_allclose(out[:, 1, 5], [4e-6 + 2e-10, 4e-6 + 1e-10], rtol=1e-12)
    np.testing.assert_allclose(total, out.sum(axis=0), rtol=1e-12)
    np.testing.assert_array_equal(out[:, 2, 3], [3e-10, 3e-10])
    assert touched[1, 5]


@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(0.0, 1e-9, allow_subnormal=True), max_size=300))
def test_the_fringe_films_are_ordered_thinnest_first(keys):
    """The heapsort that orders the thin films: numpy's stable order (films of equal thickness
    in the order they were listed)."""
    k = np.array(keys, dtype=np.float64)
    np.testing.assert_array_equal(_ascending(k), np.argsort(k, kind="stable"))


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.floats(0.05, 0.6))
def test_gathering_fringe_films_opens_no_hole_and_conserves_each_pigment(seed, thin_share):
    """Random paint of thick, thin (under the floor) and no films: the gathering keeps each
    pigment's total, leaves nothing negative and no thin film beside an unpainted texel, and
    finds no more unpainted texels enclosed by paint than it was given (here none: the holes
    it was given are filled first); a thin film left beside an unpainted texel has no thicker
    neighbour to go to."""
    rng = np.random.default_rng(seed)
    shape = (2, 24, 24)
    kind = rng.choice(3, shape[1:], p=[0.3, thin_share, 0.7 - thin_share])  # none, thin, thick
    mobile = np.where(kind == 1, rng.uniform(1e-13, 1e-9, shape), rng.uniform(1e-7, 1e-5, shape))
    mobile = np.where(kind == 0, 0.0, mobile) / 2.0
    painted = kind > 0
    mobile[:, binary_fill_holes(painted) & ~painted] = 1e-6  # start with no holes
    total = mobile.sum(axis=0)
    out, touched = mobile.copy(), np.ones(shape[1:], bool)
    gather_fringe_films(out, touched, total, 1e-9)
    np.testing.assert_allclose(out.sum(axis=(1, 2)), mobile.sum(axis=(1, 2)), rtol=1e-12)
    assert out.min() >= 0.0
    np.testing.assert_allclose(total, out.sum(axis=0), rtol=1e-12)
    now = out.sum(axis=0) > 0.0
    assert not (binary_fill_holes(now) & ~now).any()
    empty = np.pad(~now, 1)  # beyond the box counts as not known: no edge there
    empty[0, :] = empty[-1, :] = empty[:, 0] = empty[:, -1] = False
    beside = empty[:-2, 1:-1] | empty[2:, 1:-1] | empty[1:-1, :-2] | empty[1:-1, 2:]
    left = out.sum(axis=0)
    ring = np.ones((3, 3), bool)
    ring[1, 1] = False
    thickest_beside = maximum_filter(left, footprint=ring, mode="constant", cval=0.0)
    assert not (now & (left < 1e-9) & beside & (thickest_beside > left)).any()


def test_settle_on_lift_is_a_scene_switch_and_a_bad_value_names_the_key():
    from common.errors import InputError
    from paintapp.paint.paint_scene import parse_paint_scene

    assert parse_paint_scene({}, "s").settle_on_lift is True
    assert parse_paint_scene({"paint": {"settle_on_lift": False}}, "s").settle_on_lift is False
    with pytest.raises(InputError) as err:
        parse_paint_scene({"paint": {"settle_on_lift": "no"}}, "s", "my_scene.toml")
    assert err.value.key == "paint.settle_on_lift" and "my_scene.toml" in str(err.value)
