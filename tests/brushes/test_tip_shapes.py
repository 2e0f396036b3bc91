"""Signed-distance geometry of the brush tips, checked against analytic and independent answers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from brushes.tips import (
    Disc,
    Rect,
    RoundCone,
    RoundedBox,
    Section,
    Shape,
    Splayed,
    TipShape,
    lowest_point_z,
)
from common.tilt import quat_from_axis_angle, quat_to_matrix

MM = 1e-3
RNG = np.random.default_rng(7)


def hull_of_balls_sdf(cone: RoundCone, points: np.ndarray) -> np.ndarray:
    """Signed distance to the hull of two balls as the union of the interpolated balls.

    Exact outside (up to the t-grid), exact in sign everywhere; an independent check of RoundCone.
    """
    r1, r2 = cone.tip_radius_m, cone.belly_radius_m
    t = np.linspace(0.0, 1.0, 4001)
    centres_z = r1 + t * (cone.length_m - r2 - r1)
    radii = r1 + t * (r2 - r1)
    rho = np.hypot(points[:, 0], points[:, 1])[:, None]
    dist = np.hypot(rho, points[:, 2:3] - centres_z) - radii
    return dist.min(axis=1)


def inside_points(shape: Shape, half_size: float, n: int = 61, dim: int = 3) -> np.ndarray:
    axis = np.linspace(-half_size, half_size, n)
    grid = np.stack(np.meshgrid(*([axis] * dim), indexing="ij"), axis=-1).reshape(-1, dim)
    return grid[shape.sdf(grid) <= 0.0]


def test_round_cone_on_axis_distances_are_exact():
    cone = RoundCone(0.5 * MM, 2 * MM, 12 * MM)
    below = np.array([[0.0, 0.0, -d] for d in (0.1 * MM, 1 * MM, 5 * MM)])
    assert np.allclose(cone.sdf(below), [0.1 * MM, 1 * MM, 5 * MM])
    above = np.array([[0.0, 0.0, 12 * MM + 3 * MM]])
    assert np.allclose(cone.sdf(above), [3 * MM])
    assert cone.sdf(np.zeros(3)) == pytest.approx(0.0, abs=1e-15)
    belly_centre = np.array([0.0, 0.0, 10 * MM])
    assert cone.sdf(belly_centre) == pytest.approx(-2 * MM)


def test_round_cone_matches_hull_of_balls():
    cone = RoundCone(0.4 * MM, 3 * MM, 15 * MM)
    points = RNG.uniform([-6 * MM, -6 * MM, -3 * MM], [6 * MM, 6 * MM, 18 * MM], size=(4000, 3))
    ours = cone.sdf(points)
    reference = hull_of_balls_sdf(cone, points)
    clear = np.abs(reference) > 1e-8  # the sign is unambiguous away from the surface
    assert np.array_equal((ours <= 0.0)[clear], (reference <= 0.0)[clear])
    outside = reference > 0.0
    assert np.allclose(ours[outside], reference[outside], atol=1e-8)


def test_capsule_is_segment_distance_minus_radius():
    r, length = 2 * MM, 14 * MM
    capsule = RoundCone(r, r, length)
    points = RNG.normal(scale=8 * MM, size=(2000, 3)) + np.array([0, 0, 7 * MM])
    z = np.clip(points[:, 2], r, length - r)
    expected = np.linalg.norm(points - np.stack([0 * z, 0 * z, z], axis=1), axis=1) - r
    assert np.allclose(capsule.sdf(points), expected, atol=1e-15)


def test_rounded_box_analytic_values():
    box = RoundedBox(12 * MM, 2 * MM, 18 * MM, corner_radius_m=0.5 * MM)
    assert box.sdf(np.array([0.0, 0.0, -1 * MM])) == pytest.approx(1 * MM)
    assert box.sdf(np.array([6 * MM + 2 * MM, 0.0, 9 * MM])) == pytest.approx(2 * MM)
    assert box.sdf(np.array([0.0, 0.0, 9 * MM])) == pytest.approx(-1 * MM)  # half thickness
    # beyond a rounded vertical edge, along the diagonal of the x-y corner:
    edge = np.array([5.5 * MM, 0.5 * MM, 9 * MM])  # the edge's rounding centre
    d = 3 * MM
    point = edge + d * np.array([1.0, 1.0, 0.0]) / math.sqrt(2.0)
    assert box.sdf(point) == pytest.approx(d - 0.5 * MM)


def test_sharp_box_is_paper_square_probe():
    box = RoundedBox(4 * MM, 4 * MM, 10 * MM)
    corner = np.array([2 * MM, 2 * MM, 0.0])
    assert box.sdf(corner + np.array([1, 1, -1]) * MM) == pytest.approx(math.sqrt(3) * MM)
    assert box.sdf(np.array([[1 * MM, 0.0, 5 * MM]])) == pytest.approx([-1 * MM])


@pytest.mark.parametrize(
    "shape",
    [RoundCone(0.4 * MM, 2 * MM, 10 * MM), RoundedBox(8 * MM, 2 * MM, 9 * MM, 0.6 * MM)],
    ids=["round", "flat"],
)
def test_support_and_bounding_radius_agree_with_sampled_interior(shape: TipShape):
    points = inside_points(shape, 11 * MM, n=71)
    spacing = 22 * MM / 70
    assert isinstance(shape, TipShape)
    for direction in RNG.normal(size=(20, 3)):
        sampled = float((points @ direction).max())
        exact = shape.support(direction)
        assert sampled <= exact + 1e-12
        assert exact - sampled <= spacing * np.abs(direction).sum()
    radius = float(np.linalg.norm(points, axis=1).max())
    assert radius <= shape.bounding_radius_m + 1e-12
    assert shape.bounding_radius_m - radius <= 2 * spacing


def test_splayed_tip_is_wider_with_exact_sign():
    cone = RoundCone(0.5 * MM, 2 * MM, 12 * MM)
    wide = Splayed(cone, 1.5)
    belly_z = 10 * MM
    assert wide.sdf(np.array([2.9 * MM, 0.0, belly_z])) < 0.0
    assert wide.sdf(np.array([3.1 * MM, 0.0, belly_z])) > 0.0
    assert wide.sdf(np.array([0.0, 0.0, -1 * MM])) == pytest.approx(1 * MM)  # z is not scaled
    assert wide.support(np.array([1.0, 0.0, 0.0])) == pytest.approx(3 * MM)
    assert wide.bounding_radius_m == pytest.approx(1.5 * cone.bounding_radius_m)
    # the sign is exactly that of the stretched hull
    points = RNG.uniform(-8 * MM, 14 * MM, size=(2000, 3))
    inside = hull_of_balls_sdf(cone, points / [1.5, 1.5, 1.0]) <= 0.0
    assert np.array_equal(wide.sdf(points) <= 0.0, inside)
    # outside, the value never exceeds the distance to any point of the shape (a safe bound)
    solid = inside_points(wide, 14 * MM, n=57)
    outside = points[~inside][:300]
    nearest = np.linalg.norm(outside[:, None, :] - solid[None, :, :], axis=-1).min(axis=1)
    assert np.all(wide.sdf(outside) <= nearest + 1e-12)


def test_planar_shapes_exact():
    disc = Disc(3 * MM)
    assert disc.sdf(np.array([[5 * MM, 0.0], [0.0, 0.0]])) == pytest.approx([2 * MM, -3 * MM])
    rect = Rect(4 * MM, 2 * MM)
    assert rect.sdf(np.array([3 * MM, 0.0])) == pytest.approx(1 * MM)
    assert rect.sdf(np.array([3 * MM, 2 * MM])) == pytest.approx(math.hypot(1, 1) * MM)
    assert rect.sdf(np.array([0.0, 0.0])) == pytest.approx(-1 * MM)
    assert rect.bounding_radius_m == pytest.approx(math.hypot(2, 1) * MM)


def test_section_of_round_cone_at_belly_is_a_disc_of_belly_radius():
    cone = RoundCone(0.5 * MM, 2 * MM, 12 * MM)
    cut = Section(cone, 10 * MM)
    assert cut.sdf(np.array([1.99 * MM, 0.0])) < 0.0 < cut.sdf(np.array([2.01 * MM, 0.0]))
    assert np.all(Section(cone, -1 * MM).sdf(np.zeros((3, 2))) > 0.0)  # below the apex: empty


def test_lowest_point_of_tilted_tips():
    theta = 0.6
    rot = quat_to_matrix(quat_from_axis_angle(np.array([0.0, 1.0, 0.0]), theta))
    r1 = 0.5 * MM
    cone = RoundCone(r1, 2 * MM, 12 * MM)
    assert lowest_point_z(cone, np.eye(3)) == pytest.approx(0.0, abs=1e-15)
    assert lowest_point_z(cone, rot) == pytest.approx(r1 * math.cos(theta) - r1)
    box = RoundedBox(4 * MM, 4 * MM, 10 * MM)
    assert lowest_point_z(box, rot) == pytest.approx(-2 * MM * math.sin(theta))


def test_bad_geometry_rejected():
    with pytest.raises(ValueError):
        RoundCone(1 * MM, 3 * MM, 5 * MM)  # length below the belly's diameter
    with pytest.raises(ValueError):
        RoundedBox(4 * MM, 2 * MM, 10 * MM, corner_radius_m=1.5 * MM)
    with pytest.raises(ValueError):
        Disc(1 * MM).sdf(np.zeros(3))  # wrong dimension


def test_box_tip_takes_the_solver_grid_scale_corner_radius():
    """A sharp box tip (the paper's square probe) is rounded by the solver's corner radius; a tip
    already rounder keeps its own; the radius never exceeds half the smallest size."""
    from solver.shapes import with_rounded_corners

    sharp = RoundedBox(4 * MM, 4 * MM, 10 * MM)
    rounded = with_rounded_corners(sharp, 0.3 * MM)
    assert rounded == RoundedBox(4 * MM, 4 * MM, 10 * MM, corner_radius_m=0.3 * MM)
    corner = np.array([[2 * MM, 2 * MM, 5 * MM]])  # on a vertical edge of the sharp box
    assert sharp.sdf(corner)[0] == pytest.approx(0.0, abs=1e-15)
    assert rounded.sdf(corner)[0] == pytest.approx(0.3 * MM * (math.sqrt(2.0) - 1.0))
    flat = RoundedBox(8 * MM, 2 * MM, 9 * MM, 0.6 * MM)
    assert with_rounded_corners(flat, 0.3 * MM) is flat
    assert with_rounded_corners(flat, 5 * MM).corner_radius_m == pytest.approx(1 * MM)
    cone = RoundCone(0.4 * MM, 2 * MM, 10 * MM)
    assert with_rounded_corners(cone, 0.3 * MM) is cone  # smooth already


COMPILED = [
    RoundCone(0.4 * MM, 2.0 * MM, 12.0 * MM),
    RoundCone(1.5 * MM, 1.5 * MM, 9.0 * MM),  # a capsule
    RoundedBox(8.0 * MM, 1.5 * MM, 14.0 * MM, 0.3 * MM),
    RoundedBox(5.0 * MM, 5.0 * MM, 5.0 * MM),  # sharp
]


@pytest.mark.parametrize("tip", COMPILED)
@pytest.mark.parametrize("splay", [1.0, 0.7, 1.6])
def test_compiled_distances_are_the_numpy_ones(tip, splay):
    # the kernels repeat the numpy arithmetic in its order: the same values, bit for bit, for
    # the tip, its splayed form and its sections (inside, on and far outside the surface)
    pts = RNG.uniform(-12.0 * MM, 16.0 * MM, (4000, 3))
    pts[:50, :2] = 0.0  # on the axis
    shape = tip if splay == 1.0 else Splayed(tip, splay)
    stretch = np.array([splay, splay, 1.0])
    reference = (
        tip.sdf_numpy(pts / stretch) * min(1.0, splay) if splay != 1.0 else tip.sdf_numpy(pts)
    )
    np.testing.assert_array_equal(shape.sdf(pts), reference)
    np.testing.assert_array_equal(shape.sdf(pts.reshape(40, 100, 3)), reference.reshape(40, 100))
    z = 3.0 * MM
    cut = Section(shape, z).sdf(pts[:, :2])
    on_plane = np.column_stack([pts[:, :2], np.full(len(pts), z)])
    np.testing.assert_array_equal(cut, shape.sdf(on_plane))
    assert (reference < 0.0).any() and (reference > 0.0).any()
