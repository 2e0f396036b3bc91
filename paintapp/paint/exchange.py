"""Paint exchange between the brush and the paint grid's cells, conserving every pigment.

After each solver step the tip (the bristles) overlaps whatever paint the grid had where it now
is: a cell holds at most its fluid share of the capacity (:attr:`CellSpace.cap`: from the cut-cell
geometry's fluid fractions, so a cell the tip covers in part keeps paint up to its open part, and
the sweep does not jump by whole cells as the tip moves through a cell). The excess is *swept*:
the brush soaks up ``pickup_fraction`` of it (as far as its reservoir has
room, :meth:`brushes.PaintReservoir.pick_up`); the rest is pushed aside into the nearest free room
around the tip (a plough: this is what builds ridges along a stroke), ring by ring, or by the
tip's distance where the scene asks and the cut-cell geometry gives it
(:mod:`paintapp.paint.nearest_room`). Then the brush *deposits* paint from its reservoir
(:meth:`PaintReservoir.deposit`) into the free room of the cells touching it near the canvas.
Only wet paint is ever in the grid, so dry paint is never picked up or pushed.

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
from paintapp.paint.cell_kernels import (
    _ring_room,
    add_to_ring,
    probe_rings,
    spread_into_rings,
    sweep_overlap,
)
from paintapp.paint.nearest_room import FILL_WIDTH, fill_nearest
from solver import FLUID, STATIC_SOLID

#: How many rings of cells around the tip receive pushed paint before it is kept in the bristles.
MAX_RING = 8
#: Lateral travel in one step (cells) from which a tip pushes nothing into its own trail.
PLOUGH_TRAVEL_CELLS = 0.5


@dataclass(frozen=True)
class CellSpace:
    """How paint values in cells relate to volumes.

    Attributes:
        unit: volume (m^3) of a cell value of 1 (3D: the cell volume; 2D: the cell area, values
            being thicknesses).
        cap: (nx, ny, nz) largest total value each cell takes: the full capacity times the
            cell's fluid fraction (0 inside the tip; :func:`cell_caps`).
        deposit_k_max: highest layer index that receives deposits (3D: near the canvas).
        capacity: the full capacity (3D: 1, a full cell; 2D: a thickness in m).
        distance: (nx, ny, nz) the tip's signed distance at each cell centre, cells (NaN where
            unknown): pushed paint fills the room nearest the tip's surface by it
            (:mod:`paintapp.paint.nearest_room`); None: by rings of cells.
    """

    unit: float
    cap: np.ndarray
    deposit_k_max: int
    capacity: float
    distance: np.ndarray | None = None


@dataclass(frozen=True)
class ExchangeReport:
    """Volumes (m^3, all pigments) moved in one exchange."""

    swept_m3: float = 0.0
    picked_up_m3: float = 0.0
    pushed_m3: float = 0.0
    kept_in_bristles_m3: float = 0.0
    deposited_m3: float = 0.0


def deposit_volume(
    reservoir: PaintReservoir, speed_m_s: float, pressure: float, dt_s: float, length_m: float
) -> float:
    """Volume (m^3) the brush offers to lay down this step (see the module docstring)."""
    rate = max(speed_m_s, 0.0) * (0.25 + 0.75 * min(max(pressure, 0.0), 1.0)) / length_m
    return reservoir.total_m3 * -math.expm1(-rate * dt_s)


def plough_weights(
    cells_xy: tuple[int, int], centre_cells: np.ndarray, travel_cells: np.ndarray
) -> np.ndarray:
    """(nx, ny) share of each column's free room that pushed paint may take: a moving tip pushes
    its paint ahead and aside, not into the trail it leaves.

    ``centre_cells`` is the tip's lateral centre in cell units (column ``(i, j)`` centred at
    ``(i + 0.5, j + 0.5)``), ``travel_cells`` its lateral travel over the step. With ``cos`` the
    cosine between a column's offset from the centre and the travel, and ``a`` the travel in
    units of :data:`PLOUGH_TRAVEL_CELLS` (at most 1), the share is ``(1 + a cos) / (1 + a)``:
    1 straight ahead, ``1 / (1 + a)`` at the sides, ``(1 - a) / (1 + a)`` straight behind (0 for
    a tip that moved at least that far), 1 everywhere for a still tip."""
    travel = np.asarray(travel_cells, dtype=float)[:2]
    dist = float(np.hypot(*travel))
    a = min(dist / PLOUGH_TRAVEL_CELLS, 1.0)
    if a <= 0.0:
        return np.ones(cells_xy)
    ox = np.arange(cells_xy[0]) + 0.5 - float(centre_cells[0])
    oy = np.arange(cells_xy[1]) + 0.5 - float(centre_cells[1])
    dx, dy = np.meshgrid(ox, oy, indexing="ij")
    r = np.hypot(dx, dy)
    cos = np.where(r > 0.0, (dx * travel[0] + dy * travel[1]) / (dist * np.maximum(r, 1e-12)), 0.0)
    return (1.0 + a * cos) / (1.0 + a)


def cell_caps(
    capacity: float, label: np.ndarray, fluid_frac: np.ndarray | None = None
) -> np.ndarray:
    """(nx, ny, nz) capacity of each cell: ``capacity`` times its fluid fraction (cut cells), or
    the full capacity in fluid cells and 0 elsewhere (voxelized tips, ``fluid_frac`` None);
    always 0 in static solids."""
    if fluid_frac is None:
        return np.where(label == FLUID, capacity, 0.0)
    return np.where(label == STATIC_SOLID, 0.0, capacity * np.clip(fluid_frac, 0.0, 1.0))


def exchange_with_brush(
    q: np.ndarray,
    label: np.ndarray,
    reservoir: PaintReservoir,
    names: Sequence[str],
    space: CellSpace,
    pickup_fraction: float,
    deposit_m3: float,
    plough: np.ndarray | None = None,
) -> ExchangeReport:
    """Sweep the paint the tip overlaps, pick up, push aside and deposit (``q`` in place).

    Args:
        q: paint fields (P, nx, ny, nz), in the units of ``space``.
        label: the solver's cell labels (probe cells >= 0): the rings round the tip.
        reservoir: the brush's paint; its pigments must all be in ``names``.
        names: pigment name of each field.
        space: cell volume, each cell's capacity and the deposit layers.
        pickup_fraction: share of swept paint offered to the brush.
        deposit_m3: volume the brush offers to deposit (:func:`deposit_volume`).
        plough: (nx, ny) share of each column's free room open to pushed paint
            (:func:`plough_weights`); default all of it.
    """
    swept = np.zeros(len(names))
    sweep_overlap(q, space.cap, space.capacity, space.unit, swept)
    taken = np.zeros(len(names))
    offer = {n: pickup_fraction * v for n, v in zip(names, swept, strict=True) if v > 0.0}
    if offer:
        got = reservoir.pick_up(offer)
        taken = np.array([got.get(n, 0.0) for n in names])
    dist = np.empty(label.shape, dtype=np.int32)
    probe_rings(label, MAX_RING, dist)
    leftover = np.maximum(swept - taken, 0.0)
    pushed = float(leftover.sum())
    even = np.ones(label.shape[:2])
    kept = _place(q, dist, space, leftover, even if plough is None else plough)
    deposited = _deposit(q, dist, space, reservoir, names, deposit_m3, even)
    return ExchangeReport(
        swept_m3=float(swept.sum()),
        picked_up_m3=float(taken.sum()),
        pushed_m3=pushed - kept,
        kept_in_bristles_m3=kept,
        deposited_m3=deposited,
    )


def place_pushed(
    q: np.ndarray,
    label: np.ndarray,
    space: CellSpace,
    volume: np.ndarray,
    plough: np.ndarray | None = None,
) -> float:
    """Put paint volumes ``volume`` (P,) m^3 into the free room round the tip (cells of
    ``label >= 0``), nearest ring first, each column's room times ``plough`` (default all);
    returns what found no room and stays among the bristles (m^3)."""
    dist = np.empty(label.shape, dtype=np.int32)
    probe_rings(label, MAX_RING, dist)
    return _place(q, dist, space, volume, np.ones(label.shape[:2]) if plough is None else plough)


def _place(
    q: np.ndarray, dist: np.ndarray, space: CellSpace, volume: np.ndarray, weight: np.ndarray
) -> float:
    """Put ``volume`` (P,) in the room round the tip, each column's room times ``weight``,
    then (where that room ran out) in the rest of the room: nearest the tip's surface first
    (:func:`paintapp.paint.nearest_room.fill_nearest`) where ``space`` has the tip's distance,
    then in the rings around the tip; what finds no room at all stays in the probe's cells
    (among the bristles). Returns the volume kept."""
    if not volume.any():
        return 0.0
    nz = q.shape[3]
    if space.distance is not None:
        fill_nearest(q, space.distance, space.cap, weight, nz - 1, space.unit, volume, FILL_WIDTH)
        if volume.any() and weight.min() < 1.0:
            even = np.ones_like(weight)
            fill_nearest(q, space.distance, space.cap, even, nz - 1, space.unit, volume, FILL_WIDTH)
    spread_into_rings(q, dist, 1, MAX_RING, nz - 1, space.cap, weight, space.unit, volume)
    if volume.any() and weight.min() < 1.0:
        even = np.ones_like(weight)
        spread_into_rings(q, dist, 1, MAX_RING, nz - 1, space.cap, even, space.unit, volume)
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
    weight: np.ndarray,
) -> float:
    if offer_m3 <= 0.0 or reservoir.is_empty:
        return 0.0
    room = _ring_room(q, dist, 1, space.deposit_k_max, space.cap, weight) * space.unit
    request = min(offer_m3, (1.0 - 1e-9) * room)
    if request <= 0.0:
        return 0.0
    released = reservoir.deposit(request)
    volume = np.array([released.get(n, 0.0) for n in names])
    missing = set(released) - set(names)
    if missing and any(released[n] > 0.0 for n in missing):
        raise ValueError(f"the brush carries pigments the canvas lacks: {sorted(missing)}")
    total = float(volume.sum())
    spread_into_rings(q, dist, 1, 1, space.deposit_k_max, space.cap, weight, space.unit, volume)
    _place(q, dist, space, volume, weight)
    return total
