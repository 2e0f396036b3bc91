"""Strict reading of nested TOML tables: typed getters that name the key and what was expected,
and a check that no unknown key is left over."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from common.errors import InputError

_MISSING = object()


class Table:
    """A view of one TOML table at dotted path ``path`` of file ``source``."""

    def __init__(self, data: Any, source: str, path: str) -> None:
        if not isinstance(data, dict):
            raise InputError(f"expected a table, got {type(data).__name__}", source, path or None)
        self.data = data
        self.source = source
        self.path = path
        self.used: set[str] = set()

    def key(self, name: str) -> str:
        return f"{self.path}.{name}" if self.path else name

    def error(self, name: str, message: str) -> InputError:
        return InputError(message, self.source, self.key(name))

    def has(self, name: str) -> bool:
        return name in self.data

    def raw(self, name: str, default: Any = _MISSING) -> Any:
        self.used.add(name)
        if name not in self.data:
            if default is _MISSING:
                raise self.error(name, "is required but missing")
            return default
        return self.data[name]

    def number(
        self,
        name: str,
        default: Any = _MISSING,
        *,
        minimum: float | None = None,
        exclusive: bool = False,
        maximum: float | None = None,
        hint: str = "",
    ) -> float:
        """A finite number in ``[minimum, maximum]`` (``(minimum, maximum]`` when ``exclusive``);
        ``hint`` is added to the message (units, an example)."""
        value = self.raw(name, default)
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.error(name, f"expected a number{hint}, got {value!r}")
        try:
            value = float(value)
        except OverflowError:  # an integer beyond floating point's range
            raise self.error(name, f"expected a finite number{hint}, got a huge integer") from None
        too_low = minimum is not None and (value < minimum or (exclusive and value == minimum))
        too_high = maximum is not None and value > maximum
        if not math.isfinite(value):
            raise self.error(name, f"expected a finite number{hint}, got {value!r}")
        if too_low or too_high:
            wanted = _range_text(minimum, maximum, exclusive)
            raise self.error(name, f"expected a number {wanted}{hint}, got {value!r}")
        return value

    def boolean(self, name: str, default: Any = _MISSING) -> bool:
        """``true`` or ``false``."""
        value = self.raw(name, default)
        if not isinstance(value, bool):
            raise self.error(name, f"expected true or false, got {value!r}")
        return value

    def integer(
        self, name: str, default: Any = _MISSING, *, minimum: int = 0, maximum: int | None = None
    ) -> int:
        """An integer in ``[minimum, maximum]`` (no upper bound when ``maximum`` is None)."""
        value = self.raw(name, default)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(name, f"expected an integer, got {value!r}")
        if value < minimum:
            raise self.error(name, f"expected an integer >= {minimum}, got {value}")
        if maximum is not None and value > maximum:
            raise self.error(name, f"expected an integer <= {maximum}, got {value}")
        return int(value)

    def string(
        self, name: str, default: Any = _MISSING, choices: Sequence[str] | None = None
    ) -> str:
        value = self.raw(name, default)
        if not isinstance(value, str):
            raise self.error(name, f"expected a string, got {value!r}")
        if choices is not None and value not in choices:
            raise self.error(name, f"expected one of {', '.join(choices)}, got {value!r}")
        return value

    def vector(
        self, name: str, length: int, default: Any = _MISSING, *, positive: bool = False
    ) -> tuple[float, ...]:
        value = self.raw(name, default)
        if (
            not isinstance(value, list | tuple)
            or len(value) != length
            or any(isinstance(v, bool) or not isinstance(v, int | float) for v in value)
        ):
            raise self.error(name, f"expected a list of {length} numbers, got {value!r}")
        try:
            out = tuple(float(v) for v in value)
        except OverflowError:  # an integer beyond floating point's range
            raise self.error(name, "expected finite numbers, got a huge integer") from None
        if not all(math.isfinite(v) for v in out):
            raise self.error(name, f"expected finite numbers, got {value!r}")
        if positive and any(v <= 0 for v in out):
            raise self.error(name, f"expected {length} numbers > 0, got {value!r}")
        return out

    def table(self, name: str, default: Any = _MISSING) -> Table:
        """The sub-table ``name`` (``default``, e.g. ``{}``, when absent)."""
        return Table(self.raw(name, default), self.source, self.key(name))

    def tables(self, name: str) -> list[Table]:
        value = self.raw(name, [])
        if not isinstance(value, list):
            raise self.error(name, "expected an array of tables ([[...]])")
        return [Table(v, self.source, f"{self.key(name)}[{i}]") for i, v in enumerate(value)]

    def expect(self, names: Sequence[str]) -> None:
        """Raise for the first key not in ``names`` now, before any value is read (so a typo is
        reported as such, not as the missing key it was meant to be)."""
        for name in self.data:
            if name not in names:
                raise self.error(
                    name, f"is not a known key here; expected one of {', '.join(names)}"
                )

    def finish(self) -> None:
        """Raise for the first key that no getter asked for."""
        for name in self.data:
            if name not in self.used:
                raise self.error(name, "is not a known key here")


def _range_text(lo: float | None, hi: float | None, lo_open: bool) -> str:
    if lo is not None and hi is not None:
        return f"in {'(' if lo_open else '['}{lo:g}, {hi:g}]"
    if lo is not None:
        return f"{'>' if lo_open else '>='} {lo:g}"
    if hi is not None:
        return f"<= {hi:g}"
    return "(finite)"
