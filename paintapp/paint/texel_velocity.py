"""The paint grid's velocity where the canvas's wet paint is: depth-averaged, on texel faces.

The 3D grid moves each layer of a column's paint with that layer's velocity, so the column's
paint as a whole moves with the paint-weighted mean over its layers. :func:`column_face_velocity`
takes that mean on every lateral face of the grid's columns (m/s): the layers' face velocities
weighted by the paint in the two cells beside the face, faces that carry no paint in the grid
(not ``FREE``: a solid's, the grid's sides) counting as at rest; a face with no paint either side
takes the velocity of its bottom layer (where a thin film would be).

:func:`texel_face_velocity` interpolates those values to the faces of the canvas's texels
(texels per second): along its own axis linearly between the column faces, across it linearly
between the column centres (constant beyond the outermost ones), so the velocity is continuous
at texel scale and detail finer than a cell is carried, not averaged, by the flow. The faces of
the texel box's outline are walls (zero).
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import convolve1d

from solver import FREE, kernel

#: Weight (cell fraction) of the bottom layer in a face's mean: a face with no paint either side
#: moves like its bottom layer; any paint outweighs it.
BOTTOM_WEIGHT = 1e-9


@kernel
def _face_mean(q, vel, types, axis):
    """Paint-weighted mean over layers of component ``axis`` (0: x, 1: y) on the interior faces
    of the columns; ``q`` (nx, ny, nz) is the cells' paint fraction."""
    nx, ny, nz = q.shape
    out = np.zeros((vel.shape[0], vel.shape[1]))
    for i in range(vel.shape[0]):
        for j in range(vel.shape[1]):
            ia, ja = (i - 1, j) if axis == 0 else (i, j - 1)
            if ia < 0 or ja < 0 or (axis == 0 and i >= nx) or (axis == 1 and j >= ny):
                continue
            num, den = 0.0, 0.0
            for k in range(nz):
                w = 0.5 * (q[ia, ja, k] + q[i, j, k]) + (BOTTOM_WEIGHT if k == 0 else 0.0)
                if types[i, j, k] == FREE:
                    num += w * vel[i, j, k]
                den += w
            out[i, j] = num / den
    return out


def column_face_velocity(
    paint: np.ndarray, comps: list[np.ndarray], face_types: list[np.ndarray]
) -> tuple[np.ndarray, np.ndarray]:
    """Depth-averaged velocities (m/s) on the columns' faces: x (nx + 1, ny) and y (nx, ny + 1).

    Args:
        paint: (nx, ny, nz) paint fraction of the cells (all pigments).
        comps, face_types: the grid's velocity components and their face types.
    """
    q = np.ascontiguousarray(paint, dtype=np.float64)
    return (
        _face_mean(q, comps[0], face_types[0], 0),
        _face_mean(q, comps[1], face_types[1], 1),
    )


def _axis_weights(
    coords: np.ndarray, n: int, staggered: bool
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Lower index, upper index and upper weight of linear interpolation at ``coords`` (in
    cells from the grid's corner) between ``n + 1`` face values (``staggered``) or ``n`` centre
    values (constant beyond the outermost centre)."""
    f = coords if staggered else coords - 0.5
    last = n if staggered else n - 1
    lo = np.clip(np.floor(f).astype(int), 0, max(last - 1, 0))
    t = np.clip(f - lo, 0.0, 1.0)
    return lo, np.minimum(lo + 1, last), t


def _interpolate(values: np.ndarray, along: tuple, across: tuple, axis: int) -> np.ndarray:
    """Bilinear values at (rows, columns) of texel faces from column-face ``values``."""
    a0, a1, ta = along
    c0, c1, tc = across
    if axis == 0:  # values (nx + 1, ny): along x (texel columns), across y (texel rows)
        v00, v10 = values[a0[None, :], c0[:, None]], values[a1[None, :], c0[:, None]]
        v01, v11 = values[a0[None, :], c1[:, None]], values[a1[None, :], c1[:, None]]
        t, s = ta[None, :], tc[:, None]
    else:  # values (nx, ny + 1): along y (texel rows), across x (texel columns)
        v00, v10 = values[c0[None, :], a0[:, None]], values[c0[None, :], a1[:, None]]
        v01, v11 = values[c1[None, :], a0[:, None]], values[c1[None, :], a1[:, None]]
        t, s = ta[:, None], tc[None, :]
    return (1 - t) * (1 - s) * v00 + t * (1 - s) * v10 + (1 - t) * s * v01 + t * s * v11


def texel_face_velocity(
    face_u: np.ndarray,
    face_v: np.ndarray,
    origin_texel: tuple[int, int],
    k: int,
    box: tuple[int, int, int, int],
    texel_m: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Velocities (texels/s) on the texel faces of ``box`` = (x0, y0, x1, y1): x (ny, nx + 1),
    y (ny + 1, nx), from column-face velocities ``face_u`` (nx_c + 1, ny_c), ``face_v``
    (nx_c, ny_c + 1) in m/s of a grid whose corner is at ``origin_texel`` with ``k``-texel cells;
    the box's outline faces are 0."""
    x0, y0, x1, y1 = box
    ox, oy = origin_texel
    ncx, ncy = face_v.shape[0], face_u.shape[1]
    xf = (np.arange(x0, x1 + 1) - ox) / k  # texel faces along x, in cells
    yf = (np.arange(y0, y1 + 1) - oy) / k
    xc = (np.arange(x0, x1) + 0.5 - ox) / k  # texel centres, in cells
    yc = (np.arange(y0, y1) + 0.5 - oy) / k
    ux = _interpolate(face_u, _axis_weights(xf, ncx, True), _axis_weights(yc, ncy, False), 0)
    vy = _interpolate(face_v, _axis_weights(yf, ncy, True), _axis_weights(xc, ncx, False), 1)
    ux, vy = _smoothed(ux, k), _smoothed(vy, k)
    ux[:, [0, -1]] = 0.0
    vy[[0, -1], :] = 0.0
    return ux / texel_m, vy / texel_m


def cell_box(k: int) -> np.ndarray:
    """Taps of a box filter one cell (``k`` texels) wide: ``k`` equal taps for odd ``k``, else
    ``k + 1`` with half-weight ends (sums to 1)."""
    if k % 2:
        return np.full(k, 1.0 / k)
    taps = np.full(k + 1, 1.0 / k)
    taps[[0, -1]] *= 0.5
    return taps


def _smoothed(values: np.ndarray, k: int) -> np.ndarray:
    """``values`` filtered by a one-cell box along both axes (edges repeated): the bilinear
    field's slope, which jumps at the column faces and centres, becomes continuous."""
    if k < 2:
        return values
    taps = cell_box(k)
    out = convolve1d(values, taps, axis=0, mode="nearest")
    return convolve1d(out, taps, axis=1, mode="nearest")
