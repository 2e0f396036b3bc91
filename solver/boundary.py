"""Domain sides: no-slip walls (optionally moving), free-slip walls, inflow and outflow.

Sides are indexed ``(axis, end)`` with ``end`` 0 for the low side (x_min, ...) and 1 for the high
side. The normal velocity faces on each side are set here (once per step); the
tangential conditions enter the viscosity solve and the pressure solve through ``kinds``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from solver.compiled.jit import kernel
from solver.grid import Grid

WALL = 0
SLIP = 1
INFLOW = 2
OUTFLOW = 3
KIND_NAMES = {"wall": WALL, "slip": SLIP, "inflow": INFLOW, "outflow": OUTFLOW}
SIDE_NAMES = ("x_min", "x_max", "y_min", "y_max", "z_min", "z_max")


@dataclass(frozen=True)
class Side:
    """One domain side.

    Attributes:
        kind: ``"wall"`` (no-slip, may move tangentially), ``"slip"`` (free-slip wall),
            ``"inflow"`` or ``"outflow"`` (zero pressure, zero normal gradient of velocity).
        velocity: wall velocity, or the inflow (peak) velocity, m/s, one entry per axis.
        profile: inflow profile, ``"uniform"`` or ``"parabolic"`` (zero at the side's edges,
            ``velocity`` at its centre).
    """

    kind: str = "wall"
    velocity: tuple[float, ...] = ()
    profile: str = "uniform"


@dataclass
class DomainBoundary:
    """The six (2D: four) sides of a grid."""

    grid: Grid
    sides: dict[str, Side] = field(default_factory=dict)

    def side(self, axis: int, end: int) -> Side:
        return self.sides.get(SIDE_NAMES[2 * axis + end], Side())

    def kinds(self) -> np.ndarray:
        """Kind codes, int64 array (3, 2); inactive axes report WALL."""
        out = np.full((3, 2), WALL, dtype=np.int64)
        for a in range(self.grid.dim):
            for e in range(2):
                out[a, e] = KIND_NAMES[self.side(a, e).kind]
        return out

    def velocities(self) -> np.ndarray:
        """Side velocities (wall velocity or uniform inflow velocity), array (3, 2, 3), m/s."""
        out = np.zeros((3, 2, 3))
        for a in range(self.grid.dim):
            for e in range(2):
                vel = self.side(a, e).velocity
                out[a, e, : len(vel)] = vel
        return out

    def has_outflow(self) -> bool:
        return bool(np.any(self.kinds()[: self.grid.dim] == OUTFLOW))

    def apply_normal(
        self,
        comps: list[np.ndarray],
        kinds: np.ndarray | None = None,
        velocities: np.ndarray | None = None,
    ) -> None:
        """Set the normal velocity on every domain side (in place); ``kinds`` and
        ``velocities``, when given, are what :meth:`kinds` and :meth:`velocities` return."""
        kinds = self.kinds() if kinds is None else kinds
        velocities = self.velocities() if velocities is None else velocities
        for a in range(self.grid.dim):
            q = comps[a]
            set_normal_faces(q, a, kinds, velocities)
            for e in range(2):
                if kinds[a, e] == INFLOW:
                    face: list[slice | int] = [slice(None)] * 3
                    face[a] = 0 if e == 0 else q.shape[a] - 1
                    q[tuple(face)] = self._inflow_profile(a, e)

    def _inflow_profile(self, axis: int, end: int) -> np.ndarray:
        """Normal inflow velocity on the faces of side (axis, end), shape of that face slice."""
        g = self.grid
        side = self.side(axis, end)
        peak = side.velocity[axis] if len(side.velocity) > axis else 0.0
        pos = g.face_centres(axis)
        face: list[slice | int] = [slice(None)] * 3
        face[axis] = 0
        pos = pos[tuple(face)]
        shape = np.ones(pos.shape[:-1])
        if side.profile == "parabolic":
            for b in range(g.dim):
                if b == axis:
                    continue
                length = g.size_m[b]
                s = pos[..., b] - g.origin_m[b]
                shape = shape * 4.0 * s * (length - s) / length**2
        return peak * shape


@kernel
def set_normal_faces(q, axis, kinds, velocities):
    """The faces of component ``axis`` on its two sides (in place): a wall's normal velocity
    (``velocities[axis, end, axis]``: zero, or a moving wall's), an outflow side's neighbour
    value (zero normal gradient); inflow sides are left alone."""
    nx, ny, nz = q.shape
    n = q.shape[axis]
    for e in range(2):
        kind = kinds[axis, e]
        if kind == INFLOW:
            continue
        f = 0 if e == 0 else n - 1
        g = 1 if e == 0 else n - 2
        copy = kind == OUTFLOW
        value = velocities[axis, e, axis]
        if axis == 0:
            for j in range(ny):
                for k in range(nz):
                    q[f, j, k] = q[g, j, k] if copy else value
        elif axis == 1:
            for i in range(nx):
                for k in range(nz):
                    q[i, f, k] = q[i, g, k] if copy else value
        else:
            for i in range(nx):
                for j in range(ny):
                    q[i, j, f] = q[i, j, g] if copy else value
