"""A flow on an unstructured mesh (OpenFOAM's polyhedra, VTK's unstructured grids), as read:
the mesh once, and per frame the pressure, the velocity and the velocity gradient, all where the
file gave them -- at the mesh's points or at its cells, never averaged from one to the other.

The velocity gradient is taken on the mesh itself when the flow is loaded (``vtkGradientFilter``:
for point data the gradient of each cell's interpolant, averaged at its points; a wall point's
gradient therefore comes from the fluid cells at the wall only, and with the no-slip wall's zero
velocity that a CFD code writes at its wall points it is the wall's shear). The force on a probe
is then taken on a local uniform grid resampled from the mesh around the probe
(:mod:`.local_resample`).

A mesh one cell thick (all points on two planes z = const, as OpenFOAM's ``empty`` patches make
it) or flat (one plane) is a 2D flow in x and y; its thickness is the depth of the body the
solver computed the force for. Units are SI; the pressure here is in Pa (a kinematic pressure is
multiplied by the density when the flow is built).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from common.errors import InputError
from common.limits import check_elements
from paintapp.explore.cell_index import CellIndex
from paintapp.explore.cell_samples import CellSamples, cell_samples
from paintapp.explore.load_progress import Progress

PRESSURE_NAMES = ("p", "pressure", "P")
VELOCITY_NAMES = ("U", "u", "velocity", "Velocity")
#: Relative tolerance (of the mesh's extent) for points lying on one plane.
PLANE_TOLERANCE = 1e-6


@dataclass
class UnstructuredFrame:
    """One frame as a reader found it: the mesh (a ``vtkUnstructuredGrid`` holding the arrays)
    and what the file says about the fluid (None: not stated): density kg/m^3, dynamic
    viscosity Pa s, or kinematic viscosity m^2/s (an OpenFOAM case's ``nu``)."""

    source: str
    mesh: Any
    time_s: float | None = None
    density: float | None = None
    viscosity: float | None = None
    pressure_units: str | None = None
    kinematic_viscosity: float | None = None


@dataclass
class UnstructuredFlow:
    """Pressure, velocity and velocity gradient on an unstructured mesh, one frame or a series.

    Attributes:
        source: the file or case it came from.
        grid: the ``vtkUnstructuredGrid``; frame ``k``'s values are its point (or, with
            ``on_cells``, cell) array ``f{k}``: ``(p [Pa], u_0..u_{dim-1} [m/s],
            G[i, j] = du_i/dx_j [1/s] row by row)``, ``1 + dim + dim^2`` components.
        on_cells: the values sit at the cells (a finite-volume code's cell averages).
        times_s: frame times, (T,), strictly increasing.
        density_kg_m3, viscosity_pa_s: the fluid's (dynamic viscosity).
        dim: 2 or 3.
        plane_z_m: 2D: the z of the mid-plane the flow is read on (None in 3D).
        thickness_m: 2D: the mesh's thickness (None for a flat mesh or in 3D).
        cell_lo_m, cell_hi_m: each cell's bounding box, (cells, 3).
        cell_size_m: each cell's size, (cells,): its bounding box's edges' geometric mean over
            the flow's ``dim`` axes.
        samples: for cell data, the values at the cells' and boundary faces' centres that the
            local grids interpolate (:mod:`.cell_samples`; None for point data).
    """

    source: str
    grid: Any
    on_cells: bool
    times_s: np.ndarray
    density_kg_m3: float
    viscosity_pa_s: float
    dim: int
    plane_z_m: float | None
    thickness_m: float | None
    cell_lo_m: np.ndarray
    cell_hi_m: np.ndarray
    cell_size_m: np.ndarray
    samples: CellSamples | None = None
    period_s: float | None = None

    @property
    def components(self) -> int:
        return 1 + self.dim + self.dim * self.dim

    @property
    def cells(self) -> int:
        return len(self.cell_size_m)

    @property
    def extent_m(self) -> tuple[np.ndarray, np.ndarray]:
        """The mesh's bounding box in the flow's ``dim`` axes, (dim,) each, metres."""
        bounds = np.array(self.grid.GetBounds(), dtype=float)
        return bounds[0 : 2 * self.dim : 2].copy(), bounds[1 : 2 * self.dim : 2].copy()

    @cached_property
    def cell_index(self) -> CellIndex:
        """The cells' boxes bucketed, to find the cells near a probe without a scan."""
        return CellIndex.build(self.cell_lo_m, self.cell_hi_m)

    @cached_property
    def spacing_m(self) -> np.ndarray:
        """A typical fine spacing, (dim,): the 5th percentile of the cells' sizes (the mesh is
        finest at walls, where forces are taken)."""
        return np.full(self.dim, float(np.percentile(self.cell_size_m, 5.0)))

    def describe(self) -> str:
        kind = "cell" if self.on_cells else "point"
        depth = f", {self.thickness_m:g} m thick" if self.thickness_m else ""
        return (
            f"{self.dim}D unstructured mesh, {self.cells} cells{depth}, {kind} data, "
            f"{len(self.times_s)} frame(s)"
        )


def field_array(data: Any, names: tuple[str, ...]) -> tuple[str, Any] | None:
    """The first array of ``data`` (point or cell data) named one of ``names``."""
    for name in names:
        array = data.GetArray(name)
        if array is not None:
            return name, array
    return None


def build_unstructured(
    frames: list[UnstructuredFrame],
    times: np.ndarray,
    density: float,
    viscosity: float,
    kinematic: bool,
    progress: Progress | None = None,
) -> UnstructuredFlow:
    """The :class:`UnstructuredFlow` of ``frames`` (one mesh), at ``times`` (s); the pressure is
    multiplied by ``density`` where it is ``kinematic`` (m^2/s^2)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid

    first = frames[0]
    source = first.source
    mesh = first.mesh
    points = vtk_to_numpy(mesh.GetPoints().GetData()).astype(np.float64)
    on_cells = _location(mesh, source)
    dim, plane_z, thickness = _dimension(points, source)
    count = mesh.GetNumberOfCells() if on_cells else mesh.GetNumberOfPoints()
    check_elements(count * len(frames) * (1 + dim + dim * dim), 8, source, "frames")
    grid = vtkUnstructuredGrid()
    grid.CopyStructure(mesh)
    target = grid.GetCellData() if on_cells else grid.GetPointData()
    packed_frames = []
    for k, frame in enumerate(frames):
        if frame.mesh.GetNumberOfPoints() != mesh.GetNumberOfPoints() or (
            frame.mesh.GetNumberOfCells() != mesh.GetNumberOfCells()
        ):
            raise InputError("every frame of a series needs the same mesh", frame.source)
        if progress is not None:
            progress.show(f"velocity gradient, frame {k + 1} of {len(frames)}")
        packed = _pack(frame, on_cells, dim, density if kinematic else 1.0, progress)
        if on_cells:
            packed_frames.append(packed[:, : 1 + dim])
        array = numpy_to_vtk(packed, deep=True)
        array.SetName(f"f{k}")
        target.AddArray(array)
        frame.mesh = None  # the reader's copy is no longer needed
    if progress is not None:
        progress.show("cell sizes")
    lo, hi = _cell_boxes(grid, points, source)
    edges = np.maximum(hi[:, :dim] - lo[:, :dim], 0.0)
    size = np.prod(np.maximum(edges, 1e-300), axis=1) ** (1.0 / dim)
    samples = None
    if on_cells:
        if progress is not None:
            progress.show("cell centres and walls")
        flat = dim == 2 and thickness is None
        samples = cell_samples(grid, points, np.stack(packed_frames), dim, flat)
    return UnstructuredFlow(
        source,
        grid,
        on_cells,
        np.asarray(times, dtype=float),
        density,
        viscosity,
        dim,
        plane_z,
        thickness,
        lo.astype(np.float32),
        hi.astype(np.float32),
        size,
        samples,
    )


def _location(mesh: Any, source: str) -> bool:
    """True for cell data: the values as given, at the points where the file has both."""
    for on_cells, data in ((False, mesh.GetPointData()), (True, mesh.GetCellData())):
        if field_array(data, PRESSURE_NAMES) and field_array(data, VELOCITY_NAMES):
            return on_cells
    raise InputError(
        "missing field; expected point or cell arrays named one of "
        f"{', '.join(PRESSURE_NAMES)} and one of {', '.join(VELOCITY_NAMES)}",
        source,
        "p",
    )


def _dimension(points: np.ndarray, source: str) -> tuple[int, float | None, float | None]:
    if len(points) < 4 or not np.all(np.isfinite(points)):
        raise InputError("expected a mesh of at least 4 finite points", source, "points")
    lo, hi = points.min(axis=0), points.max(axis=0)
    tol = PLANE_TOLERANCE * float(np.max(hi - lo))
    if not np.all(hi[:2] - lo[:2] > tol):
        raise InputError("the mesh has no extent in x or y", source, "points")
    z = points[:, 2]
    if hi[2] - lo[2] <= tol:
        return 2, float(0.5 * (lo[2] + hi[2])), None
    if np.all((np.abs(z - lo[2]) <= tol) | (np.abs(z - hi[2]) <= tol)):
        return 2, float(0.5 * (lo[2] + hi[2])), float(hi[2] - lo[2])
    return 3, None, None


def _pack(
    frame: UnstructuredFrame, on_cells: bool, dim: int, scale: float, progress: Progress | None
) -> np.ndarray:
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkDataObject
    from vtkmodules.vtkFiltersGeneral import vtkGradientFilter

    mesh, source = frame.mesh, frame.source
    data = mesh.GetCellData() if on_cells else mesh.GetPointData()
    found_p, found_u = field_array(data, PRESSURE_NAMES), field_array(data, VELOCITY_NAMES)
    if found_p is None or found_u is None:
        raise InputError("missing field p or U in this frame", source, "p")
    p = vtk_to_numpy(found_p[1]).astype(np.float64).reshape(len(vtk_to_numpy(found_p[1])), -1)
    u = vtk_to_numpy(found_u[1]).astype(np.float64)
    if p.shape[1] != 1:
        raise InputError(f"expected 1 component, got {p.shape[1]}", source, found_p[0])
    if u.ndim != 2 or u.shape[1] != 3:
        raise InputError("expected 3 components", source, found_u[0])
    for name, values in ((found_p[0], p), (found_u[0], u)):
        if not np.all(np.isfinite(values)):
            raise InputError("non-finite values in the fluid", source, name)
    if on_cells:  # the gradient comes from the samples' interpolant (cell_samples)
        zeros = np.zeros((len(p), dim * dim))
        return np.ascontiguousarray(np.column_stack([scale * p, u[:, :dim], zeros]))
    gradient = vtkGradientFilter()
    association = (
        vtkDataObject.FIELD_ASSOCIATION_CELLS
        if on_cells
        else vtkDataObject.FIELD_ASSOCIATION_POINTS
    )
    gradient.SetInputData(mesh)
    gradient.SetInputArrayToProcess(0, 0, 0, association, found_u[0])
    gradient.SetResultArrayName("G")
    if progress is not None:
        progress.watch(gradient, "velocity gradient")
    gradient.Update()
    out = gradient.GetOutput()
    out_data = out.GetCellData() if on_cells else out.GetPointData()
    g = vtk_to_numpy(out_data.GetArray("G")).astype(np.float64).reshape(-1, 3, 3)
    g = np.nan_to_num(g[:, :dim, :dim]).reshape(len(g), dim * dim)
    return np.ascontiguousarray(np.column_stack([scale * p, u[:, :dim], g]))


def _cell_boxes(grid: Any, points: np.ndarray, source: str) -> tuple[np.ndarray, np.ndarray]:
    """Each cell's bounding box, (cells, 3) each, from the connectivity."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    cells = grid.GetCells()
    offsets = vtk_to_numpy(cells.GetOffsetsArray()).astype(np.int64)
    connectivity = vtk_to_numpy(cells.GetConnectivityArray()).astype(np.int64)
    if len(offsets) < 2 or np.any(np.diff(offsets) <= 0):
        raise InputError("expected cells of at least one point each", source, "cells")
    corner = points[connectivity]
    starts = offsets[:-1]
    return np.minimum.reduceat(corner, starts, axis=0), np.maximum.reduceat(corner, starts, axis=0)
