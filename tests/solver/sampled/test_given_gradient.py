"""A sampled flow whose velocity gradient is given (taken on the mesh it was resampled from)
uses that gradient, extended into its non-fluid nodes like the pressure."""

from __future__ import annotations

import numpy as np
import pytest

from solver import SampledFlow


def test_a_given_gradient_is_sampled_as_given_and_extended_into_bodies():
    n = 9
    gradient = np.zeros((1, 2, 2, n, n))
    gradient[0, 0, 1] = 3.0  # du/dy = 3 1/s, though the velocity (zero) says otherwise
    fluid = np.ones((n, n), dtype=bool)
    fluid[:3] = False  # a body: its nodes hold garbage
    gradient[0, 0, 1, :3] = 1e9
    flow = SampledFlow(np.zeros(2), np.full(2, 0.1), np.zeros(1), np.zeros((1, n, n)),
                       np.zeros((1, 2, n, n)), 1.0, 1e-3, fluid, None, gradient)  # fmt: skip
    _, g, outside = flow.sample(0.0, np.array([[0.45, 0.4], [0.05, 0.4]]))
    assert outside == 0
    np.testing.assert_allclose(g[:, 0, 1], 3.0)
    np.testing.assert_allclose(g[:, [0, 1, 1], [0, 0, 1]], 0.0)


def test_a_gradient_of_the_wrong_shape_is_refused():
    with pytest.raises(ValueError, match="gradient"):
        SampledFlow(np.zeros(2), np.ones(2), np.zeros(1), np.zeros((1, 4, 4)),
                    np.zeros((1, 2, 4, 4)), 1.0, 1.0, None, None, np.zeros((1, 2, 2, 4, 3)))  # fmt: skip
