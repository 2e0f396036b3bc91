"""Paint exchange between the brush and the paint grid's cells, conserving every pigment.

After each solver step the probe's cells (the bristles) hold whatever paint the grid had there.
That paint is *swept*: the brush soaks up ``pickup_fraction`` of it (as far as its reservoir has
room, :meth:`brushes.PaintReservoir.pick_up`); the rest is pushed aside into the nearest free room
around the tip, ring by ring (a plough: this is what builds ridges along a stroke). Then the brush
*deposits* paint from its reservoir (:meth:`PaintReservoir.deposit`) into the free room of the
cells touching it near the canvas. Only wet paint is ever in the grid, so dry paint is never
picked up or pushed.

Deposit rate: a brush moving at speed ``v`` with pressure ``p`` releases
``V (1 - exp(-v dt (0.25 + 0.75 p) / L))`` of its load ``V`` per step, with ``L`` the scene's
``deposit_length_m``: a stroke at full pressure lays down 1 - 1/e of the load over ``L``, and a
still brush releases nothing.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from brushes import PaintReservoir
from paintapp.paint.kernels import (
    _ring_room,
    add_to_ring,
    probe_rings,
    spread_into_rings,
    sweep_probe_cells,
)

#: How many rings of cells around the tip receive pushed paint before it is kept in the bristles.
MAX_RING = 8


@dataclass(frozen=True)
class CellSpace:
    """How paint values in cells relate to volumes.

    Attributes:
        unit: volume (m^3) of a cell value of 1 (3D: the cell volume; 2D: the cell area, values
            being thicknesses).
        capacity: largest total value a cell takes (3D: 1, a full cell; 2D: a thickness in m).
        deposit_k_max: highest layer index that receives deposits (3D: near the canvas).
    """

    unit: float
    capacity: float
    deposit_k_max: int


@dataclass(frozen=True)
class ExchangeReport:
    """Volumes (m^3, all pigments) moved in one exchange."""

    swept_m3: float = 0.0
    picked_up_m3: float = 0.0
    pushed_m3: float = 0.0
    kept_in_bristles_m3: float = 0.0
    deposited_m3: float = 0.0


def deposit_volume(reservoir: PaintReservoir, speed_m_s: float, pressure: float, dt_s: float,
                   length_m: float) -> float:  # fmt: skip
    """Volume (m^3) the brush offers to lay down this step (see the module docstring)."""
    rate = max(speed_m_s, 0.0) * (0.25 + 0.75 * min(max(pressure, 0.0), 1.0)) / length_m
    return reservoir.total_m3 * -math.expm1(-rate * dt_s)


def exchange_with_brush(
    q: np.ndarray,
    label: np.ndarray,
    reservoir: PaintReservoir,
    names: Sequence[str],
    space: CellSpace,
    pickup_fraction: float,
    deposit_m3: float,
) -> ExchangeReport:
    """Sweep the probe's cells, pick up, push aside and deposit (fields ``q`` in place).

    Args:
        q: paint fields (P, nx, ny, nz), in the units of ``space``.
        label: the solver's cell labels (probe cells >= 0).
        reservoir: the brush's paint; its pigments must all be in ``names``.
        names: pigment name of each field.
        space: cell volume, capacity and deposit layers.
        pickup_fraction: share of swept paint offered to the brush.
        deposit_m3: volume the brush offers to deposit (:func:`deposit_volume`).
    """
    swept = np.zeros(len(names))
    sweep_probe_cells(q, label, space.unit, swept)
    taken = np.zeros(len(names))
    offer = {n: pickup_fraction * v for n, v in zip(names, swept, strict=True) if v > 0.0}
    if offer:
        got = reservoir.pick_up(offer)
        taken = np.array([got.get(n, 0.0) for n in names])
    dist = np.empty(label.shape, dtype=np.int32)
    probe_rings(label, MAX_RING, dist)
    leftover = np.maximum(swept - taken, 0.0)
    pushed = float(leftover.sum())
    kept = _place(q, dist, space, leftover)
    deposited = _deposit(q, dist, space, reservoir, names, deposit_m3)
    return ExchangeReport(
        swept_m3=float(swept.sum()),
        picked_up_m3=float(taken.sum()),
        pushed_m3=pushed - kept,
        kept_in_bristles_m3=kept,
        deposited_m3=deposited,
    )


def _place(q: np.ndarray, dist: np.ndarray, space: CellSpace, volume: np.ndarray) -> float:
    """Put ``volume`` (P,) in the rings around the tip; what finds no room stays in the probe's
    cells (among the bristles). Returns the volume kept in the bristles."""
    if not volume.any():
        return 0.0
    nz = q.shape[3]
    spread_into_rings(q, dist, 1, MAX_RING, nz - 1, space.capacity, space.unit, volume)
    kept = float(volume.sum())
    if kept > 0.0 and not add_to_ring(q, dist, 0, space.unit, volume):
        if not add_to_ring(q, dist, 1, space.unit, volume):  # no probe cells: never in practice
            q[:, 0, 0, 0] += volume / space.unit
    return kept


def _deposit(
    q: np.ndarray,
    dist: np.ndarray,
    space: CellSpace,
    reservoir: PaintReservoir,
    names: Sequence[str],
    offer_m3: float,
) -> float:
    if offer_m3 <= 0.0 or reservoir.is_empty:
        return 0.0
    room = _ring_room(q, dist, 1, space.deposit_k_max, space.capacity) * space.unit
    request = min(offer_m3, (1.0 - 1e-9) * room)
    if request <= 0.0:
        return 0.0
    released = reservoir.deposit(request)
    volume = np.array([released.get(n, 0.0) for n in names])
    missing = set(released) - set(names)
    if missing and any(released[n] > 0.0 for n in missing):
        raise ValueError(f"the brush carries pigments the canvas lacks: {sorted(missing)}")
    total = float(volume.sum())
    spread_into_rings(q, dist, 1, 1, space.deposit_k_max, space.capacity, space.unit, volume)
    _place(q, dist, space, volume)
    return total
