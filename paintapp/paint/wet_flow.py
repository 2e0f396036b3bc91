"""Moving the canvas's wet paint with the paint grid's flow, at texel resolution.

Transporting the paint in the grid's columns (a cell wide, several texels) and handing each
column's change to its texels smooths detail finer than a cell (a stroke's edge, a bristle
streak) and re-draws it on the cell lattice at every step. Here the grid supplies only the
velocity: its depth-averaged flow (:mod:`paintapp.paint.texel_velocity`) moves each pigment's wet
paint over the texels under the on-canvas columns with a limited flux-form upwind scheme
(:mod:`paintapp.paint.wet_flow_kernels`), sub-stepped so that no texel sends out more than it holds.

A texel's wet paint ``w P_p`` moves, the dry part stays; the new wetness is the wet share of the
new total. Nothing crosses the on-canvas columns' outline: each pigment is conserved to round-off
(float32), no texel goes negative, and texels that do not change are not written.

The flow's thin leading edge (:func:`clear_thin_edges`): newly reached texels left with at most
:data:`paintapp.canvas.model.FILM_FLOOR_M` form 4-connected patches; a patch goes back whole to
the richest texel beside it if that is richer than the patch's own (the edge runs back into the
paint instead of painting sub-femtometre films beyond it), else into its own richest texel; a
patch surrounded by paint shares its wet paint evenly with its wet neighbours (no hole).
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import find_objects, label

from paintapp.canvas.model import FILM_FLOOR_M, Canvas
from paintapp.canvas.regions import Box
from paintapp.paint.columns import ColumnWindow, TexelWeights
from paintapp.paint.columns_kernels import FULLY_WET
from paintapp.paint.texel_velocity import texel_face_velocity
from paintapp.paint.wet_flow_kernels import advance, substeps_needed

#: Exponent of the bristle walls' block on the flow across them (:func:`combed`). With 4 a
#: straight ``round_large`` stroke's fine relief varies 12.3 times more across it than along
#: it, as with the columns' transport (12.3); without the walls, 6.9.
COMB_WALL_POWER = 4


def columns_box(window: ColumnWindow) -> Box | None:
    """Texels (x0, y0, x1, y1) of the window's on-canvas columns' blocks, or None."""
    r = window.on_canvas_range()
    if r is None:
        return None
    (ox, oy), k = window.whole_origin(), window.k
    return ox + r[0] * k, oy + r[2] * k, ox + r[1] * k, oy + r[3] * k


def _paint_box(wet: np.ndarray, margin: int) -> tuple[int, int, int, int] | None:
    """Bounding box (x0, y0, x1, y1), in ``wet``'s indices, of its non-zero texels widened by
    ``margin`` (clipped), or None."""
    rows = np.flatnonzero(wet.any(axis=1))
    if rows.size == 0:
        return None
    cols = np.flatnonzero(wet.any(axis=0))
    ny, nx = wet.shape
    return (
        max(cols[0] - margin, 0),
        max(rows[0] - margin, 0),
        min(cols[-1] + 1 + margin, nx),
        min(rows[-1] + 1 + margin, ny),
    )


def flow_wet_paint(
    canvas: Canvas,
    window: ColumnWindow,
    face_u: np.ndarray,
    face_v: np.ndarray,
    dt_s: float,
    texture: TexelWeights | None = None,
) -> int:
    """Move the wet paint under the window for ``dt_s`` seconds with the columns' face
    velocities ``face_u`` (nx + 1, ny), ``face_v`` (nx, ny + 1), m/s
    (:func:`paintapp.paint.texel_velocity.column_face_velocity`). Returns the sub-steps taken."""
    region = columns_box(window)
    if region is None or dt_s <= 0.0 or not canvas.pigment_names:
        return 0
    x0, y0, x1, y1 = region
    wetness = canvas.wetness[y0:y1, x0:x1]
    if not wetness.any():
        return 0
    ux, vy = texel_face_velocity(
        face_u, face_v, window.whole_origin(), window.k, region, window.texel_m
    )
    n = substeps_needed(ux, vy, dt_s)
    crop = _paint_box(wetness > 0.0, n + 1)
    if crop is None:
        return 0
    a0, b0, a1, b1 = crop
    ux, vy = ux[b0:b1, a0 : a1 + 1].copy(), vy[b0 : b1 + 1, a0:a1].copy()
    ux[:, [0, -1]] = 0.0
    vy[[0, -1], :] = 0.0
    box = (x0 + a0, y0 + b0, x0 + a1, y0 + b1)
    shape = texture.weights(box) if texture is not None else None
    if shape is not None:
        ux, vy = combed(ux, vy, shape[1])
    _move(canvas, box, ux, vy, dt_s, n)
    return n


def combed(ux: np.ndarray, vy: np.ndarray, loss: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Face velocities scaled by the bristles' loss weights (ny, nx) over their mean (at most 1):
    by the mean of the two texels beside each face, so paint under a clump moves slower than in
    the grooves between them, times ``(low / high) ** COMB_WALL_POWER`` of the two, so little
    crosses a clump's flank (the bristles wall a groove in, and the flow runs along it instead of
    evening the streaks out sideways). Along a streak the weights barely change and only the
    first factor acts. The weights are even (one value) beyond the footprint, so the flow is
    unchanged there; nowhere is it faster, so the sub-steps still hold."""
    values, counts = np.unique(loss, return_counts=True)
    even = float(values[np.argmax(counts)])  # the one value every texel beyond the band holds
    w = np.minimum(loss / even, 1.0)
    fx = np.ones_like(ux)
    fx[:, 1:-1] = _comb(w[:, 1:], w[:, :-1])
    fy = np.ones_like(vy)
    fy[1:-1, :] = _comb(w[1:, :], w[:-1, :])
    return ux * fx, vy * fy


