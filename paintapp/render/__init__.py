"""Canvas rendering (moderngl): Kubelka-Munk paint, impasto lighting, brush and force overlays."""

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
