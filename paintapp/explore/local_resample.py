"""The flow near the probe resampled from an unstructured mesh onto a local uniform grid, so that
the per-tick force is the grid's cheap stress integral (:func:`solver.sampled.forces.surface_force`).

A local grid is a box around the probe with nodes about as far apart as the finest cells it
covers divided by :attr:`ResampleSpec.refine` (1: the mesh's own resolution there), capped at
:attr:`ResampleSpec.max_nodes`. Its nodes take the mesh's point data by ``vtkProbeFilter``
(inside a cell, the cell's own interpolation), with the velocity gradient taken on the mesh at
load; cell data is interpolated between the cells' centres and the walls instead
(:mod:`.cell_samples`), never averaged from cells to points. The wall is
located by the mesh itself: a node lies in the fluid where some cell contains it (the probe
filter's ``vtkValidPointMask``, found with a ``vtkStaticCellLocator`` over the few cells whose
bounding boxes meet the box); nodes outside every cell (inside a body, or beyond the domain) are
not fluid, and the pressure and velocity gradient there are extended from the fluid nodes next
to them (:class:`solver.SampledFlow` with ``fluid`` and ``gradient_per_s``). A probe surface lying
on a wall therefore reads, between the last fluid node and the extension, the wall's pressure
and the gradient the mesh has at the wall; the viscous traction is ``mu (G + G^T) n`` with that
gradient.

The resample runs when the probe nears the edge of its box, on a worker thread
(:class:`LocalResampler`): never on the servo path, which keeps using the last box until the new
one is ready.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass
from typing import Any

import numpy as np

from paintapp.explore.cell_samples import interpolate_samples
from paintapp.explore.unstructured import UnstructuredFlow
from solver import SampledFlow


@dataclass(frozen=True)
class ResampleSpec:
    """How finely and how far around the probe the mesh is resampled.

    Attributes:
        refine: local grid spacing = the finest cell size in the box / refine (>= 1).
        margin: the box reaches this fraction of the probe's radius beyond it (the probe can
            move this far before a new box is needed).
        max_nodes: most nodes in a box (the spacing grows to keep within it).
    """

    refine: float = 2.0
    margin: float = 0.5
    max_nodes: int = 40_000


@dataclass(frozen=True)
class LocalBox:
    """A resampled box: its centre (dim,) and half-width (m), and the flow on it."""

    centre_m: np.ndarray
    half_width_m: float
    flow: SampledFlow

    def holds(self, centre_m: np.ndarray, radius_m: float) -> bool:
        """True while a probe of bounding radius ``radius_m`` at ``centre_m`` is inside."""
        reach = float(np.max(np.abs(np.asarray(centre_m) - self.centre_m))) + radius_m
        return reach <= self.half_width_m - float(self.flow.spacing_m.max())


def resample_box(
    flow: UnstructuredFlow, centre_m: np.ndarray, radius_m: float, spec: ResampleSpec
) -> LocalBox:
    """Resample every frame of ``flow`` onto a box around a probe of bounding radius
    ``radius_m`` (m) at ``centre_m`` (dim,)."""
    dim = flow.dim
    centre = np.asarray(centre_m, dtype=float)[:dim]
    half = radius_m * (1.0 + spec.margin)
    near = cells_meeting(flow, centre, half)
    finest = float(flow.cell_size_m[near].min()) if len(near) else float(flow.spacing_m[0])
    spacing = finest / max(spec.refine, 1.0)
    most_per_axis = max(int(spec.max_nodes ** (1.0 / dim)), 8)
    spacing = max(spacing, 2.0 * half / (most_per_axis - 1))
    count = math.ceil(2.0 * max(half, radius_m + 2.0 * spacing) / spacing) + 1
    if 0.5 * spacing * (count - 1) > half:  # a coarse grid: the box grew, so did its cells
        near = cells_meeting(flow, centre, 0.5 * spacing * (count - 1))
    half = 0.5 * spacing * (count - 1)
    nodes = (count,) * dim
    axes = [centre[a] - half + spacing * np.arange(count) for a in range(dim)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, dim)
    values, valid = _probe(flow, near, grid)
    if flow.samples is not None:  # cell data: interpolated between cell centres and walls
        reach = 2.0 * float(flow.cell_size_m[near].max()) if len(near) else spacing
        values, spanned = interpolate_samples(flow.samples, grid, reach)
        valid &= spanned
    frames = len(flow.times_s)
    comps = flow.components
    values = values.reshape(*nodes, frames, comps)
    fluid = valid.reshape(nodes)
    pressure = np.moveaxis(values[..., 0], -1, 0)
    velocity = np.moveaxis(values[..., 1 : 1 + dim], (-2, -1), (0, 1))
    gradient = np.moveaxis(
        values[..., 1 + dim :].reshape(*nodes, frames, dim, dim), (-3, -2, -1), (0, 1, 2)
    )
    if not fluid.any():  # inside a body or outside the mesh: no fluid, no force
        pressure, gradient = np.zeros_like(pressure), np.zeros_like(gradient)
        fluid = np.ones(nodes, dtype=bool)
    local = SampledFlow(
        centre - half,
        np.full(dim, spacing),
        flow.times_s,
        np.ascontiguousarray(pressure),
        np.ascontiguousarray(velocity),
        flow.density_kg_m3,
        flow.viscosity_pa_s,
        None if fluid.all() else fluid,
        None,
        np.ascontiguousarray(gradient),
        cache_frames=frames,
    )
    for k in range(frames):  # extend into the bodies now, off the servo path
        local.frame(k)
    return LocalBox(centre, half, local)


def cells_meeting(flow: UnstructuredFlow, centre: np.ndarray, half: float) -> np.ndarray:
    """Indices of the cells whose bounding boxes meet the box ``centre`` +- ``half`` (m); in
    2D, of the cells that cross the flow's plane there."""
    dim = flow.dim
    lo3, hi3 = np.full(3, -np.inf), np.full(3, np.inf)
    lo3[:dim], hi3[:dim] = centre - half, centre + half
    if flow.plane_z_m is not None:
        lo3[2] = hi3[2] = flow.plane_z_m
    # widened by a float32 step so that rounding the boxes cannot drop a cell
    lo32 = np.nextafter(lo3.astype(np.float32), np.float32(-np.inf))
    hi32 = np.nextafter(hi3.astype(np.float32), np.float32(np.inf))
    return flow.cell_index.meeting(lo32, hi32)


