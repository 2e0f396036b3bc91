"""Small validators for tables read from files; each failure is an :class:`InputError` that names
the file and the dotted key and says what was expected."""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping
from typing import Any

from solver.errors import InputError

NAME_PATTERN = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$")
_MISSING: Any = object()


def dotted(prefix: str, key: str) -> str:
    """``prefix.key``, or ``key`` when there is no prefix."""
    return f"{prefix}.{key}" if prefix else key


def check_keys(
    table: Mapping[str, Any],
    allowed: Iterable[str],
    source: str | None,
    prefix: str = "",
) -> None:
    """Reject keys of ``table`` that are not in ``allowed`` (typos are errors, not ignored)."""
    allowed = list(allowed)
    for key in table:
        if key not in allowed:
            raise InputError(
                f"unknown key; expected one of {', '.join(sorted(allowed))}",
                source=source,
                key=dotted(prefix, key),
            )


def get_table(
    table: Mapping[str, Any], key: str, source: str | None, prefix: str = "", *, required: bool
) -> dict[str, Any]:
    """The sub-table ``table[key]`` (empty when absent and not required)."""
    if key not in table:
        if required:
            raise InputError("missing table", source=source, key=dotted(prefix, key))
        return {}
    value = table[key]
    if not isinstance(value, Mapping):
        raise InputError(
            f"expected a table, got {type(value).__name__}", source=source, key=dotted(prefix, key)
        )
    return dict(value)


def get_float(
    table: Mapping[str, Any],
    key: str,
    source: str | None,
    prefix: str = "",
    *,
    default: float = _MISSING,
    lo: float | None = None,
    hi: float | None = None,
    lo_open: bool = False,
    hint: str = "",
) -> float:
    """A finite number from ``table[key]`` within ``[lo, hi]`` (``(lo, hi]`` when ``lo_open``)."""
    name = dotted(prefix, key)
    if key not in table:
        if default is _MISSING:
            raise InputError("missing value; expected a number", source=source, key=name)
        return float(default)
    value = table[key]
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise InputError(
            f"expected a number, got {type(value).__name__} {value!r}", source=source, key=name
        )
    value = float(value)
    too_low = lo is not None and (value <= lo if lo_open else value < lo)
    too_high = hi is not None and value > hi
    if not math.isfinite(value) or too_low or too_high:
        raise InputError(
            f"expected a number {_range_text(lo, hi, lo_open)}, got {value!r}{hint}",
            source=source,
            key=name,
        )
    return value


def _range_text(lo: float | None, hi: float | None, lo_open: bool) -> str:
    if lo is not None and hi is not None:
        return f"in {'(' if lo_open else '['}{lo:g}, {hi:g}]"
    if lo is not None:
        return f"{'>' if lo_open else '>='} {lo:g}"
    if hi is not None:
        return f"<= {hi:g}"
    return "(finite)"


def get_str(
    table: Mapping[str, Any],
    key: str,
    source: str | None,
    prefix: str = "",
    *,
    default: str = _MISSING,
    choices: Iterable[str] | None = None,
) -> str:
    """A string from ``table[key]``, optionally one of ``choices``."""
    name = dotted(prefix, key)
    if key not in table:
        if default is _MISSING:
            raise InputError("missing value; expected a string", source=source, key=name)
        return default
    value = table[key]
    if not isinstance(value, str):
        raise InputError(
            f"expected a string, got {type(value).__name__} {value!r}", source=source, key=name
        )
    if choices is not None and value not in (choices := list(choices)):
        raise InputError(
            f"expected one of {', '.join(choices)}, got {value!r}", source=source, key=name
        )
    return value


def check_name(value: Any, what: str) -> str:
    """A safe name (letters, digits, ``_ . -``; no path separators), else ValueError."""
    if not isinstance(value, str) or not NAME_PATTERN.match(value) or ".." in value:
        raise ValueError(
            f"expected a {what} name of letters, digits, '_', '.', '-' "
            f"(at most 64 characters, no path separators), got {value!r}"
        )
    return value
