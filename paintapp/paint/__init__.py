"""Paint on the move: the local paint grid that rides with the brush tip, and paint transfer.

Which model runs is the painting scene's choice (:class:`PaintScene.fluid_model`):

- ``grid3d``: a 3D viscous-fluid grid over the footprint (:mod:`paintapp.paint.grid3d`);
- ``depth_averaged``: a 2D grid in the canvas plane for thin paint
  (:mod:`paintapp.paint.depth_averaged`);
- ``none``: no fluid, the brush stamps and soaks (:mod:`paintapp.paint.stamp`);
- ``auto``: ``depth_averaged`` or ``grid3d`` by the paint layer's thickness, chosen per sample by
  :class:`~paintapp.paint.selector.ModelSelector` (:mod:`paintapp.paint.choice` states the rules,
  :mod:`paintapp.paint.fit` the grid sizing, :mod:`paintapp.paint.fidelity` the presets).
"""

from brushes import BrushPreset
from paintapp.canvas.model import Canvas
from paintapp.paint.depth_averaged import PaintGridDepthAveraged
from paintapp.paint.exchange import ExchangeReport
from paintapp.paint.grid3d import PaintGrid3D
from paintapp.paint.model import PaintModel, PaintStep, brush_width_m
from paintapp.paint.paint_scene import (
    FLUID_MODELS,
    PaintScene,
    list_paint_scenes,
    load_paint_scene,
    load_paint_scene_file,
)
from paintapp.paint.stamp import StampModel

MODELS: dict[str, type[PaintModel]] = {
    "grid3d": PaintGrid3D,
    "depth_averaged": PaintGridDepthAveraged,
    "none": StampModel,
}


def make_paint_model(scene: PaintScene, canvas: Canvas, preset: BrushPreset) -> PaintModel:
    """The paint model the scene asks for, for this canvas and brush (``auto``: the 3D grid it
    starts from; the session's selector switches as the paint requires)."""
    kind = "grid3d" if scene.fluid_model == "auto" else scene.fluid_model
    return MODELS[kind](scene, canvas, preset)


__all__ = [
    "FLUID_MODELS",
    "MODELS",
    "ExchangeReport",
    "PaintGrid3D",
    "PaintGridDepthAveraged",
    "PaintModel",
    "PaintScene",
    "PaintStep",
    "StampModel",
    "brush_width_m",
    "list_paint_scenes",
    "load_paint_scene",
    "load_paint_scene_file",
    "make_paint_model",
]
