"""Cell data as a finite-volume code means it: each cell's value is its value at the cell's
centre, and the mesh's boundary faces are walls at rest (no slip: zero velocity; the pressure
of the cell beside the face, as a zero normal gradient gives it).

Near a probe these samples (cell centres and boundary-face centres) are joined by a Delaunay
triangulation (tetrahedra in 3D) and interpolated linearly onto the local grid's nodes; the
velocity gradient is the gradient of that interpolant, constant on each simplex. Between a wall
and the first cell centre the gradient is thus (u_c - 0) / d across the distance d from the
wall -- the wall shear that the finite-volume code itself takes -- and no value is averaged from
cells to points. The assumption that every boundary face is a wall at rest is wrong only within
half a cell of inflow and outflow boundaries.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np


@dataclass(frozen=True)
class CellSamples:
    """Samples at the cells' centres and the boundary faces' centres.

    Attributes:
        centres_m: (cells, dim) cell centres (the mean of a cell's points), metres.
        values: (T, cells, 1 + dim): pressure (Pa) and velocity (m/s) per frame.
        wall_m: (faces, dim) boundary-face centres (in 2D the faces across the plane).
        wall_values: (T, faces, 1 + dim): the pressure of the cell beside each face, velocity 0.
    """

    centres_m: np.ndarray
    values: np.ndarray
    wall_m: np.ndarray
    wall_values: np.ndarray


def cell_samples(
    grid: Any, points: np.ndarray, values: np.ndarray, dim: int, flat: bool
) -> CellSamples:
    """The samples of ``grid`` (a ``vtkUnstructuredGrid`` with ``points`` (n, 3)) whose cells
    hold ``values`` (T, cells, 1 + dim); ``flat``: a 2D mesh of 2D cells."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkFiltersCore import vtkFeatureEdges
    from vtkmodules.vtkFiltersGeometry import vtkDataSetSurfaceFilter

    cells = grid.GetCells()
    centres = _centres(cells, points)[:, :dim]
    surface = vtkDataSetSurfaceFilter()
    surface.SetInputData(grid)
    surface.PassThroughCellIdsOn()
    surface.Update()
    poly = surface.GetOutput()
    faces = poly.GetPolys()
    if flat:
        edges = vtkFeatureEdges()
        edges.SetInputData(poly)
        edges.BoundaryEdgesOn()
        edges.FeatureEdgesOff()
        edges.NonManifoldEdgesOff()
        edges.ManifoldEdgesOff()
        edges.Update()
        poly = edges.GetOutput()
        faces = poly.GetLines()
    face_points = vtk_to_numpy(poly.GetPoints().GetData()).astype(np.float64)
    ids = poly.GetCellData().GetArray("vtkOriginalCellIds")
    if ids is None or faces.GetNumberOfCells() == 0:
        empty = np.zeros((values.shape[0], 0, values.shape[2]))
        return CellSamples(centres, values, np.zeros((0, dim)), empty)
    owner = vtk_to_numpy(ids).astype(np.int64)[: faces.GetNumberOfCells()]
    offsets = vtk_to_numpy(faces.GetOffsetsArray()).astype(np.int64)
    connectivity = vtk_to_numpy(faces.GetConnectivityArray()).astype(np.int64)
    corner = face_points[connectivity]
    counts = np.diff(offsets)
    wall = np.add.reduceat(corner, offsets[:-1], axis=0) / counts[:, None]
    if dim == 2 and not flat:  # the faces across the plane (front and back) are no walls
        z = corner[:, 2]
        spread = np.maximum.reduceat(z, offsets[:-1]) - np.minimum.reduceat(z, offsets[:-1])
        keep = spread > 1e-9 * max(float(np.ptp(points[:, 2])), 1e-300)
        wall, owner = wall[keep], owner[keep]
    wall_values = np.zeros((values.shape[0], len(wall), values.shape[2]))
    wall_values[:, :, 0] = values[:, owner, 0]
    return CellSamples(centres, values, wall[:, :dim], wall_values)


def _centres(cells: Any, points: np.ndarray) -> np.ndarray:
    from vtkmodules.util.numpy_support import vtk_to_numpy

    offsets = vtk_to_numpy(cells.GetOffsetsArray()).astype(np.int64)
    connectivity = vtk_to_numpy(cells.GetConnectivityArray()).astype(np.int64)
    total = np.add.reduceat(points[connectivity], offsets[:-1], axis=0)
    return total / np.diff(offsets)[:, None]


def interpolate_samples(
    samples: CellSamples, nodes_m: np.ndarray, reach_m: float
) -> tuple[np.ndarray, np.ndarray]:
    """Values at ``nodes_m`` (n, dim) from the samples within ``reach_m`` of the nodes' box:
    (n, T * (1 + dim + dim^2)) as ``(p, u, G row by row)`` per frame, and whether each node
    lies in the samples' triangulation (n,)."""
    from scipy.spatial import Delaunay, QhullError

    dim = nodes_m.shape[1]
    frames, comps = samples.values.shape[0], 1 + dim + dim * dim
    out = np.zeros((len(nodes_m), frames, comps))
    inside = np.zeros(len(nodes_m), dtype=bool)
    lo, hi = nodes_m.min(axis=0) - reach_m, nodes_m.max(axis=0) + reach_m
    near_c = np.all((samples.centres_m >= lo) & (samples.centres_m <= hi), axis=1)
    near_w = np.all((samples.wall_m >= lo) & (samples.wall_m <= hi), axis=1)
    points = np.concatenate([samples.centres_m[near_c], samples.wall_m[near_w]])
    values = np.concatenate(
        [samples.values[:, near_c], samples.wall_values[:, near_w]], axis=1
    )  # (T, s, 1 + dim)
    if len(points) <= dim:
        return out.reshape(len(nodes_m), -1), inside
    try:
        triangulation = Delaunay(points)
    except (QhullError, ValueError):
        return out.reshape(len(nodes_m), -1), inside
    simplex = triangulation.find_simplex(nodes_m)
    inside = simplex >= 0
    which = simplex[inside]
    transform = triangulation.transform[which]  # (m, dim + 1, dim)
    vertices = triangulation.simplices[which]  # (m, dim + 1)
    b = np.einsum("mij,mj->mi", transform[:, :dim, :], nodes_m[inside] - transform[:, dim, :])
    weights = np.column_stack([b, 1.0 - b.sum(axis=1)])  # (m, dim + 1)
    corner = values[:, vertices, :]  # (T, m, dim + 1, 1 + dim)
    out[inside, :, : 1 + dim] = np.einsum("mv,tmvc->mtc", weights, corner)
    # the gradient of the linear interpolant: sum_i (V_i - V_last) grad b_i, grad b_i = T[i, :]
    delta = corner[:, :, :dim, 1:] - corner[:, :, dim:, 1:]  # (T, m, dim, dim_u)
    gradient = np.einsum("tmic,mij->mtcj", delta, transform[:, :dim, :])  # du_c/dx_j
    out[inside, :, 1 + dim :] = gradient.reshape(len(which), frames, dim * dim)
    return out.reshape(len(nodes_m), -1), inside
