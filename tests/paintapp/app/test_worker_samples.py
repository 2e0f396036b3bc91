"""Which tablet samples the simulation worker steps on when it falls behind: the stroke stays a
trail (no jump from its start to its end), and the work stays bounded."""

from __future__ import annotations

import numpy as np

from brushes import StylusSample
from paintapp.app.worker import MAX_TRAIL_STEPS, keep_samples


def _sample(t: float, x: float, pressure: float) -> StylusSample:
    return StylusSample(t, np.array([x, 0.05, 0.0]), pressure)


def _stroke(n: int = 41, length_m: float = 0.04) -> list[StylusSample]:
    """A hover sample, a straight stroke of ``n`` pressed samples, and the pen-up."""
    xs = np.linspace(0.02, 0.02 + length_m, n)
    hover = [_sample(0.0, 0.02, 0.0)]
    pressed = [_sample(0.01 * (i + 1), float(x), 0.8) for i, x in enumerate(xs)]
    return hover + pressed + [_sample(0.01 * (n + 1), float(xs[-1]), 0.0)]


def test_a_whole_stroke_in_one_pass_keeps_a_trail_from_touch_down_to_lift_off():
    batch = _stroke()
    spacing = 0.004
    kept = keep_samples(batch, None, spacing)
    down = [s for s in kept if s.pressure > 0]
    assert down[0] is batch[1]  # the touch-down itself, not only where the pen was last
    assert down[-1] is batch[-2]  # the last pressed sample before the pen-up
    assert kept[-1] is batch[-1] and kept[-1].pressure == 0.0
    gaps = np.diff([s.position_m[0] for s in down])
    step = 0.04 / 40
    assert gaps.max() <= spacing + step  # no jump along the stroke
    assert len(down) < len(batch) // 3  # and far fewer steps than samples


def test_a_dense_batch_continues_from_the_previous_pass():
    stroke = _stroke()
    first, second = stroke[:11], stroke[11:]
    kept = keep_samples(second, first[-1], 0.004)
    gaps = np.diff([first[-1].position_m[0]] + [s.position_m[0] for s in kept if s.pressure > 0])
    assert gaps.max() <= 0.004 + 0.001


def test_hovering_collapses_to_the_newest_sample():
    batch = [_sample(0.01 * i, 0.02 + 0.001 * i, 0.0) for i in range(30)]
    assert keep_samples(batch, None, 0.004) == [batch[-1]]


def test_a_long_backlog_is_caught_up_in_a_bounded_number_of_steps():
    batch = _stroke(n=2001, length_m=0.5)  # half a metre of stroke behind
    kept = keep_samples(batch, None, 0.001)
    down = [s for s in kept if s.pressure > 0]
    assert len(down) <= MAX_TRAIL_STEPS + 3
    gaps = np.diff([s.position_m[0] for s in down])
    assert gaps.max() <= 0.5 / MAX_TRAIL_STEPS + 0.5 / 2000  # evenly spread, no single jump
