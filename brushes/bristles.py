"""Bristle texture of a brush: where across its footprint the bristles leave more or less paint.

A bristle brush's hairs gather in clumps, each leaving a streak of paint along the stroke, and
the hairs splayed at the sides push paint up into a ridge along each edge. Every clump moves with
the brush, so the pattern is a profile of ``u``, the across-motion coordinate scaled to
``[-1, 1]`` over the footprint's width. :class:`Bristles` holds a preset's ``[bristles]`` table
and gives that profile:

- ``clumps`` streaks at stratified, jittered positions, each a Gaussian ``0.35 / clumps`` of the
  width wide and of random strength in [0.5, 1]; their sum over its largest value is the *streak*
  profile ``t(u)`` in [0, 1], optionally with each Gaussian widened by a ``blur`` in quadrature
  (:meth:`Bristles.profiles`: a canvas cannot hold a streak narrower than its texels);
- the edge ridge ``e(u)`` rises from 0 to 1 over the outer ``1.5 / clumps`` of the width.

:mod:`paintapp.paint.bristles` applies it on the canvas texels: paint laid down is spread in
proportion to ``1 - contrast + contrast * t(u) + ridge * e(u)``, paint taken away in proportion
to ``1 - contrast * t(u)``; both are normalised per grid column, so the texture moves paint
*within* a column's reach and never creates or destroys any.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

#: Samples of the profile over ``u`` in [-1, 1] (interpolated linearly in between).
PROFILE_SAMPLES = 1025
MAX_CLUMPS = 400
MAX_CONTRAST = 1.0
#: Streak widenings (``u``) are tabulated at levels this ratio apart, from this least one.
BLUR_RATIO = 1.05
MIN_BLUR = 1e-4


@dataclass(frozen=True)
class Bristles:
    """A preset's bristle texture (see the module docstring).

    Attributes:
        clumps: bristle clumps across the footprint (2-400).
        contrast: 0-1: how much of the paint the clumps' tracks redistribute (0: none).
        ridge: 0-2: extra paint heaped along the two sides of the stroke.
        seed: integer >= 0 choosing the clumps' positions and strengths.
    """

    clumps: int = 24
    contrast: float = 0.5
    ridge: float = 0.5
    seed: int = 0

    def profiles(self, blur: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(u, t(u), e(u)) at ``PROFILE_SAMPLES`` points over [-1, 1], each streak widened by
        ``blur`` (a Gaussian's standard deviation in ``u``, added in quadrature: what a canvas of
        finite texels can hold of it). Read only."""
        return _tabulate(self, blur_level(blur))

    def tracks(self, u: np.ndarray, blur: float = 0.0) -> np.ndarray:
        """Track profile ``t(u)`` in [0, 1] at across-motion positions ``u`` (clipped to [-1, 1])."""
        grid, tracks, _ = self.profiles(blur)
        return np.interp(np.clip(u, -1.0, 1.0), grid, tracks)

    def edge(self, u: np.ndarray) -> np.ndarray:
        """Edge-ridge profile ``e(u)`` in [0, 1] (0 inside, 1 at the footprint's sides)."""
        grid, _, edge = self.profiles()
        return np.interp(np.clip(u, -1.0, 1.0), grid, edge)

    def gain_weight(self, u: np.ndarray, blur: float = 0.0) -> np.ndarray:
        """Relative share of laid-down paint at ``u`` (> 0)."""
        tracks = self.tracks(u, blur)
        return 1.0 - self.contrast + self.contrast * tracks + self.ridge * self.edge(u)

    def loss_weight(self, u: np.ndarray, blur: float = 0.0) -> np.ndarray:
        """Relative share of removed paint at ``u``, in [1 - contrast, 1]."""
        return 1.0 - self.contrast * self.tracks(u, blur)


def blur_level(blur: float) -> float:
    """``blur`` rounded to the nearest of levels :data:`BLUR_RATIO` apart (0 below the least),
    so that the profiles of a footprint whose width changes a little are tabulated once."""
    if not blur > MIN_BLUR:
        return 0.0
    return float(MIN_BLUR * BLUR_RATIO ** round(math.log(blur / MIN_BLUR) / math.log(BLUR_RATIO)))


@functools.lru_cache(maxsize=64)
def _tabulate(bristles: Bristles, blur: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(bristles.seed)
    n = bristles.clumps
    centres = -1.0 + (2.0 * np.arange(n) + 1.0 + rng.uniform(-0.6, 0.6, n)) / n
    strength = rng.uniform(0.5, 1.0, n)
    sigma = 0.25 * 2.0 / n
    wide = math.hypot(sigma, blur)
    u = np.linspace(-1.0, 1.0, PROFILE_SAMPLES)
    tracks = (strength[:, None] * np.exp(-0.5 * ((u - centres[:, None]) / wide) ** 2)).sum(0)
    tracks /= tracks.max()
    band = 1.5 * 2.0 / n
    edge = np.clip((np.abs(u) - (1.0 - band)) / band, 0.0, 1.0) ** 2
    for a in (u, tracks, edge):
        a.flags.writeable = False
    return u, tracks, edge
