"""The last stage before a device: nothing unsafe ever reaches it.

Every tick the commanded force and torque pass through, in order:

1. **Finite check.** A non-finite force or torque becomes zero, is counted, and counts as a fault.
2. **Engage and ramp.** Output is zero while *waiting*: on start and after any fault the stage
   waits until the commanded force (and torque) is small (chai3d-style), then ramps the gain
   from 0 to 1 over ``ramp_time_s``.
3. **Clamp** the magnitudes to the device limits (direction kept).
4. **Rate limit**: the output vector moves at most ``rate * dt`` per tick. On a fault the output
   drops to zero at once (removing force is the safe direction).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

import numpy as np

from common.errors import InputError
from paintapp.haptics.device import DeviceInfo


class SafetyState(Enum):
    """Where the engage state machine is."""

    WAITING = "waiting"
    RAMPING = "ramping"
    ENGAGED = "engaged"


@dataclass(frozen=True)
class SafetyConfig:
    """Safety parameters. Rates default to the full limit in ``full_scale_time_s``.

    Attributes:
        ramp_time_s: time to ramp the output gain from 0 to 1 after engaging.
        engage_fraction: engage once the commanded force is below this fraction of the limit.
        full_scale_time_s: the rate limit lets the output go from zero to the limit in this time.
    """

    ramp_time_s: float = 0.5
    engage_fraction: float = 0.1
    full_scale_time_s: float = 0.01

    def __post_init__(self) -> None:
        for name in ("ramp_time_s", "engage_fraction", "full_scale_time_s"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise InputError(f"must be finite and positive, got {value}", key=name)


def _norm(v: np.ndarray) -> float:
    return math.hypot(*v.tolist())  # no overflow for huge finite values; nan/inf if non-finite


def _clamp(v: np.ndarray, limit: float) -> tuple[np.ndarray, bool]:
    n = _norm(v)
    if n > limit:
        return v * (limit / n), True
    return v, False


def _step_toward(prev: np.ndarray, target: np.ndarray, max_step: float) -> tuple[np.ndarray, bool]:
    d = target - prev
    n = _norm(d)
    if n > max_step:
        return prev + d * (max_step / n), True
    return target, False


class ForceSafety:
    """Sanitizes, engages, clamps and rate-limits force and torque for one device.

    Args:
        info: the device; its ``max_force_n`` and ``max_torque_nm`` are the limits.
        config: safety parameters.
    """

    def __init__(self, info: DeviceInfo, config: SafetyConfig | None = None) -> None:
        self.config = config or SafetyConfig()
        self.max_force_n = info.max_force_n if info.has_force else 0.0
        self.max_torque_nm = info.max_torque_nm if info.has_torque else 0.0
        self.nonfinite_count = 0
        self.clamped_count = 0
        self.rate_limited_count = 0
        self.fault_count = 0
        self.reset()

    def reset(self) -> None:
        """Back to the start: waiting, zero output."""
        self.state = SafetyState.WAITING
        self.gain = 0.0
        self._force = np.zeros(3)
        self._torque = np.zeros(3)

    def fault(self) -> None:
        """Report a fault: the output drops to zero and the engage sequence starts over."""
        self.fault_count += 1
        self.reset()

    def _small(self, force: np.ndarray, torque: np.ndarray) -> bool:
        frac = self.config.engage_fraction
        force_ok = self.max_force_n == 0.0 or _norm(force) <= frac * self.max_force_n
        torque_ok = self.max_torque_nm == 0.0 or _norm(torque) <= frac * self.max_torque_nm
        return force_ok and torque_ok

    def _advance_gain(self, force: np.ndarray, torque: np.ndarray, dt_s: float) -> None:
        if self.state is SafetyState.WAITING and self._small(force, torque):
            self.state = SafetyState.RAMPING
        if self.state is SafetyState.RAMPING:
            self.gain = min(1.0, self.gain + dt_s / self.config.ramp_time_s)
            if self.gain >= 1.0:
                self.state = SafetyState.ENGAGED

    def apply(
        self, force_n: np.ndarray, torque_nm: np.ndarray, dt_s: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """Make a commanded force (N, (3,)) and torque (N m, (3,)) safe for a tick of ``dt_s``.

        Returns:
            The force and torque to write; always finite and within the limits.
        """
        if not (math.isfinite(_norm(force_n)) and math.isfinite(_norm(torque_nm))):
            self.nonfinite_count += 1
            self.fault()
            return self._force, self._torque
        dt_s = dt_s if math.isfinite(dt_s) and dt_s > 0 else 0.0
        self._advance_gain(force_n, torque_nm, dt_s)
        force, clamped_f = _clamp(self.gain * force_n, self.max_force_n)
        torque, clamped_t = _clamp(self.gain * torque_nm, self.max_torque_nm)
        self.clamped_count += clamped_f or clamped_t
        full = self.config.full_scale_time_s
        self._force, limited_f = _step_toward(self._force, force, self.max_force_n * dt_s / full)
        self._torque, limited_t = _step_toward(
            self._torque, torque, self.max_torque_nm * dt_s / full
        )
        self.rate_limited_count += limited_f or limited_t
        return self._force, self._torque

    def counters(self) -> dict[str, int]:
        """Event counts since construction."""
        return {
            "nonfinite": self.nonfinite_count,
            "clamped": self.clamped_count,
            "rate_limited": self.rate_limited_count,
            "faults": self.fault_count,
        }
