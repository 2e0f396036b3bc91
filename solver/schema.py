"""Strict reading of nested TOML tables: typed getters that name the key and what was expected,
and a check that no unknown key is left over."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from solver.errors import InputError

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
    ) -> float:
        value = self.raw(name, default)
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.error(name, f"expected a number, got {value!r}")
        value = float(value)
        if not math.isfinite(value):
            raise self.error(name, f"expected a finite number, got {value!r}")
        if minimum is not None and (value < minimum or (exclusive and value == minimum)):
            relation = ">" if exclusive else ">="
            raise self.error(name, f"expected a number {relation} {minimum:g}, got {value:g}")
        if maximum is not None and value > maximum:
            raise self.error(name, f"expected a number <= {maximum:g}, got {value:g}")
        return value

    def integer(self, name: str, default: Any = _MISSING, *, minimum: int = 0) -> int:
        value = self.raw(name, default)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(name, f"expected an integer, got {value!r}")
        if value < minimum:
            raise self.error(name, f"expected an integer >= {minimum}, got {value}")
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
        out = tuple(float(v) for v in value)
        if not all(math.isfinite(v) for v in out):
            raise self.error(name, f"expected finite numbers, got {value!r}")
        if positive and any(v <= 0 for v in out):
            raise self.error(name, f"expected {length} numbers > 0, got {value!r}")
        return out

    def table(self, name: str, default: Any = _MISSING) -> Table:
        return Table(self.raw(name, default), self.source, self.key(name))

    def tables(self, name: str) -> list[Table]:
        value = self.raw(name, [])
        if not isinstance(value, list):
            raise self.error(name, "expected an array of tables ([[...]])")
        return [Table(v, self.source, f"{self.key(name)}[{i}]") for i, v in enumerate(value)]

    def finish(self) -> None:
        """Raise for the first key that no getter asked for."""
        for name in self.data:
            if name not in self.used:
                raise self.error(name, "is not a known key here")