def _probe(
    flow: UnstructuredFlow, near: np.ndarray, grid: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Values (nodes, frames * components) and validity (nodes,) at ``grid`` (nodes, dim)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkPolyData, vtkStaticCellLocator
    from vtkmodules.vtkFiltersCore import vtkExtractCells, vtkProbeFilter

    frames, comps = len(flow.times_s), flow.components
    count = len(grid)
    if len(near) == 0:
        return np.zeros((count, frames * comps)), np.zeros(count, dtype=bool)
    if len(near) == flow.cells:
        cells = flow.grid
    else:
        extract = vtkExtractCells()
        extract.SetInputData(flow.grid)
        ids = np.ascontiguousarray(near, dtype=np.int64)
        extract.SetCellIds(ids, len(near))  # type: ignore[arg-type]  # copied
        extract.Update()
        cells = extract.GetOutput()
    locator = vtkStaticCellLocator()
    locator.SetDataSet(cells)
    locator.BuildLocator()
    points3 = np.zeros((count, 3))
    points3[:, : flow.dim] = grid
    if flow.plane_z_m is not None:
        points3[:, 2] = flow.plane_z_m
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(points3, deep=True))
    probes = vtkPolyData()
    probes.SetPoints(vtk_points)
    probe = vtkProbeFilter()
    probe.SetInputData(probes)
    probe.SetSourceData(cells)
    probe.SetCellLocator(locator)
    probe.PassPointArraysOff()
    probe.Update()
    out = probe.GetOutput().GetPointData()
    valid = vtk_to_numpy(out.GetArray(probe.GetValidPointMaskArrayName())).astype(bool)
    values = np.zeros((count, frames * comps))
    for k in range(frames):
        array = out.GetArray(f"f{k}")
        if array is not None:
            values[:, k * comps : (k + 1) * comps] = vtk_to_numpy(array).reshape(count, comps)
    return values, valid


