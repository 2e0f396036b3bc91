"""The brush's bristle texture on the canvas texels, for one paint step.

The paint grid's columns are a cell wide (several texels), far coarser than a brush's bristle
clumps, so the clumps act where the columns trade paint with the texels
(:meth:`paintapp.paint.columns.ColumnWindow.write_back`): a column's gain is laid down with its
weights times a *gain weight* per texel, its loss taken with its weights times a *loss weight*,
each normalised per column, so the texture only moves paint within a column's reach and paint
stays conserved to round-off.

The weights (:class:`brushes.bristles.Bristles`) are profiles across the tip's motion: each texel
gets its position ``u`` in [-1, 1] across the tip's footprint (its cut at half the commanded
depth, turned by its yaw). Inside the footprint and one cell around it the weights follow the
profiles, elsewhere they are even; each clump keeps its ``u`` and draws a streak along the stroke.
Only the footprint is shape code: its signed distance on the texels near it, in one kernel pass
for a tip with a compiled form (:func:`footprint_sdf`), else through the shape's own ``sdf`` on
the texels :func:`near_points` lists; the rest is one kernel pass over the box
(:func:`texture_weights`), the profiles tabulated (:func:`profile_tables`).
"""

from __future__ import annotations

import functools
import math
from typing import NamedTuple

import numpy as np

from brushes import Section
from brushes.bristles import PROFILE_SAMPLES, Bristles, blur_level
from brushes.tips_kernels import tip_distance
from paintapp.canvas.regions import Box
from solver import inline_kernel, kernel

#: Each streak is widened by a Gaussian of this many texels (added in quadrature), so that the
#: canvas can hold it: the texels sample it without a jagged, beaded line along a stroke that
#: runs across their rows.
ANTIALIAS_TEXELS = 0.5


class Apex(NamedTuple):
    """Where the tip stands over the canvas texels, as the kernels take it."""

    #: Canvas texel size (m).
    texel: float
    #: The apex on the canvas (m).
    cx: float
    cy: float
    #: Cosine and sine of the tip's yaw (body x from canvas +x).
    cos: float
    sin: float


class Across(NamedTuple):
    """The unit direction (ax, ay) across the tip's motion, and the footprint's extent along
    it, ``lo`` to ``hi`` (m from the apex; :func:`footprint_across`)."""

    ax: float
    ay: float
    lo: float
    hi: float


class FootprintSdf(NamedTuple):
    """The footprint's signed distance (m) ``sdf`` (ny, nx) on the texels of a sub-box whose
    first texel is (x0, y0); inf where not evaluated."""

    sdf: np.ndarray
    x0: int
    y0: int


