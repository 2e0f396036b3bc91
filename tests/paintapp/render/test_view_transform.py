"""The painting window's view: one map from widget pixels to canvas metres and back, the GPU's
matrix the same map, zoom and turn about a held point, and the texels left to shade in sight."""

from __future__ import annotations

import math

import numpy as np
import pytest

from paintapp.render.sight import outside, split_stale, texel_box_in_sight
from paintapp.render.view import ViewRect
from paintapp.render.view_transform import MAX_ZOOM, MIN_ZOOM, CanvasView

A4_M = (0.21, 0.297)
TEXEL_M = 1e-4
#: Odd views: zoom (device pixels per texel), angle (degrees), centre (m), widget (px).
ODD_VIEWS = [
    (1.0, 0.0, (0.105, 0.1485), (1180, 760)),
    (4.0, 30.0, (0.0371, 0.2113), (901, 633)),
    (0.073, -117.3, (0.5, -0.2), (320, 240)),
    (13.7, 179.9, (0.2, 0.01), (1599, 999)),
    (0.37, 271.0, (0.0, 0.0), (641, 1)),
]


def _view(zoom: float, angle_deg: float, centre, widget, ratio: float = 1.0) -> CanvasView:
    return CanvasView(centre, TEXEL_M * ratio / zoom, math.radians(angle_deg), widget)


@pytest.mark.parametrize(("zoom", "angle", "centre", "widget"), ODD_VIEWS)
def test_widget_to_canvas_and_back_is_the_identity(zoom, angle, centre, widget):
    view = _view(zoom, angle, centre, widget)
    rng = np.random.default_rng(3)
    for x, y in rng.uniform(-200, 2000, (50, 2)):
        x_m, y_m = view.to_canvas(x, y)
        assert view.to_widget(x_m, y_m) == pytest.approx((x, y), abs=1e-7)
    points = rng.uniform(-0.1, 0.4, (50, 2))
    px = view.to_widget_array(points)
    back = np.array([view.to_canvas(*p) for p in px])
    np.testing.assert_allclose(back, points, atol=1e-12)
    np.testing.assert_allclose(px, [view.to_widget(*p) for p in points], atol=1e-9)


@pytest.mark.parametrize(("zoom", "angle", "centre", "widget"), ODD_VIEWS)
def test_the_gpu_matrix_is_the_same_map(zoom, angle, centre, widget):
    """Clip coordinates (y up, [-1, 1] across the widget) of a canvas point agree with its
    widget pixel, so that what is drawn under the pen is what the pen paints on."""
    view = _view(zoom, angle, centre, widget)
    m = view.matrix().astype(np.float64)
    w, h = widget
    for x_m, y_m in np.random.default_rng(5).uniform(-0.1, 0.4, (20, 2)):
        clip = m @ np.array([x_m, y_m, 1.0])
        px, py = view.to_widget(x_m, y_m)
        assert clip[0] == pytest.approx(2.0 * px / w - 1.0, abs=1e-4 * max(1.0, abs(clip[0])))
        assert clip[1] == pytest.approx(1.0 - 2.0 * py / h, abs=1e-4 * max(1.0, abs(clip[1])))


def test_the_view_turns_the_canvas_counter_clockwise_on_screen():
    view = CanvasView((0.0, 0.0), 1e-3, math.radians(90.0), (200, 100))
    # canvas +x (right) shows up on screen (y down: smaller y)
    assert view.to_widget(0.01, 0.0) == pytest.approx((100.0, 40.0))
    assert view.to_widget(0.0, 0.01) == pytest.approx((90.0, 50.0))  # canvas up shows left


def test_the_upright_fit_is_the_canvas_centred_with_a_margin():
    view = CanvasView.fit(A4_M, (1180, 760))
    assert view.angle_rad == 0.0
    assert view.metres_per_px == pytest.approx(max(0.21 / 1156, 0.297 / 736))
    left, top, right, bottom = view.widget_box((0.0, 0.0, *A4_M))
    assert top == pytest.approx(12.0) and bottom == pytest.approx(748.0)
    assert 0.5 * (left + right) == pytest.approx(590.0)
    # the upright view draws what an upright rectangle of the canvas would
    half_w, half_h = 590 * view.metres_per_px, 380 * view.metres_per_px
    rect = ViewRect(0.105 - half_w, 0.1485 - half_h, 0.105 + half_w, 0.1485 + half_h)
    np.testing.assert_allclose(view.matrix(), rect.matrix(), rtol=1e-5, atol=1e-5)
    assert view.metres_per_pixel((2360, 1520)) == pytest.approx(rect.metres_per_pixel((2360, 1520)))


