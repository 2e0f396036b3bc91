"""Recording stroke files as they are painted: the header at once, then one flushed line per
record, so a crash loses at most the record being written (:func:`paintapp.strokes.files.
read_strokes` tolerates the unfinished last line it may leave)."""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from types import TracebackType
from typing import Any

from brushes.stylus import StylusSample
from common.errors import InputError
from paintapp.strokes.records import (
    StrokeHeader,
    StrokeRecord,
    event_from_dict,
    record_to_dict,
    to_json_line,
)


class StrokeRecorder:
    """Writes a stroke file: the header at once, then one flushed line per :meth:`write`.

    An existing file is never clobbered unless ``overwrite`` is True. With ``fsync`` each line is
    also forced to disk (slower; survives a power cut, not only a crash of the program). Each
    record is validated before it is written (times non-decreasing, pigments from the header).
    Use as a context manager, or call :meth:`close`.
    """

    def __init__(
        self,
        path: str | Path,
        header: StrokeHeader | Mapping[str, Any],
        *,
        overwrite: bool = False,
        fsync: bool = False,
    ) -> None:
        self.path = Path(path)
        self.header = header if isinstance(header, StrokeHeader) else StrokeHeader.from_dict(header)
        self.fsync = fsync
        self.count = 0
        self.last_t_s: float | None = None
        try:
            mode = "w" if overwrite else "x"
            self._file = open(self.path, mode, encoding="utf-8", newline="\n")
        except FileExistsError:
            raise InputError(
                "a file already exists here; refusing to overwrite it (choose another name, "
                "or allow overwriting)",
                source=str(self.path),
            ) from None
        self._write_line(self.header.to_dict())

    @property
    def closed(self) -> bool:
        """True once :meth:`close` has run."""
        return self._file.closed

    def write(self, record: StrokeRecord) -> None:
        """Validate and append one sample or event, then flush it (and fsync if asked)."""
        if self.closed:
            raise ValueError("the stroke recorder is closed")
        obj = record_to_dict(record)
        if isinstance(record, StylusSample):
            checked: StrokeRecord = record
        else:
            checked = event_from_dict(obj, self.header.pigments)
        if self.last_t_s is not None and checked.t_s < self.last_t_s:
            raise InputError(
                f"time went backwards ({checked.t_s} s after {self.last_t_s} s)",
                source=str(self.path),
                key="t",
            )
        self._write_line(obj)
        self.last_t_s = checked.t_s
        self.count += 1

    def _write_line(self, obj: Mapping[str, Any]) -> None:
        self._file.write(to_json_line(obj) + "\n")
        self._file.flush()
        if self.fsync:
            os.fsync(self._file.fileno())

    def close(self) -> None:
        """Flush and close the file (idempotent)."""
        if not self._file.closed:
            self._file.flush()
            self._file.close()

    def __enter__(self) -> StrokeRecorder:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()
