"""Latest-value channels between the simulation and the 1 kHz servo loop.

The simulation publishes a :class:`ForceSample` whenever it finishes a step (30-200 Hz, not
steady); the servo loop reads the newest one every tick and never waits for it. The servo loop in
turn publishes the newest device state for the painting session to consume at its own rate.

A channel keeps only the latest value plus a sequence number that counts publications, so a reader
can tell a fresh value from one it has already seen. Publishing and reading take a lock for a few
hundred nanoseconds; neither side ever blocks on the other's work.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from typing import Generic, TypeVar

import numpy as np
import numpy.typing as npt

from paintapp.haptics.device import DeviceState

T = TypeVar("T")


def _vector3(value: object, name: str) -> np.ndarray:
    """Copy ``value`` into a read-only float64 array of shape (3,)."""
    arr = np.array(value, dtype=np.float64)
    if arr.shape != (3,):
        raise ValueError(f"{name} must have shape (3,), got {arr.shape}")
    arr.flags.writeable = False
    return arr


@dataclass(frozen=True, slots=True)
class ForceSample:
    """One force/torque result of the simulation, in the canvas frame.

    Attributes:
        t_s: simulation time of the sample in seconds (kept for logs; the servo loop stamps each
            sample with its own clock when the sample arrives).
        force: force on the brush tip in newtons, shape (3,). May be non-finite: the servo loop
            rejects such samples and counts them.
        torque: torque on the brush tip about its centre in newton-metres, shape (3,).
    """

    t_s: float
    force: np.ndarray
    torque: np.ndarray

    def __post_init__(self) -> None:
        object.__setattr__(self, "t_s", float(self.t_s))
        object.__setattr__(self, "force", _vector3(self.force, "force"))
        object.__setattr__(self, "torque", _vector3(self.torque, "torque"))


class LatestValue(Generic[T]):
    """A thread-safe slot holding the most recently published value and a publication count."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._seq = 0
        self._value: T | None = None

    def publish(self, value: T) -> int:
        """Replace the held value; returns its sequence number (1 for the first publication)."""
        with self._lock:
            self._seq += 1
            self._value = value
            return self._seq

    def latest(self) -> tuple[int, T | None]:
        """The sequence number and value last published; ``(0, None)`` before any publication."""
        with self._lock:
            return self._seq, self._value

    @property
    def seq(self) -> int:
        """How many values have been published so far."""
        return self._seq


class ForceChannel(LatestValue[ForceSample]):
    """Where the simulation publishes force samples and the servo loop reads the latest one."""

    def publish_force(
        self, t_s: float, force: npt.ArrayLike, torque: npt.ArrayLike | None = None
    ) -> int:
        """Publish ``force`` (N, shape (3,)) and ``torque`` (N m, shape (3,), default zero) at ``t_s``."""
        force_n = _vector3(force, "force")
        torque_nm = np.zeros(3) if torque is None else _vector3(torque, "torque")
        return self.publish(ForceSample(t_s, force_n, torque_nm))


class StateChannel(LatestValue[DeviceState]):
    """Where the servo loop publishes the latest device state for the painting session."""
