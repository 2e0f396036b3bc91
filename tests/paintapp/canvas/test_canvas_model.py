"""The canvas data model: validation, derived fields, coordinates, dirty regions, drying."""

from __future__ import annotations

import math

import numpy as np
import pytest

from common.errors import InputError
from paintapp.canvas.model import DRY_BATCH, DRY_THRESHOLD, MAX_PIGMENTS, Canvas


def make_canvas(w: int = 8, h: int = 6) -> Canvas:
    return Canvas(pixels=(w, h), size_m=(w * 1e-3, h * 1e-3))


def test_new_canvas_is_bare_dry_and_fully_dirty():
    canvas = make_canvas()
    assert canvas.paint_m.shape == (0, 6, 8) and canvas.paint_m.dtype == np.float32
    assert canvas.wetness.shape == (6, 8) and not canvas.wetness.any()
    assert canvas.take_dirty() == (0, 0, 8, 6)
    assert canvas.take_dirty() is None


@pytest.mark.parametrize(
    ("pixels", "size_m"),
    [((0, 4), (1.0, 1.0)), ((4097, 4), (1.0, 1.0)), ((4, 4), (0.0, 1.0)), ((4, 4), (math.nan, 1))],
)
def test_invalid_sizes_are_rejected(pixels, size_m):
    with pytest.raises(InputError):
        Canvas(pixels=pixels, size_m=size_m)


def test_largest_canvas_is_accepted():
    canvas = Canvas(pixels=(4096, 4096), size_m=(0.4, 0.4))
    assert canvas.texel_size_m == pytest.approx((0.4 / 4096, 0.4 / 4096))


def test_non_finite_arrays_are_rejected_with_a_count():
    paint = np.zeros((1, 6, 8), np.float32)
    paint[0, 1, 2] = np.nan
    paint[0, 3, 4] = np.inf
    with pytest.raises(InputError, match="2 non-finite"):
        Canvas((8, 6), (0.008, 0.006), ("cadmium_red",), paint_m=paint)


def test_add_pigment_adds_an_empty_channel_once():
    canvas = make_canvas()
    assert canvas.add_pigment("cadmium_red") == 0
    assert canvas.add_pigment("titanium_white") == 1
    assert canvas.add_pigment("cadmium_red") == 0
    assert canvas.pigment_names == ("cadmium_red", "titanium_white")
    assert canvas.paint_m.shape == (2, 6, 8) and not canvas.paint_m.any()
    assert canvas.pigment_index("titanium_white") == 1
    with pytest.raises(InputError):
        canvas.pigment_index("ultramarine_blue")
    with pytest.raises(InputError):
        canvas.add_pigment("Not A Name")


def test_pigment_count_is_limited():
    canvas = make_canvas()
    for i in range(MAX_PIGMENTS):
        canvas.add_pigment(f"p{i}")
    with pytest.raises(InputError, match="at most"):
        canvas.add_pigment("one_more")


def test_height_is_the_sum_and_concentrations_are_fractions():
    canvas = make_canvas()
    a, b = canvas.add_pigment("a"), canvas.add_pigment("b")
    canvas.paint_m[a, 1, 1] = 3e-4
    canvas.paint_m[b, 1, 1] = 1e-4
    canvas.paint_m[b, 2, 5] = 2e-4
    assert canvas.height_m[1, 1] == pytest.approx(4e-4)
    conc = canvas.concentration
    assert conc[:, 1, 1] == pytest.approx([0.75, 0.25])
    assert conc[:, 2, 5] == pytest.approx([0.0, 1.0])
    assert not conc[:, 0, 0].any()  # bare canvas: no pigment at all, not NaN
    painted = canvas.height_m > 0
    assert np.allclose(conc.sum(axis=0)[painted], 1.0)


