"""The paint a brush carries: a volume (m^3) per pigment, up to the brush's capacity.

Paint is conserved: every method returns the volumes it moved, so that
``before + loaded + picked_up - deposited - cleaned == after`` per pigment, to round-off. Volumes
never go negative; a deposit takes at most what is there, a load or pick-up at most the free room.
The carried paint is treated as well mixed, so a deposit takes each pigment in proportion.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np


def _volume(value: float, what: str) -> float:
    value = float(value)
    if not (math.isfinite(value) and value >= 0.0):
        raise ValueError(f"{what} must be a finite volume >= 0 (m^3), got {value}")
    return value


class PaintReservoir:
    """Paint volumes per pigment name (m^3) carried by a brush of ``capacity_m3``."""

    def __init__(self, capacity_m3: float, volumes_m3: Mapping[str, float] | None = None) -> None:
        if not (math.isfinite(capacity_m3) and capacity_m3 > 0.0):
            raise ValueError(f"capacity_m3 must be positive, got {capacity_m3}")
        self.capacity_m3 = float(capacity_m3)
        self._volumes: dict[str, float] = {}
        if volumes_m3:
            self.pick_up(volumes_m3)

    @property
    def volumes_m3(self) -> dict[str, float]:
        """A copy of the volume (m^3) per pigment (pigments at zero included)."""
        return dict(self._volumes)

    @property
    def total_m3(self) -> float:
        """Total carried volume (m^3)."""
        return math.fsum(self._volumes.values())

    @property
    def free_m3(self) -> float:
        """Room left (m^3)."""
        return max(self.capacity_m3 - self.total_m3, 0.0)

    @property
    def is_empty(self) -> bool:
        """True when the brush carries no paint."""
        return self.total_m3 <= 0.0

    def fractions(self) -> dict[str, float]:
        """Volume fraction of each pigment in the carried paint (empty dict when dry)."""
        total = self.total_m3
        return {k: v / total for k, v in self._volumes.items()} if total > 0.0 else {}

    def as_array(self, pigments: Sequence[str]) -> np.ndarray:
        """Volumes (m^3) as an array in the order of ``pigments`` (0 for those not carried)."""
        return np.array([self._volumes.get(name, 0.0) for name in pigments])

    def load(self, pigment: str, volume_m3: float) -> float:
        """Load up to ``volume_m3`` of ``pigment`` from the palette; returns the volume loaded.

        Loading stops at capacity.
        """
        return self.pick_up({pigment: volume_m3})[pigment]

    def pick_up(self, volumes_m3: Mapping[str, float]) -> dict[str, float]:
        """Take paint into the brush (e.g. wet paint it drags through); returns what it took.

        When the offer exceeds the free room, every pigment is scaled down by the same factor.
        """
        offer = {name: _volume(v, f"volume of {name!r}") for name, v in volumes_m3.items()}
        total = math.fsum(offer.values())
        scale = min(1.0, self.free_m3 / total) if total > 0.0 else 0.0
        taken = {name: v * scale for name, v in offer.items()}
        for name, v in taken.items():
            self._volumes[name] = self._volumes.get(name, 0.0) + v
        return taken

    def deposit(self, volume_m3: float) -> dict[str, float]:
        """Release up to ``volume_m3`` of the carried mix; returns the volume per pigment released.

        Limited by what the brush carries; each pigment leaves in proportion to its fraction.
        """
        request = _volume(volume_m3, "deposit volume")
        total = self.total_m3
        if total <= 0.0 or request <= 0.0:
            return {name: 0.0 for name in self._volumes}
        if request >= total:
            return self.clean()
        scale = request / total
        out = {}
        for name, v in self._volumes.items():
            out[name] = v * scale
            self._volumes[name] = max(v - out[name], 0.0)
        return out

    def clean(self) -> dict[str, float]:
        """Empty the brush; returns the volume per pigment removed."""
        out = dict(self._volumes)
        self._volumes = {name: 0.0 for name in out}
        return out

    def __repr__(self) -> str:
        parts = ", ".join(f"{k}={v:.3g}" for k, v in self._volumes.items())
        return f"PaintReservoir(capacity_m3={self.capacity_m3:.3g}, {parts or 'dry'})"
