"""Canvas rendering (moderngl): Kubelka-Munk paint, impasto lighting, brush and force overlays.

Modules: :mod:`.context` the OpenGL contexts and shader programs; :mod:`.textures` the canvas
on the GPU; :mod:`.renderer` draws it; :mod:`.view` what part is shown and how it is lit;
:mod:`.overlays` the brush outline and force arrows; :mod:`.finish` waits for the GPU with the
interpreter lock released; :mod:`.headless` renders a canvas in one call (export, replay, tests).
"""

from paintapp.render.context import (
    PROGRAM_NAMES,
    RenderUnavailable,
    create_headless_context,
    load_program,
    program_sources,
)
from paintapp.render.headless import render_canvas_rgba
from paintapp.render.overlays import BrushOutline, ForceArrow
from paintapp.render.renderer import CanvasRenderer
from paintapp.render.view import Lighting, ViewRect

__all__ = [
    "PROGRAM_NAMES",
    "BrushOutline",
    "CanvasRenderer",
    "ForceArrow",
    "Lighting",
    "RenderUnavailable",
    "ViewRect",
    "create_headless_context",
    "load_program",
    "program_sources",
    "render_canvas_rgba",
]
