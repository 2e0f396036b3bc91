"""The sweep's water-filling: the scale at which capped fractions take a given loss."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from paintapp.paint.water_filling import water_fill


def _taken(frac: np.ndarray, mobile: np.ndarray, scale: float) -> float:
    return float(np.sum(np.minimum(scale * frac, 1.0) * mobile))


def _assert_root(frac: np.ndarray, mobile: np.ndarray, scale: float, lost: float) -> None:
    assert scale > 0.0
    assert abs(_taken(frac, mobile, scale) - lost) <= 1e-11 * lost
    # the root is unique where it is reached: a hair less takes less, a hair more takes more
    # (unless every texel is emptied already)
    assert _taken(frac, mobile, scale * (1 - 1e-6)) < lost
    assert scale * frac[mobile > 0].max() >= 1.0 or _taken(frac, mobile, scale * (1 + 1e-6)) > lost


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 2**31 - 1),
    share=st.floats(0.05, 0.999),
    start=st.floats(0.2, 5.0),
)
def test_the_water_filling_finds_the_scale_that_takes_exactly_the_loss(seed, share, start):
    # fractions in [0, 1] over texels holding paint (some none); the loss a share of all they
    # hold, so a scale exists; Newton's steps from below or above the root must land on it
    shape = (23, 37)
    rng = np.random.default_rng(seed)
    frac = rng.uniform(0.0, 1.0, shape) * (rng.random(shape) > 0.2)
    mobile = rng.uniform(0.0, 1e-5, shape) * (rng.random(shape) > 0.1)
    lost = share * float(np.sum(mobile[frac > 0.0]))
    scale, taken = water_fill(frac.copy(), mobile.copy(), start, lost)  # it reorders them
    _assert_root(frac, mobile, scale, lost)
    assert taken == pytest.approx(_taken(frac, mobile, scale), rel=1e-12)


@pytest.mark.parametrize("spread", [0.1, 1.0, 4.0])
def test_the_root_over_many_texels_most_of_them_emptied(spread):
    # a window's swept ratios: tens of thousands, log-normally spread over up to a dozen
    # octaves, most of them emptied at the root (the passes then drop the emptied texels)
    rng = np.random.default_rng(11)
    frac = np.exp(rng.normal(0.0, spread, 40_000)) * (rng.random(40_000) > 0.1)
    mobile = rng.uniform(0.0, 1e-5, 40_000)
    for share in (0.05, 0.5, 0.99):
        lost = share * float(np.sum(mobile[frac > 0.0]))
        start = lost / _taken(frac, mobile, 1.0)
        scale, taken = water_fill(frac.copy(), mobile.copy(), start, lost)
        _assert_root(frac, mobile, scale, lost)
        assert taken == pytest.approx(lost, rel=1e-12)