def test_metres_and_texels_convert_both_ways():
    canvas = Canvas(pixels=(100, 50), size_m=(0.2, 0.1))  # 2 mm texels
    fx, fy = canvas.metres_to_texel(0.011, 0.005)
    assert (float(fx), float(fy)) == pytest.approx((5.5, 2.5))
    x, y = canvas.texel_to_metres(5, 2)  # centre of texel (5, 2)
    assert (float(x), float(y)) == pytest.approx((0.011, 0.005))
    assert canvas.texel_box_m(0.003, 0.003, 0.0071, 0.005) == (1, 1, 4, 3)
    assert canvas.texel_box_m(-1.0, -1.0, 5.0, 5.0) == (0, 0, 100, 50)
    assert canvas.texel_box_m(1.0, 1.0, 2.0, 2.0) is None


def test_dirty_boxes_merge_and_clip():
    canvas = make_canvas()
    canvas.take_dirty()
    canvas.mark_dirty(1, 1, 3, 2)
    canvas.mark_dirty(5, 0, 20, 1)
    assert canvas.peek_dirty() == (1, 0, 8, 2)
    assert canvas.take_dirty() == (1, 0, 8, 2)
    canvas.mark_dirty(-5, -5, -1, -1)  # entirely outside
    assert canvas.take_dirty() is None


def test_write_region_clips_sanitises_and_marks_dirty():
    canvas = make_canvas()
    canvas.add_pigment("a")
    canvas.take_dirty()
    block = np.full((1, 3, 4), 1e-4, np.float32)
    block[0, 0, 0] = np.nan
    block[0, 1, 1] = -1e-9  # round-off below zero is clamped, not counted
    wet = np.ones((3, 4), np.float32)
    replaced = canvas.write_region(6, 4, block, wet)  # overhangs the top-right corner
    assert replaced == 1
    assert canvas.take_dirty() == (6, 4, 8, 6)
    assert canvas.paint_m[0, 4, 6] == 0.0  # the NaN became 0
    assert canvas.paint_m[0, 5, 6] == pytest.approx(1e-4)
    assert canvas.paint_m[0, 5, 7] == 0.0  # clamped
    assert canvas.wetness[4:6, 6:8].all()
    assert np.isfinite(canvas.paint_m).all()
    with pytest.raises(InputError, match="1 non-finite"):
        canvas.write_region(0, 0, block[:, :1, :1], strict=True)


def test_drying_decays_wetness_exponentially_then_stops():
    canvas = make_canvas()
    canvas.add_pigment("a")
    canvas.write_region(2, 2, np.full((1, 2, 2), 1e-4), np.ones((2, 2)))
    canvas.take_dirty()
    canvas.dry(dt_s=1.0, rate_per_s=0.5)
    assert canvas.wetness[2, 2] == pytest.approx(math.exp(-0.5), rel=1e-6)
    assert canvas.take_dirty() is None  # the paint did not change
    assert canvas.take_wet_dirty() == (2, 2, 4, 4)  # only the wet area's wetness is re-uploaded
    canvas.dry(dt_s=0.01, rate_per_s=0.5)  # a 0.5 % drop: gathered, not yet applied or shown
    assert canvas.take_wet_dirty() is None
    assert canvas.wetness[2, 2] == pytest.approx(math.exp(-0.5), rel=1e-6)
    for _ in range(5):
        canvas.dry(dt_s=0.01, rate_per_s=0.5)
    exact = math.exp(-0.5 - 6 * 0.005)
    assert abs(canvas.wetness[2, 2] / exact - 1.0) < DRY_BATCH  # lags by under a batch
    assert canvas.take_wet_dirty() == (2, 2, 4, 4)  # 3 % in all: shown
    canvas.dry(dt_s=100.0, rate_per_s=0.5)
    assert not canvas.wetness.any() and DRY_THRESHOLD > 0
    assert canvas.take_wet_dirty() == (2, 2, 4, 4) and canvas.take_dirty() is None
    canvas.dry(dt_s=1.0, rate_per_s=0.5)  # fully dry: nothing to do, nothing dirty
    assert canvas.take_dirty() is None and canvas.take_wet_dirty() is None
    with pytest.raises(InputError):
        canvas.dry(dt_s=-1.0, rate_per_s=0.5)
