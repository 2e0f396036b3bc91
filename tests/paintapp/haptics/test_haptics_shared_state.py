"""Shared-memory latest-value records: round trips through a second mapping, and seqlock
consistency against a writer in another process."""

from __future__ import annotations

import multiprocessing as mp

import numpy as np
import pytest

from paintapp.haptics.channel import ForceSample
from paintapp.haptics.device import DeviceState
from paintapp.haptics.shared_state import (
    SharedBlock,
    SharedForceChannel,
    SharedStateChannel,
    SharedTarget,
)
from tests.support.servo_harness import seqlock_writer


@pytest.fixture
def blocks():
    owner = SharedBlock()
    other = SharedBlock(owner.name)
    yield owner, other
    other.close()
    owner.close()


def test_force_and_state_round_trip_between_mappings(blocks):
    owner, other = blocks
    writer, reader = SharedForceChannel(owner.force), SharedForceChannel(other.force)
    assert reader.latest() == (0, None) and reader.seq == 0
    assert writer.publish_force(1.5, [0.1, -0.2, 0.3], [0.0, 0.01, 0.0]) == 1
    seq, sample = reader.latest()
    assert seq == 1 and reader.seq == 1 and isinstance(sample, ForceSample)
    assert sample.t_s == 1.5
    np.testing.assert_array_equal(sample.force, [0.1, -0.2, 0.3])
    np.testing.assert_array_equal(sample.torque, [0.0, 0.01, 0.0])
    assert reader.latest()[1] is sample  # unchanged: the cached sample, no copy
    writer.publish_force(2.0, [np.nan, 0, 0])  # non-finite passes through; the loop rejects it
    assert reader.latest()[0] == 2 and np.isnan(reader.latest()[1].force[0])

    states_w, states_r = SharedStateChannel(other.state), SharedStateChannel(owner.state)
    q = np.array([0.9, 0.1, 0.3, 0.3]) / np.linalg.norm([0.9, 0.1, 0.3, 0.3])
    states_w.publish(DeviceState(3.0, np.array([1e-3, 2e-3, -4e-4]), q, 0.7, 5, np.ones(3)))
    seq, state = states_r.latest()
    assert seq == 1 and state.t_s == 3.0 and state.pressure == 0.7 and state.buttons == 5
    np.testing.assert_array_equal(state.position_m, [1e-3, 2e-3, -4e-4])
    np.testing.assert_array_equal(state.orientation_wxyz, q)
    np.testing.assert_array_equal(state.velocity_m_per_s, np.ones(3))


def test_target_keeps_the_last_finite_position(blocks):
    owner, other = blocks
    app, device = SharedTarget(owner.target), SharedTarget(other.target, (0.01, 0.02, 0.005))
    np.testing.assert_array_equal(device(0.0)[0], [0.01, 0.02, 0.005])
    app.set_position([0.03, 0.04, -0.001])
    np.testing.assert_array_equal(device(0.0)[0], [0.03, 0.04, -0.001])
    app.set_position([np.inf, 0.0, 0.0])
    np.testing.assert_array_equal(device(0.0)[0], [0.03, 0.04, -0.001])


def test_a_writer_stuck_mid_write_never_blocks_a_reader(blocks):
    owner, other = blocks
    SharedForceChannel(owner.force).publish_force(1.0, [1.0, 0.0, 0.0])
    reader = SharedForceChannel(other.force)
    seq, sample = reader.latest()
    owner.force._version[0] += 1  # as if the writer died between its two version stores
    owner.force.data[:] = 99.0
    assert other.force.read(np.empty(7), retries=50) is None
    assert reader.latest() == (seq, sample)  # keeps the last consistent sample


def test_seqlock_reads_are_consistent_under_a_concurrent_writer(blocks):
    owner, other = blocks
    writes = 200_000
    proc = mp.get_context("spawn").Process(target=seqlock_writer, args=(owner.name, writes))
    proc.start()
    out = np.empty(7)
    seen, consistent, last = 0, 0, 0
    try:
        while proc.is_alive() or seen == 0:
            got = other.force.read(out)
            seen += 1
            if got is None:
                continue
            consistent += 1
            assert np.all(out == out[0]), f"torn read: {out}"
            assert got >= last and (got == 0 or out[0] == got)
            last = got
            if seen > 5_000_000:
                break
    finally:
        proc.join(60)
        if proc.is_alive():
            proc.kill()
    assert proc.exitcode == 0
    assert consistent > 0 and other.force.count == writes
    assert other.force.read(out) == writes and np.all(out == writes)
