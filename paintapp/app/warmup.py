"""Preparing the simulation before the first stroke: a short stroke on a scratch canvas.

numba compiles the solver's and the paint model's kernels on their first call and caches them
on disk: on a new installation the first stroke in the window would wait a minute or more with
the pen down and nothing painted, and even from the cache each kernel is loaded at its first
call. The worker paints this stroke when it starts, with the brush, scene and input kind it will
paint with, on a scratch canvas of the real canvas's texel size (which sets the grid's cells in
texels, and so which write-back paths run), into a force channel nobody reads. Nothing reaches
the canvas, the journal, the undo history or the device.
"""

from __future__ import annotations

import math
import time

import numpy as np

from brushes import BrushPreset, StylusSample
from paintapp.app.settings import brush_radius_m, rebuild_session
from paintapp.canvas.model import Canvas
from paintapp.haptics.channel import ForceChannel
from paintapp.paint.paint_scene import PaintScene
from paintapp.strokes.records import LoadPigment

#: Samples of the warm-up stroke in contact, and their interval (s).
STROKE_SAMPLES = 8
SAMPLE_S = 1.0 / 60.0
#: Pressure of the warm-up stroke (a tablet's; a haptic device's depth follows from it).
PRESSURE = 0.8
#: Side of the scratch canvas in brush radii, and its largest side in texels.
SIDE_RADII = 24.0
MAX_SIDE_TEXELS = 1024


def scratch_canvas(preset: BrushPreset, texel_m: tuple[float, float]) -> Canvas:
    """A blank canvas of ``texel_m`` texels wide enough for the brush's grid and stroke."""
    side_m = SIDE_RADII * brush_radius_m(preset)
    n = [min(MAX_SIDE_TEXELS, max(16, math.ceil(side_m / t))) for t in texel_m]
    return Canvas((n[0], n[1]), (n[0] * texel_m[0], n[1] * texel_m[1]))


def warm_up(
    preset: BrushPreset,
    scene: PaintScene,
    texel_m: tuple[float, float],
    pigment: str,
    input_kind: str = "tablet",
) -> float:
    """Paint the warm-up stroke (module docstring) and return the seconds it took.

    The stroke: a dip into ``pigment``, a sample in the air, :data:`STROKE_SAMPLES` samples in
    contact along a line of four brush radii, and a lift.
    """
    begin = time.perf_counter()
    canvas = scratch_canvas(preset, texel_m)
    session = rebuild_session(None, canvas, preset, scene, input_kind, ForceChannel())
    session.handle(LoadPigment(0.0, pigment, 0.5 * preset.capacity_m3))
    radius = brush_radius_m(preset)
    cx, cy = 0.5 * canvas.size_m[0], 0.5 * canvas.size_m[1]
    depth = preset.pressure.depth_for(PRESSURE)
    t = SAMPLE_S
    session.sample(StylusSample(t, np.array([cx - 2.0 * radius, cy, 0.01])))
    for i in range(STROKE_SAMPLES):
        t += SAMPLE_S
        x = cx + radius * (4.0 * i / (STROKE_SAMPLES - 1) - 2.0)
        session.sample(StylusSample(t, np.array([x, cy, -depth]), PRESSURE))
    session.sample(StylusSample(t + SAMPLE_S, np.array([cx + 2.0 * radius, cy, 0.01])))
    return time.perf_counter() - begin
