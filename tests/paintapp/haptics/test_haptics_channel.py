"""Force and state channels: latest value, freshness, thread safety."""

from __future__ import annotations

import threading

import numpy as np
import pytest

from paintapp.haptics.channel import ForceChannel, ForceSample


def test_latest_sample_and_sequence() -> None:
    ch = ForceChannel()
    assert ch.latest() == (0, None)
    assert ch.publish_force(0.1, [1.0, 2.0, 3.0]) == 1
    ch.publish(ForceSample(0.2, np.zeros(3), [0.0, 0.0, 1.0]))
    seq, sample = ch.latest()
    assert seq == 2 and sample is not None
    assert sample.t_s == 0.2 and sample.torque[2] == 1.0


def test_sample_copies_its_arrays_and_checks_shapes() -> None:
    f = np.array([1.0, 2.0, 3.0])
    s = ForceSample(0.0, f, np.zeros(3))
    f[0] = 99.0
    assert s.force[0] == 1.0
    with pytest.raises(ValueError):
        s.force[0] = 5.0  # read-only
    with pytest.raises(ValueError, match="shape"):
        ForceSample(0.0, np.zeros(2), np.zeros(3))


def test_non_finite_samples_can_be_published() -> None:
    """The channel carries them; the servo loop is what rejects them."""
    ch = ForceChannel()
    ch.publish_force(0.0, [np.nan, 0.0, 0.0])
    assert np.isnan(ch.latest()[1].force[0])


def test_reader_sees_consistent_samples_while_a_writer_publishes() -> None:
    ch = ForceChannel()
    stop = threading.Event()

    def writer() -> None:
        k = 0
        while not stop.is_set():
            k += 1
            ch.publish_force(float(k), [k, k, k], [k, k, k])

    thread = threading.Thread(target=writer)
    thread.start()
    last = 0
    try:
        for _ in range(20000):
            seq, s = ch.latest()
            assert seq >= last
            last = seq
            if s is not None:
                assert np.all(s.force == s.t_s) and np.all(s.torque == s.t_s)
    finally:
        stop.set()
        thread.join()
