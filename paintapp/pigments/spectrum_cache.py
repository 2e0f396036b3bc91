"""A small on-disk cache of sRGB -> spectrum upsampling results and colourimetric tables.

Fitting a spectrum to a colour takes 0.1-0.3 s (an L-BFGS-B optimisation per colour), which would
otherwise be paid by every process that loads the pigment library. The three sigmoid-polynomial
coefficients per colour are kept as JSON in ``$XDG_CACHE_HOME/paintapp/`` (``~/.cache/paintapp``).

Beside them, a second file keeps what colour-science computed from them and from its datasets
(:func:`load_table`, :func:`store_table`): the colour matching functions, the illuminant, the RGB
matrix and each colour's spectrum on the package's wavelengths, as float64 arrays whose JSON text
reads back to the same bits. With every table there, a process needs no ``import colour`` (about
0.5-1 s: colour-science's package imports matplotlib); the file's name carries colour-science's
version, so another version computes its own.

The cache is an optimisation only: an unreadable, corrupt or read-only cache is ignored.
"""

from __future__ import annotations

import contextlib
import functools
import json
import os
from pathlib import Path

import numpy as np

from paintapp.atomic import atomic_path

#: Bump when the fitting set-up (observer, illuminant, method) changes.
CACHE_NAME = "jakob2019-cie1931-d65-v1.json"
#: The tables' file, per colour-science version (bump the ``v1`` when their keys change meaning).
TABLES_NAME = "colour-tables-v1-{version}.json"


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


@functools.cache
def _colour_version() -> str | None:
    """colour-science's installed version (None when it is not installed)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("colour-science")
    except PackageNotFoundError:
        return None


def tables_path() -> Path | None:
    """Where the tables computed with colour-science live (None when it is not installed)."""
    installed = _colour_version()
    return cache_path().with_name(TABLES_NAME.format(version=installed)) if installed else None


def _read_tables(path: Path) -> dict:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def load_table(key: str, shape: tuple[int, ...]) -> np.ndarray | None:
    """The cached float64 table ``key`` of the given shape, or None (absent or malformed)."""
    path = tables_path()
    value = _read_tables(path).get(key) if path is not None else None
    if not isinstance(value, list) or not all(isinstance(v, float) for v in value):
        return None
    array = np.array(value, dtype=np.float64)
    if array.size != int(np.prod(shape)) or not np.all(np.isfinite(array)):
        return None
    return array.reshape(shape)


def store_table(key: str, values: np.ndarray) -> None:
    """Add a float64 table to the cache (best effort, atomic; concurrent writers may drop
    entries)."""
    path = tables_path()
    if path is None:
        return
    flat = [float(v) for v in np.asarray(values, dtype=np.float64).ravel()]
    with contextlib.suppress(OSError, ValueError):
        path.parent.mkdir(parents=True, exist_ok=True)
        data = _read_tables(path)
        data[key] = flat
        with atomic_path(path) as tmp:
            tmp.write_text(json.dumps(data, sort_keys=True, allow_nan=False), encoding="utf-8")
