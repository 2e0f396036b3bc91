"""The local paint grid: its canvas window, column fill and write-back, re-centring, scenes."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from brushes import StylusSample, TipTracker, load_preset_named
from common.errors import InputError
from paintapp.canvas.model import Canvas
from paintapp.paint.cell_kernels import fill_columns
from paintapp.paint.columns import AxisWeights, ColumnWindow, cell_texels, transfer_weights
from paintapp.paint.columns_kernels import axis_taps
from paintapp.paint.grid3d import PaintGrid3D
from paintapp.paint.paint_model import brush_width_m
from paintapp.paint.paint_scene import load_paint_scene, parse_paint_scene
from paintapp.paint.selector import MODEL_CLASSES
from paintapp.resources import asset_path

BRUSHES = asset_path("brushes")


def painted_canvas(seed: int = 0) -> Canvas:
    """64 x 64 texels over 16 mm, two pigments of random wet and dry paint."""
    rng = np.random.default_rng(seed)
    paint = (rng.random((2, 64, 64)) * 1e-4).astype(np.float32)
    wet = rng.random((64, 64)).astype(np.float32)
    return Canvas((64, 64), (0.016, 0.016), ("ultramarine_blue", "cadmium_yellow"), paint, wet)


def test_cell_size_is_a_whole_number_of_texels_spanning_the_brush():
    preset = load_preset_named("round_small", BRUSHES)
    width = brush_width_m(preset)
    assert 2 * 0.002 < width < 2 * 0.002 * 2.0  # the belly, splayed
    k = cell_texels(width, 0.25e-3, 32, 2.0)
    assert k == round(2.0 * width / (32 * 0.25e-3))
    assert cell_texels(width, 1e-2, 32, 2.0) == 1  # never below one texel


def test_window_snaps_to_the_block_lattice_and_recentres_only_past_the_margin():
    window = ColumnWindow(painted_canvas(), (16, 16), 2)
    window.place(0.0081, 0.0079)
    assert all(o % 2 == 0 for o in window.origin_texel)
    centre = np.array(window.origin_m) + 8 * window.cell_size_m
    assert window.recentre_offset(*centre, margin=4) == (0, 0)
    near_edge = centre + np.array([5.3, -6.4]) * window.cell_size_m
    di, dj = window.recentre_offset(*near_edge, margin=4)
    assert (di, dj) == (5, -6)


@pytest.mark.parametrize("k", [2, 3, 4, 5, 7, 12])
@pytest.mark.parametrize("kernel", ["bspline", "tent"])
def test_transfer_weights_are_a_partition_of_unity_summing_to_k_per_column(k, kernel):
    w = transfer_weights(-3 * k, k, 0, 12, 0, 6 * k, kernel)  # columns reaching past both ends
    np.testing.assert_allclose(w.sum(axis=0), 1.0, atol=1e-12)  # every texel
    np.testing.assert_allclose(w[4:8].sum(axis=1), k, rtol=1e-12)  # columns wholly inside
    assert w.min() >= 0.0
    reach = np.abs(np.arange(6 * k)[None, :] + 0.5 - (-3 * k + (np.arange(12)[:, None] + 0.5) * k))
    assert np.all(w[reach >= (1.5 if kernel == "bspline" else 1.0) * k] == 0.0)
    # What a step in the columns lays down: the spline's slope changes smoothly (second
    # differences 1 / k^2), the tent's jumps by 1 / k at a column centre (split over two texel
    # boundaries when k is even).
    curvature = np.abs(np.diff((np.arange(12) >= 6).astype(float) @ w, 2)).max()
    if kernel == "bspline":
        assert curvature < 1.01 / k**2
    elif k >= 3:
        assert curvature > 0.49 / k
    assert np.allclose(transfer_weights(0, 1, 0, 4, 0, 4, kernel), np.eye(4))  # k = 1: identity


def test_the_compiled_axis_weights_are_the_dense_weights_taps():
    """The per-texel taps a window uses, built texel by texel (``weight_taps``), are those of the
    dense weights: the same values, at whole-texel and fractional offsets, both kernels."""
    rng = np.random.default_rng(11)
    for n in range(200):
        k, columns, texels = (
            int(rng.integers(1, 7)),
            int(rng.integers(1, 40)),
            int(rng.integers(1, 300)),
        )
        offset = float(rng.uniform(-50.0, 50.0)) if n % 2 else float(rng.integers(-50, 50))
        kernel = "tent" if n % 5 == 0 else "bspline"
        dense = transfer_weights(offset, k, 0, columns, 0, texels, kernel)
        first, taps = axis_taps(dense)
        built = AxisWeights(offset, k, columns, texels, kernel)
        assert np.array_equal(built.first, first) and np.array_equal(built.taps, taps)
        np.testing.assert_allclose(built.sums, dense.sum(axis=1), rtol=1e-13, atol=1e-13)


def test_gather_takes_only_the_wet_paint_and_unchanged_columns_are_not_written():
    canvas = painted_canvas()
    window = ColumnWindow(canvas, (16, 16), 2)
    window.place(0.008, 0.008)
    columns = window.gather(canvas)
    mobile = canvas.paint_m.astype(np.float64) * canvas.wetness
    r = window.on_canvas_range()
    assert r is not None
    i, j = r[0] + 3, r[2] + 5
    x0, y0 = window.origin_texel[0] + 2 * i, window.origin_texel[1] + 2 * j
    near = mobile[:, y0 - 2 : y0 + 4, x0 - 2 : x0 + 4]  # the block and the spline's reach
    # quadratic B-spline, k = 2: texel centres 1.25, 0.75, 0.25 cells either side of the column's
    hat = np.array([0.5 * 0.25**2, 0.5 * 0.75**2, 0.75 - 0.25**2])
    hat = np.concatenate([hat, hat[::-1]])
    np.testing.assert_allclose(hat.sum(), 2.0)
    expected = (near * hat[None, :, None] * hat[None, None, :]).sum(axis=(1, 2)) / 4.0
    np.testing.assert_allclose(columns[:, i, j], expected)
    before = canvas.paint_m.copy(), canvas.wetness.copy()
    canvas.take_dirty()
    window.write_back(canvas, np.zeros_like(columns))
    assert np.array_equal(canvas.paint_m, before[0]) and np.array_equal(canvas.wetness, before[1])
    assert canvas.take_dirty() is None


def test_write_back_conserves_paint_and_keeps_dry_paint():
    canvas = painted_canvas(1)
    window = ColumnWindow(canvas, (16, 16), 2)
    window.place(0.008, 0.008)
    columns = window.gather(canvas)
    dry = canvas.paint_m.sum(axis=0, dtype=np.float64) * (1.0 - canvas.wetness)
    delta = np.zeros_like(columns)
    delta[0, 4, 4] = 3e-5  # a gain of blue
    delta[1, 6, 7] = -0.5 * columns[1, 6, 7]  # half the wet yellow leaves
    area = 4 * canvas.texel_size_m[0] ** 2
    total = canvas.paint_m.sum(axis=(1, 2), dtype=np.float64) * canvas.texel_size_m[0] ** 2
    window.write_back(canvas, delta)
    after = canvas.paint_m.sum(axis=(1, 2), dtype=np.float64) * canvas.texel_size_m[0] ** 2
    np.testing.assert_allclose(after - total, delta.sum(axis=(1, 2)) * area, rtol=1e-4, atol=1e-14)
    still_dry = canvas.paint_m.sum(axis=0, dtype=np.float64) * (1.0 - canvas.wetness)
    np.testing.assert_allclose(still_dry, dry, atol=1e-10)  # the dry paint stays


def test_columns_fill_cells_from_the_bottom_with_a_fractional_top_cell():
    h = 1e-4
    columns = np.zeros((2, 1, 1))
    columns[:, 0, 0] = (1.5 * h, 1.0 * h)  # 2.5 cells, 60 % blue
    cells = np.zeros((2, 1, 1, 5))
    fill_columns(columns, h, cells)
    np.testing.assert_allclose(cells.sum(axis=0)[0, 0], [1.0, 1.0, 0.5, 0.0, 0.0])
    np.testing.assert_allclose(cells[0, 0, 0, :3], 0.6 * np.array([1.0, 1.0, 0.5]))
    np.testing.assert_allclose(cells.sum(axis=3)[:, 0, 0] * h, columns[:, 0, 0])


def test_non_square_texels_are_refused():
    canvas = Canvas((64, 32), (0.016, 0.016))
    with pytest.raises(InputError, match="square texels"):
        ColumnWindow(canvas, (16, 16), 1)


def test_grid_recentres_by_whole_cells_and_keeps_its_fluid_state():
    canvas = painted_canvas(2)
    scene = dataclasses.replace(
        load_paint_scene(), cells=(16, 16, 8), margin_cells=4, follow="cells"
    )
    preset = load_preset_named("round_small", BRUSHES)
    model = PaintGrid3D(scene, canvas, preset)
    tracker = TipTracker(preset)
    from brushes import PaintReservoir

    reservoir = PaintReservoir(preset.capacity_m3)
    pose = tracker.update(StylusSample(0.0, np.array([0.008, 0.008, 0.0]), 0.8))
    model.touch_down(pose)
    pose = tracker.update(StylusSample(0.02, np.array([0.0085, 0.008, 0.0]), 0.8))
    model.step(pose, 0.02, reservoir)
    assert model.sim is not None
    before = [c.copy() for c in model.sim.state.comps]
    origin = model.window.origin_texel
    di, dj = model.follow(np.array([0.0085 + 6.0 * model.cell_size_m, 0.008, 0.0]))
    assert (di, dj) != (0, 0)
    assert model.window.origin_texel == (
        origin[0] + di * model.window.k,
        origin[1] + dj * model.window.k,
    )
    np.testing.assert_allclose(model.sim.grid.origin_m[:2], model.window.origin_m)
    n = 16
    for a in range(3):
        old, new = before[a], model.sim.state.comps[a]
        xs = slice(max(di, 0) + 1, n + min(di, 0) - 1)
        ys = slice(max(dj, 0) + 1, n + min(dj, 0) - 1)
        src = old[xs, ys]
        dst = new[xs.start - di : xs.stop - di, ys.start - dj : ys.stop - dj]
        np.testing.assert_array_equal(dst[:, :, :-1], src[:, :, :-1])


def test_the_scene_chooses_the_paint_model():
    canvas = painted_canvas()
    preset = load_preset_named("round_small", BRUSHES)
    for name, expected in (
        ("default", "grid3d"),
        ("thin_glaze", "depth_averaged"),
        ("no_fluid", "none"),
    ):
        scene = load_paint_scene(name)
        assert scene.fluid_model == expected
        model = MODEL_CLASSES[scene.fluid_model](scene, canvas, preset)
        assert isinstance(model, MODEL_CLASSES[expected])


def test_a_bad_scene_names_the_key():
    with pytest.raises(InputError, match="fluid_model"):
        parse_paint_scene({"fluid_model": "water"}, "bad")
    with pytest.raises(InputError, match=r"paint\.viscosity_pa_s"):
        parse_paint_scene({"paint": {"viscosity_pa_s": -1.0}}, "bad")
    with pytest.raises(InputError, match=r"grid\.typo"):
        parse_paint_scene({"grid": {"typo": 1}}, "bad")
    with pytest.raises(InputError, match=r"grid\.max_travel_cells"):
        parse_paint_scene({"grid": {"max_travel_cells": 0.0}}, "bad")
    with pytest.raises(InputError, match=r"grid\.max_travel_substeps"):
        parse_paint_scene({"grid": {"max_travel_substeps": 0}}, "bad")
    travel = parse_paint_scene({"grid": {"max_travel_cells": 0.5, "max_travel_substeps": 8}}, "ok")
    assert (travel.max_travel_cells, travel.max_travel_substeps) == (0.5, 8)
    with pytest.raises(InputError, match="unknown painting scene"):
        load_paint_scene("no_such_scene")


class RandomTexture:
    """Gain and loss weights drawn at random over any box (a bristle texture's shape)."""

    def weights(self, box):
        rng = np.random.default_rng(box[0] * 1000 + box[1])
        shape = (box[3] - box[1], box[2] - box[0])
        return rng.uniform(0.2, 1.8, shape), rng.uniform(0.05, 1.0, shape)


@pytest.mark.parametrize("texture", [None, RandomTexture()])
def test_write_back_skips_unchanged_pigments_with_the_same_bits(monkeypatch, texture):
    """A pigment whose columns do not change is left out of the texel passes; the canvas ends
    the same, bit for bit, as when every pigment goes through them (its texels keep their
    paint; the wetness still counts it)."""
    from paintapp.paint import columns_kernels

    def canvas() -> Canvas:
        rng = np.random.default_rng(4)
        paint = (rng.random((3, 64, 64)) * 1e-4).astype(np.float32)
        wet = rng.random((64, 64)).astype(np.float32)
        names = ("ultramarine_blue", "cadmium_yellow", "cadmium_red")
        return Canvas((64, 64), (0.016, 0.016), names, paint, wet)

    def painted(every: bool) -> Canvas:
        c = canvas()
        window = ColumnWindow(c, (16, 16), 3, continuous=True)
        window.place(0.0081, 0.0079)
        columns = window.gather(c)
        delta = np.zeros_like(columns)
        delta[0, 5:8, 6:9] = 2e-5  # blue laid down
        delta[2, 9:11, 4:7] = -0.6 * columns[2, 9:11, 4:7]  # red taken up; yellow unchanged
        with monkeypatch.context() as patch:
            if every:
                for name, at in (("texels_to_columns", 3), ("spread_to_texels", 4)):
                    real = getattr(columns_kernels, name)
                    patch.setattr(columns_kernels, name, all_pigments(real, at))
                real_sweep = columns_kernels.sweep_change
                patch.setattr(columns_kernels, "sweep_change", all_pigments(real_sweep, 10))
            window.write_back(c, delta, texture, gathered=columns, sweep_texels=(7.5, -3.0))
        return c

    def all_pigments(real, at):
        def call(*args):
            args = list(args)
            args[at] = np.ones_like(args[at])
            return real(*args)

        return call

    before, skipped, every = canvas(), painted(False), painted(True)
    assert np.array_equal(skipped.paint_m, every.paint_m)
    assert np.array_equal(skipped.wetness, every.wetness)
    assert np.array_equal(skipped.paint_m[1], before.paint_m[1])  # the yellow kept its paint
    assert not np.array_equal(skipped.wetness, before.wetness)
    assert not np.array_equal(skipped.paint_m[0], before.paint_m[0])
