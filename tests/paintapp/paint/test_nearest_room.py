"""Pushed paint laid by distance from the tip (paintapp.paint.nearest_room)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from common.errors import InputError
from paintapp.canvas.model import Canvas
from paintapp.paint.cell_kernels import probe_rings, spread_into_rings
from paintapp.paint.exchange import CellSpace, place_pushed
from paintapp.paint.nearest_room import FILL_WIDTH, LEVEL_TOLERANCE, fill_nearest, tip_distance
from paintapp.paint.paint_scene import load_paint_scene, parse_paint_scene
from paintapp.session.comb import period_depths
from paintapp.session.painting import PaintingSession, paint_inventory
from solver.cutcell.geometry import FAR
from solver.labels import FLUID, STATIC_SOLID
from tests.support.demo_strokes import StrokeSpec, stroke_samples

RED = "cadmium_red"


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 10_000), share=st.floats(0.01, 3.0))
def test_the_fill_keeps_the_paint_and_each_cell_s_room(seed, share):
    rng = np.random.default_rng(seed)
    shape = (2, 5, 4, 6)
    cap = rng.uniform(0.0, 1.0, shape[1:])
    q = rng.uniform(0.0, 1.0, shape) * cap / 2.0
    q[:, 0, 0, 0] = 0.9  # a cell over its capacity: it takes nothing, and keeps what it has
    distance = rng.uniform(-0.5, 6.0, shape[1:])
    distance[rng.uniform(size=shape[1:]) < 0.2] = np.nan  # unknown: takes nothing here
    weight = rng.uniform(0.0, 1.0, shape[1:3])
    weight[0, 1] = 0.0
    k_max = 4
    unit = 2.0
    room = weight[:, :, None] * np.clip(cap - q.sum(axis=0), 0.0, None)
    open_room = np.where(np.isfinite(distance), room, 0.0)[:, :, : k_max + 1].sum() * unit
    volume = share * open_room * np.array([0.25, 0.75])
    before, given_m3 = q.copy(), volume.copy()
    fill_nearest(q, distance, cap, weight, k_max, unit, volume, FILL_WIDTH)
    added = q - before
    assert added.min() >= 0.0
    np.testing.assert_allclose(added.sum(axis=(1, 2, 3)) * unit + volume, given_m3, rtol=1e-12)
    if added.sum() > 0.0:
        np.testing.assert_allclose(added[0].sum() / added.sum(), 0.25, rtol=1e-9)  # proportion
    assert (added.sum(axis=0) <= room + 1e-12).all()  # never past a cell's free room
    untouched = ~np.isfinite(distance)
    untouched[:, :, k_max + 1 :] = True
    untouched[0, 1, :] = True
    assert not added.sum(axis=0)[untouched].any()
    if share < 1.0:  # it all fits: nothing left over
        assert volume.sum() <= 1e-12 * given_m3.sum()


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 10_000), share=st.floats(0.05, 0.9))
def test_the_room_nearest_the_tip_fills_first(seed, share):
    rng = np.random.default_rng(seed)
    cap = np.ones((6, 5, 4))
    q = np.zeros((1, 6, 5, 4))
    distance = rng.uniform(-0.5, 8.0, cap.shape)
    volume = np.array([share * cap.sum()])
    fill_nearest(q, distance, cap, np.ones((6, 5)), 3, 1.0, volume, FILL_WIDTH)
    got = q[0].reshape(-1)
    d = distance.reshape(-1)
    reached = d[got > 0.0].max()
    # every cell a whole edge width nearer than the farthest cell reached is full, to the
    # level's bisection: it stops within LEVEL_TOLERANCE cells, at most that share of each of
    # the cells' room too many, which the last scaling takes from every cell alike
    slack = cap.size * LEVEL_TOLERANCE / FILL_WIDTH / (share * cap.sum())
    assert (got[d < reached - FILL_WIDTH] > 1.0 - 2.0 * slack).all()


def centroid_beside_a_face(place: str, face: float) -> float:
    """Centre (cells) of 0.6 cells of paint pushed into a row of 12 cells beside a tip face at
    ``face`` (cells; the tip fills ``x < face``): by distance, or by rings of cells (a cell is
    the tip's once its centre is inside)."""
    centres = np.arange(12) + 0.5
    cap = np.clip(centres + 0.5 - face, 0.0, 1.0).reshape(12, 1, 1)  # the cut leaves this room
    q = np.zeros((1, 12, 1, 1))
    volume = np.array([0.6])
    if place == "distance":
        fill_nearest(q, (centres - face).reshape(12, 1, 1), cap, np.ones((12, 1)), 0, 1.0,
                     volume, FILL_WIDTH)  # fmt: skip
    else:
        label = np.where(centres < face, 0, FLUID).astype(np.int32).reshape(12, 1, 1)
        dist = np.empty(label.shape, dtype=np.int32)
        probe_rings(label, 8, dist)
        spread_into_rings(q, dist, 1, 8, 0, cap, np.ones((12, 1)), 1.0, volume)
    return float((q[0, :, 0, 0] * centres).sum() / q.sum())


def test_paint_pushed_by_distance_follows_the_tip_s_face_through_the_cells():
    """A face moving through the cells by hundredths of a cell: the pushed paint's centre moves
    with it, never by more than the step; by rings it stands still, then jumps by most of a
    cell as the face passes a cell centre."""
    faces = np.linspace(2.0, 5.0, 301)
    for place, smooth in (("distance", True), ("rings", False)):
        centre = np.array([centroid_beside_a_face(place, f) for f in faces])
        jumps = np.abs(np.diff(centre))
        if smooth:
            assert jumps.max() < 0.05
            np.testing.assert_allclose(centre - faces, (centre - faces).mean(), atol=0.25)
        else:
            assert jumps.max() > 0.5


def test_what_finds_no_room_by_distance_goes_to_the_rings():
    """Cells beyond the cut geometry's window have no distance; the rings place the rest, and
    every pigment's paint is kept."""
    label = np.full((8, 8, 4), FLUID, dtype=np.int32)
    label[3:5, 3:5, :2] = 0  # the tip
    cap = np.where(label == FLUID, 1.0, 0.0)
    q = np.zeros((2, 8, 8, 4))
    phi = np.full((8, 8, 4), FAR)
    phi[2:6, 2:6, :3] = 1e-4  # known only round the tip, one cell of 1e-4 m away
    space = CellSpace(1.0, cap, 1, 1.0, tip_distance(phi, 1e-4))
    assert np.isnan(space.distance[0, 0, 0]) and space.distance[2, 2, 0] == pytest.approx(1.0)
    volume = np.array([40.0, 20.0])  # more than the 40 cells of known room hold
    kept = place_pushed(q, label, space, volume.copy())
    assert kept == 0.0
    np.testing.assert_allclose(q.sum(axis=(1, 2, 3)), volume)
    near = np.isfinite(space.distance) & (cap > 0)
    assert q.sum(axis=0)[near].min() > 1.0 - 1e-9  # the known room filled first, to the brim
    assert q.sum(axis=0).max() <= 1.0 + 1e-12


def diagonal_drag(
    push: str, follow: str = "cells", transport: str = "fct"
) -> tuple[np.ndarray, np.ndarray]:
    """The square probe dragged at 0.076 m/s and a slope of 1/7.5 through 0.5 mm of wet red on
    0.1 mm texels (on a grid re-centred by whole cells, it drifts 0.42 of its 0.2 mm cells
    sideways a sub-step); the paint height and the in-contact samples' positions over the
    middle of the drag (m). ``transport``: the scene's paint transport."""
    scene = dataclasses.replace(
        load_paint_scene("default"), push=push, follow=follow, transport=transport
    )
    layer = np.zeros((1, 240, 560), np.float32)
    layer[0, 20:220, 20:540] = 5e-4
    canvas = Canvas((560, 240), (0.056, 0.024), (RED,), layer, (layer[0] > 0).astype(np.float32))
    session = PaintingSession(canvas, "square_probe", scene)
    before = paint_inventory(canvas, session.reservoir)[RED]
    x0, x1, slope = 0.006, 0.05, 1.0 / 7.5
    y0 = 0.012 - 0.5 * slope * (x1 - x0)
    length = np.hypot(x1 - x0, slope * (x1 - x0))
    spec = StrokeSpec((x0, y0), (x1, y0 + slope * (x1 - x0)), length / 0.076, 1.0)
    points = []
    for sample in stroke_samples(spec, 0.0):
        session.sample(sample)
        if sample.pressure > 0.0 and 0.015 < sample.position_m[0] < 0.045:
            points.append(sample.position_m[:2])
    after = paint_inventory(canvas, session.reservoir)[RED]
    assert after == pytest.approx(before, rel=1e-5) and canvas.paint_m.min() >= 0.0
    return canvas.height_m.astype(float), np.array(points)


@pytest.mark.slow
def test_a_drifting_tip_s_trail_carries_no_teeth_at_its_faces_beat_when_pushed_by_distance():
    """The probe's faces pass a cell centre every 2.4 sub-steps (15.2 texels of travel): by
    rings, the paint it pushes jumps out a cell each time, and with the upwind transport its
    trail carries teeth at that period (the comb measure's three lines along the track, depth
    well over its floor); by distance it does not, and with the default (flux-corrected)
    transport, which keeps the pushed ridges from smearing, its depth stays under the floor and
    well under the rings'. On a grid re-centred by whole cells (the default): one that follows
    the tip continuously keeps its faces where they are in the cells, and neither rule prints
    these teeth."""
    found = {}
    for push, transport in (("rings", "upwind"), ("rings", "fct"), ("distance", "fct")):
        height, points = diagonal_drag(push, transport=transport)
        (fold,) = period_depths(height, 1e-4, points, np.array([15.2]))
        found[push, transport] = fold
    assert found["rings", "upwind"].depth > 1.4 * found["rings", "upwind"].floor
    by_distance = found["distance", "fct"]
    assert by_distance.depth < by_distance.floor
    assert by_distance.depth < 0.75 * found["rings", "fct"].depth


def test_a_scene_s_push_is_checked():
    scene = parse_paint_scene({"fluid_model": "grid3d", "brush": {"push": "rings"}}, "s")
    assert scene.push == "rings" and load_paint_scene("default").push == "distance"
    with pytest.raises(InputError, match="distance, rings"):
        parse_paint_scene({"brush": {"push": "nearest"}}, "s")


def _rings_by_layers(label: np.ndarray, max_ring: int) -> np.ndarray:
    """The rings as layers: each ring the fluid cells next to the last ring's, not yet taken."""
    dist = np.where(label >= 0, 0, -1)
    for r in range(1, max_ring + 1):
        last = dist == r - 1
        near = np.zeros_like(last)
        for axis in range(3):
            for s in (1, -1):
                moved = np.roll(last, s, axis=axis)
                edge = [slice(None)] * 3
                edge[axis] = 0 if s == 1 else -1
                moved[tuple(edge)] = False  # no wrapping round the grid
                near |= moved
        dist[near & (dist == -1) & (label == FLUID)] = r
    return dist


def test_the_rings_are_the_graph_distance_through_fluid_cells():
    """Random probes, fluid and static solids (which the rings go round, not through), grids
    thin along any axis: each cell's ring is its layer by layer distance from the probe."""
    rng = np.random.default_rng(5)
    for trial in range(60):
        shape = tuple(int(n) for n in rng.integers(1, 9, size=3))
        label = rng.choice([FLUID, FLUID, FLUID, FLUID, STATIC_SOLID, 0, 1], size=shape)
        label = label.astype(np.int32)
        max_ring = int(rng.integers(1, 9))
        dist = np.empty(shape, dtype=np.int32)
        probe_rings(label, max_ring, dist)
        np.testing.assert_array_equal(dist, _rings_by_layers(label, max_ring),
                                      err_msg=f"trial {trial}")  # fmt: skip
