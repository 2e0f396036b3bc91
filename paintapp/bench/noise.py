"""Force noise: the high-frequency part of a force signal, relative to its size.

Definition used throughout ``paintapp bench`` and the figures. For a signal ``f`` sampled every
``dt`` seconds (shape (n,) or (n, k): k components such as Fx, Fy):

* ``smooth(f)`` is a Savitzky-Golay fit of polynomial order 3 over a sliding window of
  ``window_s`` seconds (the odd number of samples nearest ``window_s / dt``, at least 5), applied
  per component; the paper's sweep changes over about a second, so the default window of 0.1 s
  keeps the motion and removes the staircase jitter (which flips every few steps);
* ``noise = RMS_t |f - smooth(f)| / RMS_t |smooth(f)|``, where ``|.|`` is the Euclidean norm over
  components and ``RMS_t`` the root mean square over the samples.

So a noise of 0.1 means the jitter carries a tenth of the force's RMS size. A signal with no
size (all zeros) has noise 0.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import savgol_filter

DEFAULT_WINDOW_S = 0.1
POLYORDER = 3


def window_samples(dt_s: float, window_s: float = DEFAULT_WINDOW_S) -> int:
    """The odd sample count of the smoothing window for a sample period of ``dt_s`` seconds."""
    if not (dt_s > 0 and window_s > 0):
        raise ValueError("dt and window must be positive")
    n = round(window_s / dt_s)
    n += 1 - n % 2
    return max(n, 5)  # the smallest odd window a cubic fit can smooth


def smooth(signal: np.ndarray, dt_s: float, window_s: float = DEFAULT_WINDOW_S) -> np.ndarray:
    """Savitzky-Golay smoothed copy of ``signal`` (shape (n,) or (n, k)) along time."""
    f = np.asarray(signal, dtype=float)
    n = window_samples(dt_s, window_s)
    if f.shape[0] < n:
        return np.broadcast_to(f.mean(axis=0), f.shape).copy()
    return savgol_filter(f, n, POLYORDER, axis=0, mode="interp")


def rms_norm(signal: np.ndarray) -> float:
    """RMS over time of the Euclidean norm over components (shape (n,) or (n, k))."""
    f = np.asarray(signal, dtype=float)
    if f.ndim == 1:
        f = f[:, None]
    return float(np.sqrt(np.mean(np.sum(f * f, axis=1)))) if f.size else 0.0


def relative_noise(signal: np.ndarray, dt_s: float, window_s: float = DEFAULT_WINDOW_S) -> float:
    """``RMS |f - smooth(f)| / RMS |smooth(f)|`` (dimensionless; 0 for an all-zero signal)."""
    f = np.asarray(signal, dtype=float)
    s = smooth(f, dt_s, window_s)
    size = rms_norm(s)
    return rms_norm(f - s) / size if size > 0 else 0.0


def relative_deviation(signal: np.ndarray, reference: np.ndarray) -> float:
    """``RMS |f - ref| / RMS |ref|`` for two signals on the same samples (dimensionless)."""
    ref = np.asarray(reference, dtype=float)
    size = rms_norm(ref)
    diff = np.asarray(signal, dtype=float) - ref
    return rms_norm(diff) / size if size > 0 else float("inf")
