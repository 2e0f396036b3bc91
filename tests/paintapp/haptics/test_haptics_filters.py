"""Reconstruction filters: delays, smoothing, unit gain, irregular input, configuration errors."""

from __future__ import annotations

import numpy as np
import pytest

from common.errors import InputError
from paintapp.haptics.filters import (
    CLOSED_FORM_WINDOWS,
    FilterConfig,
    FirWindowFilter,
    fir_taps,
    make_filter,
)
from tests.support.imports import loads_module

TICK = 1e-3


def run_filter(
    kind: str, t_in: np.ndarray, x_in: np.ndarray, t_out: np.ndarray, **kw
) -> np.ndarray:
    """Samples published at ``t_in`` are pushed at the first tick of ``t_out`` that sees them,
    stamped with that tick's time (as the servo loop does); one output per tick."""
    filt = make_filter(kind, TICK, dim=1, **kw)
    y = np.empty(len(t_out))
    k = 0
    for i, t in enumerate(t_out):
        while k < len(t_in) and t_in[k] <= t + 1e-12:
            filt.push(t, np.array([x_in[k]]))
            k += 1
        y[i] = filt.output(t)[0]
    return y


@pytest.mark.parametrize("kind", ["zoh", "linear", "fir"])
@pytest.mark.parametrize("period_s", [1 / 70, 1 / 33, 0.005])
def test_ramp_lag_equals_stated_delay(kind: str, period_s: float) -> None:
    """A ramp x = t published every T (at random phase to the ticks) comes out shifted by the
    filter's stated delay, on average."""
    t_in = np.arange(0, 2.0, period_s) + 0.37e-3
    t_out = np.arange(0, 2.0, TICK)
    y = run_filter(kind, t_in, t_in, t_out)
    steady = t_out > 0.3
    lag = np.mean(t_out[steady] - y[steady])
    expected = make_filter(kind, TICK, 1).delay_s(period_s)
    assert lag == pytest.approx(expected, abs=0.05 * period_s + 2e-4)


def test_linear_interpolation_lags_exactly_one_period_after_arrival() -> None:
    period = 0.02
    t_in = np.arange(0, 1.0, period)  # published on the ticks: no wait for the tick
    t_out = np.arange(0.0, 0.9, TICK)
    y = run_filter("linear", t_in, 3.0 * t_in, t_out)
    late = t_out > 0.1
    np.testing.assert_allclose(y[late], 3.0 * (t_out[late] - period), atol=1e-9)


def test_fir_step_response_is_smooth_and_centred_on_its_delay() -> None:
    """A step at t = 0.1 s rises monotonically over exactly `order` ticks, half-way after order/2."""
    t_out = np.arange(0, 0.2, TICK)
    y = run_filter("fir", np.array([0.1]), np.array([1.0]), t_out)
    assert np.all(np.diff(y) >= -1e-15)
    rising = np.flatnonzero((y > 1e-12) & (y < 1 - 1e-12))
    assert len(rising) <= 10  # barthann's end taps are zero: the transition spans < 10 ticks
    half = t_out[np.argmax(y >= 0.5)]
    assert half - 0.1 == pytest.approx(0.005, abs=TICK)
    assert y[-1] == pytest.approx(1.0)


@pytest.mark.parametrize("window", ["barthann", "hann", "hamming", ("kaiser", 4.0)])
@pytest.mark.parametrize("order", [4, 10, 21])
def test_fir_taps_unit_gain_and_linear_phase(window, order: int) -> None:
    taps = fir_taps(order, window)
    assert taps.shape == (order + 1,)
    assert taps.sum() == pytest.approx(1.0)
    np.testing.assert_allclose(taps, taps[::-1], atol=1e-15)  # symmetric: delay order/2 ticks
    assert FirWindowFilter(TICK, 1, order, window).delay_s(0.0) == pytest.approx(order / 2 * TICK)


@pytest.mark.parametrize("window", sorted(CLOSED_FORM_WINDOWS))
@pytest.mark.parametrize("points", [2, 3, 11, 22, 101])
def test_windows_built_here_are_scipys(window: str, points: int) -> None:
    from scipy.signal import get_window

    ours = CLOSED_FORM_WINDOWS[window](points)
    np.testing.assert_allclose(ours, get_window(window, points, fftbins=False), atol=1e-15)


def test_the_papers_filter_loads_no_scipy_signal() -> None:
    code = "from paintapp.haptics.filters import FirWindowFilter\nFirWindowFilter(1e-3, 6, 10)"
    assert not loads_module(code, "scipy.signal")
    kaiser = "from paintapp.haptics.filters import fir_taps\nfir_taps(10, ('kaiser', 4.0))"
    assert loads_module(kaiser, "scipy.signal")  # any other window is scipy's


def test_fir_lowpass_design_attenuates_above_cutoff() -> None:
    taps = fir_taps(40, "barthann", cutoff_hz=50.0, rate_hz=1000.0)
    freq = np.fft.rfftfreq(4096, TICK)
    gain = np.abs(np.fft.rfft(taps, 4096))
    assert gain[0] == pytest.approx(1.0)
    assert np.max(gain[freq > 150]) < 0.01


def test_filters_keep_the_mean_of_an_irregular_signal() -> None:
    rng = np.random.default_rng(1)
    t_in = np.cumsum(rng.uniform(0.005, 0.033, 400))  # 30-200 Hz, unsteady
    x_in = rng.normal(0.7, 1.0, len(t_in))
    t_out = np.arange(0, t_in[-1], TICK)
    means = {k: np.mean(run_filter(k, t_in, x_in, t_out)[50:]) for k in ("zoh", "linear", "fir")}
    assert means["fir"] == pytest.approx(means["zoh"], abs=0.02)
    assert means["linear"] == pytest.approx(means["zoh"], abs=0.02)


def test_filters_output_zero_before_any_sample_and_after_reset() -> None:
    for kind in ("zoh", "linear", "fir"):
        filt = make_filter(kind, TICK, 6)
        np.testing.assert_array_equal(filt.output(0.0), np.zeros(6))
        filt.push(0.0, np.ones(6))
        for i in range(20):
            filt.output(i * TICK)
        filt.reset()
        np.testing.assert_array_equal(filt.output(0.03), np.zeros(6))


def test_bad_configuration_is_an_input_error() -> None:
    with pytest.raises(InputError, match="unknown filter"):
        make_filter("median")
    with pytest.raises(InputError, match="window"):
        fir_taps(10, "no-such-window")
    with pytest.raises(InputError, match="order"):
        fir_taps(0)
    with pytest.raises(InputError, match="tick"):
        FilterConfig().build(tick_s=0.0)
