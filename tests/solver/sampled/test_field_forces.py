"""Forces of a stored flow on a probe: exact for linear fields, linear in time between frames."""

from __future__ import annotations

import numpy as np
import pytest

from solver.sampled.flow import SampledFlow, extend_into
from solver.sampled.forces import surface_force
from solver.sampled.quadrature import surface_rule
from solver.shapes import Ball, Box


def linear_flow(dim: int, gradient: np.ndarray, shear: float, n: int = 21, h: float = 0.05):
    axes = np.meshgrid(*[np.arange(n) * h] * dim, indexing="ij")
    p = sum(g * x for g, x in zip(gradient, axes, strict=True))
    u = np.zeros((dim, *axes[0].shape))
    u[0] = shear * axes[1]  # a simple shear u_x = a y
    return SampledFlow(np.zeros(dim), np.full(dim, h), [0.0], p[None], u[None], 1000.0, 0.3)


CASES = [
    (2, Ball(0.2), np.pi * 0.2**2),
    (2, Box((0.3, 0.2)), 0.06),
    (3, Ball(0.2), 4.0 / 3.0 * np.pi * 0.2**3),
    (3, Box((0.3, 0.2, 0.1)), 0.006),
]


@pytest.mark.parametrize(("dim", "shape", "volume"), CASES)
def test_a_pressure_gradient_pushes_with_minus_gradient_times_volume(dim, shape, volume):
    g = np.array([3.0, -2.0, 1.5])[:dim]
    flow = linear_flow(dim, g, shear=0.7)
    rule = surface_rule(shape, dim, 0.01)
    centre = np.full(dim, 0.5)
    rotation = np.eye(dim)
    result = surface_force(flow, rule, centre, rotation, 0.0)
    rel = 1e-10 if isinstance(shape, Box) else 2e-3  # the sphere's lattice is not exact
    np.testing.assert_allclose(result.force, -g * volume, rtol=rel, atol=1e-12)
    # constant shear: no net force or torque (to the quadrature's accuracy; one viscous
    # traction on the surface is mu * shear ~ 0.2 N/m^2)
    np.testing.assert_allclose(result.viscous_force, 0.0, atol=1e-6)
    assert np.all(np.abs(result.torque) < 1e-6)
    assert result.outside_fraction == 0.0


def test_a_uniform_flow_gives_no_force_and_a_shear_layer_does():
    """Zero pressure gradient: only viscous traction, which cancels for constant strain and not
    for a shear that varies across the probe (u_x = a y^2: the net force is mu * 2a * V)."""
    n, h = 41, 0.025
    x, y = np.meshgrid(np.arange(n) * h, np.arange(n) * h, indexing="ij")
    uniform = np.stack([np.full_like(x, 0.4), np.zeros_like(x)])
    curved = np.stack([2.0 * y**2, np.zeros_like(x)])
    mu = 0.5
    for u, expected in ((uniform, 0.0), (curved, mu * 2 * 2.0 * np.pi * 0.2**2)):
        flow = SampledFlow(np.zeros(2), np.full(2, h), [0.0], np.zeros((1, n, n)), u[None], 1.0, mu)
        r = surface_force(
            flow, surface_rule(Ball(0.2), 2, h / 2), np.array([0.5, 0.5]), np.eye(2), 0.0
        )
        assert r.force[0] == pytest.approx(expected, rel=0.02, abs=1e-12)
        assert abs(r.force[1]) < 1e-9 and np.allclose(r.pressure_force, 0.0)


def test_frames_are_linear_in_time_and_clamped_outside_their_span():
    flow = linear_flow(2, np.array([1.0, 0.0]), 0.0)
    p2 = 3.0 * flow.pressure_pa
    series = SampledFlow(flow.origin_m, flow.spacing_m, [0.0, 2.0],
                         np.concatenate([flow.pressure_pa, p2]),
                         np.concatenate([flow.velocity_m_s] * 2), 1.0, 0.1)  # fmt: skip
    rule = surface_rule(Ball(0.2), 2, 0.01)
    f = [surface_force(series, rule, np.array([0.5, 0.5]), np.eye(2), t).force[0]
         for t in (-1.0, 0.0, 0.5, 2.0, 5.0)]  # fmt: skip
    v = np.pi * 0.04
    np.testing.assert_allclose(f, [-v, -v, -1.5 * v, -3 * v, -3 * v], rtol=1e-9)


def test_a_probe_outside_the_data_reports_it():
    flow = linear_flow(2, np.array([1.0, 0.0]), 0.0)
    r = surface_force(flow, surface_rule(Ball(0.2), 2, 0.01), np.array([0.05, 0.5]), np.eye(2), 0.0)
    assert 0.2 < r.outside_fraction < 0.8 and np.all(np.isfinite(r.force))


def test_pressure_is_extended_from_the_fluid_into_a_body():
    p = np.arange(25.0).reshape(5, 5)
    fluid = np.ones((5, 5), dtype=bool)
    fluid[1:4, 1:4] = False
    out = extend_into(np.where(fluid, p, 1e9), fluid)
    assert np.all(out[fluid] == p[fluid])
    assert np.all((out[~fluid] >= p.min()) & (out[~fluid] <= p.max()))
    assert out[2, 2] == pytest.approx(12.0, abs=2.5)


def test_rules_sum_to_the_exact_perimeter_or_area():
    assert surface_rule(Ball(0.3), 2, 0.01).weights.sum() == pytest.approx(2 * np.pi * 0.3)
    assert surface_rule(Ball(0.3), 3, 0.02).weights.sum() == pytest.approx(4 * np.pi * 0.09)
    assert surface_rule(Box((0.2, 0.1, 0.4)), 3, 0.02).weights.sum() == pytest.approx(0.28)
    with pytest.raises(ValueError):
        surface_rule(Ball(0.3), 2, 0.0)


def test_a_periodic_series_wraps_from_its_last_frame_back_to_the_first():
    from solver.sampled.flow import frame_pair

    times = np.array([0.0, 0.1, 0.2])
    assert frame_pair(times, 0.25, period_s=0.3) == (2, 0, pytest.approx(0.5))
    assert frame_pair(times, 0.35, period_s=0.3) == (0, 1, pytest.approx(0.5))
    assert frame_pair(times, 0.25) == (2, 2, 0.0)  # not periodic: held at the last frame
    flow = linear_flow(2, np.array([1.0, 0.0]), 0.0)
    with pytest.raises(ValueError, match="period"):
        SampledFlow(flow.origin_m, flow.spacing_m, [0.0, 1.0], np.concatenate([flow.pressure_pa] * 2),
                    np.concatenate([flow.velocity_m_s] * 2), 1.0, 0.1, period_s=0.5)  # fmt: skip
