"""Errors for bad user input, shared by every layer.

An :class:`InputError` names where the problem is (file, line, key) and what was expected, so the
command line can print one clear sentence instead of a traceback.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass
class InputError(ValueError):
    """Bad input from a user or a file: a malformed scene, an impossible parameter, a bad sample.

    Attributes:
        message: what is wrong and what was expected.
        source: the file (or stream) the input came from, if any.
        key: the dotted key or field name, if any.
        line: the 1-based line number, if known.
    """

    message: str
    source: str | None = None
    key: str | None = None
    line: int | None = None

    def __post_init__(self) -> None:
        super().__init__(str(self))

    def __str__(self) -> str:
        where = []
        if self.source:
            where.append(str(self.source))
        if self.line is not None:
            where.append(f"line {self.line}")
        if self.key:
            where.append(f"'{self.key}'")
        prefix = ": ".join([", ".join(where)]) if where else ""
        return f"{prefix}: {self.message}" if prefix else self.message
