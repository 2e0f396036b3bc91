"""The painting settings the controls change, and how they become sessions, scenes and brushes.

The fluid model is chosen by scene: each model has a bundled scene tuned for it (``grid3d``:
``default``, ``depth_averaged``: ``thin_glaze``, ``none``: ``no_fluid``); a scene given with
``--scene`` is used for its own model. The viscosity control overrides the scene's paint
viscosity. The size control scales the preset's tip geometry, press depth and capacity.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from brushes import BrushPreset
from brushes.presets import list_presets, load_preset_named
from common.errors import InputError
from paintapp.canvas.model import Canvas
from paintapp.canvas.surfaces import SMOOTH, surface_spec
from paintapp.haptics.channel import ForceChannel
from paintapp.paint.paint_model import brush_width_m
from paintapp.paint.paint_scene import SCENE_FLUID_MODELS, PaintScene, load_paint_scene
from paintapp.resources import asset_path
from paintapp.session.painting import PaintingSession

#: The bundled scene the window paints with for each fluid model (``live``: the 3D grid fitted to
#: the brush, at the hand's pace).
MODEL_SCENES = {
    "grid3d": "live",
    "depth_averaged": "thin_glaze",
    "none": "no_fluid",
    "auto": "auto",
}
#: Labels for the controls.
MODEL_LABELS = {
    "grid3d": "3D grid",
    "depth_averaged": "2D depth-averaged",
    "none": "none",
    "auto": "auto (2D where thin)",
}
#: Brush size range (scale of the preset).
MIN_SCALE, MAX_SCALE = 0.5, 2.0
#: Viscosity range, Pa s.
MIN_VISCOSITY, MAX_VISCOSITY = 0.1, 1000.0


def brush_names() -> list[str]:
    """The bundled brush presets."""
    return sorted(list_presets(asset_path("brushes")))


@dataclass(frozen=True)
class PaintSettings:
    """What the painter has chosen.

    Attributes:
        brush: preset name.
        brush_scale: size relative to the preset, [0.5, 2].
        fluid_model: ``grid3d``, ``depth_averaged``, ``none`` or ``auto`` (the 3D or the 2D grid,
            chosen per sample by the paint's thickness).
        viscosity_pa_s: paint viscosity override, Pa s (None: the scene's).
        load_fraction: how full a dip in a pigment fills the brush, (0, 1] of its capacity.
        force_scale: the haptic force scale, [0, 20].
        surface: the surface of a new canvas (:mod:`paintapp.canvas.surfaces`).
    """

    brush: str = "round_large"
    brush_scale: float = 1.0
    fluid_model: str = "grid3d"
    viscosity_pa_s: float | None = None
    load_fraction: float = 0.6
    force_scale: float = 4.0
    surface: str = SMOOTH

    def __post_init__(self) -> None:
        object.__setattr__(self, "surface", surface_spec(self.surface).name)
        checks = {
            "brush_scale": MIN_SCALE <= self.brush_scale <= MAX_SCALE,
            "load_fraction": 0.0 < self.load_fraction <= 1.0,
            "force_scale": 0.0 <= self.force_scale <= 20.0,
            "fluid_model": self.fluid_model in SCENE_FLUID_MODELS,
        }
        v = self.viscosity_pa_s
        checks["viscosity_pa_s"] = v is None or (
            math.isfinite(v) and MIN_VISCOSITY <= v <= MAX_VISCOSITY
        )
        for key, ok in checks.items():
            if not ok:
                raise InputError(f"value out of range: {getattr(self, key)!r}", key=key)


def scaled_preset(preset: BrushPreset, scale: float) -> BrushPreset:
    """``preset`` with its tip ``scale`` times larger (depth too; capacity by area)."""
    if scale == 1.0:
        return preset
    size = {k: v * scale for k, v in preset.size_m.items()}
    pressure = replace(preset.pressure, depth_m=preset.pressure.depth_m * scale)
    return replace(
        preset,
        size_m=size,
        pressure=pressure,
        capacity_m3=min(preset.capacity_m3 * scale**2, 1e-4),
    )


def make_preset(settings: PaintSettings) -> BrushPreset:
    """The brush the settings describe."""
    base = load_preset_named(settings.brush, asset_path("brushes"))
    return scaled_preset(base, settings.brush_scale)


def make_scene(settings: PaintSettings, user_scene: PaintScene | None) -> PaintScene:
    """The painting scene for the chosen fluid model and viscosity."""
    if user_scene is not None and user_scene.fluid_model == settings.fluid_model:
        scene = user_scene
    else:
        scene = load_paint_scene(MODEL_SCENES[settings.fluid_model])
    if settings.viscosity_pa_s is not None:
        scene = replace(scene, viscosity_pa_s=settings.viscosity_pa_s)
    if scene.solver.threads == 0:  # auto: in the window the other core draws and runs the servo
        scene = replace(scene, solver=replace(scene.solver, threads=1))
    return scene


def brush_radius_m(preset: BrushPreset) -> float:
    """Half the brush's widest footprint, m."""
    return 0.5 * brush_width_m(preset)


def rebuild_session(
    old: PaintingSession | None,
    canvas: Canvas,
    preset: BrushPreset,
    scene: PaintScene,
    input_kind: str,
    forces: ForceChannel,
) -> PaintingSession:
    """A session for the given brush and scene that carries on from ``old``: the same clock,
    the paint bookkeeping and, when the brush capacity is unchanged, the brush's paint."""
    session = PaintingSession(canvas, preset, scene, input_kind=input_kind, forces=forces)
    if old is not None:
        carry = old.canvas is canvas and old.preset.capacity_m3 == preset.capacity_m3
        if carry:
            session.reservoir = old.reservoir
        else:
            old.clean()  # books the brush's paint as removed
        session.time_s = old.time_s
        session.loaded_m3 = old.loaded_m3
        session.removed_m3 = old.removed_m3
        session.stats = old.stats
    return session
