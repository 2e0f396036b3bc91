"""The bucketed cell index finds exactly the cells a scan of every cell's box finds."""

import numpy as np
import pytest

from paintapp.explore.cell_index import CellIndex


def scan(lo_cells: np.ndarray, hi_cells: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    return np.flatnonzero(np.all(hi_cells >= lo, axis=1) & np.all(lo_cells <= hi, axis=1))


def graded_cells(rng: np.random.Generator, cells: int, flat: bool) -> tuple[np.ndarray, np.ndarray]:
    """Boxes from 1e-4 to 0.3 m wide (a graded mesh's wall and far-field cells)."""
    centre = rng.uniform(-1.0, 1.0, (cells, 3))
    half = 10.0 ** rng.uniform(-4.0, np.log10(0.15), (cells, 1)) * rng.uniform(0.5, 1.0, (cells, 3))
    if flat:  # one cell thick: every cell spans the same slab in z
        centre[:, 2], half[:, 2] = 0.0, 0.005
    return (centre - half).astype(np.float32), (centre + half).astype(np.float32)


@pytest.mark.parametrize("flat", [False, True])
def test_the_index_finds_what_a_scan_finds(flat: bool) -> None:
    rng = np.random.default_rng(7)
    lo_cells, hi_cells = graded_cells(rng, 20_000, flat)
    index = CellIndex.build(lo_cells, hi_cells)
    assert len(index.union_lo) > 100  # bucketed, not one bucket holding all
    for _ in range(200):
        centre, half = rng.uniform(-1.2, 1.2, 3), 10.0 ** rng.uniform(-4.0, 0.0)
        lo, hi = centre - half, centre + half
        if flat:
            lo[2] = hi[2] = 0.0
        expected = scan(lo_cells, hi_cells, lo, hi)
        assert np.array_equal(index.meeting(lo, hi), expected)


def test_touching_boxes_meet_and_empty_meshes_answer_nothing() -> None:
    lo_cells = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], dtype=np.float32)
    hi_cells = lo_cells + np.float32(1.0)
    index = CellIndex.build(lo_cells, hi_cells)
    assert index.meeting(np.array([2.0, 0.5, 0.5]), np.array([3.0, 0.6, 0.6])).tolist() == [1]
    assert index.meeting(np.array([5.0, 5.0, 5.0]), np.array([6.0, 6.0, 6.0])).size == 0
    empty = CellIndex.build(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.float32))
    assert empty.meeting(np.zeros(3), np.ones(3)).size == 0
