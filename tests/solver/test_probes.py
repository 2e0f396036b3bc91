"""Probes: voxelized area, keyframed paths and the velocities they imply."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from common import quaternion as rotation
from solver.grid import Grid
from solver.probes import Probe
from solver.shapes import Ball, Box, FilletedBox


def test_voxelized_circle_and_sphere_have_the_right_size():
    g2 = Grid.from_size((1.0, 1.0), (128, 128))
    _window, mask = Probe("c", Ball(0.2), 2, np.array([0.5, 0.5])).voxelize(g2)
    assert mask.sum() * g2.cell_size_m**2 == pytest.approx(np.pi * 0.04, rel=0.01)
    g3 = Grid.from_size((1.0, 1.0, 1.0), (48, 48, 48))
    _, mask3 = Probe("s", Ball(0.3), 3, np.array([0.5, 0.5, 0.5])).voxelize(g3)
    assert mask3.sum() * g3.cell_size_m**3 == pytest.approx(4 / 3 * np.pi * 0.027, rel=0.02)


def test_rotated_box_is_rotated():
    g = Grid.from_size((1.0, 1.0), (100, 100))
    box = Probe("b", Box((0.6, 0.1)), 2, np.array([0.5, 0.5]), np.pi / 2)
    window, mask = box.voxelize(g)
    full = np.zeros(g.cells, dtype=bool)
    full[window] = mask
    xs, ys = np.nonzero(full[:, :, 0])
    assert np.ptp(ys) > 5 * np.ptp(xs)  # long along y after a quarter turn


def test_path_interpolates_and_sets_average_velocity_2d():
    path = np.array([[0.0, 0.2, 0.5, 0.0], [1.0, 0.6, 0.5, 1.0], [2.0, 0.6, 0.9, 1.0]])
    p = Probe("p", Ball(0.05), 2, np.array([0.0, 0.0]), path=path)
    assert np.allclose(p.centre_m, [0.2, 0.5])
    p.advance(0.25, 0.5)
    assert np.allclose(p.centre_m, [0.5, 0.5])
    assert np.allclose(p.velocity_m_s, [0.4, 0.0])
    assert p.angular_velocity_rad_s == pytest.approx(1.0)
    p.advance(0.9, 0.2)  # straddles a keyframe: the average over the step
    assert np.allclose(p.velocity_m_s, ((0.6, 0.54) - np.array([0.56, 0.5])) / 0.2)
    p.advance(5.0, 0.1)  # held after the last keyframe
    assert np.allclose(p.velocity_m_s, 0.0) and np.allclose(p.centre_m, [0.6, 0.9])


def test_path_orientation_3d_gives_angular_velocity():
    q1 = rotation.from_rotation_vector(np.array([0.0, 0.0, np.pi / 2]))
    path = np.array([[0.0, 0.5, 0.5, 0.5, 1.0, 0.0, 0.0, 0.0], [1.0, 0.5, 0.5, 0.5, *q1]])
    p = Probe("p", Box((0.2, 0.1, 0.1)), 3, np.zeros(3), path=path)
    p.advance(0.0, 0.5)
    assert np.allclose(p.angular_velocity_rad_s, [0.0, 0.0, np.pi / 2])
    assert np.allclose(rotation.to_rotation_vector(p.orientation), [0.0, 0.0, np.pi / 4])


def test_constant_spin_3d_integrates_orientation():
    p = Probe("p", Ball(0.1), 3, np.zeros(3), None, np.zeros(3), np.array([0.0, 2.0, 0.0]))
    for _ in range(10):
        p.advance(0.0, 0.05)
    assert np.allclose(rotation.to_rotation_vector(p.orientation), [0.0, 1.0, 0.0])


def test_drive_to_reaches_the_target_pose_in_one_step():
    q = rotation.from_rotation_vector(np.array([0.3, -0.2, 0.5]))
    p = Probe("p", Ball(0.1), 3, np.array([0.5, 0.5, 0.5]))
    p.drive_to(np.array([0.52, 0.49, 0.5]), q, 0.01)
    p.advance(0.0, 0.01)
    assert np.allclose(p.centre_m, [0.52, 0.49, 0.5])
    assert np.allclose(np.abs(p.orientation @ q), 1.0)
    assert np.allclose(p.velocity_m_s, [2.0, -1.0, 0.0])


def test_shifting_the_grid_keeps_the_fluid_in_place(build):
    sim = build.sim(16, 2, nu=1e-3)
    sim.state.comps[0][5, 7, 0] = 1.0
    origin = np.array(sim.grid.origin_m)
    sim.shift((2, -1))
    assert np.allclose(np.array(sim.grid.origin_m) - origin, [2 / 16, -1 / 16, 0.0])
    assert sim.state.comps[0][3, 8, 0] == 1.0
    assert sim.state.comps[0].sum() == 1.0


def _arc(dim: int) -> np.ndarray:
    """Keyframes every 0.1 s on a circle of radius 0.2 m at 1 rad/s, turning at 2 rad/s."""
    t = np.arange(0.0, 2.01, 0.1)
    x, y = 0.5 + 0.2 * np.cos(t), 0.5 + 0.2 * np.sin(t)
    if dim == 2:
        return np.stack([t, x, y, 2.0 * t], axis=1)
    quats = [rotation.from_rotation_vector(np.array([0.0, 0.0, 2.0 * s])) for s in t]
    return np.array([[s, a, b, 0.5, *q] for s, a, b, q in zip(t, x, y, quats, strict=True)])


@pytest.mark.parametrize("dim", [2, 3])
def test_cubic_path_keeps_the_velocity_continuous_across_keyframes(dim):
    """A linear path's velocity jumps at each keyframe (0.1 s apart: by 0.02 m/s, a kink in the
    step velocities); the cubic spline's follows the sampled motion's (0.2 m/s, 2 rad/s) without
    kinks, and both pass through the keyframes."""
    path = _arc(dim)
    jumps = {}
    for kind in ("linear", "cubic"):
        p = Probe("p", Ball(0.05), dim, np.zeros(dim), path=path, path_interpolation=kind)
        vel, spin = [], []
        for n in range(20, 180):
            p.advance(n * 0.01, 0.01)
            vel.append(p.velocity_m_s.copy())
            spin.append(np.ravel(p.angular_velocity_rad_s)[-1])
        assert np.allclose(p.pose_at(1.0)[0], path[10, 1 : 1 + dim])
        v = np.array(vel)
        assert np.allclose(np.linalg.norm(v, axis=1), 0.2, rtol=0.02)
        assert np.allclose(spin, 2.0, rtol=1e-3)
        assert np.abs(np.diff(v, axis=0)).max() < 0.02 * 1.05  # at most v * 0.1 rad per step
        jumps[kind] = float(np.abs(np.diff(v, n=2, axis=0)).max())  # a kink in the velocity
    assert jumps["cubic"] < 0.01 * jumps["linear"]


@pytest.mark.parametrize("dim", [2, 3])
def test_world_box_of_a_box_is_its_rotated_corners_extent(dim):
    """A box's support function gives the tight world box: the extent of its rotated corners,
    which the bounding sphere's box exceeds."""
    rng = np.random.default_rng(3)
    size = (0.3, 0.1, 0.05)[:dim]
    for _ in range(20):
        if dim == 2:
            pose = float(rng.uniform(-np.pi, np.pi))
        else:
            pose = rotation.normalise(rng.standard_normal(4))
        centre = rng.uniform(-1.0, 1.0, dim)
        probe = Probe("b", Box(size), dim, centre, pose)
        lower, upper = probe.world_box()
        signs = np.array(np.meshgrid(*([(-0.5, 0.5)] * dim), indexing="ij")).reshape(dim, -1).T
        corners = centre + (signs * size) @ probe.rotation_matrix().T
        assert np.allclose(lower, corners.min(axis=0), atol=1e-12)
        assert np.allclose(upper, corners.max(axis=0), atol=1e-12)
    radius = Box(size).bounding_radius_m
    assert np.all(upper - lower < 2.0 * radius)


