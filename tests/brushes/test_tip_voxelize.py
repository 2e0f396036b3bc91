"""Voxelizing tips into a grid, and the probe motion handed to the solver."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from brushes.pose import TipPose
from brushes.presets import BrushPreset, PressureResponse, TiltResponse
from brushes.probe import ProbeMotion, probe_motion, probe_motion_2d, rotation_matrix, voxelize
from brushes.tips import Disc, Rect, RoundCone, RoundedBox, Splayed
from common.tilt import quat_from_axis_angle

MM = 1e-3


def brute_force(shape, center, orientation, origin, h, cells):
    """Evaluate every cell centre (no bounding-sphere shortcut)."""
    dim = len(cells)
    axes = [origin[k] + (np.arange(cells[k]) + 0.5) * h for k in range(dim)]
    centres = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    body = (centres - np.asarray(center)) @ rotation_matrix(orientation, dim)
    return shape.sdf(body) <= 0.0


def test_disc_area_and_agreement_with_brute_force():
    h, cells, origin = 0.25 * MM, (64, 64), np.zeros(2)
    disc = Disc(5 * MM)
    center = np.array([8.1 * MM, 7.9 * MM])
    mask = voxelize(disc, center, 0.0, origin, h, cells)
    assert np.array_equal(mask, brute_force(disc, center, 0.0, origin, h, cells))
    area = mask.sum() * h * h
    assert area == pytest.approx(math.pi * (5 * MM) ** 2, rel=0.03)


def test_rotated_rect_equals_swapped_rect():
    h, cells, origin = 0.5 * MM, (40, 40), np.zeros(2)
    center = np.array([10 * MM, 10 * MM])  # a cell corner: the grid is symmetric about it
    turned = voxelize(Rect(8 * MM, 3 * MM), center, 0.5 * math.pi, origin, h, cells)
    swapped = voxelize(Rect(3 * MM, 8 * MM), center, 0.0, origin, h, cells)
    assert np.array_equal(turned, swapped)
    assert turned.sum() == (3 * MM / h) * (8 * MM / h)


def test_capsule_volume_in_3d():
    r, length, h = 2 * MM, 12 * MM, 0.2 * MM
    cells = (40, 40, 70)
    center = np.array([4 * MM, 4 * MM, 1 * MM])
    mask = voxelize(
        RoundCone(r, r, length), center, np.array([1.0, 0, 0, 0]), np.zeros(3), h, cells
    )
    volume = mask.sum() * h**3
    expected = math.pi * r**2 * (length - 2 * r) + 4.0 / 3.0 * math.pi * r**3
    assert volume == pytest.approx(expected, rel=0.03)
    # nothing below the apex, nothing above the top
    z_centres = (np.arange(cells[2]) + 0.5) * h
    solid_z = z_centres[mask.any(axis=(0, 1))]
    assert solid_z.min() >= center[2] and solid_z.max() <= center[2] + length


def test_quaternion_turn_of_flat_brush_swaps_width_and_thickness():
    h, cells, origin = 0.25 * MM, (48, 48, 48), np.zeros(3)
    center = np.array([6 * MM, 6 * MM, 0.0])
    quarter = quat_from_axis_angle(np.array([0.0, 0.0, 1.0]), 0.5 * math.pi)
    turned = voxelize(RoundedBox(8 * MM, 2 * MM, 6 * MM), center, quarter, origin, h, cells)
    swapped = voxelize(RoundedBox(2 * MM, 8 * MM, 6 * MM), center, np.eye(4)[0], origin, h, cells)
    assert np.array_equal(turned, swapped)


def test_probe_partly_or_wholly_outside_the_grid():
    h, cells, origin = 1 * MM, (16, 16, 8), np.zeros(3)
    cone = RoundCone(1 * MM, 3 * MM, 10 * MM)
    q = quat_from_axis_angle(np.array([1.0, 1.0, 0.0]), 0.7)
    edge = np.array([-1 * MM, 15 * MM, 2 * MM])
    assert np.array_equal(
        voxelize(cone, edge, q, origin, h, cells), brute_force(cone, edge, q, origin, h, cells)
    )
    far = np.array([1.0, 1.0, 1.0])
    assert not voxelize(cone, far, q, origin, h, cells).any()


def test_rigid_velocity_of_probe_points():
    motion = ProbeMotion(
        "brush",
        Disc(1 * MM),
        center=np.array([1.0, 2.0, 0.0]),
        orientation=np.array([1.0, 0, 0, 0]),
        velocity=np.array([0.1, 0.0, 0.0]),
        angular_velocity=np.array([0.0, 0.0, 2.0]),
    )
    v = motion.solid_velocity(np.array([[1.0, 2.0, 0.0], [1.0, 3.0, 0.0]]))
    assert np.allclose(v, [[0.1, 0.0, 0.0], [0.1 - 2.0, 0.0, 0.0]])
    flat = ProbeMotion("p", Disc(1 * MM), np.zeros(2), 0.0, np.zeros(2), 3.0)
    assert np.allclose(flat.solid_velocity(np.array([1.0, 0.0])), [0.0, 3.0])


def _preset(spread=1.0, stiffness=0.5):
    return BrushPreset(
        name="t",
        shape="round",
        size_m={"tip_radius_m": 0.5 * MM, "belly_radius_m": 2 * MM, "length_m": 12 * MM},
        stiffness=stiffness,
        capacity_m3=1e-8,
        pressure=PressureResponse(depth_m=2 * MM, spread=spread),
        tilt=TiltResponse(),
    )


def _pose(splay=1.0, twist=0.3):
    q = quat_from_axis_angle(np.array([0.0, 0.0, 1.0]), twist)
    return TipPose(
        t_s=0.0,
        position_m=np.array([0.01, 0.02, 0.0]),
        orientation=q,
        velocity_m_s=np.array([0.05, -0.02, 0.0]),
        angular_velocity_rad_s=np.array([0.0, 0.0, 1.5]),
        in_contact=True,
        press_depth_m=1 * MM,
        pressure=0.5,
        splay=splay,
        compression_m=0.0,
    )


def test_probe_motion_carries_pose_and_splayed_shape():
    pose, preset = _pose(splay=1.4), _preset()
    motion = probe_motion(pose, preset)
    assert motion.dim == 3 and motion.name == "brush"
    assert np.allclose(motion.center, pose.position_m)
    assert np.allclose(motion.orientation, pose.orientation)
    assert np.allclose(motion.velocity, pose.velocity_m_s)
    assert np.allclose(motion.angular_velocity, pose.angular_velocity_rad_s)
    assert isinstance(motion.shape, Splayed) and motion.shape.lateral_scale == 1.4
    assert isinstance(probe_motion(_pose(splay=1.0), preset).shape, RoundCone)


def test_probe_motion_2d_uses_yaw_and_footprint():
    pose, preset = _pose(twist=0.3), _preset()
    motion = probe_motion_2d(pose, preset)
    assert motion.dim == 2
    assert motion.orientation == pytest.approx(0.3)
    assert motion.angular_velocity == pytest.approx(1.5)
    assert np.allclose(motion.velocity, [0.05, -0.02])
    h = 0.05 * MM
    mask = motion.voxelize([0.0, 0.01], h, (400, 400))
    # the footprint is the disc cut from the tip half the press depth above the apex
    cone = preset.base_tip()
    radii = np.linspace(0.0, 2 * MM, 20001)
    cut = cone.sdf(np.stack([radii, 0 * radii, 0 * radii + 0.5 * MM], axis=1))
    rho = radii[cut <= 0.0].max()
    assert mask.sum() * h * h == pytest.approx(math.pi * rho**2, rel=0.05)
    cells = np.argwhere(mask)
    centre = (cells.mean(axis=0) + 0.5) * h + [0.0, 0.01]
    assert np.allclose(centre, pose.position_m[:2], atol=0.5 * h)


@pytest.mark.parametrize("dim", [2, 3])
def test_to_probe_voxelizes_like_our_voxelizer(dim):
    from solver.grid import Grid

    pose = replace(
        _pose(splay=1.3, twist=0.8),
        orientation=quat_from_axis_angle(np.array([0.3, -0.5, 1.0]), 0.9),
    )
    preset = _preset()
    motion = probe_motion(pose, preset) if dim == 3 else probe_motion_2d(pose, preset, 2 * MM)
    probe = motion.to_probe()
    assert probe.dim == dim and probe.name == "brush"
    assert np.allclose(probe.centre_m, motion.center)
    cells = (48, 40, 36)[:dim]
    h = 0.25 * MM
    origin = np.array([0.004, 0.013, -0.001])[:dim]
    grid = Grid(dim=dim, cells=(*cells, 1)[:3], cell_size_m=h, origin_m=tuple((*origin, 0.0)[:3]))
    window, inside = probe.voxelize(grid)
    solver_mask = np.zeros(grid.cells, dtype=bool)
    solver_mask[window] = inside
    ours = motion.voxelize(origin, h, cells)
    assert ours.any()
    assert np.array_equal(solver_mask.reshape(cells), ours)


class _SphereBound:
    """A tip without its support function: the cut geometry falls back to its bounding sphere."""

    def __init__(self, tip):
        self._tip = tip
        self.bounding_radius_m = tip.bounding_radius_m

    def sdf(self, points):
        return self._tip.sdf(points)


@pytest.mark.parametrize(
    "tip",
    [
        RoundCone(0.3 * MM, 2.0 * MM, 12.0 * MM),
        Splayed(RoundCone(0.3 * MM, 2.0 * MM, 12.0 * MM), 1.4),
        RoundedBox(6.0 * MM, 1.5 * MM, 10.0 * MM, 0.5 * MM),
    ],
)
def test_cut_geometry_in_the_tight_window_equals_the_bounding_spheres(tip):
    """The cut geometry samples a tip only inside its tight world box (from its support
    function) plus a margin: its face fractions, fluid fractions and owners are those sampled
    over the whole bounding sphere, tilted or not."""
    from solver.cutcell.geometry import CutGeometry
    from solver.grid import Grid
    from solver.probes import Probe

    grid = Grid(3, (40, 40, 24), 0.4 * MM, (-8.0 * MM, -8.0 * MM, -1.0 * MM))
    for axis, angle in (((1.0, 0.0, 0.0), 0.0), ((1.0, 1.0, 0.0), 0.6), ((0.0, 1.0, 0.2), 1.1)):
        orientation = quat_from_axis_angle(np.asarray(axis) / np.linalg.norm(axis), angle)
        geos = []
        for shape in (tip, _SphereBound(tip)):
            geo = CutGeometry.empty(grid)
            probe = Probe("tip", shape, 3, np.array([0.1, -0.2, -0.5]) * MM, orientation)
            geo.update(grid, [probe])
            geos.append(geo)
        tight, sphere = geos
        (lo_t, hi_t), (lo_s, hi_s) = tight.windows[0], sphere.windows[0]
        assert np.prod(hi_t - lo_t) < np.prod(hi_s - lo_s)  # the tight window is smaller
        for a in range(3):
            assert np.array_equal(tight.open_frac[a], sphere.open_frac[a])
            assert np.array_equal(tight.owner_face[a], sphere.owner_face[a])
        assert np.array_equal(tight.fluid_frac, sphere.fluid_frac)
        assert np.array_equal(tight.owner_cell, sphere.owner_cell)
        assert (tight.open_frac[2] < 1.0).any()  # the tip is in the grid
