"""The fluid force path of the servo loop: latest sample -> checks -> filter -> watchdog -> scale.

Each tick :meth:`FluidForceInput.update` looks at the :class:`ForceChannel`. A sample it has not
seen before is stamped with the tick time (the simulation's own clock may drift from the servo
clock) and, if it is finite and not an absurd spike, pushed into the reconstruction filter.
Rejected samples are counted, the filter keeps its previous input, and they do not feed the
watchdog: a simulation that publishes only garbage counts as stalled.

Watchdog: if no fresh sample has arrived for ``watchdog_timeout_s`` (the simulation stalled or
died), a gain fades the fluid force to zero over ``fade_time_s`` instead of holding a stale value;
once it reaches zero the filter is cleared so the stale value cannot come back. When samples
resume the gain fades back in over the same time.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from common.errors import InputError
from paintapp.haptics.channel import ForceChannel
from paintapp.haptics.filters import ReconstructionFilter


@dataclass(frozen=True)
class FluidConfig:
    """Fluid force parameters.

    Attributes:
        force_scale: user-set scale on the simulated force (the paper uses 2-10); 0 turns the
            fluid force off.
        torque_scale: scale on the simulated torque; None uses ``force_scale``.
        watchdog_timeout_s: age of the newest sample after which the fluid force fades.
        fade_time_s: time to fade out (and back in).
        spike_limit_n: a sample whose *scaled* force exceeds this is rejected as a spike; None
            uses ten times the device's force limit.
    """

    force_scale: float = 4.0
    torque_scale: float | None = None
    watchdog_timeout_s: float = 0.1
    fade_time_s: float = 0.1
    spike_limit_n: float | None = None

    def __post_init__(self) -> None:
        for name in ("force_scale", "torque_scale", "spike_limit_n"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value >= 0):
                raise InputError(f"must be finite and >= 0, got {value}", key=name)
        for name in ("watchdog_timeout_s", "fade_time_s"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise InputError(f"must be finite and positive, got {value}", key=name)


class FluidForceInput:
    """Reads the force channel once per tick and produces the scaled, filtered fluid force.

    Args:
        channel: where the simulation publishes.
        filt: the reconstruction filter (dimension 6: force then torque; dimension 3: force
            only, for a device without torque output -- the torque is then always zero).
        config: scale, watchdog and spike parameters.
        max_force_n: the device's force limit (for the default spike limit).
    """

    def __init__(
        self,
        channel: ForceChannel,
        filt: ReconstructionFilter,
        config: FluidConfig | None = None,
        max_force_n: float = 10.0,
    ) -> None:
        self.channel = channel
        self.filter = filt
        self.config = config or FluidConfig()
        self.torque_scale = (
            self.config.force_scale
            if self.config.torque_scale is None
            else self.config.torque_scale
        )
        limit = self.config.spike_limit_n
        self.spike_limit_n = 10.0 * max_force_n if limit is None else limit
        self._seen_seq = channel.seq
        self._last_arrival_s: float | None = None
        self.gain = 0.0
        self.fresh_samples = 0
        self.rejected_nonfinite = 0
        self.rejected_spikes = 0
        self.watchdog_trips = 0

    def _take_fresh(self, t_s: float) -> None:
        seq, sample = self.channel.latest()
        if seq == self._seen_seq or sample is None:
            return
        self._seen_seq = seq
        value = np.concatenate([sample.force, sample.torque])
        if self.filter.dim == 3:
            value = value[:3]
        if not np.all(np.isfinite(value)):
            self.rejected_nonfinite += 1
            return
        if self.config.force_scale * math.hypot(*sample.force) > (self.spike_limit_n):
            self.rejected_spikes += 1
            return
        self.fresh_samples += 1
        self._last_arrival_s = t_s
        self.filter.push(t_s, value)

    def _update_gain(self, t_s: float, dt_s: float) -> None:
        alive = (
            self._last_arrival_s is not None
            and t_s - self._last_arrival_s <= self.config.watchdog_timeout_s
        )
        step = dt_s / self.config.fade_time_s
        if alive:
            self.gain = min(1.0, self.gain + step)
        elif self.gain > 0.0:
            self.gain = max(0.0, self.gain - step)
            if self.gain == 0.0:
                self.watchdog_trips += 1
                self.filter.reset()

    def set_scale(self, force_scale: float, torque_scale: float | None = None) -> None:
        """Change the user's force scale (and torque scale; None: the same) while running.

        Two attribute swaps; the loop reads them once per tick. Raises InputError for a
        non-finite or negative scale.
        """
        self.config = replace(self.config, force_scale=force_scale, torque_scale=torque_scale)
        self.torque_scale = force_scale if torque_scale is None else torque_scale

    def update(self, t_s: float, dt_s: float) -> tuple[np.ndarray, np.ndarray]:
        """Fluid force (N, (3,)) and torque (N m, (3,)) for the tick at ``t_s`` of length ``dt_s``."""
        self._take_fresh(t_s)
        self._update_gain(t_s, dt_s)
        out = self.filter.output(t_s)
        g = self.gain
        torque = (g * self.torque_scale) * out[3:] if len(out) > 3 else np.zeros(3)
        return (g * self.config.force_scale) * out[:3], torque

    def counters(self) -> dict[str, int]:
        """Event counts since construction."""
        return {
            "fresh_samples": self.fresh_samples,
            "rejected_nonfinite": self.rejected_nonfinite,
            "rejected_spikes": self.rejected_spikes,
            "watchdog_trips": self.watchdog_trips,
        }
