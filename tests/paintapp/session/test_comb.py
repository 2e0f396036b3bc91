"""The tooth-depth measure along a stroke's path."""

from __future__ import annotations

import numpy as np
import pytest

from paintapp.session.comb import (
    across_width,
    main,
    period_depths,
    period_scan,
    scan_periods,
    stroke_paths,
    tooth_depth,
)
from paintapp.strokes.files import read_strokes

TEXEL = 2.5e-4


def straight_path(step_texels: float, steps: int = 40) -> np.ndarray:
    x = (20.0 + step_texels * np.arange(steps + 1)) * TEXEL
    return np.stack([x, np.full_like(x, 50.5 * TEXEL)], axis=1)


def test_even_streaks_along_a_diagonal_stroke_read_no_comb():
    """Streaks along a 3-4-5 diagonal, even along it and wide enough for the texels: read
    bilinearly, each would swell and thin wherever the line read crosses a texel row or column
    (teeth every 2.5 and 3.3 texels, at 4-6 times their floor); read on the cubic spline, nothing
    stands over the floor."""
    yy, xx = np.mgrid[0:300, 0:300] + 0.5
    across = 0.6 * xx + 0.8 * yy
    relief = 1.0 + 0.02 * np.random.default_rng(3).standard_normal(xx.shape)
    streaks = sum(np.exp(-0.5 * (across - c) ** 2) for c in np.arange(150.0, 270.0, 4.3))
    height = (relief + 0.5 * streaks) * 1e-4
    along = np.linspace(-110.0, 110.0, 45)[:, None] * np.array([0.8, -0.6])[None, :]
    path = (150.1 + along) * TEXEL
    found = period_depths(height, TEXEL, path, np.array([2.5, 10.0 / 3.0, 5.0]))
    assert len(found) == 3
    for d in found:
        assert d.depth < 2.0 * d.floor, d


def test_teeth_one_per_step_are_measured_and_a_smooth_trail_stays_at_its_floor():
    path = straight_path(5.0)
    x = np.arange(260) + 0.5
    rng = np.random.default_rng(1)
    relief = 1.0 + 0.05 * rng.standard_normal((100, 260))
    combed = relief + 0.1 * np.cos(2.0 * np.pi * (x - 20.0) / 5.0)[None, :]
    depth, floor = tooth_depth(combed * 1e-4, TEXEL, path)
    assert depth == pytest.approx(0.2, rel=0.15)  # peak-to-peak of a +-0.1 tooth
    assert floor < 0.25 * depth
    smooth_depth, smooth_floor = tooth_depth(relief * 1e-4, TEXEL, path)
    assert smooth_depth < 2.0 * smooth_floor
    assert np.isnan(tooth_depth(np.zeros((100, 260)), TEXEL, path)[0])  # nothing painted
    assert np.isnan(tooth_depth(relief, TEXEL, straight_path(5.0, steps=5))[0])  # too short


def test_the_period_scan_finds_teeth_that_recur_every_few_steps():
    """Teeth every 1.6 steps (a grid re-centring every few cells prints such a period): the fold
    at the step misses them, the scan finds them at their period; a smooth trail stays near its
    floor at every period."""
    path = straight_path(5.0, steps=60)
    x = np.arange(340) + 0.5
    rng = np.random.default_rng(2)
    relief = 1.0 + 0.05 * rng.standard_normal((100, 340))
    combed = relief + 0.1 * np.cos(2.0 * np.pi * (x - 20.0) / 8.0)[None, :]
    step_depth, step_floor = tooth_depth(combed * 1e-4, TEXEL, path)
    assert step_depth < 2.0 * step_floor  # at the step's own period: nothing
    worst = period_scan(combed * 1e-4, TEXEL, path)
    assert worst is not None
    assert worst.period_texels == pytest.approx(8.0, rel=0.03)
    assert worst.depth == pytest.approx(0.2, rel=0.15)
    assert worst.floor < 0.3 * worst.depth
    smooth = period_depths(relief * 1e-4, TEXEL, path, scan_periods(5.0))
    assert len(smooth) > 30
    # noise alone: each period's ratio is about 1, the largest of some 50 periods about 2
    assert np.median([d.depth / d.floor for d in smooth]) < 1.3
    assert max(d.depth / d.floor for d in smooth) < 2.5
    assert period_scan(np.zeros((100, 340)), TEXEL, path) is None  # nothing painted
    assert period_depths(relief, TEXEL, path, np.array([100.0])) == []  # under four periods


