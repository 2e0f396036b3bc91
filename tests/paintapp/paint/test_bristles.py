"""Bristle texture: streaks along the stroke, ridges at its sides, paint still conserved."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.ndimage import binary_dilation, gaussian_filter

from brushes import Section, load_preset_named
from brushes.bristles import Bristles
from paintapp.canvas.model import Canvas
from paintapp.paint.bristles import Apex, BristleTexture, near_points
from paintapp.paint.columns import ColumnWindow, transfer_weights
from paintapp.resources import asset_path
from paintapp.session.painting import PaintingSession
from tests.paintapp.paint.test_paint_transfer import BLUE, balance, small_scene
from tests.support.demo_strokes import StrokeSpec, stroke_samples

BRUSHES = asset_path("brushes")


def stroke(brush: str, bristles: Bristles | str | None = "preset", scene: str = "default"):
    """A straight stroke along +x; returns the canvas and the session."""
    canvas = Canvas((160, 96), (0.04, 0.024), (BLUE,))
    preset = load_preset_named(brush, BRUSHES)
    if bristles != "preset":
        preset = dataclasses.replace(preset, bristles=bristles)
    session = PaintingSession(canvas, preset, small_scene(scene))
    session.load_pigment(BLUE, 3e-8)
    for sample in stroke_samples(StrokeSpec((0.006, 0.012), (0.034, 0.012), 0.6, 0.8), 0.0):
        session.sample(sample)
    return canvas, session


def stroke_rows(height: np.ndarray) -> slice:
    """The rows the stroke's middle stretch (texel columns 40-100) covers."""
    profile = height[:, 40:100].mean(axis=1)
    rows = np.flatnonzero(profile > 0.2 * profile.max())
    return slice(rows[0], rows[-1] + 1)


def streak_anisotropy(height: np.ndarray) -> float:
    """Fine relief (height less its 3-texel blur) across the stroke (y) over along it (x)."""
    fine = (height - gaussian_filter(height, 3.0))[stroke_rows(height), 40:100]
    return float(np.abs(np.diff(fine, axis=0)).mean() / np.abs(np.diff(fine, axis=1)).mean())


@pytest.mark.parametrize("scene", ["default", "thin_glaze"])
def test_bristles_streak_the_paint_along_the_stroke(scene):
    textured, _ = stroke("round_large", scene=scene)
    even, _ = stroke("round_large", None, scene=scene)
    a_textured = streak_anisotropy(textured.height_m.astype(float))
    a_even = streak_anisotropy(even.height_m.astype(float))
    assert a_textured > 4.0  # the fine relief varies across the stroke far more than along it
    assert a_textured > 1.8 * a_even


def test_the_ridge_heaps_paint_at_the_stroke_sides():
    def sides_over_centre(ridge: float) -> float:
        canvas, _ = stroke("round_large", Bristles(clumps=12, contrast=0.5, ridge=ridge))
        height = canvas.height_m.astype(float)
        profile = height[stroke_rows(height), 40:100].mean(axis=1)
        q = len(profile) // 4
        return min(profile[:q].max(), profile[-q:].max()) / profile[q:-q].mean()

    assert sides_over_centre(2.0) > sides_over_centre(0.0) + 0.03


@pytest.mark.parametrize("brush", ["round_large", "flat_wide"])
def test_paint_is_conserved_and_stays_near_the_stroke_with_bristles(brush):
    canvas, session = stroke(brush)
    assert session.preset.bristles is not None
    total = sum(session.loaded_m3.values())
    for name, error in balance(session).items():
        assert abs(error) < 2e-6 * total, (name, error)
    assert canvas.paint_m.min() >= 0.0
    # The texture moves paint only within a column's reach: no paint (nor wetness) beyond what
    # the same stroke without bristles painted, widened by one cell.
    even, _ = stroke(brush, None)
    near = binary_dilation(even.height_m > 0.0, iterations=session.model.window.k)
    assert canvas.height_m.max() > 1e-5
    assert not canvas.height_m[~near].any() and not canvas.wetness[~near].any()


