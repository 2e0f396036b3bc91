"""Stylus samples to tip poses: pressure, tilt, twist, rigid canvas, velocities."""

from __future__ import annotations

import math

import numpy as np
import pytest

from brushes.pose import TipTracker, place_tip
from brushes.presets import BrushPreset, PressureResponse, TiltResponse
from brushes.stylus import StylusSample
from common.errors import InputError
from common.tilt import quat_to_matrix

MM = 1e-3


def make_preset(shape="round", stiffness=0.5, spread=1.0, exponent=1.0, tilt=None):
    size = (
        {"tip_radius_m": 0.5 * MM, "belly_radius_m": 2 * MM, "length_m": 12 * MM}
        if shape == "round"
        else {"width_m": 10 * MM, "thickness_m": 2 * MM, "length_m": 15 * MM, "corner_radius_m": 0}
    )
    return BrushPreset(
        name="test",
        shape=shape,
        size_m=size,
        stiffness=stiffness,
        capacity_m3=1e-8,
        pressure=PressureResponse(depth_m=2 * MM, exponent=exponent, spread=spread),
        tilt=tilt or TiltResponse(gain=1.0, max_rad=1.2, twist_gain=1.0),
    )


def sample(t=0.0, pos=(0.05, 0.05, 0.0), pressure=0.0, tilt=(0.0, 0.0), twist=0.0):
    return StylusSample(t, np.array(pos), pressure, np.array(tilt), twist, 0)


def test_tablet_pressure_sets_press_depth_below_paint_surface():
    preset = make_preset(exponent=2.0)
    surface = 3 * MM  # thick paint: the tip never reaches the canvas
    hover = place_tip(sample(pressure=0.0), preset, "tablet", surface)
    assert hover.position_m[2] == pytest.approx(surface)
    assert not hover.in_contact and hover.press_depth_m == 0.0 and hover.splay == 1.0
    half = place_tip(sample(pressure=0.5), preset, "tablet", surface)
    depth = 2 * MM * 0.5**2
    assert half.in_contact
    assert half.position_m[2] == pytest.approx(surface - depth)
    assert half.press_depth_m == pytest.approx(depth)
    assert half.pressure == pytest.approx(0.5)
    assert np.allclose(half.position_m[:2], [0.05, 0.05])


def test_haptic_depth_gives_the_same_pose_as_tablet_pressure():
    preset = make_preset(exponent=1.5)
    surface = 1 * MM
    for p in (0.1, 0.4, 0.8, 1.0):
        tilt, twist = (0.3, -0.2), 0.7
        tablet = place_tip(sample(pressure=p, tilt=tilt, twist=twist), preset, "tablet", surface)
        z = surface - preset.pressure.depth_for(p)
        haptic = place_tip(
            sample(pos=(0.05, 0.05, z), tilt=tilt, twist=twist), preset, "haptic", surface
        )
        assert np.allclose(tablet.position_m, haptic.position_m, atol=1e-15)
        assert np.allclose(tablet.orientation, haptic.orientation)
        for field in ("press_depth_m", "pressure", "splay", "compression_m"):
            assert getattr(tablet, field) == pytest.approx(getattr(haptic, field)), field
        assert tablet.in_contact and haptic.in_contact


def test_rigid_canvas_stops_the_tip_and_splays_it():
    preset = make_preset(stiffness=0.25, spread=1.0)
    surface = 0.5 * MM  # thin paint: full pressure would go 1.5 mm into the canvas
    pose = place_tip(sample(pressure=1.0), preset, "tablet", surface)
    assert pose.position_m[2] == pytest.approx(0.0, abs=1e-15)
    assert pose.compression_m == pytest.approx(1.5 * MM)
    assert pose.press_depth_m == pytest.approx(surface)
    assert pose.splay == pytest.approx(1.0 + 1.0 * (1 - 0.25))
    rigid = place_tip(sample(pressure=1.0), make_preset(stiffness=1.0), "tablet", surface)
    assert rigid.splay == 1.0
    above = place_tip(sample(pos=(0.0, 0.0, 4 * MM)), preset, "haptic", surface)
    assert not above.in_contact and above.press_depth_m == 0.0
    assert above.position_m[2] == pytest.approx(4 * MM)


def test_tilt_leans_the_axis_toward_the_handle():
    preset = make_preset()
    pose = place_tip(sample(pressure=0.5, tilt=(0.4, 0.0)), preset, "tablet", 1 * MM)
    assert np.allclose(pose.axis, [math.sin(0.4), 0.0, math.cos(0.4)])
    pose = place_tip(sample(pressure=0.5, tilt=(0.0, -0.3)), preset, "tablet", 1 * MM)
    assert np.allclose(pose.axis, [0.0, -math.sin(0.3), math.cos(0.3)])
    half_gain = make_preset(tilt=TiltResponse(gain=0.5, max_rad=0.25, twist_gain=0.0))
    small = place_tip(sample(tilt=(0.3, 0.0)), half_gain, "tablet", 1 * MM)
    assert math.acos(small.axis[2]) == pytest.approx(0.15)
    clamped = place_tip(sample(tilt=(1.2, 0.0)), half_gain, "tablet", 1 * MM)
    assert math.acos(clamped.axis[2]) == pytest.approx(0.25)


