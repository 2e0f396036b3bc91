"""Sizing the paint grid to the brush's footprint (``[choose] fit_grid = true``).

A scene's ``cells`` span ``span`` brush widths at full splay, and reach ``nz`` cells above the
canvas: room for the whole bristle body. Only the part of the tip that meets paint matters: paint
is at most ``max_height_m`` thick and the tip presses at most ``pressure.depth_m`` into it, so the
*contact height* is ``z_c = max_height_m + depth_m``; above it the tip moves air a thousand times
thinner than the paint. The fitted grid keeps the scene's cell size ``h`` (the same resolution)
and shrinks the box:

- height: ``nz = ceil(z_c / h) + 2`` cells (two cells of air headroom under the open top), at
  least 3 and at most the scene's ``nz``;
- width: ``span`` footprint widths, the footprint being the widest cut of the tip below ``z_c``
  at full splay (full pressure: the largest the stroke can reach, so pressure changes never
  rebuild the grid), moved sideways by the lean of the brush axis:
  ``n = ceil(span * 2 (r + z_c tan(lean)) / h)``, rounded up to an even number, at least 8 and
  at most the scene's ``nx``. ``lean`` is the brush's tilt at touch-down plus
  :data:`LEAN_ALLOWANCE_RAD`; a brush that leans further later in the stroke gets a new fit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from brushes import BrushPreset, TipPose
from paintapp.paint.columns import cell_texels
from paintapp.paint.paint_model import brush_width_m
from paintapp.paint.paint_scene import PaintScene

#: Extra lean (rad) a fitted grid allows beyond the tilt it was fitted at.
LEAN_ALLOWANCE_RAD = 0.2
#: Cells of air between the contact height and the grid's open top.
HEADROOM_CELLS = 2
#: Smallest lateral size of a fitted grid (cells).
MIN_CELLS = 8


@dataclass(frozen=True)
class GridFit:
    """A grid size and why.

    Attributes:
        cells: (nx, ny, nz) cells (the depth-averaged grid uses nx, ny).
        lean_limit_rad: the fit holds while the brush axis leans at most this far from the
            canvas normal (rad); ``pi / 2`` for a grid that is not fitted.
        reason: one line for ``--explain``.
    """

    cells: tuple[int, int, int]
    lean_limit_rad: float
    reason: str


def lean_rad(pose: TipPose) -> float:
    """Angle (rad) between the brush axis and the canvas normal."""
    return math.acos(min(max(float(pose.axis[2]), -1.0), 1.0))


_RADII: dict[tuple[str, float], float] = {}


def section_radius_m(preset: BrushPreset, height_m: float, samples: int = 121) -> float:
    """Largest distance (m) from the axis of the upright tip, at full splay, of any point of
    the tip below ``height_m`` above its apex (sampled on a lattice, a slight over-estimate)."""
    key = (repr(preset), height_m)
    if key not in _RADII:
        _RADII[key] = _section_radius(preset, height_m, samples)
    return _RADII[key]


def _section_radius(preset: BrushPreset, height_m: float, samples: int) -> float:
    tip = preset.tip(preset.splay_for_depth(preset.pressure.depth_m))
    reach = 0.5 * brush_width_m(preset) * 1.05
    xs = np.linspace(-reach, reach, samples)
    x, y = np.meshgrid(xs, xs, indexing="ij")
    radius = 0.0
    step = 2.0 * reach / (samples - 1)
    for z in np.linspace(0.0, height_m, 9):
        pts = np.stack([x.ravel(), y.ravel(), np.full(x.size, z)], axis=1)
        inside = tip.sdf(pts) <= 0.0
        if inside.any():
            radius = max(radius, float(np.hypot(pts[inside, 0], pts[inside, 1]).max()))
    return radius + step


def cell_size_m(scene: PaintScene, preset: BrushPreset, texel_m: float, kind: str) -> float:
    """The cell edge (m) a model of ``kind`` has with ``scene.cells`` (fitted or not)."""
    ref = scene.cells[0] + 2 if kind == "depth_averaged" else scene.cells[0]
    return cell_texels(brush_width_m(preset), texel_m, ref, scene.span) * texel_m


def full_grid(scene: PaintScene) -> GridFit:
    """The scene's own grid, unfitted."""
    return GridFit(scene.cells, 0.5 * math.pi, "the scene's [grid] cells (fit_grid = false)")


def fit_grid(
    scene: PaintScene, preset: BrushPreset, texel_m: float, kind: str, lean: float
) -> GridFit:
    """The grid for ``preset`` leaning ``lean`` rad in a model of ``kind`` (module docstring)."""
    h = cell_size_m(scene, preset, texel_m, kind)
    nx, ny, nz = scene.cells
    z_c = scene.max_height_m + preset.pressure.depth_m
    limit = min(lean + LEAN_ALLOWANCE_RAD, 0.5 * math.pi - 0.05)
    half = section_radius_m(preset, z_c) + z_c * math.tan(limit)
    n = math.ceil(scene.span * 2.0 * half / h)
    n += n % 2
    fx, fy = min(max(n, MIN_CELLS), nx), min(max(n, MIN_CELLS), ny)
    fz = nz if kind != "grid3d" else min(max(math.ceil(z_c / h) + HEADROOM_CELLS, 3), nz)
    shown = f"{fx}x{fy}" + (f"x{fz}" if kind == "grid3d" else "")
    reason = (
        f"fit_grid: contact height {z_c * 1e3:.2g} mm (paint {scene.max_height_m * 1e3:.2g} + "
        f"press {preset.pressure.depth_m * 1e3:.2g}), footprint radius {half * 1e3:.2g} mm at "
        f"lean <= {math.degrees(limit):.0f} deg, h = {h * 1e3:.3g} mm: {shown} of "
        f"{nx}x{ny}" + (f"x{nz}" if kind == "grid3d" else "")
    )
    return GridFit((fx, fy, fz), limit, reason)
