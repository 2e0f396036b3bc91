"""The renderer lights the canvas's tooth with the paint: bare and under thin paint, not under thick."""

from __future__ import annotations

import numpy as np
import pytest

from paintapp.canvas.model import Canvas
from paintapp.render import (
    CanvasRenderer,
    Lighting,
    ViewRect,
)

SIZE = (240, 160)  # 0.1 mm texels


@pytest.fixture(scope="module")
def renderer(ctx, library):
    r = CanvasRenderer(ctx, library)
    yield r
    r.release()


def painted(surface: str, thickness_m: float) -> Canvas:
    """The left half bare, the right half under ``thickness_m`` of cadmium red."""
    canvas = Canvas(SIZE, (0.024, 0.016), ("cadmium_red",), surface=surface)
    canvas.paint_m[0, :, 120:] = thickness_m
    return canvas


def luminance(renderer: CanvasRenderer, canvas: Canvas, lighting: Lighting | None = None):
    renderer.lighting = lighting or Lighting()
    rgba = renderer.render_linear_rgba(canvas)
    return rgba[..., :3] @ np.array([0.2126, 0.7152, 0.0722])


def shading_relief(lum: np.ndarray, cols: slice) -> float:
    """Spread of the brightness over a half (away from its edges), relative to its mean."""
    part = lum[10:-10, cols]
    return float(part.std() / part.mean())


def test_bare_and_thinly_painted_tooth_shows_and_thick_paint_hides_it(renderer):
    thin = luminance(renderer, painted("cotton_duck", 10e-6))
    assert shading_relief(thin, slice(10, 110)) > 0.02  # bare tooth
    assert shading_relief(thin, slice(130, 230)) > 0.02  # through thin paint
    thick = luminance(renderer, painted("cotton_duck", 1e-3))
    assert shading_relief(thick, slice(130, 230)) < 1e-3  # a millimetre of paint hides it
    smooth = luminance(renderer, painted("smooth", 10e-6))
    assert shading_relief(smooth, slice(10, 110)) < 1e-4  # the flat canvas, as before


def test_the_tooth_follows_the_light_and_is_absent_unlit(renderer):
    canvas = painted("cold_press", 0.0)
    lit = luminance(renderer, canvas)
    tooth = canvas.tooth_m.astype(float)
    # slopes facing the light (the tooth falling towards it) are brighter: the shading follows
    # minus the tooth's slope along the light (measured: r = -0.995)
    light = Lighting().direction()
    slope = np.gradient(tooth, axis=1) * light[0] + np.gradient(tooth, axis=0) * light[1]
    r = np.corrcoef(lit[5:-5, 5:-5].ravel(), slope[5:-5, 5:-5].ravel())[0, 1]
    assert r < -0.9
    unlit = luminance(renderer, canvas, Lighting(enabled=False))
    assert np.ptp(unlit) < 1e-5


def test_a_zoomed_view_renders_the_tooth_at_800_percent(renderer):
    canvas = painted("fine_linen", 5e-6)
    renderer.lighting = Lighting()
    canvas.mark_all_dirty()
    renderer.update(canvas)
    renderer.render(size=(160, 160), view=ViewRect(0.005, 0.005, 0.007, 0.007))
    lum = renderer.read_linear_rgba()[..., :3].mean(axis=2)
    assert np.all(np.isfinite(lum)) and lum.std() / lum.mean() > 0.01
