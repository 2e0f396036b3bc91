"""A paint grid that follows the tip continuously: the window between texels, the fluid moved by
fractions of a cell, and a fast tip's trail without the lumps of whole-cell re-centring."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from common.errors import InputError
from paintapp.canvas.model import Canvas
from paintapp.paint.columns import ColumnWindow, transfer_weights
from paintapp.paint.paint_scene import load_paint_scene, parse_paint_scene
from paintapp.session.comb import period_depths
from solver.field_shift import shifted_by
from tests.paintapp.paint.test_nearest_room import diagonal_drag

BLUE = "ultramarine_blue"


@pytest.mark.parametrize("kernel", ["bspline", "tent"])
@pytest.mark.parametrize("origin", [0.0, 0.37, -2.81, 5.5])
def test_the_transfer_weights_stay_a_partition_of_unity_between_texels(kernel, origin):
    k = 4
    t0 = -20
    w = transfer_weights(origin, k, 0, 12, t0, 80, kernel)
    # the texels whose every column is in the window: centres from 2 to 10 cells in
    inside = slice(int(np.ceil(origin + 2 * k)) - t0, int(np.floor(origin + 10 * k)) - 1 - t0)
    np.testing.assert_allclose(w[:, inside].sum(axis=0), 1.0, atol=1e-12)  # over the columns
    np.testing.assert_allclose(w[3:9].sum(axis=1), k, atol=1e-12)  # over a column's texels


@pytest.mark.parametrize("kernel", ["bspline", "tent"])
@pytest.mark.parametrize("k", [1, 2, 3, 9, 12])
def test_the_write_back_box_holds_every_texel_a_column_weighs(kernel, k):
    """The box the write-back reads (its columns' blocks and as far around as their weights
    reach) holds every texel with a weight from them, wherever between texels the window's
    corner lies, and a texel more at most on each side."""
    canvas = Canvas((400, 400), (0.04, 0.04), (BLUE,))
    window = ColumnWindow(canvas, (6, 5), k, kernel, continuous=True)
    rng = np.random.default_rng(k)
    for _ in range(20):
        window.origin_texel = tuple(rng.uniform(k + 1.0, 100.0, 2))
        r = (1, 5, 0, 4)  # some of the columns
        x0, y0, x1, y1 = window._texel_block(r)
        for axis, (lo, hi, c0, c1) in enumerate(((x0, x1, r[0], r[1]), (y0, y1, r[2], r[3]))):
            w = transfer_weights(window.origin_texel[axis], k, c0, c1, 0, 400, kernel)
            weighed = np.flatnonzero(w.sum(axis=0) > 0.0)
            assert lo <= weighed[0] and weighed[-1] < hi
            assert weighed[0] - lo <= 1 and hi - 1 - weighed[-1] <= 1


def test_a_window_between_texels_moves_paint_conserved_and_never_negative():
    rng = np.random.default_rng(3)
    canvas = Canvas((90, 80), (0.0225, 0.02), (BLUE, "cadmium_red"))
    paint = rng.uniform(0.0, 2e-4, (2, 80, 90)).astype(np.float32)
    canvas.write_region(0, 0, paint, np.ones((80, 90), np.float32))
    window = ColumnWindow(canvas, (12, 12), 3, continuous=True)
    window.place(0.01113, 0.00987)
    ox, oy = window.origin_texel
    assert ox != round(ox) and oy != round(oy)  # between texels
    owned = window.gather(canvas)
    delta = rng.uniform(-1.0, 1.0, owned.shape) * owned
    before = canvas.paint_m.astype(np.float64).sum(axis=(1, 2))
    window.write_back(canvas, delta)
    after = canvas.paint_m.astype(np.float64).sum(axis=(1, 2))
    np.testing.assert_allclose(after - before, delta.sum(axis=(1, 2)) * 9, rtol=1e-5)
    assert canvas.paint_m.min() >= 0.0
    # re-centring moves it by exactly the tip's travel, in cells
    di, dj = window.recentre_offset(0.01113 + 0.00031, 0.00987 - 0.0002, 0)
    assert di == pytest.approx(0.31 / 0.75) and dj == pytest.approx(-0.2 / 0.75)


def test_the_fluid_moves_by_fractions_of_a_cell_as_a_whole():
    i, j, k = np.meshgrid(np.arange(10.0), np.arange(8.0), np.arange(6.0), indexing="ij")
    field = 2.0 * i - 0.5 * j + 3.0 * k + 1.0  # linear: interpolation moves it exactly
    moved = shifted_by(field, [0.3, -1.6, 0.0])
    expected = 2.0 * (i + 0.3) - 0.5 * (j - 1.6) + 3.0 * k + 1.0
    np.testing.assert_allclose(moved[:-1, 2:, :], expected[:-1, 2:, :], atol=1e-12)
    # what comes from outside is zero: the last row takes 0.7 of its own, the first column none
    np.testing.assert_allclose(moved[-1, 2:], 0.7 * expected[-1, 2:] - 0.7 * 0.6, atol=1e-12)
    assert not moved[:, 0].any()


@pytest.mark.slow
def test_a_grid_that_follows_the_tip_prints_no_lumps_where_whole_cells_step():
    """The square probe at 0.076 m/s and a slope of 1/7.5 moves 3.14 of its 0.2 mm cells a
    sub-step: by whole cells, its place within its cell comes back every 7.2 sub-steps (45.6
    texels of travel), the paint it leaves depends on that place, and its trail carries a lump
    there (measured: 0.486 against a floor of 0.197 at 44 texels); following the tip, its place
    stays put and the lumps go (0.133 against 0.082: the level the worst of ten periods reaches
    by chance). (Not the slip walls, which jump at the same moments: on a grid twice as long or
    twice as wide the lumps stay; see the README.)"""
    found = {}
    for follow in ("cells", "continuous"):
        height, points = diagonal_drag("distance", follow)
        folds = period_depths(height, 1e-4, points, np.arange(40.0, 50.0))
        found[follow] = max(folds, key=lambda d: d.depth / d.floor)
    assert found["cells"].depth > 2.0 * found["cells"].floor
    assert found["continuous"].depth < 0.35 * found["cells"].depth
    assert found["continuous"].depth < 2.0 * found["continuous"].floor


def test_a_scene_s_follow_is_checked():
    scene = parse_paint_scene({"grid": {"follow": "continuous"}}, "s")
    assert scene.follow == "continuous" and load_paint_scene("default").follow == "continuous"
    assert (
        load_paint_scene("follow_cells").follow == "cells"
        and parse_paint_scene({}, "s").follow == "cells"
    )
    with pytest.raises(InputError, match="cells, continuous"):
        parse_paint_scene({"grid": {"follow": "smooth"}}, "s")
    for table, why in (
        ({"grid": {"follow": "continuous", "sides": "open"}}, 'sides = "open"'),
        ({"grid": {"follow": "continuous"}, "paint": {"texel_flow": True}}, "texel_flow"),
        ({"fluid_model": "depth_averaged", "grid": {"follow": "continuous"}}, "depth_averaged"),
    ):
        with pytest.raises(InputError, match=why):
            parse_paint_scene(table, "s")
    base = load_paint_scene("default")
    with pytest.raises(InputError, match=r"grid\.follow"):
        dataclasses.replace(base, follow="continuous", sides="open")
