"""Clocks and timing metrics."""

from __future__ import annotations

import sys
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from common.errors import InputError
from paintapp.haptics.clock import RealTimeClock, VirtualClock
from paintapp.haptics.metrics import TimingRecorder, interval_stats


def test_virtual_clock_ticks_on_schedule_and_continues() -> None:
    clock = VirtualClock(period_s=1e-3, start_s=2.0)
    seen: list[tuple[int, float]] = []
    report = clock.run(lambda i, t: seen.append((i, t)) or True, max_ticks=5)
    assert [i for i, _ in seen] == list(range(5))
    np.testing.assert_allclose([t for _, t in seen], 2.0 + 1e-3 * np.arange(5))
    assert report.ticks == 5 and report.missed_deadlines == 0
    assert report.achieved_rate_hz == pytest.approx(1000.0)
    clock.run(lambda i, t: seen.append((i, t)) or True, max_ticks=2)
    assert seen[-1] == (6, pytest.approx(2.006))
    assert clock.now_s() == pytest.approx(2.006)


def test_virtual_clock_stops_when_the_tick_says_so() -> None:
    clock = VirtualClock()
    report = clock.run(lambda i, t: i < 9, max_ticks=100)
    assert report.ticks == 10


def test_clock_period_must_be_positive() -> None:
    with pytest.raises(InputError):
        VirtualClock(period_s=0.0)
    with pytest.raises(InputError):
        RealTimeClock(period_s=-1.0)


def test_recorder_percentiles_and_missed_deadlines() -> None:
    rec = TimingRecorder(1e-3)
    lateness = np.concatenate([np.zeros(9000), np.full(980, 2e-4), np.full(20, 5e-3)])
    for late in lateness:
        rec.record(late, 1e-5)
    rec.skip(3)
    rec.duration_s = 10.0
    r = rec.report()
    assert r.ticks == 10000 and r.achieved_rate_hz == pytest.approx(1000.0)
    assert r.lateness_p50_s == 0.0
    assert r.lateness_p99_s == pytest.approx(2e-4)
    assert r.lateness_p999_s == pytest.approx(5e-3)
    assert r.lateness_max_s == pytest.approx(5e-3)
    assert r.missed_deadlines == 3
    assert r.tick_cost_p50_s == pytest.approx(1e-5)
    assert dict(r.rows())["missed deadlines"] == "3"


def test_real_time_clock_counts_slots_lost_to_a_stall_and_restores_switch_interval() -> None:
    before = sys.getswitchinterval()
    clock = RealTimeClock(period_s=1e-3, switch_interval_s=2e-4)
    inside: list[float] = []

    def tick(i: int, t: float) -> bool:
        inside.append(sys.getswitchinterval())
        if i == 5:
            time.sleep(0.006)  # a stall: at least five slots pass
        return True

    report = clock.run(tick, max_ticks=20)
    assert report.ticks == 20
    assert report.missed_deadlines >= 5
    assert report.lateness_max_s >= 5e-3
    assert inside[0] == pytest.approx(2e-4)
    assert sys.getswitchinterval() == before


def test_real_time_clock_background_thread_runs_until_stopped() -> None:
    clock = RealTimeClock()
    times: list[float] = []
    clock.start(lambda i, t: times.append(t) or True)
    time.sleep(0.05)
    assert clock.running
    report = clock.stop()
    assert not clock.running
    assert report is not None and report.ticks == len(times) > 0
    assert np.all(np.diff(times) > 0)


@settings(max_examples=200, deadline=None)
@given(
    st.lists(st.floats(1e-5, 0.05, allow_nan=False), min_size=2, max_size=3000),
    st.sampled_from([1e-3, 5e-4, 2e-3]),
)
def test_the_live_jitter_is_numpy_s_99th_percentile(intervals, period_s):
    data = np.array(intervals)
    rate, jitter_ms = interval_stats(data, period_s)
    assert rate == pytest.approx(1.0 / np.mean(data), rel=1e-12)
    assert jitter_ms == pytest.approx(1e3 * np.percentile(np.abs(data - period_s), 99), rel=1e-12)
