"""The staggered MAC grid: cell counts, cell size and where each sample lives.

Every array is stored three-dimensional, indexed ``[i, j, k]`` with x first. A 2D grid is a 3D grid
one cell deep whose z axis is inactive (``dim == 2``: no z faces, no w velocity), so the same
kernels serve both. Velocity component ``a`` lives on the faces normal to axis ``a``: its array has
one more entry than there are cells along ``a``. Pressure lives at cell centres.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Grid:
    """A uniform MAC grid.

    Attributes:
        dim: 2 or 3.
        cells: cells per axis, always three entries (the third is 1 in 2D).
        cell_size_m: edge length h of every (square/cubic) cell, metres.
        origin_m: position of the grid's lower corner, metres, three entries.
    """

    dim: int
    cells: tuple[int, int, int]
    cell_size_m: float
    origin_m: tuple[float, float, float] = (0.0, 0.0, 0.0)

    @classmethod
    def from_size(
        cls, size_m: tuple[float, ...], cells: tuple[int, ...], rel_tol: float = 1e-6
    ) -> Grid:
        """A grid covering ``size_m`` (2 or 3 entries) with ``cells`` per axis; cells must be cubes."""
        dim = len(size_m)
        if dim not in (2, 3) or len(cells) != dim:
            raise ValueError("size and cells must both have 2 or 3 entries")
        hs = [float(s) / int(n) for s, n in zip(size_m, cells, strict=True)]
        h = hs[0]
        if any(abs(x - h) > rel_tol * h for x in hs):
            raise ValueError(f"cell size differs between axes: {hs}")
        full = tuple(int(n) for n in cells) + (1,) * (3 - dim)
        return cls(dim=dim, cells=full, cell_size_m=h)  # type: ignore[arg-type]

    @property
    def size_m(self) -> np.ndarray:
        """Extent of the domain along each active axis, metres, shape (dim,)."""
        return np.array(self.cells[: self.dim], dtype=float) * self.cell_size_m

    @property
    def cell_volume(self) -> float:
        """Cell volume (m^3 in 3D; m^2 per unit depth in 2D)."""
        return self.cell_size_m**self.dim

    @property
    def face_area(self) -> float:
        """Face area (m^2 in 3D; m per unit depth in 2D)."""
        return self.cell_size_m ** (self.dim - 1)

    def face_shape(self, axis: int) -> tuple[int, int, int]:
        """Shape of the array of velocity component ``axis`` (0, 1, 2)."""
        shape = list(self.cells)
        shape[axis] += 1
        return tuple(shape)  # type: ignore[return-value]

    def cell_centres(self) -> np.ndarray:
        """Cell-centre coordinates, shape (nx, ny, nz, 3), metres (z is 0.5 h in 2D)."""
        return self.sample_positions(None)

    def face_centres(self, axis: int) -> np.ndarray:
        """Face-centre coordinates of velocity component ``axis``, shape (*face_shape, 3)."""
        return self.sample_positions(axis)

    def sample_positions(self, axis: int | None) -> np.ndarray:
        """Positions of cell centres (axis None) or of the faces normal to ``axis``."""
        h = self.cell_size_m
        shape = self.cells if axis is None else self.face_shape(axis)
        axes = []
        for b in range(3):
            offset = 0.0 if b == axis else 0.5
            axes.append(self.origin_m[b] + (np.arange(shape[b]) + offset) * h)
        mesh = np.meshgrid(*axes, indexing="ij")
        return np.stack(mesh, axis=-1)
