"""The machine's own timing floor: the servo process's clock with an empty tick."""

from __future__ import annotations

import pytest

from paintapp.haptics.bare_loop import MAX_LISTED, STALL_S, measure_bare_loop


def test_the_bare_loop_runs_its_ticks_in_a_process_and_lists_its_stalls() -> None:
    result = measure_bare_loop(0.4)
    timing = result.timing
    assert timing.ticks == 400  # the ticks asked for, each run once
    assert timing.duration_s >= 0.4 - 1e-3
    assert 0.0 <= timing.lateness_p50_s <= timing.lateness_p99_s <= timing.lateness_max_s
    assert result.granted  # what the OS granted, said in words
    assert len(result.listed) == min(result.stalls, MAX_LISTED)
    for at_s, late_s in result.listed:
        assert 0.0 < at_s <= timing.duration_s + 1e-3
        assert late_s > STALL_S
    line = result.describe()
    assert "bare 1 kHz loop" in line and "lateness p99" in line and f"{result.stalls} ticks" in line


def test_a_bare_loop_that_fails_says_why() -> None:
    with pytest.raises(RuntimeError, match="period"):
        measure_bare_loop(0.1, period_s=0.0)
