"""The mixing slab: a small palette area where paint is put out and mixed with the brush.

The slab is a small :class:`~paintapp.canvas.model.Canvas` (4 x 4 cm, 64 x 64 texels) owned by the
simulation worker, like the brush's reservoir. What happens on it is deliberately simple:

- **put**: a blob of a pure palette pigment (``PUT_VOLUME_M3``) is laid in a disc at the
  pigment's spot; spots sit on a ring around the slab's middle, one per pigment, in the order the
  pigments were first put out.
- **dab** (the brush touches the slab in a disc): the brush first leaves ``DEPOSIT_SHARE`` of its
  load there, the paint under it is stirred (every texel in the disc keeps its thickness and takes
  the disc's mean composition), and the brush then picks up ``PICKUP_SHARE`` of that paint, as
  much as fits (:meth:`brushes.PaintReservoir.deposit` and :meth:`~brushes.PaintReservoir.pick_up`).
  Dragging the brush from one blob to another therefore mixes them on the slab and in the brush.
- **mix all** (a palette knife): the same over all the paint on the slab at once.
- **clear**: scrape the slab clean.

Paint is conserved: what the brush leaves is added to the slab and what it takes is removed.
"""

from __future__ import annotations

import math

import numpy as np

from brushes import PaintReservoir
from paintapp.canvas.model import Canvas

#: Slab size, texels and metres.
SLAB_PIXELS = (64, 64)
SLAB_SIZE_M = (0.04, 0.04)
#: Paint put out per click, m^3, in a disc of ``PUT_RADIUS_M``.
PUT_VOLUME_M3 = 1.5e-7
PUT_RADIUS_M = 0.005
#: Spots for the blobs: a ring of ``SPOTS`` around the middle, radius ``SPOT_RING_M``.
SPOTS = 6
SPOT_RING_M = 0.012
#: The brush's footprint on the slab, m.
DAB_RADIUS_M = 0.004
#: Share of the brush's load left on the slab per dab, and of the paint under it taken up.
DEPOSIT_SHARE = 0.5
PICKUP_SHARE = 0.5


class MixingSlab:
    """See the module docstring. ``canvas`` holds the paint (its pigments are added as they come)."""

    def __init__(self) -> None:
        self.canvas = Canvas(SLAB_PIXELS, SLAB_SIZE_M)
        self.spots: dict[str, tuple[float, float]] = {}
        self.version = 0

    # --- geometry -------------------------------------------------------------------------------
    def spot(self, pigment: str) -> tuple[float, float]:
        """Where ``pigment`` is put out (m, slab frame: origin bottom-left, y up)."""
        if pigment not in self.spots:
            i = len(self.spots) % SPOTS
            angle = math.pi / 2 + 2 * math.pi * i / SPOTS
            cx, cy = SLAB_SIZE_M[0] / 2, SLAB_SIZE_M[1] / 2
            self.spots[pigment] = (
                cx + SPOT_RING_M * math.cos(angle),
                cy + SPOT_RING_M * math.sin(angle),
            )
        return self.spots[pigment]

    def _disc(self, x_m: float, y_m: float, radius_m: float) -> np.ndarray:
        """(H, W) mask of the texels whose centres lie within the disc (at least the nearest)."""
        c = self.canvas
        xs, ys = c.texel_to_metres(np.arange(c.width), np.arange(c.height))
        mask = (xs[None, :] - x_m) ** 2 + (ys[:, None] - y_m) ** 2 <= radius_m**2
        if not mask.any():
            ix, iy = c.metres_to_texel(x_m, y_m)
            ix = min(max(int(ix), 0), c.width - 1)
            iy = min(max(int(iy), 0), c.height - 1)
            mask[iy, ix] = True
        return mask

    @property
    def texel_area_m2(self) -> float:
        dx, dy = self.canvas.texel_size_m
        return dx * dy

    # --- actions ----------------------------------------------------------------------------------
    def put(self, pigment: str, volume_m3: float = PUT_VOLUME_M3) -> tuple[float, float]:
        """Put a blob of ``pigment`` at its spot; returns the spot (m)."""
        x, y = self.spot(pigment)
        mask = self._disc(x, y, PUT_RADIUS_M)
        i = self.canvas.add_pigment(pigment)
        thickness = volume_m3 / (int(mask.sum()) * self.texel_area_m2)
        self.canvas.paint_m[i][mask] += np.float32(thickness)
        self.canvas.wetness[mask] = 1.0
        self._changed()
        return x, y

    def dab(
        self, reservoir: PaintReservoir, x_m: float, y_m: float, radius_m: float = DAB_RADIUS_M
    ) -> dict[str, float]:
        """The brush touches the slab at (x_m, y_m); returns what it picked up (m^3/pigment)."""
        return self._work(reservoir, self._disc(x_m, y_m, radius_m))

    def mix_all(self, reservoir: PaintReservoir) -> dict[str, float]:
        """Knife all the paint on the slab together and dab the brush in it."""
        mask = self.canvas.height_m > 0
        if not mask.any():
            mask = self._disc(SLAB_SIZE_M[0] / 2, SLAB_SIZE_M[1] / 2, DAB_RADIUS_M)
        return self._work(reservoir, mask)

    def clear(self) -> None:
        """Scrape the slab clean."""
        self.canvas = Canvas(SLAB_PIXELS, SLAB_SIZE_M)
        self.spots.clear()
        self._changed()

    @property
    def total_m3(self) -> float:
        """Paint on the slab, m^3."""
        return float(self.canvas.paint_m.sum(dtype=np.float64)) * self.texel_area_m2

    # --- the dab --------------------------------------------------------------------------------
    def _work(self, reservoir: PaintReservoir, mask: np.ndarray) -> dict[str, float]:
        canvas, area = self.canvas, self.texel_area_m2
        n = int(mask.sum())
        # 1. The brush leaves part of its load under it.
        left = reservoir.deposit(DEPOSIT_SHARE * reservoir.total_m3)
        for name, v in left.items():
            if v > 0.0:
                i = canvas.add_pigment(name)
                canvas.paint_m[i][mask] += np.float32(v / (n * area))
        paint = canvas.paint_m[:, mask].astype(np.float64)  # (P, n)
        per_pigment = paint.sum(axis=1)
        total = float(per_pigment.sum())
        if total <= 0.0:
            self._changed()
            return {}
        # 2. It stirs the paint under it: each texel keeps its thickness, the mixture is shared.
        thickness = paint.sum(axis=0)
        mixed = (per_pigment / total)[:, None] * thickness[None, :]
        # 3. It picks up part of that paint, as much as fits.
        offer = {
            name: PICKUP_SHARE * float(per_pigment[i]) * area
            for i, name in enumerate(canvas.pigment_names)
            if per_pigment[i] > 0.0
        }
        taken = reservoir.pick_up(offer)
        keep = max(1.0 - math.fsum(taken.values()) / (total * area), 0.0)
        canvas.paint_m[:, mask] = (mixed * keep).astype(np.float32)
        canvas.wetness[mask & (canvas.height_m > 0)] = 1.0
        self._changed()
        return taken

    def _changed(self) -> None:
        self.canvas.mark_all_dirty()
        self.version += 1