def _comb(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """A face's speed factor from the weights ``a``, ``b`` (in [0, 1]) of its two texels."""
    low, high = np.minimum(a, b), np.maximum(a, b)
    with np.errstate(invalid="ignore", divide="ignore"):
        wall = np.where(high > 0.0, low / high, 1.0) ** COMB_WALL_POWER
    return 0.5 * (a + b) * wall


def _move(canvas: Canvas, box: Box, ux: np.ndarray, vy: np.ndarray, dt_s: float, n: int) -> None:
    """Advance the wet paint of ``box`` by ``n`` sub-steps and write the texels that changed."""
    x0, y0, x1, y1 = box
    paint = canvas.paint_m[:, y0:y1, x0:x1].astype(np.float64)
    wet = canvas.wetness[y0:y1, x0:x1].astype(np.float64)
    wet[wet >= FULLY_WET] = 1.0  # float32 round-off of fresh paint is no dry residue
    mobile = paint * wet
    used = np.flatnonzero(mobile.reshape(len(paint), -1).any(axis=1))
    if used.size == 0:
        return
    moved = np.ascontiguousarray(mobile[used])
    advance(moved, ux, vy, dt_s, n)
    dry = paint * (1.0 - wet)
    changed = np.any(moved != mobile[used], axis=0)
    dry_total = dry.sum(axis=0)
    clear_thin_edges(dry_total, moved, changed & ~paint.any(axis=0), changed, FILM_FLOOR_M)
    if not changed.any():
        return
    new_mobile = mobile.copy()
    new_mobile[used] = moved
    new_paint = dry + new_mobile
    total = new_paint.sum(axis=0)
    stored = new_paint.astype(np.float32).sum(axis=0) > 0.0  # no wetness without stored paint
    with np.errstate(invalid="ignore", divide="ignore"):
        new_wet = np.where((total > 0.0) & stored, new_mobile.sum(axis=0) / total, 0.0)
    rows = np.flatnonzero(changed.any(axis=1))
    cols = np.flatnonzero(changed.any(axis=0))
    r0, r1, c0, c1 = rows[0], rows[-1] + 1, cols[0], cols[-1] + 1
    keep = ~changed[r0:r1, c0:c1]
    out_paint = new_paint[:, r0:r1, c0:c1]
    out_wet = new_wet[r0:r1, c0:c1]
    out_paint[:, keep] = paint[:, r0:r1, c0:c1][:, keep]
    out_wet[keep] = canvas.wetness[y0 + r0 : y0 + r1, x0 + c0 : x0 + c1][keep]
    canvas.write_region(x0 + c0, y0 + r0, out_paint, np.clip(out_wet, 0.0, 1.0))


def _beside(patch: np.ndarray) -> np.ndarray:
    """The texels 4-adjacent to ``patch`` (a boolean mask) and not in it."""
    out = np.zeros_like(patch)
    out[1:] |= patch[:-1]
    out[:-1] |= patch[1:]
    out[:, 1:] |= patch[:, :-1]
    out[:, :-1] |= patch[:, 1:]
    return out & ~patch


def clear_thin_edges(
    dry: np.ndarray, wet: np.ndarray, eligible: np.ndarray, changed: np.ndarray, floor: float
) -> None:
    """Clear the thin films among the ``eligible`` texels (module docstring), in place: ``wet``
    (P, ny, nx) wet paint, ``dry`` (ny, nx) the dry paint that stays; texels that receive or give
    are marked in ``changed``. Each pigment's total is conserved to round-off (every amount moved
    leaves one texel and enters another) and nothing goes negative."""
    wet_total = wet.sum(axis=0)
    total = dry + wet_total
    thin = eligible & (wet_total > 0.0) & (total <= floor)
    if not thin.any():
        return
    labels, _ = label(thin)
    ny, nx = total.shape
    for i, found in enumerate(find_objects(labels), start=1):
        if found is None:
            continue
        r0, r1 = max(found[0].start - 1, 0), min(found[0].stop + 1, ny)
        c0, c1 = max(found[1].start - 1, 0), min(found[1].stop + 1, nx)
        patch = labels[r0:r1, c0:c1] == i
        around = _beside(patch)
        held = total[r0:r1, c0:c1]
        w = wet[:, r0:r1, c0:c1]
        edge = r0 == 0 or c0 == 0 or r1 == ny or c1 == nx
        enclosed = not edge and not (around & (held <= 0.0)).any()
        if enclosed and (dry[r0:r1, c0:c1][patch] <= 0.0).any():
            donors = around & (w.sum(axis=0) > 0.0)
            share = patch | donors
            pool = w[:, share].sum(axis=1) / share.sum()
            w[:, share] = pool[:, None]
            changed[r0:r1, c0:c1] |= share
            continue
        richest = np.where(around, held, -1.0)
        ty, tx = np.unravel_index(np.argmax(richest), richest.shape)
        if richest[ty, tx] <= held[patch].max():  # richer than all beside it: gather in place
            inside = np.where(patch, held, -1.0)
            ty, tx = np.unravel_index(np.argmax(inside), inside.shape)
        gift = w[:, patch].sum(axis=1)
        w[:, patch] = 0.0
        w[:, ty, tx] += gift
        changed[r0 + ty, c0 + tx] = True
