"""One-call headless rendering of a canvas (export, replay, tests)."""

from __future__ import annotations

import numpy as np

from paintapp.canvas.model import Canvas
from paintapp.canvas.regions import Box
from paintapp.pigments.bands import Bands
from paintapp.pigments.library import PigmentLibrary, load_pigment_library
from paintapp.render.context import create_headless_context
from paintapp.render.renderer import CanvasRenderer
from paintapp.render.textures import content_box
from paintapp.render.view import Lighting


def render_canvas_rgba(
    canvas: Canvas,
    library: PigmentLibrary | None = None,
    lighting: Lighting | None = None,
    bands: Bands | None = None,
) -> np.ndarray:
    """Render a canvas at one pixel per texel in a fresh EGL context.

    Args:
        canvas: the canvas (its dirty region is consumed; every texel is drawn regardless).
        library: pigments; default the bundled library.
        lighting: light and relief; default :class:`Lighting()`.
        bands: spectral bands; default :class:`Bands()`.

    Returns:
        Linear RGBA (sRGB primaries, D65), shape (H, W, 4) float32, row 0 = canvas bottom.

    Raises:
        RenderUnavailable: no EGL context could be made.
    """
    ctx = create_headless_context()
    try:
        renderer = CanvasRenderer(ctx, library or load_pigment_library(), bands, lighting)
        canvas.mark_all_dirty()
        renderer.update(canvas)
        rgba = _shade(renderer, canvas)
        renderer.release()
        return rgba
    finally:
        ctx.release()


#: Texels beyond the paint (and wetness) from which a bare texel of a smooth canvas shows the
#: bare canvas's colour, whatever is near: its shading reads its neighbours one texel away (the
#: relief's slope), each read linearly filtered (a texel more).
BARE_MARGIN = 3

#: Share of the canvas that the painted box (with its margin) may cover for the bare texels to
#: be filled instead of shaded; beyond it everything is shaded.
BARE_FILL_SHARE = 0.8


def _shade(renderer: CanvasRenderer, canvas: Canvas) -> np.ndarray:
    """The canvas shaded at one pixel per texel (:meth:`CanvasRenderer.render` then
    :meth:`CanvasRenderer.read_linear_rgba`). On a smooth canvas, every texel :data:`BARE_MARGIN`
    or more beyond its paint and wetness shades to the same colour: one such texel is shaded,
    the whole picture cleared to its colour, and only the painted box shaded over it (the same
    values, bit for bit; llvmpipe shades a texel in about 70 ns)."""
    w, h = canvas.pixels
    painted = None if canvas.has_tooth else content_box(canvas, (0, 0, w, h))
    box: Box | None = None
    if painted is not None:
        x0, y0, x1, y1 = painted
        m = BARE_MARGIN
        box = (max(0, x0 - m), max(0, y0 - m), min(w, x1 + m), min(h, y1 + m))
    corner = _corner_outside(box, w, h)
    if canvas.has_tooth or corner is None or _area(box) > BARE_FILL_SHARE * w * h:
        renderer.render()
        return renderer.read_linear_rgba()
    x, y = corner
    renderer.render(box=(x, y, x + 1, y + 1))
    bare = renderer.read_linear_rgba((x, y, x + 1, y + 1))[0, 0]
    fill = (float(bare[0]), float(bare[1]), float(bare[2]), float(bare[3]))
    if box is None:  # no paint at all
        renderer.render(box=(x, y, x + 1, y + 1), fill=fill)
    else:
        renderer.render(box=box, fill=fill)
    return renderer.read_linear_rgba()


def _area(box: Box | None) -> int:
    return 0 if box is None else (box[2] - box[0]) * (box[3] - box[1])


def _corner_outside(box: Box | None, w: int, h: int) -> tuple[int, int] | None:
    """A corner texel of a w x h canvas outside ``box`` (any, without a box), or None."""
    for x, y in ((0, 0), (w - 1, 0), (0, h - 1), (w - 1, h - 1)):
        if box is None or not (box[0] <= x < box[2] and box[1] <= y < box[3]):
            return x, y
    return None
