"""Which cells of an unstructured mesh meet a box, without scanning every cell.

The cells are bucketed by their centres on a uniform grid of about :data:`CELLS_PER_BUCKET` cells
a bucket, and each bucket keeps the union of its cells' bounding boxes. A query tests the
buckets' unions (a few ten thousand boxes on a 1M-cell mesh), then the cells of the buckets that
pass, exactly: the answer is the same set, in the same (ascending) order, as testing every cell's
box. A graded mesh's large far-field cells widen only their own buckets' unions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Cells a bucket holds on average.
CELLS_PER_BUCKET = 32


@dataclass(frozen=True)
class CellIndex:
    """Cells bucketed by centre, with each bucket's union box.

    Attributes:
        cell_lo, cell_hi: the cells' bounding boxes, (cells, 3), as given.
        order: cell indices sorted by bucket, (cells,).
        starts: the ``i``-th non-empty bucket's cells are ``order[starts[i]:starts[i + 1]]``,
            (buckets + 1,).
        union_lo, union_hi: each non-empty bucket's union of its cells' boxes, (buckets, 3).
    """

    cell_lo: np.ndarray
    cell_hi: np.ndarray
    order: np.ndarray
    starts: np.ndarray
    union_lo: np.ndarray
    union_hi: np.ndarray

    @classmethod
    def build(
        cls, cell_lo: np.ndarray, cell_hi: np.ndarray, per_bucket: int = CELLS_PER_BUCKET
    ) -> CellIndex:
        """Index the boxes ``cell_lo`` / ``cell_hi`` (cells, 3)."""
        cells = len(cell_lo)
        centre = 0.5 * (cell_lo.astype(np.float64) + cell_hi.astype(np.float64))
        lo = centre.min(axis=0) if cells else np.zeros(3)
        span = (centre.max(axis=0) - lo) if cells else np.zeros(3)
        counts = _bucket_counts(span, max(cells // max(per_bucket, 1), 1))
        size = np.where(counts > 1, span / counts, 1.0)
        ijk = np.minimum(((centre - lo) / size).astype(np.int64), counts - 1)
        bucket = (ijk[:, 0] * counts[1] + ijk[:, 1]) * counts[2] + ijk[:, 2]
        order = np.argsort(bucket, kind="stable")
        sorted_bucket = bucket[order]
        first = np.unique(sorted_bucket, return_index=True)[1]
        starts = np.append(first, cells).astype(np.int64)
        if cells:
            union_lo = np.minimum.reduceat(cell_lo[order], first, axis=0)
            union_hi = np.maximum.reduceat(cell_hi[order], first, axis=0)
        else:
            union_lo = union_hi = np.zeros((0, 3), dtype=cell_lo.dtype)
        return cls(cell_lo, cell_hi, order, starts, union_lo, union_hi)

    def meeting(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """Ascending indices of the cells whose boxes meet the box ``lo``..``hi`` (3,) (closed:
        touching counts)."""
        hit = np.flatnonzero(
            np.all(self.union_hi >= lo, axis=1) & np.all(self.union_lo <= hi, axis=1)
        )
        if len(hit) == 0:
            return np.zeros(0, dtype=np.int64)
        begin, end = self.starts[hit], self.starts[hit + 1]
        lengths = end - begin
        offsets = np.repeat(begin - np.cumsum(lengths) + lengths, lengths)
        candidates = self.order[offsets + np.arange(int(lengths.sum()))]
        inside = np.all(self.cell_hi[candidates] >= lo, axis=1) & np.all(
            self.cell_lo[candidates] <= hi, axis=1
        )
        return np.sort(candidates[inside])


def _bucket_counts(span: np.ndarray, buckets: int) -> np.ndarray:
    """Buckets per axis, (3,), about ``buckets`` in all, cubes along the axes with extent."""
    axes = span > 1e-12 * max(float(span.max()), 1e-300)
    if not axes.any():
        return np.ones(3, dtype=np.int64)
    side = (float(np.prod(span[axes])) / buckets) ** (1.0 / int(axes.sum()))
    counts = np.ones(3, dtype=np.int64)
    for a in np.flatnonzero(axes):
        counts[a] = max(1, min(math.ceil(span[a] / side), 1 << 20))
    return counts