class LocalResampler:
    """Keeps a :class:`LocalBox` around a moving probe of bounding radius ``radius_m``.

    :meth:`box_for` returns at once with the latest box; when the probe nears its edge a new box
    is resampled, on the worker thread (``background``) or right away (scripted runs, which must
    be deterministic)."""

    def __init__(
        self,
        flow: UnstructuredFlow,
        radius_m: float,
        spec: ResampleSpec | None = None,
        background: bool = False,
    ) -> None:
        self.flow = flow
        self.radius_m = radius_m
        self.spec = spec or ResampleSpec()
        self.background = background
        self.box: LocalBox | None = None
        self.resamples = 0
        self._wanted: np.ndarray | None = None
        self._cond = threading.Condition()
        self._thread: threading.Thread | None = None
        self._stop = False

    def box_for(self, centre_m: np.ndarray) -> LocalBox:
        """The box to evaluate a probe at ``centre_m`` in (the first one is always made here)."""
        centre = np.array(centre_m, dtype=float)[: self.flow.dim]
        box = self.box
        if box is not None and box.holds(centre, self.radius_m):
            return box
        if box is None or not self.background:
            self.box = resample_box(self.flow, centre, self.radius_m, self.spec)
            self.resamples += 1
            return self.box
        self._request(centre)
        return box

    def _request(self, centre: np.ndarray) -> None:
        with self._cond:
            self._wanted = centre
            if self._thread is None:
                self._thread = threading.Thread(
                    target=self._work, name="local-resample", daemon=True
                )
                self._thread.start()
            self._cond.notify()

    def _work(self) -> None:
        while True:
            with self._cond:
                while self._wanted is None and not self._stop:
                    self._cond.wait()
                if self._stop:
                    return
                centre, self._wanted = self._wanted, None
            assert centre is not None
            box = resample_box(self.flow, centre, self.radius_m, self.spec)
            self.box = box  # one reference swap: the servo side sees the old box or the new
            self.resamples += 1

    def close(self) -> None:
        """Stop the worker thread (if one was started)."""
        with self._cond:
            self._stop = True
            self._cond.notify()
        if self._thread is not None:
            self._thread.join(timeout=5.0)
            self._thread = None


def probe_radius(shape: Any, dim: int) -> float:
    """The bounding radius (m) of a :class:`solver.Ball` or :class:`solver.Box`."""
    if hasattr(shape, "radius_m"):
        return float(shape.radius_m)
    return 0.5 * float(np.linalg.norm(np.asarray(shape.size_m, dtype=float)[:dim]))


def display_grid(flow: UnstructuredFlow, most_nodes: int = 160_000) -> SampledFlow:
    """The whole mesh resampled onto a uniform grid of at most ``most_nodes`` nodes, every
    frame, with its fluid mask: what a window shows (forces are not taken on it)."""
    lo, hi = flow.extent_m
    span = hi - lo
    spacing = float((np.prod(span) / most_nodes) ** (1.0 / flow.dim))
    counts = [max(int(s / spacing) + 1, 2) for s in span]
    axes = [np.linspace(lo[a], hi[a], counts[a]) for a in range(flow.dim)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, flow.dim)
    values, valid = _probe(flow, np.arange(flow.cells), grid)
    nodes = tuple(counts)
    frames, dim = len(flow.times_s), flow.dim
    values = values.reshape(*nodes, frames, flow.components)
    fluid = valid.reshape(nodes) if valid.any() else np.ones(nodes, dtype=bool)
    return SampledFlow(
        lo,
        np.array([(hi[a] - lo[a]) / (counts[a] - 1) for a in range(dim)]),
        flow.times_s,
        np.ascontiguousarray(np.moveaxis(values[..., 0], -1, 0)),
        np.ascontiguousarray(np.moveaxis(values[..., 1 : 1 + dim], (-2, -1), (0, 1))),
        flow.density_kg_m3,
        flow.viscosity_pa_s,
        None if fluid.all() else fluid,
    )
