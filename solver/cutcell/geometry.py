"""Cut-cell geometry of the moving probes: open face fractions and fluid volume fractions.

Every step the probes' signed distances are sampled in a window around each probe at the grid
nodes, face and cell centres (3D: the nodes only, the others the mean of their corners):

* the **open fraction** ``w`` of every face, its weight in the pressure projection. 2D: the fluid
  share of the face's staggered control volume (Batty, Bertails & Bridson 2007), which, unlike
  the face's open length, changes smoothly as a surface crosses it; 3D: the part of the face's
  area outside all probes. Both by the square rule on corner values. Fractions below
  ``MIN_FRACTION`` are closed (a sliver of a face between a probe and a wall would otherwise
  carry the probe's whole displaced volume into the flow; a cell with all faces closed leaves
  the pressure system);
* each cell's **fluid fraction** (2D: the square rule on its corners; 3D: its faces' mean ``w``);
* each face's solid part's owner (the nearest probe), whose rigid velocity enters there.

Arrays are stored like the MAC samples (``[i, j, k]``, x first); outside the probes' windows
``w = 1``, fluid fraction 1, signed distance ``FAR``, owner -1. A box probe's corners can be
rounded (``SolverSettings.corner_radius_cells``, given to :meth:`CutGeometry.update` in metres).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from solver.compiled.jit import inline_kernel, kernel
from solver.compiled.layers import layer_count
from solver.grid import Grid
from solver.probes import Probe
from solver.shapes import Shape, with_rounded_corners

FAR = 1e30
UNIT = np.eye(3, dtype=np.int64)  # UNIT[a]: one step along axis a (a face window's extra)
UNIT.flags.writeable = False
MIN_FRACTION = 0.1


@inline_kernel
def fraction_inside_segment(a, b):
    """Fraction of a segment inside (SDF < 0) for a linear SDF with end values ``a``, ``b``."""
    if a < 0.0 and b < 0.0:
        return 1.0
    if a < 0.0 <= b:
        return a / (a - b)
    if b < 0.0 <= a:
        return b / (b - a)
    return 0.0


@kernel
def _corner(c0, c1, c2, c3, i):
    """Corner ``i % 4`` of a square with corners ``c0..c3`` in cyclic order."""
    i = i % 4
    if i == 0:
        return c0
    if i == 1:
        return c1
    if i == 2:
        return c2
    return c3


@kernel
def fraction_inside_square(c0, c1, c2, c3):
    """Fraction of a square inside, corners ``c0..c3`` in cyclic order (Batty's rule). The
    corners are read cyclically from a start corner ``o`` chosen per case (no arrays: this runs
    for every face near a probe in 3D, every step)."""
    inside = (c0 < 0) + (c1 < 0) + (c2 < 0) + (c3 < 0)
    if inside == 4:
        return 1.0
    if inside == 0:
        return 0.0
    o = 0
    if inside == 3:  # start at the one corner outside
        while _corner(c0, c1, c2, c3, o) < 0:
            o += 1
    elif inside == 1:  # start at the one corner inside
        while _corner(c0, c1, c2, c3, o) >= 0:
            o += 1
    else:  # start at an inside corner followed by another inside corner one or two steps on
        while _corner(c0, c1, c2, c3, o) >= 0 or not (
            _corner(c0, c1, c2, c3, o + 1) < 0 or _corner(c0, c1, c2, c3, o + 2) < 0
        ):
            o += 1
    l0 = _corner(c0, c1, c2, c3, o)
    l1 = _corner(c0, c1, c2, c3, o + 1)
    l2 = _corner(c0, c1, c2, c3, o + 2)
    l3 = _corner(c0, c1, c2, c3, o + 3)
    if inside == 3:
        s0 = 1.0 - fraction_inside_segment(l0, l3)
        s1 = 1.0 - fraction_inside_segment(l0, l1)
        return 1.0 - 0.5 * s0 * s1
    if inside == 1:
        return 0.5 * fraction_inside_segment(l0, l3) * fraction_inside_segment(l0, l1)
    if l1 < 0:  # the two inside corners are adjacent
        return 0.5 * (fraction_inside_segment(l0, l3) + fraction_inside_segment(l1, l2))
    if 0.25 * (l0 + l1 + l2 + l3) < 0:  # diagonal, centre inside
        a = 0.5 * (1.0 - fraction_inside_segment(l0, l3)) * (1.0 - fraction_inside_segment(l2, l3))
        a += 0.5 * (1.0 - fraction_inside_segment(l2, l1)) * (1.0 - fraction_inside_segment(l0, l1))
        return 1.0 - a
    a = 0.5 * fraction_inside_segment(l0, l1) * fraction_inside_segment(l0, l3)
    a += 0.5 * fraction_inside_segment(l2, l1) * fraction_inside_segment(l2, l3)
    return a


@kernel
def open_fractions(phi_node, phi_other, owner_node, dim, axis, lo, hi, w, owner, layers):
    """Open fraction and solid owner of the faces of component ``axis`` in the window
    ``lo <= (i, j, k) < hi`` (face indices): 2D, the fluid share of each face's staggered control
    volume, whose corners are the other component's face centres ``phi_other`` (on the domain's
    sides the half inside it); 3D, the open share of the face from the node SDF ``phi_node``.
    ``layers``: as :func:`solver.compiled.layers.layer_count` gives it for the grid (on a 2D grid the
    window holds the one layer of the x and y faces)."""
    k0 = 0 if layers is None else lo[2]  # constants on a 2D grid (see solver.compiled.layers)
    k1 = 1 if layers is None else hi[2]
    for i in range(lo[0], hi[0]):
        for j in range(lo[1], hi[1]):
            for k in range(k0, k1):
                if dim == 2:
                    i1, j1 = (i, j + 1) if axis == 0 else (i + 1, j)
                    a, b = phi_node[i, j, 0], phi_node[i1, j1, 0]
                    if axis == 0:  # control volume: cell centre to cell centre across the face
                        il, ir = max(i - 1, 0), min(i, phi_other.shape[0] - 1)
                        c0, c1 = phi_other[il, j, 0], phi_other[ir, j, 0]
                        c2, c3 = phi_other[ir, j + 1, 0], phi_other[il, j + 1, 0]
                    else:
                        jl, jr = max(j - 1, 0), min(j, phi_other.shape[1] - 1)
                        c0, c1 = phi_other[i, jl, 0], phi_other[i + 1, jl, 0]
                        c2, c3 = phi_other[i + 1, jr, 0], phi_other[i, jr, 0]
                    f = 1.0 - fraction_inside_square(c0, c1, c2, c3)
                    o = owner_node[i, j, 0] if a <= b else owner_node[i1, j1, 0]
                else:
                    if axis == 0:
                        c = (
                            phi_node[i, j, k],
                            phi_node[i, j + 1, k],
                            phi_node[i, j + 1, k + 1],
                            phi_node[i, j, k + 1],
                        )
                        oo = (
                            owner_node[i, j, k],
                            owner_node[i, j + 1, k],
                            owner_node[i, j + 1, k + 1],
                            owner_node[i, j, k + 1],
                        )
                    elif axis == 1:
                        c = (
                            phi_node[i, j, k],
                            phi_node[i + 1, j, k],
                            phi_node[i + 1, j, k + 1],
                            phi_node[i, j, k + 1],
                        )
                        oo = (
                            owner_node[i, j, k],
                            owner_node[i + 1, j, k],
                            owner_node[i + 1, j, k + 1],
                            owner_node[i, j, k + 1],
                        )
                    else:
                        c = (
                            phi_node[i, j, k],
                            phi_node[i + 1, j, k],
                            phi_node[i + 1, j + 1, k],
                            phi_node[i, j + 1, k],
                        )
                        oo = (
                            owner_node[i, j, k],
                            owner_node[i + 1, j, k],
                            owner_node[i + 1, j + 1, k],
                            owner_node[i, j + 1, k],
                        )
                    f = 1.0 - fraction_inside_square(c[0], c[1], c[2], c[3])
                    o = oo[0]
                    best = c[0]
                    for n in range(1, 4):
                        if c[n] < best:
                            best = c[n]
                            o = oo[n]
                if f < MIN_FRACTION:
                    f = 0.0
                w[i, j, k] = f
                owner[i, j, k] = o if f < 1.0 else -1


@kernel
def fluid_fractions(phi_node, wx, wy, wz, dim, lo, hi, out):
    """Fluid volume fraction of the cells in the window ``lo <= (i, j, k) < hi``."""
    for i in range(lo[0], hi[0]):
        for j in range(lo[1], hi[1]):
            for k in range(lo[2], hi[2]):
                if dim == 2:
                    out[i, j, k] = 1.0 - fraction_inside_square(
                        phi_node[i, j, 0],
                        phi_node[i + 1, j, 0],
                        phi_node[i + 1, j + 1, 0],
                        phi_node[i, j + 1, 0],
                    )
                else:
                    s = wx[i, j, k] + wx[i + 1, j, k] + wy[i, j, k] + wy[i, j + 1, k]
                    s += wz[i, j, k] + wz[i, j, k + 1]
                    out[i, j, k] = s / 6.0


@kernel
def _fill(a, lo, hi, value):
    """``a[lo:hi] = value`` over a 3D window (``lo >= 0``), clipped to ``a``'s shape as a slice
    is. A window across the whole last axis (every one on a 2D grid) fills a contiguous run per
    first index (``a`` is C-contiguous): a loop over the last axis's one or two layers cost more
    than the stores."""
    nx, ny, nz = a.shape
    j0, j1 = lo[1], min(hi[1], ny)
    if lo[2] == 0 and hi[2] >= nz:
        flat = a.reshape(-1)
        for i in range(lo[0], min(hi[0], nx)):
            for n in range((i * ny + j0) * nz, (i * ny + j1) * nz):
                flat[n] = value
        return
    for i in range(lo[0], min(hi[0], nx)):
        for j in range(j0, j1):
            for k in range(lo[2], min(hi[2], nz)):
                a[i, j, k] = value


class CutArrays(NamedTuple):
    """The arrays of a :class:`CutGeometry` (the same arrays, not copies), as its kernels take
    them."""

    phi_node: np.ndarray
    owner_node: np.ndarray
    phi_face: tuple[np.ndarray, ...]
    open_frac: tuple[np.ndarray, ...]
    owner_face: tuple[np.ndarray, ...]
    owner_sample: tuple[np.ndarray, ...]
    fluid_frac: np.ndarray
    phi_cell: np.ndarray
    owner_cell: np.ndarray


@kernel
def reset_window(lo, hi, dim, arrays):
    """Clear a probe's window of cells ``lo..hi`` back to no probe at all in the geometry's
    ``arrays`` (:class:`CutArrays`): its nodes (one more along each of the grid's axes), cells and
    the faces of each component (one more along the component's axis), in one compiled pass
    rather than a numpy slice assignment per array."""
    node_hi = hi.copy()
    for a in range(dim):
        node_hi[a] += 1
    _fill(arrays.phi_node, lo, node_hi, FAR)
    _fill(arrays.owner_node, lo, node_hi, -1)
    _fill(arrays.fluid_frac, lo, hi, 1.0)
    _fill(arrays.phi_cell, lo, hi, FAR)
    _fill(arrays.owner_cell, lo, hi, -1)
    for a in range(3):
        face_hi = hi.copy()
        face_hi[a] += 1
        _fill(arrays.phi_face[a], lo, face_hi, FAR)
        _fill(arrays.open_frac[a], lo, face_hi, 1.0)
        _fill(arrays.owner_face[a], lo, face_hi, -1)
        _fill(arrays.owner_sample[a], lo, face_hi, -1)


@dataclass
class CutGeometry:
    """Per-step cut-cell geometry of all probes on one grid (see the module docstring).

    Attributes:
        phi_node: min probe SDF at the grid nodes, shape (nx+1, ny+1, nz+1) (2D: nz+1 -> 1), m.
        owner_node: index of the nearest probe at each node (-1 far from all).
        phi_face: min probe SDF at the face centres, per component, face shapes, m.
        open_frac: open (fluid) fraction per face, per component.
        owner_face: probe owning each face's solid part (-1 when the face is open).
        owner_sample: nearest probe at each face centre (-1 far from all).
        fluid_frac: fluid volume fraction per cell.
        phi_cell: min probe SDF at the cell centres, m.
        owner_cell: the probe whose SDF is that minimum where it is ``<= 0`` (the cell's centre
            lies inside it: the voxelized label), -1 elsewhere.
        windows: the cell windows (lo, hi) recomputed at the last update.
    """

    phi_node: np.ndarray
    owner_node: np.ndarray
    phi_face: tuple[np.ndarray, ...]
    open_frac: tuple[np.ndarray, ...]
    owner_face: tuple[np.ndarray, ...]
    owner_sample: tuple[np.ndarray, ...]
    fluid_frac: np.ndarray
    phi_cell: np.ndarray
    owner_cell: np.ndarray
    windows: list[tuple[np.ndarray, np.ndarray]] = field(default_factory=list)

    @classmethod
    def empty(cls, grid: Grid) -> CutGeometry:
        nx, ny, nz = grid.cells
        nodes = (nx + 1, ny + 1, nz + 1 if grid.dim == 3 else 1)
        shapes = [grid.face_shape(a) for a in range(3)]
        return cls(
            phi_node=np.full(nodes, FAR),
            owner_node=np.full(nodes, -1, dtype=np.int32),
            phi_face=tuple(np.full(s, FAR) for s in shapes),
            open_frac=tuple(np.ones(s) for s in shapes),
            owner_face=tuple(np.full(s, -1, dtype=np.int32) for s in shapes),
            owner_sample=tuple(np.full(s, -1, dtype=np.int32) for s in shapes),
            fluid_frac=np.ones(grid.cells),
            phi_cell=np.full(grid.cells, FAR),
            owner_cell=np.full(grid.cells, -1, dtype=np.int32),
        )

    @property
    def arrays(self) -> CutArrays:
        """The geometry's arrays, as its kernels take them."""
        return CutArrays(
            self.phi_node,
            self.owner_node,
            self.phi_face,
            self.open_frac,
            self.owner_face,
            self.owner_sample,
            self.fluid_frac,
            self.phi_cell,
            self.owner_cell,
        )

    def _reset(self, dim: int) -> None:
        arrays = self.arrays
        for lo, hi in self.windows:
            reset_window(lo, hi, dim, arrays)
        self.windows = []

    def shift(self, offset: tuple[int, int, int], cells: tuple[int, int, int]) -> bool:
        """Move the geometry with a grid of ``cells`` that moved by whole cells ``offset``
        (``new[i] = old[i + offset]``), the probes standing still: every array moved in place,
        what enters the grid empty (no probe), the windows moved with it. The same geometry an
        :meth:`update` on the moved grid computes, to round-off in the distances (the nodes are
        the same points), at a fraction of its cost. Returns False, changing nothing, when a
        window touches a side it moves across or would leave the grid (the geometry beyond
        the old grid is not known): an :meth:`update` is needed then."""
        off = np.asarray(offset, dtype=np.int64)
        n = np.asarray(cells, dtype=np.int64)
        moved = []
        for lo, hi in self.windows:
            new_lo, new_hi = lo - off, hi - off
            across = off != 0
            if (across & ((lo <= 0) | (hi >= n))).any() or (new_lo < 0).any() or (new_hi > n).any():
                return False
            moved.append((new_lo, new_hi))
        for a, fill in (
            (self.phi_node, FAR),
            (self.owner_node, -1),
            (self.fluid_frac, 1.0),
            (self.phi_cell, FAR),
            (self.owner_cell, -1),
            *((f, FAR) for f in self.phi_face),
            *((f, 1.0) for f in self.open_frac),
            *((f, -1) for f in self.owner_face),
            *((f, -1) for f in self.owner_sample),
        ):
            _shift_in_place(a, off, fill)
        self.windows = moved
        return True

    def update(self, grid: Grid, probes: list[Probe], corner_radius_m: float = 0.0) -> None:
        """Recompute the geometry around every probe (and clear it where probes have left), box
        probes with their corners rounded by ``corner_radius_m``."""
        self._reset(grid.dim)
        d = grid.dim
        for n, probe in enumerate(probes):
            lo, hi = probe_window(grid, probe)
            if (hi <= lo).any():
                continue
            self.windows.append((lo, hi))
            shape = with_rounded_corners(probe.shape, corner_radius_m)
            _sample_sdf(grid, probe, shape, n, lo, hi, self)
        layers = layer_count(self.fluid_frac.shape)
        for lo, hi in self.windows:
            for a in range(d):
                face_hi = hi + UNIT[a]
                open_fractions(
                    self.phi_node,
                    self.phi_face[1 - a] if d == 2 else self.phi_node,
                    self.owner_node,
                    d,
                    a,
                    lo,
                    face_hi,
                    self.open_frac[a],
                    self.owner_face[a],
                    layers,
                )
            wx, wy, wz = self.open_frac
            fluid_fractions(self.phi_node, wx, wy, wz, d, lo, hi, self.fluid_frac)


@kernel
def _shift_kernel(a, oi, oj, ok, fill):
    """``a[i, j, k] = a[i + oi, j + oj, k + ok]`` in place, ``fill`` where that is outside ``a``.
    Each axis runs in the direction that reads every source before it is overwritten."""
    nx, ny, nz = a.shape
    for ii in range(nx):
        i = ii if oi >= 0 else nx - 1 - ii
        si = i + oi
        for jj in range(ny):
            j = jj if oj >= 0 else ny - 1 - jj
            sj = j + oj
            for kk in range(nz):
                k = kk if ok >= 0 else nz - 1 - kk
                sk = k + ok
                if 0 <= si < nx and 0 <= sj < ny and 0 <= sk < nz:
                    a[i, j, k] = a[si, sj, sk]
                else:
                    a[i, j, k] = fill


def _shift_in_place(a: np.ndarray, off: np.ndarray, fill: float) -> None:
    """``a`` moved by whole cells in place, ``new[i] = old[i + off]``, ``fill`` where it enters."""
    _shift_kernel(a, int(off[0]), int(off[1]), int(off[2]), a.dtype.type(fill))


def probe_window(grid: Grid, probe: Probe, margin: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """Cell index window ``lo <= idx < hi`` (int64 (3,)) covering the probe plus ``margin``
    cells: its world box (:meth:`~solver.probes.Probe.world_box`), every cell outside the window
    at least ``margin`` cells from the probe."""
    h = grid.cell_size_m
    lo = np.zeros(3, dtype=np.int64)
    hi = np.array(grid.cells, dtype=np.int64)
    lower, upper = probe.world_box()
    for a in range(grid.dim):
        n = grid.cells[a]
        lo[a] = min(max(math.floor((lower[a] - grid.origin_m[a]) / h) - margin, 0), n)
        hi[a] = min(max(math.ceil((upper[a] - grid.origin_m[a]) / h) + margin, 0), n)
    return lo, hi


def _lattice_sdf(
    probe: Probe,
    shape: Shape,
    lattice: tuple[np.ndarray, np.ndarray, float],
    counts: list[int],
) -> list[np.ndarray]:
    """The probe's SDF on the half-cell lattice ``lattice`` (the grid's origin, the window's
    first cell and the cell size; ``counts`` points along each axis). 2D: ``[sdf]`` at every
    point of the lattice exactly, in one call of the SDF (its sub-lattices tile it). 3D: ``[node,
    face x, face y, face z, cell]``, each shaped like the window of its array, from the SDF at
    the nodes only (a brush tip's SDF is by far the most expensive part of the cut geometry); a
    face centre takes the mean of its face's four corners and a cell centre that of its eight,
    the same corners the open fractions come from (exact for a linear SDF)."""
    d = len(counts)
    rot = probe.rotation_matrix()
    centre = np.asarray(probe.centre_m, dtype=float)
    origin, lo, h = lattice
    if d == 2:
        rel = np.empty((counts[0], counts[1], 2))
        lattice_offsets_2d(origin, lo, h, 1, centre, rel)
        return [np.asarray(shape.sdf(rel @ rot), dtype=float)]
    rel = np.empty((*((n + 1) // 2 for n in counts), 3))
    lattice_offsets_3d(origin, lo, h, 2, centre, rel)
    node = np.ascontiguousarray(shape.sdf(rel @ rot), dtype=float)
    nx, ny, nz = node.shape
    faces = [
        np.empty((nx, ny - 1, nz - 1)),
        np.empty((nx - 1, ny, nz - 1)),
        np.empty((nx - 1, ny - 1, nz)),
    ]
    cell = np.empty((nx - 1, ny - 1, nz - 1))
    node_means(node, faces[0], faces[1], faces[2], cell)
    return [node, *faces, cell]


@inline_kernel
def _lattice_point(origin, lo, h, step, a, m):
    """Coordinate ``a`` of point ``m`` (every ``step``-th) of the half-cell lattice from cell
    ``lo``: ``origin[a] + (lo[a] + m step / 2) h``."""
    return origin[a] + (lo[a] + 0.5 * (step * m)) * h


@kernel
def lattice_offsets_2d(origin, lo, h, step, centre, out):
    """``out[i, j]`` = point (i, j) of every ``step``-th point of the half-cell lattice from cell
    ``lo`` less ``centre``: the probe-relative points, as numpy's grid of the lattice's axes less
    the centre would give them (one pass, no temporaries)."""
    for i in range(out.shape[0]):
        x = _lattice_point(origin, lo, h, step, 0, i)
        for j in range(out.shape[1]):
            out[i, j, 0] = x - centre[0]
            out[i, j, 1] = _lattice_point(origin, lo, h, step, 1, j) - centre[1]


@kernel
def lattice_offsets_3d(origin, lo, h, step, centre, out):
    """:func:`lattice_offsets_2d` in 3D."""
    for i in range(out.shape[0]):
        x = _lattice_point(origin, lo, h, step, 0, i)
        for j in range(out.shape[1]):
            y = _lattice_point(origin, lo, h, step, 1, j)
            for k in range(out.shape[2]):
                out[i, j, k, 0] = x - centre[0]
                out[i, j, k, 1] = y - centre[1]
                out[i, j, k, 2] = _lattice_point(origin, lo, h, step, 2, k) - centre[2]


@kernel
def node_means(node, face_x, face_y, face_z, cell):
    """Each face's mean of its four corner nodes, and each cell's of its eight (``node`` (nx, ny,
    nz); a face of axis ``a`` lies across the other two axes). The sums run in a fixed order: a
    face's two pairs along its first axis, a cell's halvings along x, then y, then z."""
    nx, ny, nz = node.shape
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if j + 1 < ny and k + 1 < nz:
                    face_x[i, j, k] = 0.25 * (
                        (0.0 + (node[i, j, k] + node[i, j, k + 1]))
                        + (node[i, j + 1, k] + node[i, j + 1, k + 1])
                    )
                if i + 1 < nx and k + 1 < nz:
                    face_y[i, j, k] = 0.25 * (
                        (0.0 + (node[i, j, k] + node[i, j, k + 1]))
                        + (node[i + 1, j, k] + node[i + 1, j, k + 1])
                    )
                if i + 1 < nx and j + 1 < ny:
                    face_z[i, j, k] = 0.25 * (
                        (0.0 + (node[i, j, k] + node[i, j + 1, k]))
                        + (node[i + 1, j, k] + node[i + 1, j + 1, k])
                    )
                if i + 1 < nx and j + 1 < ny and k + 1 < nz:
                    a00 = 0.5 * (node[i, j, k] + node[i + 1, j, k])
                    a10 = 0.5 * (node[i, j + 1, k] + node[i + 1, j + 1, k])
                    a01 = 0.5 * (node[i, j, k + 1] + node[i + 1, j, k + 1])
                    a11 = 0.5 * (node[i, j + 1, k + 1] + node[i + 1, j + 1, k + 1])
                    cell[i, j, k] = 0.5 * (0.5 * (a00 + a10) + 0.5 * (a01 + a11))


def _sample_sdf(
    grid: Grid,
    probe: Probe,
    shape: Shape,
    index: int,
    lo: np.ndarray,
    hi: np.ndarray,
    geo: CutGeometry,
) -> None:
    """Take the min of the stored SDFs and probe ``index``'s (its ``shape``, in its pose) over
    the window ``lo..hi`` (cells) at the nodes, the face centres and the cell centres (see
    :func:`_lattice_sdf`)."""
    d = grid.dim
    counts = [2 * int(hi[a] - lo[a]) + 1 for a in range(d)]
    lattice = (np.asarray(grid.origin_m, dtype=float), lo, grid.cell_size_m)
    if d == 2:  # every sub-lattice in one pass
        (sdf,) = _lattice_sdf(probe, shape, lattice, counts)
        take_closer_2d(
            sdf,
            lo,
            index,
            geo.phi_node,
            geo.owner_node,
            geo.phi_face[0],
            geo.owner_sample[0],
            geo.phi_face[1],
            geo.owner_sample[1],
            geo.phi_cell,
            geo.owner_cell,
        )
        return
    targets = [(geo.phi_node, geo.owner_node)]
    targets += [(geo.phi_face[a], geo.owner_sample[a]) for a in range(d)]
    targets += [(geo.phi_cell, geo.owner_cell)]
    values_of = _lattice_sdf(probe, shape, lattice, counts)
    for (phi, owner), values in zip(targets, values_of, strict=True):
        # a cell belongs to the probe its centre lies inside
        _take_closer(values, phi, owner, lo, index, owner is geo.owner_cell)


@inline_kernel
def _closer(phi, owner, i, j, value, index, inside_only):
    """One sample of :func:`_take_closer` (2D: ``k`` = 0)."""
    if value < phi[i, j, 0]:
        phi[i, j, 0] = value
        if not inside_only or value <= 0.0:
            owner[i, j, 0] = index


@kernel
def take_closer_2d(
    sdf, lo, index, phi_node, owner_node, phi_fx, owner_fx, phi_fy, owner_fy, phi_cell, owner_cell
):
    """:func:`_take_closer` for each sub-lattice of a 2D half-cell lattice's SDF ``sdf`` (from
    cell ``lo``) in one pass: the nodes (even, even), the x faces (even, odd), the y faces (odd,
    even) and the cell centres (odd, odd; owned only where inside)."""
    for i in range(sdf.shape[0]):
        gi = lo[0] + i // 2
        for j in range(sdf.shape[1]):
            gj = lo[1] + j // 2
            value = sdf[i, j]
            if i % 2 == 0:
                if j % 2 == 0:
                    _closer(phi_node, owner_node, gi, gj, value, index, False)
                else:
                    _closer(phi_fx, owner_fx, gi, gj, value, index, False)
            elif j % 2 == 0:
                _closer(phi_fy, owner_fy, gi, gj, value, index, False)
            else:
                _closer(phi_cell, owner_cell, gi, gj, value, index, True)


@kernel
def _take_closer(values, phi, owner, lo, index, inside_only):
    """Where ``values`` (a window at ``lo`` of ``phi``) are below ``phi``, take them, and make
    ``index`` the owner there (only where also ``<= 0`` with ``inside_only``)."""
    ni, nj, nk = values.shape
    for i in range(ni):
        for j in range(nj):
            for k in range(nk):
                value = values[i, j, k]
                gi, gj, gk = lo[0] + i, lo[1] + j, lo[2] + k
                if value < phi[gi, gj, gk]:
                    phi[gi, gj, gk] = value
                    if not inside_only or value <= 0.0:
                        owner[gi, gj, gk] = index
