"""A synthetic fluid force source: the servo loop's counterpart when no solver is running.

It plays the part of the painting session: at the simulation's own rate it reads the latest
published tip state and publishes a force sample: the drag of a viscous layer on the tip,
``F = -c v`` while the tip is below the layer's top (no torque). Because the sample is computed
from a state that is already old when it is published, and is then filtered, the drag reaches
the hand late: with a large force scale this delayed damping pumps energy into the hand, the
instability the paper warns about (section 5.1).
"""

from __future__ import annotations

import threading
import time

import numpy as np

from paintapp.haptics.channel import ForceChannel, ForceSample, StateChannel


class ViscousDragSource:
    """Publishes ``F = -drag * v`` for the latest tip state, one sample per :meth:`step`.

    Args:
        states: where the servo loop publishes tip states (canvas frame).
        forces: where to publish the force samples.
        drag_ns_per_m: drag coefficient c, N s/m.
        layer_top_m: the drag acts while the tip is below this height above the canvas, m.
    """

    def __init__(
        self,
        states: StateChannel,
        forces: ForceChannel,
        drag_ns_per_m: float = 0.5,
        layer_top_m: float = 0.01,
    ) -> None:
        self.states = states
        self.forces = forces
        self.drag_ns_per_m = float(drag_ns_per_m)
        self.layer_top_m = float(layer_top_m)
        self.published = 0

    def force_for(self, position_m: np.ndarray, velocity_m_per_s: np.ndarray) -> np.ndarray:
        """The drag force, N, (3,), for a tip at ``position_m`` moving at ``velocity_m_per_s``."""
        if position_m[2] > self.layer_top_m:
            return np.zeros(3)
        return -self.drag_ns_per_m * np.asarray(velocity_m_per_s, dtype=np.float64)

    def step(self, t_s: float) -> ForceSample | None:
        """Publish one sample for the latest tip state (none before the first state)."""
        _, state = self.states.latest()
        if state is None:
            return None
        sample = ForceSample(
            t_s, self.force_for(state.position_m, state.velocity_m_per_s), np.zeros(3)
        )
        self.forces.publish(sample)
        self.published += 1
        return sample


def run_source_thread(
    source: ViscousDragSource, rate_hz: float, stop: threading.Event
) -> threading.Thread:
    """Step ``source`` at about ``rate_hz`` in a daemon thread until ``stop`` is set."""

    def loop() -> None:
        period = 1.0 / rate_hz
        while not stop.wait(period):
            source.step(time.perf_counter())

    thread = threading.Thread(target=loop, name="synthetic-fluid", daemon=True)
    thread.start()
    return thread
