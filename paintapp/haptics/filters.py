"""Reconstruction filters: from irregular simulation samples to a 1 kHz force signal.

The simulation delivers force samples at its own, unsteady rate (30-200 Hz); the servo loop needs
a value every tick. A filter takes samples with :meth:`ReconstructionFilter.push` (arrival time,
value) and gives one output per servo tick with :meth:`ReconstructionFilter.output`. Values are
vectors (force and torque stacked: shape (6,)).

Delay each filter adds (lag of a ramp), for samples published every ``T`` seconds at random phase
to servo ticks of ``dt`` (a sample is stamped with the tick that first sees it):

- zero-order hold: ``T/2`` on average (each value held for one period);
- linear: ``T + dt/2`` (interpolates between the last two samples: one sample behind);
- FIR window: ``T/2 + (N-1)/2 * dt`` (the hold, then a linear-phase FIR of N = order + 1 taps).

The paper's choice (section 4.2) is the FIR window filter with a 10th-order Bartlett-Hanning
window: at 1 kHz it turns each step of the held signal into a smooth 10 ms transition. By default
the normalized window is the impulse response (unit DC gain: the mean force is kept); with
``cutoff_hz`` the taps are a windowed-sinc low-pass from :func:`scipy.signal.firwin`.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal, get_args

import numpy as np

from common.errors import InputError

#: The reconstruction filters by name: zero-order hold, linear interpolation, FIR window.
FilterKind = Literal["zoh", "linear", "fir"]
FILTER_KINDS: tuple[FilterKind, ...] = get_args(FilterKind)


class ReconstructionFilter(ABC):
    """Turns samples arriving at irregular times into one output per servo tick.

    Args:
        tick_s: servo period in seconds (1 ms for 1 kHz).
        dim: length of the value vectors (6: force then torque).
    """

    name = "filter"

    def __init__(self, tick_s: float = 1e-3, dim: int = 6) -> None:
        if not tick_s > 0:
            raise InputError(f"tick must be positive, got {tick_s}", key="tick_s")
        self.tick_s = float(tick_s)
        self.dim = int(dim)
        self.reset()

    @abstractmethod
    def reset(self) -> None:
        """Forget every sample; the output returns to zero."""

    @abstractmethod
    def push(self, t_s: float, value: np.ndarray) -> None:
        """Add a sample that arrived at ``t_s`` (non-decreasing) with ``value`` of shape (dim,)."""

    @abstractmethod
    def output(self, t_s: float) -> np.ndarray:
        """The filtered value at tick time ``t_s``, shape (dim,); call exactly once per tick."""

    @abstractmethod
    def delay_s(self, input_period_s: float) -> float:
        """Nominal delay in seconds this filter adds for inputs every ``input_period_s``."""


class ZeroOrderHold(ReconstructionFilter):
    """Output the latest sample until the next arrives (a staircase)."""

    name = "zoh"

    def reset(self) -> None:
        self._last = np.zeros(self.dim)

    def push(self, t_s: float, value: np.ndarray) -> None:
        self._last = np.array(value, dtype=np.float64)

    def output(self, t_s: float) -> np.ndarray:
        return self._last

    def delay_s(self, input_period_s: float) -> float:
        return 0.5 * input_period_s


class LinearInterpolation(ReconstructionFilter):
    """Interpolate between the last two samples over the last observed sample interval.

    The output reaches a sample's value one interval after the sample arrived, so it lags by
    exactly one input period after arrival; if no new sample comes it holds the last value.
    """

    name = "linear"

    def reset(self) -> None:
        self._t = [0.0, 0.0]
        self._x = [np.zeros(self.dim), np.zeros(self.dim)]
        self._count = 0

    def push(self, t_s: float, value: np.ndarray) -> None:
        self._t = [self._t[1], float(t_s)]
        self._x = [self._x[1], np.array(value, dtype=np.float64)]
        self._count += 1

    def output(self, t_s: float) -> np.ndarray:
        interval = self._t[1] - self._t[0]
        if self._count < 2 or interval <= 0.0:
            return self._x[1]
        alpha = min(max((t_s - self._t[1]) / interval, 0.0), 1.0)
        return self._x[0] + alpha * (self._x[1] - self._x[0])

    def delay_s(self, input_period_s: float) -> float:
        return input_period_s + 0.5 * self.tick_s


def _barthann(n: int) -> np.ndarray:
    """The symmetric Bartlett-Hann window of ``n`` points (as :func:`scipy.signal.get_window`'s
    ``"barthann"``)."""
    x = np.arange(n) / max(n - 1, 1)
    return 0.62 - 0.48 * np.abs(x - 0.5) + 0.38 * np.cos(2.0 * np.pi * (x - 0.5))


def _cosine_sum(a0: float) -> Callable[[int], np.ndarray]:
    """The symmetric window ``a0 - (1 - a0) cos(2 pi k / (n - 1))`` (Hann: 0.5; Hamming: 0.54)."""

    def window(n: int) -> np.ndarray:
        x = np.arange(n) / max(n - 1, 1)
        return a0 - (1.0 - a0) * np.cos(2.0 * np.pi * x)

    return window


#: Windows built here rather than by :func:`scipy.signal.get_window` (the same values, tested):
#: the servo process and a replay start without loading ``scipy.signal``, 0.5-0.7 s of imports,
#: for the paper's filter. Any other window, and every low-pass design, is scipy's.
CLOSED_FORM_WINDOWS: dict[str, Callable[[int], np.ndarray]] = {
    "barthann": _barthann,
    "hann": _cosine_sum(0.5),
    "hamming": _cosine_sum(0.54),
}


def fir_taps(
    order: int = 10,
    window: str | tuple = "barthann",
    cutoff_hz: float | None = None,
    rate_hz: float = 1000.0,
) -> np.ndarray:
    """Linear-phase FIR taps (``order + 1`` of them) with unit DC gain.

    Args:
        order: filter order; the taps span ``order`` ticks.
        window: any window :func:`scipy.signal.get_window` knows, e.g. ``"barthann"``,
            ``"hann"``, ``("kaiser", 4.0)``.
        cutoff_hz: None uses the normalized window as the impulse response (the paper's smoothing
            window); a frequency designs a windowed-sinc low-pass with :func:`scipy.signal.firwin`.
        rate_hz: the rate the filter runs at (the servo rate).

    Returns:
        Taps, shape (order + 1,), summing to 1.
    """
    if int(order) != order or order < 1:
        raise InputError(f"FIR order must be a positive integer, got {order}", key="order")
    numtaps = int(order) + 1
    closed = CLOSED_FORM_WINDOWS.get(window) if isinstance(window, str) else None
    if cutoff_hz is None and closed is not None:
        taps = closed(numtaps)
    else:
        from scipy import signal  # here: loading scipy.signal takes 0.5-0.7 s

        try:
            if cutoff_hz is None:
                taps = signal.get_window(window, numtaps, fftbins=False)
            else:
                taps = signal.firwin(numtaps, cutoff_hz, window=window, fs=rate_hz)
        except (ValueError, TypeError) as exc:
            raise InputError(f"cannot build FIR taps: {exc}", key="window") from exc
    total = float(np.sum(taps))
    if not np.all(np.isfinite(taps)) or abs(total) < 1e-12:
        raise InputError(f"window {window!r} gives taps with zero sum", key="window")
    return np.asarray(taps, dtype=np.float64) / total


class FirWindowFilter(ReconstructionFilter):
    """Zero-order hold sampled at the tick rate, then an FIR window filter (the paper's Fig. 3).

    Args:
        tick_s: servo period in seconds.
        dim: value length.
        order: FIR order (taps = order + 1); the paper uses 10.
        window: a :func:`scipy.signal.get_window` window; the paper uses Bartlett-Hanning.
        cutoff_hz: optional low-pass cutoff (see :func:`fir_taps`).
    """

    name = "fir"

    def __init__(
        self,
        tick_s: float = 1e-3,
        dim: int = 6,
        order: int = 10,
        window: str | tuple = "barthann",
        cutoff_hz: float | None = None,
    ) -> None:
        if not tick_s > 0:
            raise InputError(f"tick must be positive, got {tick_s}", key="tick_s")
        self.taps = fir_taps(order, window, cutoff_hz, 1.0 / tick_s)
        # Newest sample pairs with taps[0]: the window holds samples oldest -> newest.
        self._weights = self.taps[::-1].copy()
        super().__init__(tick_s, dim)

    def reset(self) -> None:
        n = len(self.taps)
        self._held = np.zeros(self.dim)
        self._ring = np.zeros((2 * n, self.dim))  # doubled ring: any n consecutive rows in order
        self._i = 0

    def push(self, t_s: float, value: np.ndarray) -> None:
        self._held = np.array(value, dtype=np.float64)

    def output(self, t_s: float) -> np.ndarray:
        n = len(self.taps)
        self._i = (self._i + 1) % n
        self._ring[self._i] = self._held
        self._ring[self._i + n] = self._held
        return self._weights @ self._ring[self._i + 1 : self._i + 1 + n]

    def delay_s(self, input_period_s: float) -> float:
        return 0.5 * input_period_s + 0.5 * (len(self.taps) - 1) * self.tick_s


@dataclass(frozen=True)
class FilterConfig:
    """Which reconstruction filter the servo loop uses, and its FIR parameters."""

    kind: FilterKind = "fir"
    order: int = 10
    window: str | tuple = "barthann"
    cutoff_hz: float | None = None

    def __post_init__(self) -> None:
        if self.kind not in FILTER_KINDS:
            raise InputError(
                f"expected one of {', '.join(FILTER_KINDS)}, got {self.kind!r}", key="kind"
            )

    def build(self, tick_s: float = 1e-3, dim: int = 6) -> ReconstructionFilter:
        """A fresh filter of this configuration for a servo period of ``tick_s`` seconds."""
        return make_filter(self.kind, tick_s, dim, self.order, self.window, self.cutoff_hz)


def make_filter(
    kind: str,
    tick_s: float = 1e-3,
    dim: int = 6,
    order: int = 10,
    window: str | tuple = "barthann",
    cutoff_hz: float | None = None,
) -> ReconstructionFilter:
    """Build a filter by name: ``"zoh"``, ``"linear"`` or ``"fir"``."""
    if kind == "zoh":
        return ZeroOrderHold(tick_s, dim)
    if kind == "linear":
        return LinearInterpolation(tick_s, dim)
    if kind == "fir":
        return FirWindowFilter(tick_s, dim, order, window, cutoff_hz)
    raise InputError(
        f"unknown filter {kind!r}; expected one of {', '.join(FILTER_KINDS)}", key="filter"
    )