def profile_tables(bristles: Bristles, blur: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """The gain and loss weights at ``PROFILE_SAMPLES`` evenly spaced ``u`` over [-1, 1], the
    streaks widened by ``blur`` (``u``; rounded to a tabulated level): both are affine in the
    linearly interpolated profiles, so interpolating these tables linearly gives the same weights
    (to round-off). Read only."""
    return _tables(bristles, blur_level(blur))


@functools.lru_cache(maxsize=64)
def _tables(bristles: Bristles, blur: float) -> tuple[np.ndarray, np.ndarray]:
    u = np.linspace(-1.0, 1.0, PROFILE_SAMPLES)
    gain, loss = bristles.gain_weight(u, blur), bristles.loss_weight(u, blur)
    gain.flags.writeable = False
    loss.flags.writeable = False
    return gain, loss


@inline_kernel
def _lookup(table, u):
    """``table`` (samples over [-1, 1]) interpolated linearly at ``u`` (clipped)."""
    n = table.shape[0]
    pos = (min(max(u, -1.0), 1.0) + 1.0) * 0.5 * (n - 1)
    i = min(int(pos), n - 2)
    frac = pos - i
    return table[i] * (1.0 - frac) + table[i + 1] * frac


@kernel
def near_points(apex, radius_sq, sx0, sy0, nx, ny, body, index):
    """The texels of the (ny, nx) box at (sx0, sy0) whose centres lie within ``sqrt(radius_sq)``
    of the :class:`Apex`, row by row: their centres in the footprint's body frame (turned by the
    yaw) into ``body`` and their flat indices in the box into ``index``; returns how many."""
    texel, cx, cy, cos, sin = apex
    count = 0
    for y in range(ny):
        gy = (sy0 + y + 0.5) * texel - cy
        for x in range(nx):
            gx = (sx0 + x + 0.5) * texel - cx
            if gx * gx + gy * gy <= radius_sq:
                body[count, 0] = cos * gx + sin * gy
                body[count, 1] = -sin * gx + cos * gy
                index[count] = y * nx + x
                count += 1
    return count


#: Texels a side of the blocks in which :func:`footprint_sdf` first reads the footprint's
#: distance at the block's centre: the distance is 1-Lipschitz in the plane, so a block whose
#: centre lies farther than the texture's reach plus the block's half diagonal holds no texel
#: within the reach, and is skipped.
CULL_TEXELS = 8


@inline_kernel
def _distance_at(apex, tip, gx, gy):
    """The tip's distance at the canvas offset (gx, gy) m from the :class:`Apex`, turned into
    the body frame as :func:`near_points` turns it."""
    _, _, _, cos, sin = apex
    kind, params, scale, z = tip
    return tip_distance(kind, params, scale, cos * gx + sin * gy, -sin * gx + cos * gy, z)


@kernel
def footprint_sdf(apex, radius_sq, tip, reach, sx0, sy0, out):
    """The footprint's signed distance (m) into ``out`` (ny, nx), the texels of the box whose
    first texel is (sx0, sy0), where the texture needs it: at the texels whose centres lie within
    ``sqrt(radius_sq)`` of the :class:`Apex` and within ``reach`` of the footprint; inf elsewhere
    (blocks of :data:`CULL_TEXELS` farther from it are skipped). ``tip`` = (kind, params, scale,
    z): the tip's compiled form (:mod:`brushes.tips_kernels`) cut at body height z. Each value
    is :func:`brushes.tips_kernels.section_sdf`'s at :func:`near_points`'s body-frame centre,
    the same arithmetic. Returns how many texels were evaluated."""
    texel, cx, cy = apex.texel, apex.cx, apex.cy
    ny, nx = out.shape
    out[:] = np.inf
    b = CULL_TEXELS
    far = reach + 0.5 * b * math.sqrt(2.0) * texel
    count = 0
    for by in range(0, ny, b):
        for bx in range(0, nx, b):
            gx = (sx0 + bx + 0.5 * b) * texel - cx
            gy = (sy0 + by + 0.5 * b) * texel - cy
            if _distance_at(apex, tip, gx, gy) > far:
                continue
            for y in range(by, min(by + b, ny)):
                gy = (sy0 + y + 0.5) * texel - cy
                for x in range(bx, min(bx + b, nx)):
                    gx = (sx0 + x + 0.5) * texel - cx
                    if gx * gx + gy * gy <= radius_sq:
                        out[y, x] = _distance_at(apex, tip, gx, gy)
                        count += 1
    return count


@kernel
def footprint_across(apex, ax, ay, footprint):
    """(lowest, highest) position across the motion (m from the :class:`Apex`, along the unit
    (ax, ay)) of the texel centres inside the footprint (a :class:`FootprintSdf`); (inf, -inf)
    when it covers none."""
    texel, cx, cy = apex.texel, apex.cx, apex.cy
    sdf, sx0, sy0 = footprint
    sny, snx = sdf.shape
    a_lo, a_hi = np.inf, -np.inf
    for y in range(sny):
        gy = (sy0 + y + 0.5) * texel - cy
        for x in range(snx):
            if sdf[y, x] <= 0.0:
                across = ax * ((sx0 + x + 0.5) * texel - cx) + ay * gy
                a_lo, a_hi = min(a_lo, across), max(a_hi, across)
    return a_lo, a_hi


@kernel
def texture_weights(x0, y0, apex, across, reach, footprint, tables, out):
    """Fill ``out`` = (gain, loss) (ny, nx) over the box whose first texel is (x0, y0), from the
    profile ``tables`` = (gain, loss) (:func:`profile_tables`): see
    :meth:`BristleTexture.weights`. ``footprint`` (a :class:`FootprintSdf`) is evaluated on the
    texels within the texture's ``reach`` (m) of it, texels outside it are farther; ``apex`` and
    ``across``: :class:`Apex`, :class:`Across`."""
    texel, cx, cy = apex.texel, apex.cx, apex.cy
    ax, ay, a_lo, a_hi = across
    sdf, sx0, sy0 = footprint
    gain_table, loss_table = tables
    gain, loss = out
    ny, nx = gain.shape
    sny, snx = sdf.shape
    span = max(a_hi - a_lo, texel)
    wide = 1.0 + 2.0 * reach / span
    count, gain_sum, loss_sum = 0, 0.0, 0.0
    for y in range(ny):
        gy = (y0 + y + 0.5) * texel - cy
        for x in range(nx):
            gx = (x0 + x + 0.5) * texel - cx
            u = 2.0 * (ax * gx + ay * gy - a_lo) / span - 1.0
            textured = ay * gx - ax * gy <= 0.0 and abs(u) <= wide  # the wake
            sy, sx = y0 + y - sy0, x0 + x - sx0
            if 0 <= sy < sny and 0 <= sx < snx and sdf[sy, sx] <= reach:
                textured = True  # the footprint and the cell round it
            if textured:
                g, b = _lookup(gain_table, u), _lookup(loss_table, u)
                gain[y, x], loss[y, x] = g, b
                count += 1
                gain_sum += g
                loss_sum += b
            else:
                loss[y, x] = -1.0
    gain_mean, loss_mean = gain_sum / count, loss_sum / count
    for y in range(ny):
        for x in range(nx):
            if loss[y, x] < 0.0:
                gain[y, x], loss[y, x] = 1.0, loss_mean
            else:
                gain[y, x] /= gain_mean


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
        radius = self.radius_m + self.reach_m
        # the texels whose centres may lie within ``radius`` of the apex
        sx0 = max(x0, math.floor((c[0] - radius) / t - 0.5))
        sx1 = min(x1, math.ceil((c[0] + radius) / t + 0.5))
        sy0 = max(y0, math.floor((c[1] - radius) / t - 0.5))
        sy1 = min(y1, math.ceil((c[1] + radius) / t + 0.5))
        if sx1 <= sx0 or sy1 <= sy0:
            return None
        apex = Apex(t, float(c[0]), float(c[1]), self.cos, self.sin)
        sdf = self._footprint_sdf(apex, radius, (sx0, sy0, sx1, sy1))
        if sdf is None:
            return None
        ax, ay = float(self.across[0]), float(self.across[1])
        footprint = FootprintSdf(sdf, sx0, sy0)
        a_lo, a_hi = footprint_across(apex, ax, ay, footprint)
        if a_hi < a_lo:
            return None
        # the streaks no narrower than the texels can hold (u spans the width over 2)
        blur = ANTIALIAS_TEXELS * t * 2.0 / max(a_hi - a_lo, t)
        gain_table, loss_table = profile_tables(self.bristles, blur)
        gain, loss = np.empty((y1 - y0, x1 - x0)), np.empty((y1 - y0, x1 - x0))
        across = Across(ax, ay, a_lo, a_hi)
        texture_weights(
            x0, y0, apex, across, self.reach_m, footprint, (gain_table, loss_table), (gain, loss)
        )
        return gain, loss

    def _footprint_sdf(self, apex: Apex, radius: float, box: Box) -> np.ndarray | None:
        """The footprint's signed distance over the texels of ``box`` within ``radius`` of the
        apex (inf elsewhere; :func:`footprint_sdf` where the tip has a compiled form, which also
        leaves inf beyond the texture's reach), or None when no texel is that near."""
        sx0, sy0, sx1, sy1 = box
        shape = (sy1 - sy0, sx1 - sx0)
        compiled = getattr(self.footprint.base, "kernel", None)
        if compiled is not None:
            kind, params, scale = compiled
            tip = (kind, params, float(scale), float(self.footprint.z_m))
            sdf = np.empty(shape)
            count = footprint_sdf(apex, radius**2, tip, self.reach_m, sx0, sy0, sdf)
            return sdf if count > 0 else None
        body = np.empty((shape[0] * shape[1], 2))
        index = np.empty(shape[0] * shape[1], np.int64)
        count = near_points(apex, radius**2, sx0, sy0, shape[1], shape[0], body, index)
        if count == 0:
            return None
        sdf = np.full(shape, np.inf)
        sdf.reshape(-1)[index[:count]] = self.footprint.sdf(body[:count])
        return sdf
