"""The canvas tooth in the paint transfer: a dry brush leaves its paint on the peaks."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.ndimage import gaussian_filter

from brushes import load_preset_named
from paintapp.canvas.model import Canvas
from paintapp.paint.tooth import GAIN_FLOOR, ToothTexture, contact_depth_m, engagement
from paintapp.resources import asset_path
from paintapp.session.painting import PaintingSession
from tests.paintapp.paint.test_paint_transfer import BLUE, small_scene
from tests.support.demo_strokes import StrokeSpec, stroke_samples

PIXELS, SIZE_M = (400, 240), (0.04, 0.024)  # 0.1 mm texels
DRY_LOAD_M3 = 3e-9  # a brush with little paint on it


def dry_stroke(surface: str, scene: str = "live") -> Canvas:
    """A quick stroke (0.3 s, pressure 0.8) along +x of a brush with little paint (a dry brush)
    on a canvas of ``surface``."""
    canvas = Canvas(PIXELS, SIZE_M, (BLUE,), surface=surface)
    preset = load_preset_named("round_large", asset_path("brushes"))
    session = PaintingSession(canvas, preset, small_scene(scene))
    session.load_pigment(BLUE, DRY_LOAD_M3)
    for sample in stroke_samples(StrokeSpec((0.006, 0.012), (0.034, 0.012), 0.3, 0.8), 0.0):
        session.sample(sample)
    return canvas


def tooth_correlation(paint: np.ndarray, tooth: np.ndarray) -> tuple[float, float]:
    """(correlation, peak-to-valley ratio) of the paint with the tooth over the stroke (texels
    with a tenth of the thickest paint): the paint relative to its 0.8 mm average (the stroke's
    own profile divided out) against the tooth height, and the mean paint on the highest
    quarter of the tooth over that on the lowest quarter."""
    paint = paint.astype(float)
    stroke = paint > 0.1 * paint.max()
    relative = paint / np.maximum(gaussian_filter(paint, 8.0), 1e-12)
    r = float(np.corrcoef(relative[stroke], tooth[stroke])[0, 1])
    low, high = np.quantile(tooth[stroke], [0.25, 0.75])
    ratio = paint[stroke & (tooth >= high)].mean() / paint[stroke & (tooth <= low)].mean()
    return r, float(ratio)


@pytest.mark.parametrize("surface", ["cotton_duck", "fine_linen", "cold_press"])
def test_a_dry_brush_leaves_paint_on_the_peaks(surface):
    canvas = dry_stroke(surface)
    r, ratio = tooth_correlation(canvas.height_m, canvas.tooth_m.astype(float))
    assert r > 0.5  # measured: cotton duck 0.76, fine linen 0.65, cold-press 0.82
    assert ratio > 1.2  # measured: 1.5, 1.3, 2.4


def test_on_the_smooth_canvas_the_paint_ignores_any_tooth():
    canvas = dry_stroke("smooth")
    duck = Canvas(PIXELS, SIZE_M, surface="cotton_duck").tooth_m.astype(float)
    r, ratio = tooth_correlation(canvas.height_m, duck)
    assert abs(r) < 0.1  # measured: -0.03
    assert abs(ratio - 1.0) < 0.05


def test_the_tooth_conserves_paint():
    volumes = []
    for surface in ("smooth", "cotton_duck"):
        canvas = dry_stroke(surface)
        volumes.append(float(canvas.paint_m.sum(dtype=np.float64)))
    np.testing.assert_allclose(volumes[1], volumes[0], rtol=1e-3)


def test_engagement_follows_the_contact_depth_and_the_paint_levels_it():
    tooth = np.linspace(-50e-6, 50e-6, 11)
    none = np.zeros_like(tooth)
    light = engagement(tooth, none, 50e-6, contact_depth_m("cotton_duck", 0.0))
    firm = engagement(tooth, none, 50e-6, contact_depth_m("cotton_duck", 1.0))
    assert light[-1] == 1.0 and light[0] == 0.0 and np.all(np.diff(light) >= 0)
    assert np.count_nonzero(firm > 0) > np.count_nonzero(light > 0)  # pressed, it reaches deeper
    thick = engagement(tooth, np.full_like(tooth, 200e-6), 50e-6, 30e-6)
    np.testing.assert_array_equal(thick, 1.0)  # a thick layer hides the tooth


def test_tooth_weights_are_positive_and_bounded():
    canvas = Canvas(PIXELS, SIZE_M, (BLUE,), surface="cold_press")
    gain, loss = ToothTexture(canvas, 0.5, None).weights((10, 20, 90, 70))
    assert gain.shape == loss.shape == (50, 80)
    assert gain.min() >= GAIN_FLOOR and gain.max() <= 1.0 + GAIN_FLOOR
    assert loss.min() > 0.0 and loss.max() <= 1.0
