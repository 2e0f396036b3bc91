"""The paint round a moving tip: sub-cell sweeps, faces open in part, the trail, the plough."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.ndimage import uniform_filter1d

from paintapp.canvas.model import Canvas
from paintapp.paint.cell_kernels import sweep_overlap
from paintapp.paint.exchange import CellSpace, cell_caps, plough_weights
from paintapp.paint.paint_scene import load_paint_scene
from paintapp.paint.trail import MIN_UPWIND_FLUID, lay_trail, paint_faces, vacated_share
from paintapp.session.comb import period_depths, scan_periods
from paintapp.session.painting import PaintingSession, paint_inventory
from solver.advection.scalars import transport
from solver.labels import FLUID, FREE, STATIC_SOLID
from tests.support.demo_strokes import StrokeSpec, stroke_samples

RED = "cadmium_red"
TEXEL = 2.5e-4


def test_a_tip_sweeps_only_the_paint_that_overlaps_it():
    q = np.array([0.8, 0.8, 1.2, 0.3]).reshape(1, 4, 1, 1) * np.array([1.0, 0.5]).reshape(
        2, 1, 1, 1
    )
    cap = np.array([0.5, 0.0, 1.0, 0.5]).reshape(4, 1, 1)  # part, inside, untouched, part
    before = q.copy()
    swept = np.zeros(2)
    sweep_overlap(q, cap, 1.0, 2.0, swept)
    totals = q.sum(axis=0)[:, 0, 0]
    np.testing.assert_allclose(totals, [0.5, 0.0, 1.8, 0.45])  # untouched keeps its excess
    kept = totals > 0.0
    np.testing.assert_allclose(q[0, kept] / q[1, kept], 2.0)  # pigments in proportion
    np.testing.assert_allclose(2.0 * (before.sum(axis=(1, 2, 3)) - q.sum(axis=(1, 2, 3))), swept)


def test_cell_caps_are_the_fluid_share_of_the_capacity():
    label = np.array([FLUID, 0, STATIC_SOLID, FLUID]).reshape(4, 1, 1)
    fluid = np.array([0.25, 0.0, 1.0, 1.0]).reshape(4, 1, 1)
    np.testing.assert_allclose(cell_caps(2.0, label, fluid)[:, 0, 0], [0.5, 0.0, 0.0, 2.0])
    np.testing.assert_allclose(cell_caps(2.0, label)[:, 0, 0], [2.0, 0.0, 0.0, 2.0])


def one_row(n: int) -> tuple[list[np.ndarray], list[np.ndarray], np.ndarray]:
    """Velocity (u = 1 m/s along x), face types and labels of an n x 1 x 1 row of fluid."""
    comps = [np.ones((n + 1, 1, 1)), np.zeros((n, 2, 1)), np.zeros((n, 1, 2))]
    types = [np.full(c.shape, FREE, dtype=np.int8) for c in comps]
    for t in types:
        t[0], t[-1] = 1, 1  # closed ends
    return comps, types, np.full((n, 1, 1), FLUID, dtype=np.int32)


def test_a_face_open_in_part_passes_that_part_of_the_flux():
    comps, types, label = one_row(4)
    frac = [np.ones(c.shape) for c in comps]
    frac[0][2] = 0.5  # the face between cells 1 and 2 is half covered
    fluid = np.ones(label.shape)
    vel, open_types = paint_faces(comps, types, label, frac, fluid)
    q = np.zeros((1, 4, 1, 1))
    q[0, 1] = 1.0
    transport(q, vel, open_types, 3, 1.0, 0.1)
    np.testing.assert_allclose(q[0, :, 0, 0], [0.0, 0.95, 0.05, 0.0])
    full = np.zeros((1, 4, 1, 1))
    full[0, 1] = 1.0
    transport(full, comps, types, 3, 1.0, 0.1)
    np.testing.assert_allclose(full[0, 2, 0, 0], 0.1)


def test_paint_enters_the_tip_and_never_a_static_solid():
    comps, types, label = one_row(5)
    label[3] = 0  # the tip
    label[4] = STATIC_SOLID
    frac = [np.ones(c.shape) for c in comps]
    frac[0][3] = 0.0  # the tip's trailing face is closed to the fluid ...
    vel, open_types = paint_faces(comps, types, label, frac, np.ones(label.shape))
    assert open_types[0][3] == FREE  # ... but open to the paint that follows the tip
    assert vel[0][3, 0, 0] == pytest.approx(1.0)  # at the face's own velocity
    assert open_types[0][4] != FREE  # a static solid takes nothing


def test_a_face_s_paint_flux_is_spread_over_its_upwind_cell_s_fluid_part():
    comps, types, label = one_row(5)
    comps[0][:, 0, 0] = [0.0, 1.0, -1.0, 1.0, -1.0, 0.0]
    label[4] = 0  # the tip
    fluid = np.array([1.0, 0.5, 0.25, 0.05, 1.0]).reshape(5, 1, 1)
    frac = [np.ones(c.shape) for c in comps]
    vel, open_types = paint_faces(comps, types, label, frac, fluid)
    # face 1 (flow +x): cell 0 upwind, all fluid; face 2 (-x): cell 2, a quarter; face 3 (+x):
    # cell 2 again; face 4 (-x): the tip's cell, taken as whole
    np.testing.assert_allclose(vel[0][1:5, 0, 0], [1.0, -1.0 / 0.25, 1.0 / 0.25, -1.0])
    assert [int(t) for t in open_types[0][:, 0, 0]] == [1, FREE, FREE, FREE, FREE, 1]
    fluid[2] = 0.01  # an all but covered cell counts as MIN_UPWIND_FLUID of fluid
    vel, _ = paint_faces(comps, types, label, frac, fluid)
    np.testing.assert_allclose(vel[0][2:4, 0, 0], [-1.0 / MIN_UPWIND_FLUID, 1.0 / MIN_UPWIND_FLUID])
    vel, _ = paint_faces(comps, types, label, frac, None)  # no fractions: no spreading
    np.testing.assert_allclose(vel[0][:, 0, 0], comps[0][:, 0, 0])


def test_the_trail_takes_what_piled_against_the_tip_where_the_tip_left_room():
    label = np.array([FLUID, FLUID, FLUID, 0]).reshape(4, 1, 1)
    before = np.array([FLUID, 0, 0, 0]).reshape(4, 1, 1)
    fluid_before = np.array([1.0, 0.5, 0.0, 0.0]).reshape(4, 1, 1)
    fluid = np.array([1.0, 1.0, 1.0, 0.0]).reshape(4, 1, 1)
    share = vacated_share(before, label, fluid_before, fluid)
    np.testing.assert_allclose(share[:, 0, 0], [0.0, 0.5, 1.0, 0.0])
    q = np.zeros((1, 4, 1, 1))
    q[0, :, 0, 0] = [0.2, 0.1, 0.0, 0.6]  # the tip's cell holds paint that followed it
    space = CellSpace(1.0, cell_caps(1.0, label, fluid), 0, 1.0)
    moved = lay_trail(q, label, share, space)
    assert moved == pytest.approx(0.6)
    # Room x share: 0.9 x 0.5 and 1.0 x 1.0; the 0.6 goes in that proportion.
    np.testing.assert_allclose(q[0, :, 0, 0], [0.2, 0.1 + 0.6 * 0.45 / 1.45, 0.6 / 1.45, 0.0])
    # Voxelized tips: every cell a tip's voxel left, in full.
    np.testing.assert_allclose(vacated_share(before, label)[:, 0, 0], [0, 1, 1, 0])


def test_the_plough_pushes_ahead_and_aside_not_into_the_trail():
    w = plough_weights((9, 9), np.array([4.5, 4.5]), np.array([1.0, 0.0]))
    assert w[8, 4] == pytest.approx(1.0)  # straight ahead
    assert w[4, 8] == pytest.approx(0.5)  # aside
    assert w[0, 4] == pytest.approx(0.0)  # behind
    assert w.min() >= 0.0 and w.max() <= 1.0
    np.testing.assert_array_equal(plough_weights((5, 5), np.array([2.5, 2.5]), np.zeros(2)), 1.0)
    slow = plough_weights((9, 9), np.array([4.5, 4.5]), np.array([0.25, 0.0]))
    assert slow[0, 4] == pytest.approx(1.0 / 3.0)  # half of PLOUGH_TRAVEL_CELLS: a = 0.5


def scrape(
    travel_cells: float | None = None,
    substeps: int | None = None,
    sweep: bool = True,
    margin_cells: int | None = None,
    follow: str = "cells",
) -> np.ndarray:
    """Drag the square probe (one texel per cell) at 0.076 m/s through 0.5 mm of wet red: 5 cells
    of travel per 60 Hz sample. Returns the paint height along the trail's centre line."""
    scene = dataclasses.replace(load_paint_scene("default"), sweep=sweep, follow=follow)
    if margin_cells is not None:
        scene = dataclasses.replace(scene, margin_cells=margin_cells)
    if travel_cells is not None:
        scene = dataclasses.replace(
            scene, max_travel_cells=travel_cells, max_travel_substeps=substeps
        )
    layer = np.zeros((1, 160, 240), np.float32)
    layer[0, 20:140, 10:230] = 5e-4
    wet = (layer[0] > 0).astype(np.float32)
    canvas = Canvas((240, 160), (240 * TEXEL, 160 * TEXEL), (RED,), layer, wet)
    session = PaintingSession(canvas, "square_probe", scene)
    for sample in stroke_samples(StrokeSpec((0.01, 0.02), (0.05, 0.02), 0.04 / 0.076, 1.0), 0.0):
        session.sample(sample)
    return canvas.height_m[80, 80:160].astype(float)


