"""Brush tips: signed-distance geometry (:mod:`.tips`, its numba kernels :mod:`.tips_kernels`),
presets (:mod:`.presets`), the stylus sample (:mod:`.stylus`) and its mapping to a tip pose
(:mod:`.pose`), the tip as a moving solver probe (:mod:`.probe`), the bristle texture
(:mod:`.bristles`) and the paint reservoir (:mod:`.reservoir`)."""

from brushes.pose import INPUT_KINDS, InputKind, TipPose, TipTracker, place_tip
from brushes.presets import (
    BrushPreset,
    PressureResponse,
    TiltResponse,
    find_preset,
    list_presets,
    load_preset,
    load_preset_named,
)
from brushes.probe import ProbeMotion, probe_motion, probe_motion_2d, voxelize
from brushes.reservoir import PaintReservoir
from brushes.stylus import StylusSample
from brushes.tips import Disc, Rect, RoundCone, RoundedBox, Section, Shape, Splayed, TipShape

__all__ = [
    "INPUT_KINDS",
    "BrushPreset",
    "Disc",
    "InputKind",
    "PaintReservoir",
    "PressureResponse",
    "ProbeMotion",
    "Rect",
    "RoundCone",
    "RoundedBox",
    "Section",
    "Shape",
    "Splayed",
    "StylusSample",
    "TiltResponse",
    "TipPose",
    "TipShape",
    "TipTracker",
    "find_preset",
    "list_presets",
    "load_preset",
    "load_preset_named",
    "place_tip",
    "probe_motion",
    "probe_motion_2d",
    "voxelize",
]
