"""One-call headless rendering of a canvas (export, replay, tests)."""

from __future__ import annotations

import numpy as np

from paintapp.canvas.model import Canvas
from paintapp.pigments.bands import Bands
from paintapp.pigments.library import PigmentLibrary, load_pigment_library
from paintapp.render.context import create_headless_context
from paintapp.render.renderer import CanvasRenderer
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
        rgba = renderer.render_linear_rgba(canvas)
        renderer.release()
        return rgba
    finally:
        ctx.release()