def test_the_period_scan_finds_teeth_at_a_sub_step_between_its_scanned_periods():
    """Two sub-steps a sample of 12.61 texels print teeth every 6.305 texels, between the
    scan's periods 6.24 and 6.37: over 70 teeth the fold at either drifts by a third of a period
    and halves them, and beside a second, shallower comb (every 15.1 texels) the coarse scan's
    worst lies elsewhere (at three sub-steps, 18.9: measured) and the refinement never looks near
    6.3 (as on the demo's probe). The step's halves are folded exactly."""
    step = 12.61
    periods = scan_periods(step)
    assert not np.isclose(periods, step / 2.0, rtol=2e-3).any()
    path = straight_path(step, steps=36)
    x = np.arange(520) + 0.5 - 20.0
    rng = np.random.default_rng(3)
    relief = 1.0 + 0.05 * rng.standard_normal((100, 520))
    teeth = 0.1 * np.cos(2.0 * np.pi * x / (step / 2.0)) + 0.05 * np.cos(2.0 * np.pi * x / 15.1)
    combed = (relief + teeth[None, :]) * 1e-4
    coarse = [d for d in period_depths(combed, TEXEL, path, periods) if d.floor > 0.0]
    assert abs(max(coarse, key=lambda d: d.depth / d.floor).period_texels - step / 2.0) > 1.0
    worst = period_scan(combed, TEXEL, path)
    assert worst is not None
    assert worst.period_texels == pytest.approx(step / 2.0, rel=2e-3)
    assert worst.depth == pytest.approx(0.2, rel=0.15)


def test_the_demo_strokes_split_at_their_markers(tmp_path, capsys):
    from paintapp.resources import asset_path

    paths = stroke_paths(read_strokes(asset_path("strokes", "demo.jsonl")))
    assert [p.label for p in paths][-1] == "clean probe dragged through red"
    assert [p.brush for p in paths] == ["round_large"] * 2 + ["flat_wide"] * 2 + [
        "round_small",
        "square_probe",
    ]
    assert len(paths) == 6 and all(len(p.points_m) > 50 for p in paths)
    assert main([str(tmp_path)]) == 2  # no demo folder: a message, not a traceback
    assert "expected a paintapp demo folder" in capsys.readouterr().err


def test_teeth_on_a_stroke_s_side_are_read_across_its_width():
    """A stroke 40 texels wide, smooth along its middle, with one tooth per step on a ridge 16
    texels to its left (the sides a fast square tip leaves): the centre lines read nothing over
    their floor; across the width, the ridge's line does."""
    path = straight_path(5.0)
    yy, xx = np.mgrid[0:100, 0:260] + 0.5
    rng = np.random.default_rng(2)
    band = np.abs(yy - 50.5) < 20.0
    ridge = np.exp(-0.5 * ((yy - 66.5) / 2.0) ** 2)
    teeth = 1.0 + 0.3 * ridge * np.cos(2.0 * np.pi * (xx - 20.0) / 5.0)
    height = band * (1.0 + 0.02 * rng.standard_normal(xx.shape)) * teeth * 1e-4
    depth, floor = tooth_depth(height, TEXEL, path)
    assert depth < 2.0 * floor
    side = across_width(height, TEXEL, path, 40.0)
    assert side is not None
    assert side.offset_texels == pytest.approx(15.0, abs=2.5)
    assert side.depth > 0.3 and side.depth > 5.0 * side.floor
    smooth = across_width(band * (1.0 + 0.02 * rng.standard_normal(xx.shape)), TEXEL, path, 40.0)
    assert smooth is not None and smooth.depth < 2.0 * smooth.floor
    assert across_width(np.zeros_like(height), TEXEL, path, 40.0) is None