def test_a_textured_write_back_moves_exactly_the_column_change():
    rng = np.random.default_rng(4)
    canvas = Canvas((120, 120), (0.03, 0.03), (BLUE, "cadmium_red"))
    paint = rng.uniform(0.0, 2e-4, (2, 120, 120)).astype(np.float32)
    canvas.write_region(0, 0, paint, np.ones((120, 120), np.float32))
    window = ColumnWindow(canvas, (16, 16), 5)
    window.place(0.015, 0.015)
    preset = load_preset_named("flat_wide", BRUSHES)
    assert preset.bristles is not None
    texture = BristleTexture(
        preset.bristles,
        Section(preset.tip(1.2), 0.002),
        np.array([0.015, 0.015]),
        0.3,
        np.array([1.0, 0.5]),
        canvas.texel_size_m[0],
        window.cell_size_m,
        0.01,
    )
    owned = window.gather(canvas)
    delta = rng.uniform(-1.0, 1.0, owned.shape) * owned  # losses up to all a column holds
    before = canvas.paint_m.astype(np.float64).sum(axis=(1, 2))
    window.write_back(canvas, delta, texture)
    after = canvas.paint_m.astype(np.float64).sum(axis=(1, 2))
    np.testing.assert_allclose(after - before, delta.sum(axis=(1, 2)) * 25, rtol=1e-5)
    assert canvas.paint_m.min() >= 0.0


def test_the_write_back_lays_gains_with_the_weights_and_takes_losses_as_fractions():
    """Each texel against the transfer written with dense weight matrices: a texel gains
    ``g * sum_c w_c gain_c`` and loses ``m * (b * sum_c w_c f_c + (1 - b) * sum_c w_c r_c)``."""
    rng = np.random.default_rng(5)
    canvas = Canvas((90, 80), (0.0225, 0.02), (BLUE, "cadmium_red"))
    paint = rng.uniform(0.0, 2e-4, (2, 80, 90)).astype(np.float32)
    wet = rng.uniform(0.2, 1.0, (80, 90)).astype(np.float32)
    canvas.write_region(0, 0, paint, wet)
    window = ColumnWindow(canvas, (12, 12), 5)
    window.place(0.011, 0.01)
    g = rng.uniform(0.5, 1.5, (80, 90))
    b = rng.uniform(0.3, 1.0, (80, 90))

    class Texture:
        def weights(self, box):
            x0, y0, x1, y1 = box
            return g[y0:y1, x0:x1], b[y0:y1, x0:x1]

    owned = window.gather(canvas)
    delta = rng.uniform(-0.8, 1.0, owned.shape) * owned.mean()
    delta[:, :, :2] = 0.0  # two rows of columns unchanged
    delta[:, 7, 5] = -10.0 * owned[:, 7, 5]  # a column losing all it holds
    ox, oy = window.origin_texel
    wx = transfer_weights(ox, 5, 0, 12, 0, 90)  # dense (columns, texels)
    wy = transfer_weights(oy, 5, 0, 12, 0, 80)
    share = np.where(wet >= 1.0 - 2.0**-20, 1.0, wet.astype(np.float64))
    mobile = paint.astype(np.float64) * share
    on = window.on_canvas()
    wx_on, wy_on = wx * on.any(axis=1)[:, None], wy * on.any(axis=0)[:, None]

    def to_columns(texels):
        return np.einsum("it,jy,...yt->...ij", wx_on, wy_on, texels)

    def to_texels(columns):
        return np.einsum("it,jy,...ij->...yt", wx_on, wy_on, columns)

    change, held = delta * 25, owned * 25
    first, support = to_columns(mobile * b), to_columns(g)
    loss = np.maximum(-change, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        gain = np.where(on, np.maximum(change, 0.0) / support, 0.0)
        f = np.where(on & (loss > 0), np.minimum(loss / first, 1.0), 0.0)
        rest = np.maximum(held - first, 0.0)
        left = np.maximum(loss - f * first, 0.0)
        r = np.where(on & (left > 0) & (rest > 0), np.minimum(left / rest, 1.0), 0.0)
    new_mobile = np.maximum(mobile - mobile * (b * to_texels(f) + (1 - b) * to_texels(r)), 0.0)
    new_mobile += g * to_texels(gain)
    expected = paint * (1.0 - share) + new_mobile
    expected_wet = new_mobile.sum(axis=0) / expected.sum(axis=0)

    window.write_back(canvas, delta, Texture())
    np.testing.assert_allclose(canvas.paint_m, expected, rtol=2e-6, atol=1e-12)
    np.testing.assert_allclose(canvas.wetness, expected_wet, rtol=2e-6)
    assert not np.array_equal(canvas.paint_m, paint)
    untouched = to_texels(np.abs(delta).sum(axis=0)) == 0.0  # beyond every changed column
    assert untouched.any() and np.array_equal(canvas.paint_m[:, untouched], paint[:, untouched])


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31))
def test_the_footprint_s_near_texels_are_numpy_s(seed):
    """``near_points``: the texels of a box within a radius of the apex, in row order, their
    centres turned into the body frame, as the numpy grid of the box's centres gives them."""
    rng = np.random.default_rng(seed)
    t = float(rng.uniform(5e-5, 5e-4))
    sx0, sy0 = (int(v) for v in rng.integers(0, 500, 2))
    nx, ny = (int(v) for v in rng.integers(1, 40, 2))
    cx, cy = float(rng.uniform(sx0, sx0 + nx) * t), float(rng.uniform(sy0, sy0 + ny) * t)
    yaw = float(rng.uniform(-4, 4))
    cos, sin = np.cos(yaw), np.sin(yaw)
    radius = float(rng.uniform(0.0, 0.6) * max(nx, ny) * t)
    gx, gy = np.meshgrid((np.arange(sx0, sx0 + nx) + 0.5) * t - cx,
                         (np.arange(sy0, sy0 + ny) + 0.5) * t - cy)  # fmt: skip
    near = gx**2 + gy**2 <= radius**2
    want = np.stack([cos * gx[near] + sin * gy[near], -sin * gx[near] + cos * gy[near]], axis=-1)
    body, index = np.empty((nx * ny, 2)), np.empty(nx * ny, np.int64)
    count = near_points(Apex(t, cx, cy, cos, sin), radius**2, sx0, sy0, nx, ny, body, index)
    assert count == int(near.sum())
    np.testing.assert_array_equal(body[:count], want)
    np.testing.assert_array_equal(index[:count], np.flatnonzero(near))


