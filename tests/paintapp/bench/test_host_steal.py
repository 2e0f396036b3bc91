"""The host's CPU steal: /proc/stat read and its share between two readings."""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from paintapp.bench.host_steal import (
    CpuTimes,
    StealMonitor,
    describe_steal,
    format_share,
    parse_cpu_times,
    read_cpu_times,
    steal_share,
)

STAT = """cpu  1605076 1 160388 2108294 8252 0 1016 2172 0 0
cpu0 802538 0 80194 1054147 4126 0 508 1086 0 0
cpu1 802538 1 80194 1054147 4126 0 508 1086 0 0
intr 123
"""


def test_the_aggregate_line_s_eight_columns_make_the_total_and_the_eighth_is_steal():
    times = parse_cpu_times(STAT)
    assert times == CpuTimes(
        total=1605076 + 1 + 160388 + 2108294 + 8252 + 0 + 1016 + 2172, steal=2172
    )


@pytest.mark.parametrize(
    "text",
    [
        "",
        "intr 1 2 3\n",
        "cpu  1 2 3 4 5 6 7\n",  # a kernel without the steal column
        "cpu  1 2 3 4 5 6 7 x 0 0\n",
        "cpu  1 2 3 4 5 6 7 -8 0 0\n",
        "cpu0 1 2 3 4 5 6 7 8\n",  # one CPU's line is not the machine's
    ],
)
def test_a_stat_text_without_a_whole_cpu_line_gives_no_reading(text):
    assert parse_cpu_times(text) is None


def test_an_unreadable_file_gives_no_reading(tmp_path: Path):
    assert read_cpu_times(tmp_path / "missing") is None
    (tmp_path / "stat").write_text(STAT)
    assert read_cpu_times(tmp_path / "stat") == parse_cpu_times(STAT)


def test_the_share_is_the_steal_over_the_time_between_the_readings():
    before = CpuTimes(total=1000, steal=10)
    assert steal_share(before, CpuTimes(total=1200, steal=30)) == pytest.approx(0.1)
    assert steal_share(before, CpuTimes(total=1200, steal=10)) == 0.0
    assert format_share(0.1) == "10.0 %" and format_share(None) == "-"
    assert describe_steal(0.004, 0.093) == "0.4 % (peak 9.3 %)"
    assert describe_steal(None, None) == "-" and describe_steal(0.1, None) == "-"


@given(
    st.integers(0, 10**9),
    st.integers(0, 10**9),
    st.integers(-(10**6), 10**6),
    st.integers(-(10**6), 10**6),
)
def test_a_share_is_between_0_and_1_or_unknown(total, steal, d_total, d_steal):
    before = CpuTimes(total=total, steal=min(steal, total))
    after = CpuTimes(total=total + d_total, steal=before.steal + d_steal)
    share = steal_share(before, after)
    if share is None:
        assert d_total <= 0 or d_steal < 0 or d_steal > d_total
    else:
        assert 0.0 <= share <= 1.0
    assert steal_share(None, after) is None and steal_share(before, None) is None


def test_this_machine_s_counters_advance_or_are_absent():
    first = read_cpu_times()
    if first is None:  # not Linux: the share is unknown, never a guess
        assert steal_share(first, read_cpu_times()) is None
        return
    sum(i * i for i in range(200_000))  # some CPU time between the readings
    second = read_cpu_times()
    assert second is not None and second.total >= first.total and second.steal >= first.steal


def _write_stat(path: Path, total: int, steal: int) -> None:
    """A stat file with these counters, replaced whole (the monitor never reads half of one)."""
    idle = total - steal
    part = path.with_suffix(".part")
    part.write_text(f"cpu  0 0 0 {idle} 0 0 0 {steal} 0 0\n")
    os.replace(part, path)


def test_a_monitor_keeps_the_block_s_share_and_its_worst_interval(tmp_path: Path):
    """The host takes 0 of the first 1000 ticks' worth, then 90 of 1000 in one burst, then 10
    of 1000: over the block 100 / 3000, at worst 9 % in one interval."""
    stat = tmp_path / "stat"
    _write_stat(stat, 0, 0)
    with StealMonitor(interval_s=0.05, path=stat) as monitor:
        for total, steal in ((1000, 0), (2000, 90), (3000, 100)):
            time.sleep(0.2)  # several samples of each state
            _write_stat(stat, total, steal)
        time.sleep(0.2)
    assert monitor.share == pytest.approx(100 / 3000)
    assert monitor.peak == pytest.approx(0.09)
    assert monitor.describe() == "3.3 % (peak 9.0 %)"


def test_a_monitor_without_counters_knows_nothing(tmp_path: Path):
    with StealMonitor(interval_s=0.01, path=tmp_path / "missing") as monitor:
        time.sleep(0.05)
    assert monitor.share is None and monitor.peak is None and monitor.describe() == "-"
    with pytest.raises(ValueError, match="interval_s"):
        StealMonitor(interval_s=0.0)
