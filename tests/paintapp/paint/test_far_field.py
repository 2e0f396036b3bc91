"""Open sides for the 3D paint grid: paint through the sides, traded with a band of canvas."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from common.errors import InputError
from paintapp.figures import sides
from paintapp.paint.far_field import band_change, band_weights, padded_transport
from paintapp.paint.paint_scene import parse_paint_scene
from solver.advection.scalars import transport
from solver.labels import BOUNDARY, FREE


def random_faces(rng: np.random.Generator, nx: int, ny: int, nz: int):
    """Interior paint faces with random velocities (every side face closed, as
    :func:`paintapp.paint.trail.paint_faces` leaves them) and random open side faces."""
    vel, types = [], []
    for axis, shape in enumerate(((nx + 1, ny, nz), (nx, ny + 1, nz), (nx, ny, nz + 1))):
        v = rng.normal(0.0, 0.01, shape)
        t = np.full(shape, FREE, dtype=np.int8)
        index = [slice(None)] * 3
        for end in (0, shape[axis] - 1):
            index[axis] = end
            t[tuple(index)] = BOUNDARY
        vel.append(v)
        types.append(t)
    side_vel = [rng.normal(0.0, 0.01, (2, ny, nz)), rng.normal(0.0, 0.01, (2, nx, nz))]
    side_open = [rng.random((2, ny, nz)) < 0.8, rng.random((2, nx, nz)) < 0.8]
    return vel, types, side_vel, side_open


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31 - 1))
def test_paint_through_open_sides_is_conserved_with_the_ghosts(seed):
    rng = np.random.default_rng(seed)
    nx, ny, nz, h = 6, 5, 4, 2e-4
    q = rng.random((2, nx, ny, nz)) * 0.5
    ring = rng.random((2, nx + 2, ny + 2)) * 5e-4
    vel, types, side_vel, side_open = random_faces(rng, nx, ny, nz)
    total = q.sum(axis=(1, 2, 3)) * h
    steps, gains = padded_transport(q, vel, types, side_vel, side_open, ring, h, 0.05)
    assert steps >= 1
    assert q.min() >= 0.0
    np.testing.assert_allclose(q.sum(axis=(1, 2, 3)) * h + gains.sum(axis=(1, 2, 3)), total,
                               rtol=1e-12)  # fmt: skip
    # a closed side trades nothing
    assert np.all(gains[:, 0, :, :ny][:, ~side_open[0].any(axis=2)] == 0.0)
    # no ghost can give more than the canvas column beyond it holds
    assert np.all(-gains[:, 0, 0, :ny] <= ring[:, 0, 1:-1] + 1e-15)


def test_closed_sides_transport_as_the_grid_alone():
    rng = np.random.default_rng(3)
    nx, ny, nz, h = 6, 5, 4, 2e-4
    q = rng.random((1, nx, ny, nz)) * 0.5
    vel, types, side_vel, _ = random_faces(rng, nx, ny, nz)
    shut = [np.zeros((2, ny, nz), bool), np.zeros((2, nx, nz), bool)]
    alone = q.copy()
    transport(alone, vel, types, 3, h, 0.05)
    _, gains = padded_transport(q, vel, types, side_vel, shut, np.ones((1, nx + 2, ny + 2)), h,
                                0.05)  # fmt: skip
    np.testing.assert_allclose(q, alone, rtol=0, atol=1e-15)
    assert not gains.any()


def test_the_band_lays_gains_and_takes_losses_without_emptying_a_column():
    depth, nx, ny = 4, 6, 5
    rng = np.random.default_rng(7)
    outer = rng.random((2, nx + 2 * depth, ny + 2 * depth)) * 1e-4
    outer[:, :, -1] = 0.0  # a bare strip beyond the y_max side
    on_canvas = np.ones(outer.shape[1:], bool)
    on_canvas[-2:, :] = False  # the canvas ends inside the x_max band
    gains = np.zeros((2, 2, 2, max(nx, ny)))
    gains[:, 0, 0, :ny] = rng.normal(0.0, 3e-5, (2, ny))
    gains[:, 0, 1, :ny] = rng.random((2, ny)) * 1e-4
    gains[:, 1, 0, :nx] = -outer[:, depth : depth + nx, depth - 1]  # all the first column holds
    gains[:, 1, 1, :nx] = -rng.random((2, nx)) * 1e-5
    change = band_change(gains, outer, on_canvas, depth)
    np.testing.assert_allclose(change.sum(axis=(1, 2)), gains.sum(axis=(1, 2, 3)), rtol=1e-12)
    assert (outer + change).min() >= -1e-18
    assert not change[:, depth : depth + nx, depth : depth + ny].any()  # the grid's own columns
    assert not change[:, -2:, :].any()  # off the canvas
    assert np.all(change[:, :, -1] >= 0.0)  # nothing taken from bare columns
    w = band_weights(depth)
    assert w.sum() == pytest.approx(1.0) and np.all(np.diff(w) < 0.0)


def test_open_sides_bring_the_force_and_the_trail_s_shoulders_near_a_wide_grid_s():
    """Slip walls one brush width from a fast probe confine the flow (`paintapp figures sides`,
    measured: drag 31 % high and no lift against a grid twice as wide; open sides 10 % and 7 %
    low) and make the force buzz as the walls' distance from the tip's faces steps between
    re-centrings (rms change from one sample to the next: drag 4.4 and lift 3.9 mN with slip
    walls, 1.2 and 1.4 open, 1.4 and 1.7 on the wide grid). Beside the stroke, the paint height
    across it beyond its ridges: rms off the wide grid's 10.5 um with slip walls, 8.2 open
    (measured with the share sweep of these two-texel cells; 12.0 and 8.0 with the amount sweep;
    41 and 20 before the write-back's sweep took each texel's loss whole along the path, which
    also settles the shoulders the slip walls' re-centring had combed)."""
    slip, following, open_, wide = (sides.drag(*case) for case in sides.CASES)
    assert open_.drift < 1e-8 and following.drift < 1e-8
    for axis in (0, 2):  # drag and lift
        near, far, ref = open_.mean_force()[axis], slip.mean_force()[axis], wide.mean_force()[axis]
        assert abs(near - ref) < 0.5 * abs(far - ref)
        assert open_.jitter()[axis] < 0.5 * slip.jitter()[axis]
    assert abs(open_.mean_force()[0] / wide.mean_force()[0] - 1.0) < 0.15

    def shoulders(result: sides.DragResult) -> np.ndarray:
        return np.r_[result.across_m[30:66], result.across_m[134:170]]

    rms = [float(np.sqrt(np.mean((shoulders(r) - shoulders(wide)) ** 2))) for r in (slip, open_)]
    assert max(rms) < 15e-6
    # The same slip walls, following the tip continuously: the walls' distance no longer steps,
    # and with it goes the buzz (measured: drag 1.2, lift 0.35 mN against 4.4 and 3.9 by whole
    # cells); the tip's place within its cell is then always the same, and the drag (56.1 mN,
    # 9 % over the wide grid's against 31 %) and the lift (-4.8 mN) are those of that place.
    for axis in (0, 2):
        assert following.jitter()[axis] < 0.5 * slip.jitter()[axis]
    ref = wide.mean_force()[0]
    assert abs(following.mean_force()[0] - ref) < abs(slip.mean_force()[0] - ref)


def test_open_sides_at_the_canvas_s_edge_keep_the_paint(monkeypatch):
    """Along the canvas's edge the grid's side and its band reach off the canvas: no paint
    crosses a side there, and none is laid or taken off the canvas."""
    monkeypatch.setattr(sides, "START_M", (0.006, 0.0035))
    monkeypatch.setattr(sides, "END_M", (0.05, 0.0035))
    result = sides.drag("edge", "open", 32, 2.0)
    assert result.drift < 1e-8
    assert np.isfinite(result.force_n).all()


def test_a_scene_s_sides_are_checked():
    base = {"fluid_model": "grid3d"}
    scene = parse_paint_scene({**base, "grid": {"sides": "open", "far_field_cells": 4}}, "s")
    assert (scene.sides, scene.far_field_cells) == ("open", 4)
    with pytest.raises(InputError, match="slip, open"):
        parse_paint_scene({**base, "grid": {"sides": "periodic"}}, "s")
    with pytest.raises(InputError, match="far_field_cells"):
        parse_paint_scene({**base, "grid": {"sides": "open", "far_field_cells": 0}}, "s")
    with pytest.raises(InputError, match="far_field_cells"):
        parse_paint_scene({**base, "grid": {"far_field_cells": 99}}, "s")
    with pytest.raises(InputError, match="only the 3D grid"):
        parse_paint_scene({"fluid_model": "depth_averaged", "grid": {"sides": "open"}}, "s")
    with pytest.raises(InputError, match="texel_flow"):
        parse_paint_scene({**base, "grid": {"sides": "open"}, "paint": {"texel_flow": True}}, "s")
