"""Paint round a moving tip inside the cells: the faces paint crosses, and the tip's trail.

The paint grid's step moves the tip to its new pose in one jump and then transports the paint
with the tip standing there, so anything that depends on where the tip's surface falls inside a
cell prints that phase into the paint as a row of teeth along a stroke (a comb). Two remedies:

* :func:`paint_faces`: paint crosses each face in proportion to its open fraction (the cut-cell
  geometry's, as in the pressure solve), with the face velocity the solver left there (the tip's
  own where the tip covers the face), so a partly covered face passes part of the flow.
* :func:`lay_trail`: after the transport, what a cell holds beyond its capacity (its fluid share,
  :func:`paintapp.paint.exchange.cell_caps`: the pile against the tip's trailing side, and any
  paint carried into the tip) goes to the room the tip vacated during the step, where a tip
  moving continuously would have left it: each cell takes a share proportional to the volume
  fraction the tip left there (:func:`vacated_share`) times its free room. What does not fit
  goes into the free room round the tip like pushed paint.

Paint stays conserved to round-off and non-negative.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from paintapp.paint.cell_kernels import paint_face_axis, sweep_overlap
from paintapp.paint.exchange import CellSpace, place_pushed
from solver import BOUNDARY, FLUID, STATIC_SOLID

#: Smallest fluid fraction an upwind cell's paint concentration is taken over (a cell the tip
#: all but covers would otherwise need ever more transport sub-steps).
MIN_UPWIND_FLUID = 0.1


def paint_faces(
    comps: list[np.ndarray],
    face_types: list[np.ndarray],
    label: np.ndarray,
    open_frac: Sequence[np.ndarray] | None,
    fluid_frac: np.ndarray | None = None,
) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Velocities and face types for the paint transport: each interior face between two cells
    that are not static solid carries the face velocity times its open fraction (``FREE``), the
    others nothing (``BOUNDARY``); a face beside a tip cell is open in full (paint follows the
    tip). With ``fluid_frac``, a face's flux is spread over its upwind cell's fluid part only (at
    least ``MIN_UPWIND_FLUID`` of it). Without open fractions (voxelized tips) the grid's own.
    One kernel pass per axis (:func:`paintapp.paint.cell_kernels.paint_face_axis`)."""
    if open_frac is None:
        return comps, face_types
    fluid = np.zeros((0, 0, 0)) if fluid_frac is None else fluid_frac
    vel, types = [], []
    for axis, (u, frac) in enumerate(zip(comps[: len(face_types)], open_frac, strict=False)):
        t = np.full(face_types[axis].shape, BOUNDARY, dtype=face_types[axis].dtype)
        v = np.empty_like(u)
        paint_face_axis(u, frac, label, fluid, MIN_UPWIND_FLUID, axis, v, t)
        vel.append(v)
        types.append(t)
    return vel + comps[len(vel) :], types


def vacated_share(
    label_before: np.ndarray,
    label: np.ndarray,
    fluid_before: np.ndarray | None = None,
    fluid: np.ndarray | None = None,
) -> np.ndarray:
    """Per cell, the volume fraction a tip left during the step: the fluid fraction gained (cut
    cells: ``fluid - fluid_before``, at least 0), or 1 in each fluid cell a tip's voxel left
    (``label_before >= 0``) when no fractions are given; 0 in static solids."""
    if fluid_before is None or fluid is None:
        return ((label_before >= 0) & (label == FLUID)).astype(float)
    return np.where(label == STATIC_SOLID, 0.0, np.clip(fluid - fluid_before, 0.0, 1.0))


def lay_trail(q: np.ndarray, label: np.ndarray, share: np.ndarray, space: CellSpace) -> float:
    """Move what each cell of fields ``q`` (P, nx, ny, nz, in ``space``'s units) holds beyond its
    capacity (``space.cap``) into the room the tip vacated (``share``, :func:`vacated_share`,
    times each cell's free room); the rest as pushed paint. Returns the volume (m^3) moved."""
    volume = np.zeros(q.shape[0])
    sweep_overlap(q, space.cap, space.capacity, space.unit, volume)
    moved = float(volume.sum())
    if moved <= 0.0:
        return 0.0
    room = share * np.clip(space.cap - q.sum(axis=0), 0.0, None)
    total_room = float(room.sum()) * space.unit
    if total_room > 0.0:
        laid = min(moved, (1.0 - 1e-12) * total_room)
        q += (volume * (laid / (moved * total_room)))[:, None, None, None] * room
        volume *= 1.0 - laid / moved
    if volume.any():
        place_pushed(q, label, space, volume, None)
    return moved