def test_the_streaks_are_no_finer_than_the_texels_hold():
    """A diagonal stroke's texture, sampled by the texels: little of its relief lies near the
    texels' Nyquist frequency, where a sampled streak turns into a jagged, beaded line (without
    the widening, a quarter of it does)."""
    preset = load_preset_named("round_large", BRUSHES)
    assert preset.bristles is not None
    texel = 1e-4
    texture = BristleTexture(
        preset.bristles,
        Section(preset.tip(1.0), 0.0015),
        np.array([0.02, 0.02]),
        0.0,
        np.array([0.8, -0.6]),
        texel,
        12 * texel,
        0.012,
    )
    weights = texture.weights((100, 100, 300, 300))
    assert weights is not None
    gain = weights[0]
    window = np.hanning(200)[:, None] * np.hanning(200)[None, :]
    power = np.abs(np.fft.fft2((gain - gain.mean()) * window)) ** 2
    f = np.fft.fftfreq(200)
    radius = np.hypot(f[:, None], f[None, :])
    assert gain.max() - gain.min() > 0.3  # the streaks are there
    assert power[radius > 0.4].sum() < 0.1 * power[radius > 0.02].sum()


class _Uncompiled:
    """A tip shape without its compiled form: the texture reads its distances through ``sdf``."""

    def __init__(self, shape) -> None:
        self.shape = shape
        self.bounding_radius_m = shape.bounding_radius_m

    def sdf(self, points: np.ndarray) -> np.ndarray:
        return self.shape.sdf(points)


@settings(max_examples=30, deadline=None)
@given(
    seed=st.integers(0, 2**31),
    brush=st.sampled_from(["round_large", "round_small", "flat_wide"]),
)
def test_the_compiled_footprint_gives_the_same_weights_as_the_shape_s_own_distances(seed, brush):
    """Through the tip's compiled form (one pass over the texels near the footprint, skipping
    blocks beyond the texture's reach) the texture's weights are those of the shape's own
    ``sdf`` at every texel near the apex, bit for bit, at any yaw, depth and place."""
    rng = np.random.default_rng(seed)
    preset = load_preset_named(brush, BRUSHES)
    tip = preset.tip(float(rng.uniform(1.0, 1.6)))
    texel = 1e-4
    depth = float(rng.uniform(0.0002, 0.004))
    args = (
        np.array([0.02, 0.02]) + rng.uniform(-0.001, 0.001, 2),
        float(rng.uniform(-4.0, 4.0)),
        rng.normal(size=2),
        texel,
        float(rng.uniform(4, 14)) * texel,
        float(rng.uniform(0.004, 0.012)),
    )
    compiled = BristleTexture(preset.bristles, Section(tip, depth), *args)
    plain = BristleTexture(preset.bristles, Section(_Uncompiled(tip), depth), *args)
    box = (100, 90, 310, 300)
    got, want = compiled.weights(box), plain.weights(box)
    assert (got is None) == (want is None)
    if want is not None:
        np.testing.assert_array_equal(got[0], want[0])
        np.testing.assert_array_equal(got[1], want[1])
