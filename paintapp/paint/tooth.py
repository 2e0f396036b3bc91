"""The canvas's tooth where the brush lays paint down: thin paint catches on the peaks.

The paint grid's columns are a cell wide (several texels) and know nothing of the canvas surface
(:mod:`paintapp.canvas.surfaces`) under them; the tooth acts where a column trades paint with its
texels (:meth:`paintapp.paint.columns.ColumnWindow.write_back`), as per-texel gain and loss
weights like the bristle texture's (:mod:`paintapp.paint.bristles`), so paint stays conserved to
round-off and moves only within a column's reach.

The brush meets the surface ``s = min(t + h, t_top)``: the tooth height ``t`` of the texel plus the
paint ``h`` already on it (paint fills the valleys; above the highest peak ``t_top`` it is level
with the peaks). The bristles reach a *contact depth* ``d`` below the peaks, from the pressure
``p`` of the step's pose: ``d = R (REACH_LIGHT + (REACH_FIRM - REACH_LIGHT) p)`` with ``R`` the
surface's peak-to-valley relief. A texel's *engagement* is
``e = clip((s - (t_top - d)) / d, 0, 1)``: 1 on the peaks, falling to 0 at the contact depth.

- **Deposit**: a column's gain is laid down with gain weight ``g = GAIN_FLOOR + e`` (times the
  bristles' gain weight): on bare tooth nearly all of it lands on the peaks the bristles touch.
- **Pick-up**: a column's loss is taken first from the paint of the engaged texels, loss weight
  ``b = max(LOSS_FLOOR, e)`` (times the bristles'), then from the rest
  (:func:`paintapp.paint.columns.column_rates`): the brush lifts paint off the peaks first.
- Once the paint on a texel is as thick as the relief (``t + h >= t_top``), ``e = 1`` there: a
  thick layer hides the tooth, and a ground covered that thickly takes paint evenly, as the smooth
  canvas does. The wet flow over the texels (:mod:`paintapp.paint.wet_flow`) is not changed.

On the ``smooth`` surface no tooth texture is made and nothing changes. The weights are a few
whole-array numpy operations over the write-back's texel box per step.
"""

from __future__ import annotations

import functools

import numpy as np

from paintapp.canvas.model import Canvas
from paintapp.canvas.regions import Box
from paintapp.canvas.surfaces import blurred_tile, relief_m
from paintapp.paint.columns import TexelWeights

#: Contact depth below the peaks, in reliefs, at zero pressure and at full pressure.
REACH_LIGHT = 0.25
REACH_FIRM = 1.0
#: Gain weight of a texel the bristles do not reach (relative to 1 more on a peak): a little
#: paint still reaches the valleys (bristle tips, splashes), and the weights stay positive.
GAIN_FLOOR = 0.02
#: Loss weight of a texel the bristles do not reach.
LOSS_FLOOR = 0.02


@functools.lru_cache(maxsize=16)
def tooth_top_m(surface: str, texel_m: float) -> float:
    """The highest tooth height (m) a canvas of ``texel_m`` texels holds on ``surface``: the
    maximum of the tile low-passed to the texel, as :func:`paintapp.canvas.surfaces.
    tooth_on_texels` samples it."""
    return float(blurred_tile(surface, 0.5 * texel_m).max())


def contact_depth_m(surface: str, pressure: float) -> float:
    """How far below the peaks the bristles reach at ``pressure`` in [0, 1], m."""
    p = min(max(float(pressure), 0.0), 1.0)
    return relief_m(surface) * (REACH_LIGHT + (REACH_FIRM - REACH_LIGHT) * p)


def engagement(tooth: np.ndarray, paint: np.ndarray, top_m: float, depth_m: float) -> np.ndarray:
    """``e`` of the module docstring for tooth heights ``tooth`` and paint ``paint`` (m, same
    shape), the highest peak ``top_m`` and contact depth ``depth_m``; float64 in [0, 1]."""
    surface = np.minimum(tooth.astype(np.float64) + paint, top_m)
    return np.clip((surface - (top_m - depth_m)) / depth_m, 0.0, 1.0)


class ToothTexture:
    """Gain and loss weights of the canvas's tooth for one paint step (module docstring), times
    those of ``bristles`` where it gives any.

    Args:
        canvas: the canvas (with tooth).
        pressure: the step's pressure in [0, 1].
        bristles: the brush's own texture for the step, or None.
    """

    def __init__(self, canvas: Canvas, pressure: float, bristles: TexelWeights | None) -> None:
        self.canvas = canvas
        self.bristles = bristles
        self.top_m = tooth_top_m(canvas.surface, canvas.texel_size_m[0])
        self.depth_m = max(contact_depth_m(canvas.surface, pressure), 1e-12)

    def weights_and_gains(self, box: Box) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(gain, loss, tooth gain) weights (ny, nx) over the texels of ``box`` = (x0, y0, x1,
        y1): :meth:`weights`, and the tooth's own gain weights without the bristles' (how
        readily each texel takes paint, > 0; the write-back's sweep lays gains by them), from
        one reading of the engagement."""
        x0, y0, x1, y1 = box
        c = self.canvas
        paint = c.paint_m[:, y0:y1, x0:x1].sum(axis=0, dtype=np.float64)
        e = engagement(c.tooth_m[y0:y1, x0:x1], paint, self.top_m, self.depth_m)
        tooth_gain = GAIN_FLOOR + e
        gain = tooth_gain.copy()
        loss = np.maximum(e, LOSS_FLOOR)
        inner = self.bristles.weights(box) if self.bristles is not None else None
        if inner is not None:
            gain *= inner[0]
            loss *= inner[1]
        return gain, loss, tooth_gain

    def weights(self, box: Box) -> tuple[np.ndarray, np.ndarray]:
        """(gain, loss) weights (ny, nx) over the texels of ``box`` = (x0, y0, x1, y1): gains
        > 0, losses in (0, 1]."""
        gain, loss, _ = self.weights_and_gains(box)
        return gain, loss


def bristles_only(texture: TexelWeights | None) -> TexelWeights | None:
    """The bristle texture inside a tooth texture (the wet flow's), or ``texture`` itself."""
    return texture.bristles if isinstance(texture, ToothTexture) else texture
