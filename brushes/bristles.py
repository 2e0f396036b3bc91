"""Bristle texture of a brush: where across its footprint the bristles leave more or less paint.

A bristle brush does not lay paint down as one even sheet: its hairs gather in clumps, each of
which leaves a streak of paint along the stroke (thinner paint, grooves, between the streaks),
and the hairs splayed at the sides of the footprint push paint up into a ridge along each edge
of the stroke.
Because every clump moves with the brush, the pattern depends only on the position *across* the
motion: it is a profile of ``u``, the across-motion coordinate scaled to ``[-1, 1]`` over the
footprint's width.

:class:`Bristles` holds a preset's ``[bristles]`` table and gives that profile:

- ``clumps`` streaks at stratified, jittered positions across the width, each a Gaussian of width
  ``0.35 / clumps`` of the full width and of random strength in [0.5, 1]; their sum, divided by
  its largest value, is the *streak* profile ``t(u)`` in [0, 1];
- the edge ridge ``e(u)`` rises from 0 to 1 over the outer ``1.5 / clumps`` of the width on each
  side.

Where the paint goes (:mod:`paintapp.paint.bristles` applies it on the canvas texels): paint laid
down is spread in proportion to ``1 - contrast + contrast * t(u) + ridge * e(u)``, and paint taken
away (picked up, pushed on) is taken in proportion to ``1 - contrast * t(u)``; both are
normalised per grid column, so the texture moves paint *within* a column's reach and never
creates or destroys any.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

#: Samples of the profile over ``u`` in [-1, 1] (interpolated linearly in between).
PROFILE_SAMPLES = 1025
MAX_CLUMPS = 400
MAX_CONTRAST = 1.0


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

    @cached_property
    def _profiles(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        rng = np.random.default_rng(self.seed)
        n = self.clumps
        centres = -1.0 + (2.0 * np.arange(n) + 1.0 + rng.uniform(-0.6, 0.6, n)) / n
        strength = rng.uniform(0.5, 1.0, n)
        sigma = 0.25 * 2.0 / n
        u = np.linspace(-1.0, 1.0, PROFILE_SAMPLES)
        tracks = (strength[:, None] * np.exp(-0.5 * ((u - centres[:, None]) / sigma) ** 2)).sum(0)
        tracks /= tracks.max()
        band = 1.5 * 2.0 / n
        edge = np.clip((np.abs(u) - (1.0 - band)) / band, 0.0, 1.0) ** 2
        return u, tracks, edge

    def tracks(self, u: np.ndarray) -> np.ndarray:
        """Track profile ``t(u)`` in [0, 1] at across-motion positions ``u`` (clipped to [-1, 1])."""
        grid, tracks, _ = self._profiles
        return np.interp(np.clip(u, -1.0, 1.0), grid, tracks)

    def edge(self, u: np.ndarray) -> np.ndarray:
        """Edge-ridge profile ``e(u)`` in [0, 1] (0 inside, 1 at the footprint's sides)."""
        grid, _, edge = self._profiles
        return np.interp(np.clip(u, -1.0, 1.0), grid, edge)

    def gain_weight(self, u: np.ndarray) -> np.ndarray:
        """Relative share of laid-down paint at ``u`` (> 0)."""
        return 1.0 - self.contrast + self.contrast * self.tracks(u) + self.ridge * self.edge(u)

    def loss_weight(self, u: np.ndarray) -> np.ndarray:
        """Relative share of removed paint at ``u``, in [1 - contrast, 1]."""
        return 1.0 - self.contrast * self.tracks(u)
