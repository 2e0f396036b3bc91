"""A small on-disk cache of sRGB -> spectrum upsampling results (Jakob 2019 coefficients).

Fitting a spectrum to a colour takes 0.1-0.3 s (an L-BFGS-B optimisation per colour), which would
otherwise be paid by every process that loads the pigment library. The three sigmoid-polynomial
coefficients per colour are kept as JSON in ``$XDG_CACHE_HOME/paintapp/`` (``~/.cache/paintapp``).
The cache is an optimisation only: an unreadable, corrupt or read-only cache is ignored.
"""

from __future__ import annotations

import contextlib
import json
import os
from pathlib import Path

from paintapp.atomic import atomic_path

#: Bump when the fitting set-up (observer, illuminant, method) changes.
CACHE_NAME = "jakob2019-cie1931-d65-v1.json"


def cache_path() -> Path:
    """Where the cache lives (the directory may not exist yet)."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "paintapp" / CACHE_NAME


def _key(srgb: tuple[float, float, float]) -> str:
    return ",".join(f"{c:.6f}" for c in srgb)


def load_coefficients(srgb: tuple[float, float, float]) -> list[float] | None:
    """Cached coefficients for an sRGB colour, or None."""
    try:
        data = json.loads(cache_path().read_text(encoding="utf-8"))
        value = data.get(_key(srgb))
    except (OSError, ValueError, AttributeError):
        return None
    if isinstance(value, list) and len(value) == 3 and all(isinstance(v, float) for v in value):
        return value
    return None


def store_coefficients(srgb: tuple[float, float, float], coefficients: list[float]) -> None:
    """Add coefficients to the cache (best effort, atomic; concurrent writers may drop entries)."""
    path = cache_path()
    with contextlib.suppress(OSError, ValueError):
        path.parent.mkdir(parents=True, exist_ok=True)
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
            data = data if isinstance(data, dict) else {}
        except (OSError, ValueError):
            data = {}
        data[_key(srgb)] = [float(c) for c in coefficients]
        with atomic_path(path) as tmp:
            tmp.write_text(
                json.dumps(data, indent=0, sort_keys=True, allow_nan=False), encoding="utf-8"
            )
