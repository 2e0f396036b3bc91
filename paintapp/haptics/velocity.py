"""Tip velocity from timestamped positions, shared by every device.

Differentiating encoder positions amplifies their quantization noise, so the finite difference
between successive *new* readings is passed through a first-order low-pass filter with time
constant ``tau_s`` (a 5 ms default gives a 32 Hz corner, above the hand's few hertz). Readings
with the same timestamp as the previous one (a device that has not updated) are ignored, as are
non-finite positions, so the estimate simply holds.
"""

from __future__ import annotations

import math

import numpy as np


class VelocityEstimator:
    """Low-pass filtered finite-difference velocity.

    Args:
        tau_s: filter time constant in seconds; 0 gives the raw finite difference.
        max_gap_s: a gap between readings longer than this restarts the estimate at zero (a
            device that stalled and came back must not produce a velocity spike).
    """

    def __init__(self, tau_s: float = 5e-3, max_gap_s: float = 0.1) -> None:
        self.tau_s = max(float(tau_s), 0.0)
        self.max_gap_s = float(max_gap_s)
        self.reset()

    def reset(self) -> None:
        """Forget the history; the velocity is zero until two readings have arrived."""
        self._t_s: float | None = None
        self._x = np.zeros(3)
        self._v = np.zeros(3)

    @property
    def velocity_m_per_s(self) -> np.ndarray:
        """The current estimate, m/s, shape (3,)."""
        return self._v

    def update(self, t_s: float, position_m: np.ndarray) -> np.ndarray:
        """Add a reading taken at ``t_s`` seconds at ``position_m`` (3,); returns the velocity."""
        if not (math.isfinite(t_s) and np.isfinite(position_m).all()):
            return self._v
        if self._t_s is None:
            self._t_s, self._x = t_s, np.array(position_m, dtype=np.float64)
            return self._v
        dt = t_s - self._t_s
        if dt <= 0.0:
            return self._v
        position = np.array(position_m, dtype=np.float64)
        if dt > self.max_gap_s:
            self._v = np.zeros(3)
        else:
            raw = (position - self._x) / dt
            alpha = 1.0 if self.tau_s == 0.0 else 1.0 - math.exp(-dt / self.tau_s)
            self._v = self._v + alpha * (raw - self._v)
        self._t_s, self._x = t_s, position
        return self._v
