"""Open lateral sides for the 3D paint grid: paint through its sides, fed from a band of canvas.

Slip walls at the grid's lateral sides confine the flow round the tip (the drag comes out higher
and the lift lower than in an unbounded layer, and the trail changes with the walls' distance).
Open sides (zero pressure) let the flow through, and with it paint from or to outside the grid.

The paint transport runs on the grid with one ring of *ghost* cells. A ghost column holds the wet
paint of the canvas column just beyond the side (filled bottom-up like the grid's own), and only
the open side faces pass paint to and from it, with the solver's velocity there. What a ghost
column gained or lost over the step is then laid on, or taken from, a band of ``depth`` canvas
columns outwards from the side, weights falling linearly with the distance (the flow crossing the
side spreads and slows beyond it, so its paint comes from or goes to a wide strip). A loss is
taken in proportion to the weight times each column's paint (never more than the first column
holds), a gain with the weights alone. Paint stays conserved to round-off and non-negative;
nothing crosses a side next to a column off the canvas.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from paintapp.paint.cell_kernels import fill_columns
from solver import BOUNDARY, FREE, transport


def band_weights(depth: int) -> np.ndarray:
    """Weights (depth,) of the band's columns at distances 1..depth from the side: linear, from
    ``depth`` down to 1, summing to 1."""
    w = np.arange(depth, 0, -1, dtype=float)
    return w / w.sum()


def side_faces(
    comps: Sequence[np.ndarray],
    face_types: Sequence[np.ndarray],
    open_frac: Sequence[np.ndarray] | None,
    on_canvas: np.ndarray,
    depth: int,
) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """The open side faces' paint velocity and where they pass paint, as
    :func:`padded_transport` takes them: the solver's face velocities ``comps`` times the faces'
    open fractions, on faces the solver left ``FREE`` (not beside a solid column) whose ghost
    column is wholly on the canvas (``on_canvas``: the columns of the grid widened by ``depth``
    a side)."""
    u, v = comps[0], comps[1]
    nx, ny = u.shape[0] - 1, v.shape[1] - 1
    fu = np.ones_like(u) if open_frac is None else open_frac[0]
    fv = np.ones_like(v) if open_frac is None else open_frac[1]
    ring = on_canvas[depth - 1 : depth + nx + 1, depth - 1 : depth + ny + 1]
    tu, tv = face_types[0], face_types[1]
    vel = [
        np.stack([u[0] * fu[0], u[nx] * fu[nx]]),
        np.stack([v[:, 0] * fv[:, 0], v[:, ny] * fv[:, ny]]),
    ]
    passes = [
        np.stack([(tu[0] == FREE) & ring[0, 1:-1, None], (tu[nx] == FREE) & ring[-1, 1:-1, None]]),
        np.stack(
            [(tv[:, 0] == FREE) & ring[1:-1, 0, None], (tv[:, ny] == FREE) & ring[1:-1, -1, None]]
        ),
    ]
    return vel, passes


def padded_transport(
    q: np.ndarray,
    vel: Sequence[np.ndarray],
    types: Sequence[np.ndarray],
    side_vel: Sequence[np.ndarray],
    side_open: Sequence[np.ndarray],
    ring_columns_m: np.ndarray,
    h: float,
    dt_s: float,
    threads: int = 1,
    scheme: str = "upwind",
) -> tuple[int, np.ndarray]:
    """Transport cell fields ``q`` (P, nx, ny, nz) in place with the paint faces ``vel`` /
    ``types`` (:func:`paintapp.paint.trail.paint_faces`: no flux through the sides) plus the
    open side faces: ``side_vel[a]`` (2, ...) the solver's velocity on the low and high sides of
    axis ``a`` (x: (2, ny, nz), y: (2, nx, nz)), ``side_open[a]`` (2, ...) bool where they pass
    paint. ``ring_columns_m`` (P, nx + 2, ny + 2) is the canvas's wet paint per column in the grid
    and the ring around it (metres): the ghosts' paint. Returns the sub-steps and the ghosts'
    gains over the step, metres of column per pigment: (P, 2, 2, n) for axis, side, position
    along the side (x sides: n = ny; y sides: n = nx, padded to the larger). ``threads`` and
    ``scheme``: as :func:`solver.advection.scalars.transport`'s."""
    n_p, nx, ny, nz = q.shape
    padded = np.zeros((n_p, nx + 2, ny + 2, nz))
    fill_columns(np.ascontiguousarray(ring_columns_m), h, padded)
    padded[:, 1:-1, 1:-1] = q
    before = padded.copy()
    u = np.zeros((nx + 3, ny + 2, nz))
    v = np.zeros((nx + 2, ny + 3, nz))
    w = np.zeros((nx + 2, ny + 2, nz + 1))
    tu, tv, tw = (np.full(a.shape, BOUNDARY, dtype=types[0].dtype) for a in (u, v, w))
    u[1:-1, 1:-1], tu[1:-1, 1:-1] = vel[0], types[0]
    v[1:-1, 1:-1], tv[1:-1, 1:-1] = vel[1], types[1]
    w[1:-1, 1:-1], tw[1:-1, 1:-1] = vel[2], types[2]
    for side, i in ((0, 1), (1, nx + 1)):
        u[i, 1:-1] = np.where(side_open[0][side], side_vel[0][side], 0.0)
        tu[i, 1:-1] = np.where(side_open[0][side], FREE, BOUNDARY)
    for side, j in ((0, 1), (1, ny + 1)):
        v[1:-1, j] = np.where(side_open[1][side], side_vel[1][side], 0.0)
        tv[1:-1, j] = np.where(side_open[1][side], FREE, BOUNDARY)
    substeps = transport(padded, [u, v, w], [tu, tv, tw], 3, h, dt_s, threads, scheme)
    q[:] = padded[:, 1:-1, 1:-1]
    gained = (padded - before).sum(axis=3) * h  # (P, nx + 2, ny + 2), nonzero on the ring only
    n = max(nx, ny)
    out = np.zeros((n_p, 2, 2, n))
    out[:, 0, 0, :ny] = gained[:, 0, 1:-1]
    out[:, 0, 1, :ny] = gained[:, -1, 1:-1]
    out[:, 1, 0, :nx] = gained[:, 1:-1, 0]
    out[:, 1, 1, :nx] = gained[:, 1:-1, -1]
    return substeps, out


