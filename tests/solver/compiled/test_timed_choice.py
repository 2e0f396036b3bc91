"""Choosing between ways of doing the same work by their measured costs."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from solver.compiled.timed_choice import TimedChoice


def _run(choice: TimedChoice, costs: tuple[float, ...], picks: int) -> list[int]:
    """``picks`` choices, each option costing ``costs[option]``."""
    taken = []
    for _ in range(picks):
        option = choice.pick()
        choice.record(option, costs[option])
        taken.append(option)
    return taken


def test_each_option_is_tried_first_then_the_cheapest_runs_and_the_other_is_probed():
    choice = TimedChoice(2, probe_every=10, window=3)
    taken = _run(choice, (2.0, 1.0), 40)
    assert taken[:2] == [0, 1]
    assert choice.best() == 1
    assert [i for i, o in enumerate(taken) if o == 0] == [0, 9, 19, 29, 39]  # every 10th pick


def test_a_best_option_that_turns_slow_loses_its_place_once_its_median_says_so():
    choice = TimedChoice(2, probe_every=25, window=3)
    _run(choice, (2.0, 1.0), 10)
    assert choice.best() == 1
    taken = _run(choice, (2.0, 5.0), 4)  # the other core got busy: threads now cost 5
    assert taken[:2] == [1, 1]  # one slow cost is an outlier, two are the median
    assert taken[2:] == [0, 0]


def test_a_slow_option_that_turns_fast_is_found_at_the_next_probe():
    choice = TimedChoice(2, probe_every=5, window=1)
    _run(choice, (1.0, 3.0), 6)
    assert choice.best() == 0
    taken = _run(choice, (1.0, 0.5), 10)
    assert 1 in taken[:5] and taken[-1] == 1


def test_costs_that_are_not_finite_or_negative_are_ignored():
    choice = TimedChoice(2)
    for bad in (math.nan, math.inf, -1.0):
        choice.record(0, bad)
    assert choice.cost(0) is None and choice.best() is None
    assert choice.pick() == 0


def test_impossible_settings_are_refused():
    for kwargs in ({"options": 0}, {"probe_every": 1}, {"window": 0}):
        with pytest.raises(ValueError, match="need options"):
            TimedChoice(**kwargs)


@given(
    st.lists(st.floats(0.001, 1000.0), min_size=2, max_size=4),
    st.integers(2, 30),
    st.integers(1, 5),
)
def test_with_steady_costs_the_cheapest_runs_all_but_the_probes(costs, probe_every, window):
    choice = TimedChoice(len(costs), probe_every=probe_every, window=window)
    taken = _run(choice, tuple(costs), 200)
    n = len(costs)
    assert taken[:n] == list(range(n))
    cheapest = min(range(n), key=lambda o: costs[o])
    assert choice.best() == cheapest
    probes = [i for i in range(n, 200) if (i + 1) % probe_every == 0]
    others = [i for i in range(n, 200) if taken[i] != cheapest]
    assert set(others) <= set(probes)