@settings(max_examples=40, deadline=None)
@given(dim=st.sampled_from([2, 3]), seed=st.integers(0, 2**31), filleted=st.booleans())
def test_half_extents_are_the_support_of_each_row(dim, seed, filleted):
    """A box's (or filleted box's) ``half_extents``, which the world box takes in one call, are
    its support function along each row of the rotation, bit for bit: the box's lower corner is
    the support towards minus each row."""
    rng = np.random.default_rng(seed)
    size = tuple(float(s) for s in rng.uniform(0.01, 0.4, dim))
    shape = FilletedBox(size, 0.2 * min(size)) if filleted else Box(size)
    pose = float(rng.uniform(-9, 9)) if dim == 2 else rotation.normalise(rng.standard_normal(4))
    rot = rotation.rotation_matrix(dim, pose)
    half = shape.half_extents(rot)
    assert half == [shape.support(rot[a]) for a in range(dim)]
    assert [-h for h in half] == [-shape.support(-rot[a]) for a in range(dim)]


def test_world_box_without_a_support_function_is_the_bounding_spheres():
    probe = Probe("c", Ball(0.2), 3, np.array([0.1, 0.2, 0.3]))
    lower, upper = probe.world_box()
    assert np.allclose(lower, [-0.1, 0.0, 0.1])
    assert np.allclose(upper, [0.3, 0.4, 0.5])


@settings(max_examples=40, deadline=None)
@given(
    dim=st.sampled_from([2, 3]),
    seed=st.integers(0, 2**31),
    spread=st.sampled_from([1e-3, 0.1, 10.0]),
)
def test_compiled_distances_are_the_numpy_ones(dim, seed, spread):
    rng = np.random.default_rng(seed)
    size = tuple(float(s) for s in rng.uniform(0.01, 0.5, dim))
    points = spread * rng.standard_normal((6, 5, dim))
    points[0, 0] = 0.0  # the centre, and points on the box's faces and edges
    points[0, 1] = 0.5 * np.array(size)
    points[0, 2, 0] = -0.5 * size[0]
    for shape in (
        Ball(float(rng.uniform(0.01, 0.5))),
        Box(size),
        FilletedBox(size, 0.2 * min(size)),
    ):
        compiled, reference = shape.sdf(points), _numpy_sdf(shape, points)
        assert compiled.shape == reference.shape == points.shape[:-1]
        np.testing.assert_array_equal(compiled, reference)
    assert Box(size).sdf(points)[0, 0] == pytest.approx(-0.5 * min(size))  # the centre: inside


def _numpy_sdf(shape, points):
    if isinstance(shape, FilletedBox):
        return Box(tuple(s - 2 * shape.radius_m for s in shape.size_m)).sdf_numpy(points) - (
            shape.radius_m
        )
    return shape.sdf_numpy(points)
