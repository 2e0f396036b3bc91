"""The headless picture's bare canvas filled with one shaded texel's colour: the same bits as
shading every texel."""

from __future__ import annotations

import numpy as np
import pytest

from paintapp.canvas.model import Canvas
from paintapp.render import headless
from paintapp.render.headless import render_canvas_rgba
from paintapp.render.view import Lighting

PIGMENTS = ("ultramarine_blue", "cadmium_yellow")


def canvas(paint: bool = True, surface: str = "smooth") -> Canvas:
    c = Canvas((64, 48), (64e-4, 48e-4), PIGMENTS, surface=surface)
    if paint:
        rng = np.random.default_rng(2)
        c.paint_m[:, 20:30, 25:41] = rng.uniform(0.0, 3e-4, (2, 10, 16))
        c.wetness[20:30, 25:41] = rng.uniform(0.0, 1.0, (10, 16))
        c.wetness[5, 6] = 0.5  # wet but unpainted: its specular shows
    return c


def shaded_whole(monkeypatch, c: Canvas, lighting: Lighting | None = None) -> np.ndarray:
    with monkeypatch.context() as patch:
        patch.setattr(headless, "BARE_FILL_SHARE", -1.0)  # every texel shaded
        return render_canvas_rgba(c, lighting=lighting)


@pytest.mark.parametrize("paint", [True, False])
@pytest.mark.parametrize("lit", [True, False])
def test_filled_bare_canvas_is_the_same_picture(ctx, monkeypatch, paint, lit):
    c = canvas(paint)
    lighting = Lighting() if lit else Lighting(enabled=False)
    drawn: list[object] = []
    real = headless.CanvasRenderer.render

    def spy(self, *args, **kwargs):
        drawn.append(kwargs.get("box"))
        return real(self, *args, **kwargs)

    with monkeypatch.context() as patch:
        patch.setattr(headless.CanvasRenderer, "render", spy)
        filled = render_canvas_rgba(c, lighting=lighting)
    assert drawn and all(box is not None for box in drawn)  # the fill path ran
    whole = shaded_whole(monkeypatch, c, lighting)
    assert np.array_equal(filled, whole)
    corner, middle = whole[0, 0], whole[25, 30]
    assert np.array_equal(whole[47, 63], corner)
    if paint:
        assert not np.array_equal(middle, corner)  # the paint is shaded


def test_a_canvas_with_tooth_is_shaded_everywhere(ctx, monkeypatch):
    c = canvas(surface="fine_linen")
    drawn: list[object] = []
    real = headless.CanvasRenderer.render

    def spy(self, *args, **kwargs):
        drawn.append(kwargs.get("box"))
        return real(self, *args, **kwargs)

    monkeypatch.setattr(headless.CanvasRenderer, "render", spy)
    render_canvas_rgba(c)
    assert drawn == [None]
