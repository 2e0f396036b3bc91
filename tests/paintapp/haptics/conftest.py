"""Shared pieces of the haptics tests: a closed loop of simulated hand, servo and synthetic fluid."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pytest

from paintapp.haptics.clock import VirtualClock
from paintapp.haptics.devices.simulated import SimulatedDevice
from paintapp.haptics.servo import ServoConfig, ServoLoop
from paintapp.haptics.synthetic import ViscousDragSource


@dataclass
class ClosedLoop:
    """Hand + device + servo loop + a synthetic fluid stepping at an irregular ~60 Hz."""

    clock: VirtualClock
    device: SimulatedDevice
    loop: ServoLoop
    source: ViscousDragSource
    rng: np.random.Generator
    max_energy_j: float = 0.0
    next_sim_s: float = 0.0

    def run(self, seconds: float, on_sim: Callable[[float], bool] | None = None) -> None:
        """Run ``seconds``; ``on_sim(t)`` may replace a simulation step (return True if it did)."""

        def tick(_i: int, t: float) -> bool:
            if t >= self.next_sim_s:
                if on_sim is None or not on_sim(t):
                    self.source.step(t)
                self.next_sim_s = t + self.rng.uniform(0.012, 0.022)
            ok = self.loop.tick(t)
            self.max_energy_j = max(self.max_energy_j, self.device.energy_j())
            return ok

        self.clock.run(tick, round(seconds / self.clock.period_s))


@pytest.fixture
def closed_loop() -> Callable[..., ClosedLoop]:
    """Factory: ``closed_loop(config=..., device_kwargs=..., drag_ns_per_m=..., seed=...)``."""

    def make(
        config: ServoConfig | None = None,
        drag_ns_per_m: float = 0.5,
        seed: int = 0,
        **device_kwargs: object,
    ) -> ClosedLoop:
        clock = VirtualClock()
        device = SimulatedDevice(clock.now_s, **device_kwargs)
        loop = ServoLoop(device, config=config)
        loop.open()
        source = ViscousDragSource(loop.states, loop.forces, drag_ns_per_m=drag_ns_per_m)
        return ClosedLoop(clock, device, loop, source, np.random.default_rng(seed))

    return make