def band_change(
    gains: np.ndarray, outer_columns_m: np.ndarray, on_canvas: np.ndarray, depth: int
) -> np.ndarray:
    """Column changes (P, nx + 2 depth, ny + 2 depth) on the grid widened by ``depth`` columns a
    side that lay the ghosts' ``gains`` (:func:`padded_transport`) on the band beyond each side
    (module docstring). ``outer_columns_m`` is the widened grid's wet paint per column, and
    ``on_canvas`` its columns wholly on the canvas."""
    _, wx, wy = outer_columns_m.shape
    nx, ny = wx - 2 * depth, wy - 2 * depth
    out = np.zeros_like(outer_columns_m)
    weights = band_weights(depth)
    d = np.arange(depth)
    for axis, n in ((0, ny), (1, nx)):
        along = depth + np.arange(n)
        size = nx if axis == 0 else ny
        for side, away in ((0, depth - 1 - d), (1, depth + size + d)):  # distance 1..depth
            g = gains[:, axis, side, :n]  # (P, n)
            if not g.any():
                continue
            ii, jj = (
                (away[:, None], along[None, :]) if axis == 0 else (along[None, :], away[:, None])
            )
            wt = weights[:, None] * on_canvas[ii, jj]  # (depth, n)
            norm = wt.sum(axis=0)
            wt = np.divide(wt, norm, out=np.zeros_like(wt), where=norm > 0.0)
            held = wt[None] * outer_columns_m[:, ii, jj]  # (P, depth, n)
            total = held.sum(axis=1, keepdims=True)
            share = np.divide(held, total, out=np.zeros_like(held), where=total > 0.0)
            out[:, ii, jj] += np.maximum(g, 0.0)[:, None, :] * wt[None]
            out[:, ii, jj] -= np.maximum(-g, 0.0)[:, None, :] * share
    return out
