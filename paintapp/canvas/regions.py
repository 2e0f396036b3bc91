"""Texel boxes: half-open rectangles ``(x0, y0, x1, y1)`` of texel indices, [x0, x1) x [y0, y1)."""

from __future__ import annotations

import numpy as np

Box = tuple[int, int, int, int]


def clip_box(box: Box, pixels: tuple[int, int]) -> Box | None:
    """``box`` clipped to a (W, H) canvas; None if nothing is left."""
    x0, y0, x1, y1 = box
    x0, y0 = max(x0, 0), max(y0, 0)
    x1, y1 = min(x1, pixels[0]), min(y1, pixels[1])
    if x1 <= x0 or y1 <= y0:
        return None
    return (x0, y0, x1, y1)


def union_box(a: Box | None, b: Box | None) -> Box | None:
    """Smallest box containing both (None is the empty box)."""
    if a is None:
        return b
    if b is None:
        return a
    return (min(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), max(a[3], b[3]))


def box_of_nonzero(array: np.ndarray) -> Box | None:
    """Bounding box of the non-zero entries of a (H, W) array, or None if all are zero."""
    rows = np.flatnonzero(array.any(axis=1))
    if rows.size == 0:
        return None
    cols = np.flatnonzero(array.any(axis=0))
    return (int(cols[0]), int(rows[0]), int(cols[-1]) + 1, int(rows[-1]) + 1)
