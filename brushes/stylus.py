"""One reading of a stylus (pen tablet, mouse or haptic device), validated at construction.

Canvas frame (metres, right-handed, as the painter sees it): origin at the canvas's bottom-left
corner, x right, y up, z out of the canvas plane toward the painter. Tilt follows
:mod:`common.tilt`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from common.errors import InputError

MAX_BUTTONS = 2**31 - 1
#: Largest coordinate of a position, metres: far beyond any canvas or device workspace, and small
#: enough that grid indices computed from it stay exact.
MAX_POSITION_M = 1e6


def _finite_vector(value: Any, size: int, key: str) -> np.ndarray:
    try:
        arr = np.array(value, dtype=float)
    except OverflowError:  # an integer beyond floating point's range
        raise InputError(f"expected {size} finite numbers, got a huge integer", key=key) from None
    except (TypeError, ValueError):
        raise InputError(f"expected {size} numbers, got {value!r:.80}", key=key) from None
    if arr.shape != (size,):
        raise InputError(f"expected {size} numbers, got shape {arr.shape}", key=key)
    if not np.all(np.isfinite(arr)):
        raise InputError(f"expected finite numbers, got {arr.tolist()}", key=key)
    return arr


def _finite(value: Any, key: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | np.number):
        raise InputError(f"expected a number, got {value!r:.80}", key=key)
    try:
        value = float(value)
    except OverflowError:  # an integer beyond floating point's range
        raise InputError("expected a finite number, got a huge integer", key=key) from None
    if not math.isfinite(value):
        raise InputError(f"expected a finite number, got {value}", key=key)
    return value


@dataclass(frozen=True)
class StylusSample:
    """A timestamped stylus reading.

    Attributes:
        t_s: time (s).
        position_m: (3,) tip position in the canvas frame (m). A tablet gives z = 0 (ignored); a
            haptic device gives a real height above the canvas plane.
        pressure: 0..1 (a haptic device may leave it 0; its z says how deep it presses).
        tilt_rad: (2,) ``[tilt_x, tilt_y]`` (rad), each within [-pi/2, pi/2].
        twist_rad: rotation of the pen about its own axis (rad).
        buttons: bit mask of pressed buttons (>= 0).

    Raises :class:`InputError` naming the field for a non-finite or out-of-range value.
    """

    t_s: float
    position_m: np.ndarray
    pressure: float = 0.0
    tilt_rad: np.ndarray = field(default_factory=lambda: np.zeros(2))
    twist_rad: float = 0.0
    buttons: int = 0

    def __post_init__(self) -> None:
        t = _finite(self.t_s, "t_s")
        pos = _finite_vector(self.position_m, 3, "position_m")
        if np.any(np.abs(pos) > MAX_POSITION_M):
            raise InputError(
                f"expected coordinates within +-{MAX_POSITION_M:g} m, got {pos.tolist()}",
                key="position_m",
            )
        pressure = _finite(self.pressure, "pressure")
        if not 0.0 <= pressure <= 1.0:
            raise InputError(f"expected a pressure in [0, 1], got {pressure}", key="pressure")
        tilt = _finite_vector(self.tilt_rad, 2, "tilt_rad")
        if np.any(np.abs(tilt) > 0.5 * math.pi):
            raise InputError(
                f"expected tilts in [-pi/2, pi/2], got {tilt.tolist()}", key="tilt_rad"
            )
        twist = _finite(self.twist_rad, "twist_rad")
        buttons = self.buttons
        if isinstance(buttons, bool) or not isinstance(buttons, int | np.integer):
            raise InputError(f"expected an integer bit mask, got {buttons!r}", key="buttons")
        if not 0 <= buttons <= MAX_BUTTONS:
            raise InputError(
                f"expected 0 <= buttons <= {MAX_BUTTONS}, got {buttons}", key="buttons"
            )
        pos.flags.writeable = False
        tilt.flags.writeable = False
        for name, value in (
            ("t_s", t),
            ("position_m", pos),
            ("pressure", pressure),
            ("tilt_rad", tilt),
            ("twist_rad", twist),
            ("buttons", int(buttons)),
        ):
            object.__setattr__(self, name, value)
