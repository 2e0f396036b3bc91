"""Replay a recorded stroke through the servo loop and record the forces that were output.

A stroke is a sequence of samples with attributes ``t_s`` (s), ``position_m`` ((3,), canvas
frame, z = 0 on the canvas, z < 0 below it), ``pressure`` ([0, 1]), ``tilt_rad`` ((2,)),
``twist_rad`` and ``buttons`` -- the records of :func:`paintapp.strokes.files.read_strokes`, or anything
shaped like them. Between samples, position, pressure, tilt and twist are interpolated linearly;
buttons take the earlier sample's value. The replay's time starts when the device is opened.

Every :meth:`ReplayDevice.write` is recorded (time, force, torque), so a replay yields the force
trace the painter would have felt; the trace survives a loop that stopped early.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

import numpy as np

from common.errors import InputError
from paintapp.haptics.device import DeviceError, DeviceInfo, DeviceState
from paintapp.haptics.devices.simulated import SIMULATED_INFO
from paintapp.haptics.orientation import quat_from_tilt_twist


def _stack_samples(samples: Iterable[Any], source: str | None) -> dict[str, np.ndarray]:
    rows: dict[str, list] = {k: [] for k in ("t", "pos", "pressure", "tilt", "twist", "buttons")}
    for i, s in enumerate(samples):
        try:
            rows["t"].append(float(s.t_s))
            rows["pos"].append(np.asarray(s.position_m, dtype=np.float64).reshape(3))
            rows["pressure"].append(float(s.pressure))
            rows["tilt"].append(np.asarray(s.tilt_rad, dtype=np.float64).reshape(2))
            rows["twist"].append(float(s.twist_rad))
            rows["buttons"].append(int(s.buttons))
        except (AttributeError, TypeError, ValueError) as exc:
            raise InputError(f"sample {i} is malformed: {exc}", source=source) from exc
    if not rows["t"]:
        raise InputError("the stroke has no samples", source=source)
    return {k: np.array(v) for k, v in rows.items()}


def _validate(data: dict[str, np.ndarray], source: str | None) -> None:
    for key in ("t", "pos", "pressure", "tilt", "twist"):
        bad = np.flatnonzero(~np.all(np.isfinite(data[key].reshape(len(data["t"]), -1)), axis=1))
        if len(bad):
            raise InputError(f"sample {bad[0]} has a non-finite value", source=source, key=key)
    back = np.flatnonzero(np.diff(data["t"]) < 0)
    if len(back):
        raise InputError(f"time goes backwards at sample {back[0] + 1}", source=source, key="t_s")
    outside = np.flatnonzero((data["pressure"] < 0) | (data["pressure"] > 1))
    if len(outside):
        raise InputError(
            f"sample {outside[0]} has pressure outside [0, 1]", source=source, key="pressure"
        )


class ReplayDevice:
    """Plays back stroke samples as device states (implements :class:`HapticDevice`).

    Args:
        samples: the stroke's samples (see the module docstring).
        time_source: returns the current time in seconds (a clock's ``now_s``).
        info: the capabilities to claim; by default those of the simulated 6-DOF stylus, so the
            loop computes and records the full force.
        source: name of the stroke file, for error messages.
    """

    def __init__(
        self,
        samples: Iterable[Any],
        time_source: Callable[[], float],
        info: DeviceInfo | None = None,
        source: str | None = None,
    ) -> None:
        data = _stack_samples(samples, source)
        _validate(data, source)
        self._t = data["t"] - data["t"][0]
        #: Per sample, what is interpolated between samples: position (3), tilt (2), twist
        #: (unwrapped) and pressure, one row each (one interpolation a read).
        self._rows = np.column_stack(
            [data["pos"], data["tilt"], np.unwrap(data["twist"]), data["pressure"]]
        )
        #: Per sample: whether its tilt and twist equal the next sample's (then the read takes
        #: them as they are, and the orientation is not computed again).
        self._held = np.append(np.all(self._rows[1:, 3:6] == self._rows[:-1, 3:6], axis=1), True)
        self._buttons = data["buttons"]
        #: The sample a read at the playback's time ``t`` starts from (``_t[k] <= t < _t[k+1]``),
        #: kept from the last read: the time only moves forward, a sample at a time.
        self._k = 0
        self.time_source = time_source
        self._info = info or SIMULATED_INFO
        self._t0: float | None = None
        self._now = 0.0
        self._forces: list[tuple[float, ...]] = []
        #: The last orientation computed, with the tilt and twist it was computed from: a
        #: stroke holds its tilt for many ticks, and the quaternion costs more than the rest of
        #: a read.
        self._last_quat: tuple[bytes, np.ndarray] | None = None

    @property
    def info(self) -> DeviceInfo:
        return self._info

    @property
    def duration_s(self) -> float:
        """Length of the stroke, s."""
        return float(self._t[-1])

    @property
    def finished(self) -> bool:
        """Whether playback has passed the last sample."""
        return self._t0 is not None and self._now >= self.duration_s

    def open(self) -> None:
        self._t0 = self.time_source()
        self._now = 0.0

    def close(self) -> None:
        self._t0 = None

    def _interp(self, t: float) -> tuple[int, float]:
        times, k = self._t, self._k
        if k + 1 < len(times) and times[k] <= t < times[k + 1]:
            span = times[k + 1] - times[k]
            return k, 0.0 if span <= 0 else (t - times[k]) / span
        k = int(np.searchsorted(times, t, side="right")) - 1
        self._k = max(k, 0)
        if k < 0:
            return 0, 0.0
        if k >= len(self._t) - 1:
            return len(self._t) - 2, 1.0
        span = self._t[k + 1] - self._t[k]
        return k, 0.0 if span <= 0 else (t - self._t[k]) / span

    def read(self) -> DeviceState:
        if self._t0 is None:
            raise DeviceError("replay device is not open")
        now = self.time_source()
        self._now = now - self._t0
        if len(self._t) == 1:
            k, a, j = 0, 0.0, 0
        else:
            k, a = self._interp(self._now)
            j = k + 1
        rows = self._rows
        row = (1 - a) * rows[k] + a * rows[j]
        angles = rows[k, 3:6] if self._held[k] else row[3:6]  # tilt and twist
        buttons = int(self._buttons[j if a >= 1.0 else k])
        return DeviceState(now, row[:3], self._quat(angles), float(row[6]), buttons)

    def _quat(self, angles: np.ndarray) -> np.ndarray:
        """:func:`quat_from_tilt_twist` of ``angles`` (tilt x, tilt y, twist), computed again
        only when they change."""
        key = angles.tobytes()  # bit for bit (a -0.0 is not 0.0)
        if self._last_quat is None or self._last_quat[0] != key:
            self._last_quat = (key, quat_from_tilt_twist(angles[:2], float(angles[2])))
        return self._last_quat[1].copy()

    def write(self, force_n: np.ndarray, torque_nm: np.ndarray) -> None:
        if self._t0 is None:
            raise DeviceError("replay device is not open")
        self._forces.append((self._now, *map(float, force_n), *map(float, torque_nm)))

    def recorded(self) -> dict[str, np.ndarray]:
        """The forces written so far: ``t_s`` (n,), ``force_n`` (n, 3), ``torque_nm`` (n, 3)."""
        table = np.array(self._forces, dtype=np.float64).reshape(-1, 7)
        return {"t_s": table[:, 0], "force_n": table[:, 1:4], "torque_nm": table[:, 4:7]}

    def save_forces(self, path: str | Path) -> None:
        """Write the recorded forces to an ``.npz`` file (plain arrays)."""
        np.savez(Path(path), allow_pickle=True, **self.recorded())
