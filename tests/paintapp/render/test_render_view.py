"""The renderer through the painting window's view: a turned view draws the canvas turned, a
canvas point is drawn where the view maps it, magnified texels are sharp, and only the stale
texels in sight are shaded."""

from __future__ import annotations

import math

import numpy as np
import pytest

from paintapp.canvas.model import Canvas
from paintapp.pigments.bands import canvas_band_table, canvas_linear_rgb
from paintapp.render import CanvasRenderer, Lighting
from paintapp.render.view_transform import CanvasView

UNLIT = Lighting(enabled=False)
TEXEL_M = 1e-4


def striped_canvas(w: int = 24, h: int = 16) -> Canvas:
    """Blue on the left, yellow in the middle, a red block, bare ground elsewhere."""
    canvas = Canvas((w, h), (w * TEXEL_M, h * TEXEL_M))
    blue, yellow, red = (
        canvas.add_pigment(n) for n in ("ultramarine_blue", "cadmium_yellow", "cadmium_red")
    )
    canvas.paint_m[blue, :, 0:6] = 1e-3
    canvas.paint_m[yellow, 3:, 9:13] = 1e-3
    canvas.paint_m[red, 10:14, 16:21] = 1e-3
    return canvas


def marked_canvas(w: int, h: int, at: tuple[int, int], side: int) -> Canvas:
    """Bare ground with one red square of ``side`` texels from texel ``at``."""
    canvas = Canvas((w, h), (w * TEXEL_M, h * TEXEL_M))
    red = canvas.add_pigment("cadmium_red")
    x, y = at
    canvas.paint_m[red, y : y + side, x : x + side] = 1e-3
    return canvas


def reference(canvas: Canvas, library) -> np.ndarray:
    return canvas_linear_rgb(canvas, canvas_band_table(canvas, library))


def test_a_quarter_turn_draws_the_canvas_turned(ctx, library):
    """Turned 90 degrees counter-clockwise at one texel per pixel: output pixel (row r, column c;
    row 0 at the bottom) shows canvas texel (column r, row H - 1 - c)."""
    canvas = striped_canvas()
    h, w = canvas.height, canvas.width
    view = CanvasView((0.5 * w * TEXEL_M, 0.5 * h * TEXEL_M), TEXEL_M, 0.5 * math.pi, (h, w))
    renderer = CanvasRenderer(ctx, library, lighting=UNLIT)
    rgba = renderer.render_linear_rgba(canvas, size=(h, w), view=view)
    ref = reference(canvas, library)
    rows, cols = np.meshgrid(np.arange(w), np.arange(h), indexing="ij")
    expected = ref[h - 1 - cols, rows]
    np.testing.assert_allclose(rgba[..., :3], expected, rtol=1e-2, atol=3e-3)
    renderer.release()


@pytest.mark.parametrize(("zoom", "angle_deg"), [(1.0, 0.0), (4.0, 30.0), (2.5, -117.0)])
@pytest.mark.parametrize("cached", [False, True])
def test_a_canvas_point_is_drawn_where_the_view_maps_it(ctx, library, zoom, angle_deg, cached):
    canvas = marked_canvas(120, 90, (70, 31), 4)
    centre_m = (71 * TEXEL_M + 0.3e-4, 40 * TEXEL_M)
    size = (160, 120)
    view = CanvasView(centre_m, TEXEL_M / zoom, math.radians(angle_deg), size)
    renderer = CanvasRenderer(ctx, library, lighting=UNLIT)
    renderer.update(canvas)
    if cached:
        renderer.render_cached(size, view)
    else:
        renderer.render(size, view)
    rgba = renderer.read_linear_rgba()[::-1]  # row 0 = top, as the widget's pixels
    red = (rgba[..., 0] > 0.2) & (rgba[..., 2] < 0.1)
    ys, xs = np.nonzero(red)
    if cached:  # sharp texels: the square covers its own area (the direct path blurs it)
        assert len(xs) == pytest.approx(16 * zoom**2, rel=0.25)
    x_px, y_px = view.to_widget(72 * TEXEL_M, 33 * TEXEL_M)  # the square's centre
    assert xs.mean() + 0.5 == pytest.approx(x_px, abs=0.5)
    assert ys.mean() + 0.5 == pytest.approx(y_px, abs=0.5)
    renderer.release()


def test_magnified_texels_are_drawn_sharp(ctx, library):
    """At 400 % each texel is a uniform 4 x 4 block of its own colour (no blur between them)."""
    canvas = striped_canvas()
    view = CanvasView((12 * TEXEL_M, 8 * TEXEL_M), TEXEL_M / 4, 0.0, (96, 64))
    renderer = CanvasRenderer(ctx, library, lighting=UNLIT)
    renderer.update(canvas)
    renderer.render_cached((96, 64), view)
    rgba = renderer.read_linear_rgba()[..., :3]
    blocks = rgba.reshape(16, 4, 24, 4, 3)
    assert np.ptp(blocks, axis=(1, 3)).max() == 0.0
    np.testing.assert_allclose(blocks[:, 0, :, 0], reference(canvas, library), rtol=2e-3, atol=2e-3)
    renderer.release()


def test_only_the_stale_texels_in_sight_are_shaded_and_the_rest_when_shown(ctx, library):
    lit = Lighting(enabled=True, relief=50.0)
    canvas = striped_canvas(240, 160)
    renderer = CanvasRenderer(ctx, library, lighting=lit)
    renderer.update(canvas)
    close = CanvasView((30 * TEXEL_M, 20 * TEXEL_M), TEXEL_M / 8, math.radians(30.0), (160, 120))
    shaded = renderer.render_cached((160, 120), close)
    assert shaded is not None
    x0, y0, x1, y1 = shaded
    assert (x1 - x0) * (y1 - y0) < 0.05 * 240 * 160  # a corner of the canvas, not all of it
    sx0, _sy0, sx1, _sy1 = close.visible_box_m()
    assert x0 >= math.floor(sx0 / TEXEL_M) - 1 and x1 <= math.ceil(sx1 / TEXEL_M) + 1
    assert renderer.render_cached((160, 120), close) is None  # nothing stale in sight
    whole = CanvasView.fit(canvas.size_m, (240, 160), margin_px=0)
    assert renderer.render_cached((240, 160), whole) is not None  # the rest, now in sight
    picture = renderer.read_linear_rgba()
    fresh = CanvasRenderer(ctx, library, lighting=lit)
    fresh.update(canvas)
    fresh.render_cached((240, 160), whole)
    np.testing.assert_array_equal(picture, fresh.read_linear_rgba())
    renderer.release()
    fresh.release()
