"""The brush's bristle texture on the canvas texels, for one paint step.

The paint grid's columns are a cell wide (several texels), far coarser than a brush's bristle
clumps, so the clumps act where the columns trade paint with the texels
(:meth:`paintapp.paint.columns.ColumnWindow.write_back`): a column's gain is laid down with its
weights times a *gain weight* per texel, and its loss taken with its weights times a
*loss weight*, each normalised per column, so the texture only moves paint within a column's reach
and paint stays conserved to round-off.

The weights (:class:`brushes.bristles.Bristles`) are profiles across the tip's direction of
motion: the footprint of the tip (its cut at half the commanded depth, as the stamp and the
depth-averaged models use, turned by its yaw) is measured across the motion, and each texel gets
its position ``u`` in [-1, 1] over that width. Inside the footprint and one cell around it (where
the brush deposits) the weights follow the profiles; elsewhere they are even. As the brush moves,
each clump keeps its ``u`` and so draws a streak along the stroke, and the ridge profile heaps
paint along both sides.
"""

from __future__ import annotations

import math

import numpy as np

from brushes import Section
from brushes.bristles import Bristles
from paintapp.canvas.regions import Box


class BristleTexture:
    """Gain and loss weights over canvas texels for one paint step.

    Args:
        bristles: the preset's bristle texture.
        footprint: the tip's footprint in its body (x, y) frame (a 2D shape).
        centre_m: (2,) the apex on the canvas (m).
        yaw_rad: the tip's yaw (body x from canvas +x).
        heading: (2,) direction of motion in the canvas plane (any length > 0).
        texel_m: canvas texel size (m).
        reach_m: how far beyond the footprint the texture reaches (one cell).
        radius_m: the footprint's largest distance from the apex in the canvas plane (at most
            the tip's lateral extent).
    """

    def __init__(
        self,
        bristles: Bristles,
        footprint: Section,
        centre_m: np.ndarray,
        yaw_rad: float,
        heading: np.ndarray,
        texel_m: float,
        reach_m: float,
        radius_m: float,
    ) -> None:
        self.bristles = bristles
        self.footprint = footprint
        self.centre = np.asarray(centre_m, dtype=float)[:2]
        self.cos, self.sin = math.cos(yaw_rad), math.sin(yaw_rad)
        h = np.asarray(heading, dtype=float)[:2]
        h = h / float(np.hypot(*h))
        self.across = np.array([-h[1], h[0]])
        self.texel_m = texel_m
        self.reach_m = reach_m
        self.radius_m = radius_m

    def weights(self, box: Box) -> tuple[np.ndarray, np.ndarray] | None:
        """(gain, loss) weights (ny, nx) over the texels of ``box`` = (x0, y0, x1, y1), or None
        when the footprint misses the box (even weights). Gains are > 0 with mean 1 over the
        textured texels (1 elsewhere); losses are in (0, 1], their mean over the textured texels
        elsewhere."""
        x0, y0, x1, y1 = box
        t, c = self.texel_m, self.centre
        dx = (np.arange(x0, x1) + 0.5) * t - c[0]
        dy = (np.arange(y0, y1) + 0.5) * t - c[1]
        gx, gy = np.meshgrid(dx, dy)  # (ny, nx)
        radius = self.radius_m + self.reach_m
        near = gx**2 + gy**2 <= radius**2
        if not near.any():
            return None
        body = np.stack([self.cos * gx[near] + self.sin * gy[near],
                         -self.sin * gx[near] + self.cos * gy[near]], axis=-1)  # fmt: skip
        sdf = np.full(gx.shape, np.inf)
        sdf[near] = self.footprint.sdf(body)
        inside = sdf <= 0.0
        if not inside.any():
            return None
        across = self.across[0] * gx + self.across[1] * gy
        along = self.across[1] * gx - self.across[0] * gy
        a_lo, a_hi = float(across[inside].min()), float(across[inside].max())
        span = max(a_hi - a_lo, t)
        u = 2.0 * (across - a_lo) / span - 1.0
        # The footprint and the cell round it, and the wake: the band the footprint swept.
        wake = (along <= 0.0) & (np.abs(u) <= 1.0 + 2.0 * self.reach_m / span)
        textured = (sdf <= self.reach_m) | wake
        gain_in = self.bristles.gain_weight(u[textured])
        loss_in = self.bristles.loss_weight(u[textured])
        gain = np.ones(gx.shape)
        loss = np.full(gx.shape, float(loss_in.mean()))
        gain[textured] = gain_in / gain_in.mean()
        loss[textured] = loss_in
        return gain, loss