def comb(profile: np.ndarray) -> tuple[float, float]:
    """(roughness, comb): the profile's RMS about its 21-texel running mean, and the peak-to-peak
    of its mean over the 5-texel sample period, both over its mean."""
    trend = uniform_filter1d(profile, 21, mode="nearest")
    rough = float(np.sqrt(np.mean((profile - trend) ** 2)) / profile.mean())
    fold = profile[: len(profile) // 5 * 5].reshape(-1, 5).mean(axis=0)
    return rough, float(np.ptp(fold) / profile.mean())


def test_a_fast_rigid_tip_leaves_a_trail_without_a_comb():
    """The probe's surface comes back to the same place in a cell once per sample: a voxelized,
    closed tip printed that as a row of teeth (measured: roughness 0.24, comb 0.24). Measured
    now: roughness 0.082 and comb 0.116 with the grid re-centred every step and pushed paint
    laid by distance (the defaults; 0.081 and 0.109 by rings), 0.171 and 0.112 with the old
    margin of 10 cells (by rings)."""
    rough, teeth = comb(scrape())
    assert teeth < 0.15
    assert rough < 0.12


def test_a_grid_asked_to_follow_continuously_follows_by_cells_where_a_cell_is_one_texel():
    """With one texel a cell nothing lays a step's change along the path, and a window whose
    corner lies between texels combed this trail at its sample period (measured: 0.31)."""
    rough, teeth = comb(scrape(follow="continuous"))
    assert teeth < 0.15
    assert rough < 0.12


@pytest.mark.slow
def test_a_third_of_a_cell_of_travel_per_step_smooths_the_trail_further():
    """Sub-steps of a third of a cell: roughness 0.040, comb 0.077 (measured, grid re-centred
    only near its sides, so that the sub-steps alone are tested). With the default margin the
    grid shifts one cell every 3.2 sub-steps, the same sub-steps of every sample, so its slip
    walls' distance from the tip is a one-cell sawtooth at the sample period: roughness 0.038,
    comb 0.118, about the default travel's 0.109 (measured)."""
    rough, teeth = comb(scrape(5.0 / 16.0, 16, margin_cells=10))
    assert teeth < 0.1
    assert rough < 0.06


def scrape_fine(
    sweep: bool, margin_cells: int | None = None, follow: str | None = None
) -> tuple[Canvas, PaintingSession]:
    """The probe dragged at 0.076 m/s through 0.5 mm of wet red on 0.1 mm texels (two texels per
    cell): 12.7 texels of travel per 60 Hz sample."""
    scene = dataclasses.replace(load_paint_scene("default"), sweep=sweep)
    if margin_cells is not None:
        scene = dataclasses.replace(scene, margin_cells=margin_cells)
    if follow is not None:
        scene = dataclasses.replace(scene, follow=follow)
    layer = np.zeros((1, 200, 560), np.float32)
    layer[0, 30:170, 20:540] = 5e-4
    wet = (layer[0] > 0).astype(np.float32)
    canvas = Canvas((560, 200), (0.056, 0.02), (RED,), layer, wet)
    session = PaintingSession(canvas, "square_probe", scene)
    for sample in stroke_samples(StrokeSpec((0.006, 0.01), (0.05, 0.01), 0.044 / 0.076, 1.0), 0.0):
        session.sample(sample)
    return canvas, session


def teeth_at_the_sample_period(canvas: Canvas) -> float:
    """Peak-to-peak, over its mean, of the trail's centre-line height averaged by its phase in
    the sample period (eight phase bins over texels 250-450)."""
    profile = canvas.height_m[100, 250:450].astype(float)
    period = 0.076 / 60.0 / 1e-4  # texels per sample
    phase = ((np.arange(250, 450) + 0.5 - 60.0) / period) % 1.0
    bins = np.floor(phase * 8).astype(int)
    fold = np.array([profile[bins == b].mean() for b in range(8)])
    return float(np.ptp(fold) / profile.mean())


def test_a_step_laid_along_the_path_the_tip_swept_leaves_no_comb():
    """Measured: teeth 0.256 with the change laid at each step's end pose, 0.053 swept (0.101
    when the sweep took the mean of the fractions each texel on the path lost, times the texel's
    own paint: not linear in the change, it left part of each step's teeth)."""
    before = None
    teeth = {}
    for sweep in (False, True):
        canvas, session = scrape_fine(sweep)
        teeth[sweep] = teeth_at_the_sample_period(canvas)
        assert session.model.window.k == 2
        inventory = paint_inventory(canvas, session.reservoir)[RED]
        before = inventory if before is None else before
        np.testing.assert_allclose(inventory, before, rtol=1e-5)  # the same paint either way
        assert canvas.paint_m.min() >= 0.0
    assert teeth[True] < 0.1 < 0.15 < teeth[False]


def test_a_grid_that_re_centres_on_the_tip_every_step_prints_no_teeth_at_its_shifts():
    """The paint grid's sides are slip walls; a grid that re-centres only once the tip nears a
    side (the old margin, 10 of 32 cells) lets the tip's leading face close in on the wall ahead
    between shifts, and the bow wave it pushes, and so the trail, repeats with the shifts (every
    7-9 cells: 22 texels here, measured depth 0.77 against its floor 0.31; 1.06 against 0.39
    before the write-back's sweep took each texel's loss whole along the path). Re-centred every
    step, the wall stays where it was: the deepest fold of the trail at any period up to two
    samples' travel is 0.28 (floor 0.12; 0.24 and 0.13 before)."""
    path = np.array([[0.006 + 0.044 * s, 0.01] for s in np.linspace(0.1, 0.9, 30)])
    periods = scan_periods(12.7)
    periods = periods[periods < 26.0]  # up to two samples' travel: six chunks of the path or more
    worst = {}
    for margin in (10, None):
        canvas, session = scrape_fine(True, margin, follow="cells")
        height = canvas.height_m.astype(float)
        found = period_depths(height, 1e-4, path, periods)
        worst[margin] = max(found, key=lambda d: d.depth)
    assert session.model.margin_cells == 15  # a scene's default: every step
    assert 15.0 < worst[10].period_texels < 26.0 and worst[10].depth > 0.6
    assert worst[None].depth < 0.35 and worst[None].depth < 0.5 * worst[10].depth


@pytest.mark.parametrize("brush", ["round_small", "square_probe"])
def test_a_glaze_through_wet_paint_leaves_no_lines_along_the_window_s_edges(brush):
    """The depth-averaged grid's sides were open, with a one-column halo of canvas taking and
    giving the paint that crossed them; fluid drawn in behind the tip drained the halo, which
    was left behind as a thin line along each edge of the window (measured: 90 µm of 100 with
    the small round brush, 2 µm with the probe). With free-slip sides the layer beyond the
    stroke's reach keeps its thickness, and the paint is conserved."""
    scene = load_paint_scene("thin_glaze")
    layer = np.zeros((1, 200, 560), np.float32)
    layer[0, 10:190, 20:540] = 1e-4
    wet = (layer[0] > 0).astype(np.float32)
    canvas = Canvas((560, 200), (0.056, 0.02), (RED,), layer, wet)
    session = PaintingSession(canvas, brush, scene)
    before = paint_inventory(canvas, session.reservoir)[RED]
    for sample in stroke_samples(StrokeSpec((0.006, 0.01), (0.05, 0.01), 0.044 / 0.076, 1.0), 0.0):
        session.sample(sample)
    assert session.model.margin_cells == 23  # re-centred every step
    across = canvas.height_m[:, 250:450].astype(float).mean(axis=1)  # the track along row 100
    beyond = np.r_[15:60, 141:185]  # 4-8.5 mm from the track: past its ridges, inside the layer
    np.testing.assert_allclose(across[beyond], 1e-4, rtol=0.02)
    after = paint_inventory(canvas, session.reservoir)[RED]
    np.testing.assert_allclose(after, before, rtol=1e-6)
