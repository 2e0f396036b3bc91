"""The write-back's texel passes on two threads: the same canvas, bit for bit, as on one."""

from __future__ import annotations

import threading

import numpy as np
import pytest

from paintapp.canvas.model import Canvas
from paintapp.paint import texel_halves
from paintapp.paint.columns import ColumnWindow
from paintapp.paint.texel_halves import on_halves, split_threads


class RandomTexture:
    """Gain and loss weights drawn at random over any box (a bristle texture's shape)."""

    def weights(self, box):
        rng = np.random.default_rng(box[0] * 1000 + box[1])
        shape = (box[3] - box[1], box[2] - box[0])
        return rng.uniform(0.2, 1.8, shape), rng.uniform(0.05, 1.0, shape)


def canvas() -> Canvas:
    rng = np.random.default_rng(11)
    paint = (rng.random((3, 96, 80)) * 1e-4).astype(np.float32)
    paint[:, 40:52, 30:44] = 0.0  # a bare patch: holes, fringes and pinholes get work
    wet = rng.random((96, 80)).astype(np.float32)
    names = ("ultramarine_blue", "cadmium_yellow", "cadmium_red")
    return Canvas((80, 96), (0.020, 0.024), names, paint, wet)


def painted(threads: int, texture, sweep) -> tuple[Canvas, np.ndarray, list[str]]:
    """A gather and a write-back with the passes forced onto ``threads`` threads; also the
    gathered columns and the threads that ran a texel pass."""
    c = canvas()
    window = ColumnWindow(c, (17, 19), 3, continuous=True)
    window.place(0.0101, 0.0117)
    ran: list[str] = []
    real = texel_halves.run_components

    def spy(work, count, n):
        ran.append("split")
        return real(work, count, n)

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(texel_halves, "SPLIT_MIN_TEXELS", 0 if threads > 1 else 2**62)
        patch.setattr(texel_halves, "usable_cores", lambda: threads)
        patch.setattr(texel_halves, "run_components", spy)
        columns = window.gather(c)
        delta = np.zeros_like(columns)
        delta[0, 4:9, 6:10] = 3e-5  # blue laid down
        delta[2, 9:13, 3:8] = -0.7 * columns[2, 9:13, 3:8]  # red taken up
        delta[1, 2:5, 12:15] = -columns[1, 2:5, 12:15]  # yellow emptied
        window.write_back(c, delta, texture, gathered=columns, sweep_texels=sweep)
    return c, columns, ran


@pytest.mark.parametrize("texture", [None, RandomTexture()])
@pytest.mark.parametrize("sweep", [None, (6.5, -2.0)])
def test_two_threads_give_the_same_bits_as_one(texture, sweep):
    one, columns_one, ran_one = painted(1, texture, sweep)
    two, columns_two, ran_two = painted(2, texture, sweep)
    assert ran_one == [] and len(ran_two) >= 3  # gather, spread and store (and the textured sums)
    assert np.array_equal(columns_one, columns_two)
    assert np.array_equal(one.paint_m, two.paint_m)
    assert np.array_equal(one.wetness, two.wetness)
    assert one.peek_dirty() == two.peek_dirty() is not None
    assert not np.array_equal(one.paint_m, canvas().paint_m)  # the write-back did change paint


def test_halves_split_the_range_and_run_on_two_threads():
    names: list[tuple[int, int, str]] = []

    def work(lo: int, hi: int) -> int:
        names.append((lo, hi, threading.current_thread().name))
        return hi - lo

    assert on_halves(work, 9, 2) == [4, 5]
    assert sorted(n[:2] for n in names) == [(0, 4), (4, 9)]
    assert len({n[2] for n in names}) == 2
    names.clear()
    assert on_halves(work, 9, 1) == [9] and names[0][:2] == (0, 9)
    assert on_halves(work, 1, 2) == [1]  # nothing to split


def test_small_boxes_stay_on_one_thread(monkeypatch):
    monkeypatch.setattr(texel_halves, "usable_cores", lambda: 2)
    assert split_threads(texel_halves.SPLIT_MIN_TEXELS - 1) == 1
    assert split_threads(texel_halves.SPLIT_MIN_TEXELS) == 2
    monkeypatch.setattr(texel_halves, "usable_cores", lambda: 1)
    assert split_threads(10**7) == 1