def test_twist_turns_the_tip_about_its_axis():
    pose = place_tip(sample(twist=0.6), make_preset(shape="flat"), "tablet", 1 * MM)
    assert np.allclose(pose.rotation[:, 0], [math.cos(0.6), math.sin(0.6), 0.0])
    assert np.allclose(pose.axis, [0.0, 0.0, 1.0])


def test_tilted_flat_brush_never_goes_below_the_canvas():
    preset = make_preset(shape="flat", spread=0.5)
    for tilt in [(0.9, 0.0), (0.5, -0.7), (0.0, 1.1)]:
        pose = place_tip(sample(pressure=1.0, tilt=tilt, twist=0.4), preset, "tablet", 0.2 * MM)
        shape = preset.tip(pose.splay)
        axis = np.linspace(-20 * MM, 20 * MM, 81)
        grid = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)
        body_inside = grid[shape.sdf(grid) <= 0.0]
        world_z = body_inside @ quat_to_matrix(pose.orientation).T[:, 2] + pose.position_m[2]
        assert world_z.min() >= -1e-12
        assert world_z.min() <= 0.5 * MM  # and it does rest on it (within the sampling)


def test_tracker_finite_difference_velocities():
    tracker = TipTracker(make_preset(), "tablet")
    first = tracker.update(sample(t=0.0, pos=(0.0, 0.0, 0.0), pressure=0.5, twist=0.0), 1 * MM)
    assert np.all(first.velocity_m_s == 0.0) and np.all(first.angular_velocity_rad_s == 0.0)
    dt, speed, spin = 0.005, 0.2, 3.0
    for k in range(1, 5):
        pose = tracker.update(
            sample(t=k * dt, pos=(speed * k * dt, 0.0, 0.0), pressure=0.5, twist=spin * k * dt),
            1 * MM,
        )
        assert np.allclose(pose.velocity_m_s, [speed, 0.0, 0.0])
        assert np.allclose(pose.angular_velocity_rad_s, [0.0, 0.0, spin])
    assert tracker.jumps == 0


def test_tracker_pressure_change_moves_tip_vertically():
    tracker = TipTracker(make_preset(), "tablet")
    tracker.update(sample(t=0.0, pressure=0.0), 2 * MM)
    pose = tracker.update(sample(t=0.01, pressure=0.5), 2 * MM)
    assert pose.velocity_m_s[2] == pytest.approx(-1 * MM / 0.01)


def test_tracker_repeated_and_backward_timestamps():
    tracker = TipTracker(make_preset(), "haptic")
    tracker.update(sample(t=1.0, pos=(0.0, 0.0, 0.001)))
    moving = tracker.update(sample(t=1.01, pos=(0.001, 0.0, 0.001)))
    assert moving.velocity_m_s[0] == pytest.approx(0.1)
    repeated = tracker.update(sample(t=1.01, pos=(0.0015, 0.0, 0.001)))
    assert np.all(np.isfinite(repeated.velocity_m_s))
    assert np.allclose(repeated.velocity_m_s, moving.velocity_m_s)
    assert np.allclose(repeated.position_m[0], 0.0015)
    later = tracker.update(sample(t=1.02, pos=(0.0025, 0.0, 0.001)))
    assert later.velocity_m_s[0] == pytest.approx(0.1)
    backwards = tracker.update(sample(t=0.5, pos=(0.0025, 0.0, 0.001)))
    assert np.all(backwards.velocity_m_s == 0.0)


def test_tracker_clamps_jumps():
    tracker = TipTracker(make_preset(), "tablet", max_speed_m_s=1.5)
    tracker.update(sample(t=0.0, pos=(0.0, 0.0, 0.0), pressure=0.3))
    pose = tracker.update(sample(t=0.001, pos=(0.08, 0.06, 0.0), pressure=0.3))
    assert np.linalg.norm(pose.velocity_m_s) == pytest.approx(1.5)
    assert np.allclose(pose.velocity_m_s / 1.5, [0.8, 0.6, 0.0])
    assert tracker.jumps == 1


def test_tracker_smoothing_low_passes_a_velocity_step():
    raw, smooth = TipTracker(make_preset()), TipTracker(make_preset(), smoothing_s=0.02)
    for tracker in (raw, smooth):
        tracker.update(sample(t=0.0, pos=(0.0, 0.0, 0.0)))
        tracker.update(sample(t=0.01, pos=(0.001, 0.0, 0.0)))
    assert raw.last.velocity_m_s[0] == pytest.approx(0.1)
    assert smooth.last.velocity_m_s[0] == pytest.approx(0.1 * 0.01 / 0.03)


def test_switching_preset_midway():
    tracker = TipTracker(make_preset(spread=0.0), "tablet")
    a = tracker.update(sample(t=0.0, pressure=1.0), 0.0)
    tracker.preset = make_preset(stiffness=0.0, spread=2.0)
    b = tracker.update(sample(t=0.01, pressure=1.0), 0.0)
    assert a.splay == 1.0 and b.splay == pytest.approx(3.0)


def test_bad_arguments():
    with pytest.raises(ValueError):
        place_tip(sample(), make_preset(), "joystick")  # type: ignore[arg-type]
    with pytest.raises(ValueError):
        place_tip(sample(), make_preset(), "tablet", surface_z_m=-1.0)
    with pytest.raises(InputError) as err:
        StylusSample(0.0, np.array([0.0, np.nan, 0.0]), 0.5)
    assert err.value.key == "position_m"
    with pytest.raises(InputError) as err:
        StylusSample(0.0, np.zeros(3), 1.2)
    assert err.value.key == "pressure"