@pytest.mark.parametrize("angle", [0.0, 30.0, 90.0, -135.0])
def test_a_turned_fit_shows_the_whole_canvas(angle):
    view = CanvasView.fit(A4_M, (900, 600), math.radians(angle))
    left, top, right, bottom = view.widget_box((0.0, 0.0, *A4_M))
    assert left >= 12 - 1e-6 and top >= 12 - 1e-6
    assert right <= 888 + 1e-6 and bottom <= 588 + 1e-6
    assert min(left - 12, top - 12, 888 - right, 588 - bottom) < 1e-6  # touches a margin


@pytest.mark.parametrize(("zoom", "angle", "centre", "widget"), ODD_VIEWS)
def test_zoom_pan_and_turn_keep_the_held_point_under_the_pointer(zoom, angle, centre, widget):
    view = _view(zoom, angle, centre, widget)
    anchor = (0.37 * widget[0], 0.81 * widget[1])
    held = view.to_canvas(*anchor)
    for changed in (view.zoomed(1.25**3, anchor), view.zoomed(0.41, anchor)):
        assert changed.to_canvas(*anchor) == pytest.approx(held, abs=1e-12)
    turned = view.rotated(math.radians(47.0), anchor)
    assert turned.to_canvas(*anchor) == pytest.approx(held, abs=1e-12)
    assert math.degrees(turned.angle_rad - view.angle_rad) % 360 == pytest.approx(47.0)
    moved = view.panned(13.5, -7.25)  # the canvas follows the hand
    assert moved.to_canvas(anchor[0] + 13.5, anchor[1] - 7.25) == pytest.approx(held, abs=1e-12)


def test_the_zoom_counts_device_pixels_per_texel_and_is_held_within_its_limits():
    view = CanvasView.fit(A4_M, (1180, 760))
    for ratio in (1.0, 2.0, 1.25):
        actual = view.with_zoom(1.0, TEXEL_M, ratio)
        assert actual.zoom(TEXEL_M, ratio) == pytest.approx(1.0)
        # one texel spans 1/ratio logical pixels: one device pixel
        a = actual.to_widget(0.1, 0.1)
        b = actual.to_widget(0.1 + TEXEL_M, 0.1)
        assert (b[0] - a[0]) * ratio == pytest.approx(1.0)
    assert view.with_zoom(100.0, TEXEL_M, 1.0).zoom(TEXEL_M, 1.0) == pytest.approx(MAX_ZOOM)
    assert view.with_zoom(1e-4, TEXEL_M, 1.0).zoom(TEXEL_M, 1.0) == pytest.approx(MIN_ZOOM)
    far = view.zoomed(1e6)
    assert far.clamped(TEXEL_M, 1.0).zoom(TEXEL_M, 1.0) == pytest.approx(MAX_ZOOM)


def test_a_view_refuses_what_no_screen_shows():
    with pytest.raises(ValueError):
        CanvasView((0.0, math.nan), 1e-4)
    with pytest.raises(ValueError):
        CanvasView((0.0, 0.0), 0.0)
    view = CanvasView((0.0, 0.0), 1e-4, 0.0, (100, 100))
    assert view.zoomed(math.inf) is view and view.panned(math.nan, 0.0) is view


def test_what_is_in_sight_is_shaded_and_the_rest_waits():
    view = CanvasView((0.0105, 0.0052), 1e-5, math.radians(30.0), (200, 100))
    x0, y0, x1, y1 = view.visible_box_m()
    corners = [view.to_canvas(x, y) for x, y in ((0, 0), (200, 0), (0, 100), (200, 100))]
    for cx, cy in corners:
        assert x0 - 1e-12 <= cx <= x1 + 1e-12 and y0 - 1e-12 <= cy <= y1 + 1e-12
    sight = texel_box_in_sight(view.visible_box_m(), (TEXEL_M, TEXEL_M), (300, 200))
    assert sight is not None
    sx0, _sy0, sx1, _sy1 = sight
    assert sx0 <= math.floor(x0 / TEXEL_M) and sx1 >= math.ceil(x1 / TEXEL_M)
    whole = (0, 0, 300, 200)
    shade, rest = split_stale([whole], sight)
    assert shade == [sight]
    covered = np.zeros((200, 300), int)
    for bx0, by0, bx1, by1 in [sight, *rest]:
        covered[by0:by1, bx0:bx1] += 1
    assert covered.min() == 1 and covered.max() == 1  # the rest is the whole less the sight
    shade, rest = split_stale(rest, sight)
    assert shade == [] and len(rest) == 4  # nothing more in sight
    shade, rest = split_stale(rest, None)  # everything in sight
    assert shade == [whole] and rest == []
    assert outside((0, 0, 10, 10), (20, 20, 30, 30)) == [(0, 0, 10, 10)]
