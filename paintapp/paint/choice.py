"""Model only what the scene requires: the choice of paint model, grid and outputs per sample.

:class:`ModelSelector` picks, per sample in contact, the least model that serves the scene
(:class:`~paintapp.paint.paint_scene.ModelChoice`), logging each decision's reason. In order:

1. **Air**: no step at all.
2. **Dry brush** (``dry_brush``): an empty brush touching down where no texel is wet runs no
   fluid (zero force; nothing could change). The fluid starts at rest once wet paint enters the
   window or the brush holds paint, and runs until the brush lifts.
3. **Fluid model**: the scene's; ``auto`` touches down ``depth_averaged`` where the mean wet layer
   within the tip's contact radius is under ``thin_below_m``, else ``grid3d``, and switches below
   ``thin_below_m`` and above ``thick_above_m``. A new grid starts at rest (no paint is lost).
4. **Grid size** (``fit_grid``): :mod:`paintapp.paint.fit`, refitted when the brush leans past it.
5. **Outputs**: :class:`~paintapp.paint.paint_model.ForceNeeds` from the device (no force work for
   an input-only device, no torque for one without torque output).
6. **Pigment channels** (``used_pigments``): only those in the window or the brush.
7. **Inertia** (``stokes_below_re``): no momentum advection while the tip's Reynolds number is
   below it (:meth:`~paintapp.paint.paint_model.PaintModel.step_settings`).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from paintapp.canvas.model import Canvas
from paintapp.paint.columns import square_texel_m
from paintapp.paint.fit import GridFit
from paintapp.paint.paint_model import ForceNeeds
from solver import Decision

if TYPE_CHECKING:
    from paintapp.haptics.device import DeviceInfo

DRY = "dry"


@dataclass(frozen=True)
class Plan:
    """What one sample in contact runs: the paint model ``fluid`` (``grid3d``,
    ``depth_averaged`` or ``none``) on the grid ``fit`` -- or nothing at all when ``dry``
    (then ``fluid`` and ``fit`` are what will run once paint arrives)."""

    fluid: str
    fit: GridFit
    dry: bool = False

    @property
    def label(self) -> str:
        """``grid3d 20x20x6``, ``depth_averaged 24x24``, ``none`` or ``dry``."""
        if self.dry:
            return DRY
        if self.fluid == "none":
            return "none"
        cells = self.fit.cells if self.fluid == "grid3d" else self.fit.cells[:2]
        return f"{self.fluid} " + "x".join(str(c) for c in cells)


@dataclass(frozen=True)
class TimedDecision:
    """A decision taken at ``t_s`` seconds (None: when the session was set up)."""

    t_s: float | None
    decision: Decision

    def __str__(self) -> str:
        when = "setup" if self.t_s is None else f"t={self.t_s:7.3f} s"
        return f"{when}  {self.decision}"


@dataclass
class ChoiceStats:
    """Counts of what ran: paint steps and solver steps per model kind, steps per grid (plan
    label), steps per number of pigment channels, model switches and refits, and paint-step
    wall time per kind (ms), and solver steps taken as Stokes flow per kind."""

    steps: Counter = field(default_factory=Counter)
    solver_steps: Counter = field(default_factory=Counter)
    grids: Counter = field(default_factory=Counter)
    channels: Counter = field(default_factory=Counter)
    step_ms: Counter = field(default_factory=Counter)
    stokes_steps: Counter = field(default_factory=Counter)
    switches: int = 0
    refits: int = 0


def needs_for_device(info: DeviceInfo | None) -> ForceNeeds:
    """What a device reads: force if it outputs force, torque if it outputs torque (None: a
    6-DOF device, both)."""
    if info is None:
        return ForceNeeds()
    return ForceNeeds(force=info.has_force, torque=info.has_force and info.has_torque)


def layer_thickness_m(canvas: Canvas, x_m: float, y_m: float, radius_m: float) -> float:
    """Mean wet paint thickness (m) over the texels with wet paint within ``radius_m`` (a
    square) of (x, y); 0 where there is none."""
    wet, paint = _texel_block(canvas, x_m, y_m, radius_m)
    if wet is None or not wet.any():
        return 0.0
    mobile = paint.sum(axis=0, dtype=np.float64) * wet
    covered = mobile > 0.0
    return float(mobile[covered].mean()) if covered.any() else 0.0


def window_is_dry(canvas: Canvas, x_m: float, y_m: float, half_m: float) -> bool:
    """Whether no texel within ``half_m`` (a square) of (x, y) holds wet paint."""
    wet, paint = _texel_block(canvas, x_m, y_m, half_m)
    if wet is None or not wet.any():
        return True
    return not bool((paint.sum(axis=0)[wet > 0.0] > 0.0).any())


def _texel_block(canvas: Canvas, x_m: float, y_m: float, half_m: float):
    texel = square_texel_m(canvas)
    fx, fy = canvas.metres_to_texel(x_m, y_m)
    r = int(np.ceil(half_m / texel))
    x0, x1 = max(int(fx) - r, 0), min(int(fx) + r + 1, canvas.width)
    y0, y1 = max(int(fy) - r, 0), min(int(fy) + r + 1, canvas.height)
    if x1 <= x0 or y1 <= y0:
        return None, None
    return canvas.wetness[y0:y1, x0:x1], canvas.paint_m[:, y0:y1, x0:x1]
