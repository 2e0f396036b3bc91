"""Paint that holds still: the slow creep far from the brush is not written to the canvas.

Oil paint has a yield stress: away from the brush, where the stress falls below it, the paint
stops. The paint grid's fluid is Newtonian, so its flow reaches every cell, ever more slowly with
the distance from the tip, and its transport changes every column a little at every step. A
column whose every pigment changes in a step by less than a share of the column's wet paint
(:func:`keep_still`; the scene's ``still_rate_per_s`` times the step) is left as it is, and the
write-back's box shrinks to the paint the brush moves (:meth:`paintapp.paint.columns.ColumnWindow.write_back`
reads and writes only the texels of changed columns).

The velocity is not touched (a velocity cut-off makes the transport's flow non-solenoidal, and
cells drain and pile where the flow crosses it), and the paint stays conserved: what the still
columns would have gained or lost goes to the columns that keep their change.
"""

from __future__ import annotations

import numpy as np


def keep_still(owned: np.ndarray, change: np.ndarray, share: float) -> np.ndarray:
    """Column changes (P, ni, nj) with the still columns' changes removed.

    ``owned`` (P, ni, nj) is each column's wet paint per pigment and ``change`` its change, in
    the same units (metres of paint, or texel volumes). A column is *still* when it has paint and
    every pigment's change is below ``share`` of its wet paint (all pigments); a column with no
    paint is never still. Per pigment, the net change the still columns leave out goes to the
    columns that keep theirs: a net gain to the columns gaining that pigment (in proportion to
    their gains), else to those losing it (their losses shrink); a net loss is taken from the
    gains (when they hold at least twice it), else from the paint the losing columns keep (when it
    holds at least twice it). Where neither can take it, ``change`` is returned as it is. The
    total per pigment is kept to round-off, and no column is asked for more than it holds.
    ``share <= 0`` keeps every change."""
    if share <= 0.0:
        return change
    held = owned.sum(axis=0)
    moving = np.any(change != 0.0, axis=0)
    still = moving & (held > 0.0) & np.all(np.abs(change) < share * held[None], axis=0)
    keep = moving & ~still
    if not still.any() or not keep.any():
        return change
    out = change.copy()
    out[:, still] = 0.0
    left = change[:, still].sum(axis=1)
    for p in np.flatnonzero(left != 0.0):
        placed = _place(owned[p], change[p], keep, float(left[p]))
        if placed is None:
            return change
        out[p] += placed
    return out


def _place(
    owned: np.ndarray, change: np.ndarray, keep: np.ndarray, left: float
) -> np.ndarray | None:
    """The amounts (ni, nj) that add ``left`` (a gain when positive, a loss when negative) to the
    columns ``keep`` of one pigment's ``change`` (module docstring), or None where it cannot."""
    gains = np.where(keep & (change > 0.0), change, 0.0)
    losses = np.where(keep & (change < 0.0), -change, 0.0)
    if left > 0.0:
        for weights in (gains, losses):
            total = weights.sum()
            if total > 0.0 and (weights is gains or total >= left):
                return left * weights / total
        return None
    for weights in (gains, np.where(losses > 0.0, np.maximum(owned - losses, 0.0), 0.0)):
        total = weights.sum()
        if total >= -2.0 * left:
            return left * weights / total
    return None
