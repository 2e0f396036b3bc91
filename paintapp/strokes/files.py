"""Stroke files: JSON Lines recordings of stylus samples and brush events (format version 1).

Line 1 is the header (:class:`StrokeHeader`); every further line is one stylus sample or one event
(:mod:`paintapp.strokes.records`), with non-decreasing times. :func:`read_strokes` loads and
validates a file: a malformed line stops with an :class:`InputError` giving the line number and
the field, except that an unfinished last line (no trailing newline, not valid JSON: what a crash
in the middle of a write leaves) is dropped and reported through ``StrokeFile.truncated``. Writing files as they are painted is
:mod:`paintapp.strokes.recorder`'s job.

Hostile input gets the same treatment: a UTF-8 byte order mark at the start is skipped (Windows
editors write one); JSON nested more than :data:`MAX_JSON_DEPTH` levels is refused with its line.
Times may jump: a pause longer than :data:`MAX_GAP_S` between two records is kept and listed in
``StrokeFile.gaps`` (line, seconds), and a replay plays it in bounded work
(:mod:`paintapp.session.playback`).
"""

from __future__ import annotations

import json
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from itertools import pairwise
from pathlib import Path
from typing import Any

import numpy as np

from brushes.stylus import StylusSample
from common.errors import InputError
from paintapp.strokes.records import (
    EVENT_TYPES,
    FORMAT_NAME,
    FORMAT_VERSION,
    CanvasSpec,
    CleanBrush,
    LoadPigment,
    Marker,
    StrokeEvent,
    StrokeHeader,
    StrokeRecord,
    SwitchBrush,
    event_from_dict,
    sample_from_dict,
)

__all__ = [
    "EVENT_TYPES",
    "FORMAT_NAME",
    "FORMAT_VERSION",
    "CanvasSpec",
    "CleanBrush",
    "LoadPigment",
    "Marker",
    "SampleArrays",
    "StrokeEvent",
    "StrokeFile",
    "StrokeHeader",
    "StrokeRecord",
    "StylusSample",
    "SwitchBrush",
    "read_strokes",
]

#: How deeply a line's JSON may nest (a header's free-form ``device`` object included).
MAX_JSON_DEPTH = 16
#: A pause between two consecutive records longer than this (s) is a gap (``StrokeFile.gaps``).
MAX_GAP_S = 1.0
_BOM = b"\xef\xbb\xbf"


@dataclass(frozen=True)
class SampleArrays:
    """All samples of a file as arrays (N samples): ``t_s`` (N,), ``position_m`` (N, 3),
    ``pressure`` (N,), ``tilt_rad`` (N, 2), ``twist_rad`` (N,), ``buttons`` (N,) int64."""

    t_s: np.ndarray
    position_m: np.ndarray
    pressure: np.ndarray
    tilt_rad: np.ndarray
    twist_rad: np.ndarray
    buttons: np.ndarray


@dataclass(frozen=True)
class StrokeFile:
    """A loaded stroke file.

    Attributes:
        header: the header line.
        records: samples and events in file order.
        samples: the stylus samples, in order.
        events: the events, in order.
        truncated: True when an unfinished last line was dropped.
        warning: what was dropped and why, when ``truncated``; else None.
        source: the file it came from.
        lines: the line number of each record (empty when the records did not come from a file).
        gaps: (line, seconds) for every record more than :data:`MAX_GAP_S` after the one before.
    """

    header: StrokeHeader
    records: tuple[StrokeRecord, ...]
    truncated: bool = False
    warning: str | None = None
    source: str | None = None
    lines: tuple[int, ...] = ()
    samples: tuple[StylusSample, ...] = field(init=False)
    events: tuple[StrokeEvent, ...] = field(init=False)
    gaps: tuple[tuple[int | None, float], ...] = field(init=False)

    def __post_init__(self) -> None:
        samples = tuple(r for r in self.records if isinstance(r, StylusSample))
        events = tuple(r for r in self.records if not isinstance(r, StylusSample))
        object.__setattr__(self, "samples", samples)
        object.__setattr__(self, "events", events)
        gaps = tuple(
            (self.line_of(i), b.t_s - a.t_s)
            for i, (a, b) in enumerate(pairwise(self.records), start=1)
            if b.t_s - a.t_s > MAX_GAP_S
        )
        object.__setattr__(self, "gaps", gaps)

    def line_of(self, index: int) -> int | None:
        """The line number of record ``index`` (None when unknown)."""
        return self.lines[index] if 0 <= index < len(self.lines) else None

    @property
    def duration_s(self) -> float:
        """Time (s) from the first to the last record (0 when there are none)."""
        return self.records[-1].t_s - self.records[0].t_s if self.records else 0.0

    def sample_arrays(self) -> SampleArrays:
        """The samples as arrays (see :class:`SampleArrays`)."""
        s = self.samples
        return SampleArrays(
            t_s=np.array([x.t_s for x in s], dtype=float),
            position_m=np.array([x.position_m for x in s], dtype=float).reshape(-1, 3),
            pressure=np.array([x.pressure for x in s], dtype=float),
            tilt_rad=np.array([x.tilt_rad for x in s], dtype=float).reshape(-1, 2),
            twist_rad=np.array([x.twist_rad for x in s], dtype=float),
            buttons=np.array([x.buttons for x in s], dtype=np.int64),
        )


def _no_duplicates(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise ValueError(f"duplicate field {key!r}")
        out[key] = value
    return out


def _lines(data: bytes) -> Iterator[tuple[int, bytes, bool]]:
    """(1-based line number, bytes without newline, whether the line is unfinished)."""
    parts = data.split(b"\n")
    for number, raw in enumerate(parts[:-1], start=1):
        yield number, raw, False
    if parts[-1]:
        yield len(parts), parts[-1], True


def _parse_json(raw: bytes) -> Any:
    text = raw.decode("utf-8").rstrip("\r")
    try:
        obj = json.loads(text, object_pairs_hook=_no_duplicates)
    except RecursionError:
        raise _TooDeep() from None
    if _depth(obj) > MAX_JSON_DEPTH:
        raise _TooDeep()
    return obj


class _TooDeep(ValueError):
    def __str__(self) -> str:
        return f"JSON nested more than {MAX_JSON_DEPTH} levels deep; expected a flat record"


def _depth(obj: Any) -> int:
    """How deeply ``obj`` nests lists and objects (a scalar: 0), without recursion."""
    deepest, stack = 0, [(obj, 1)]
    while stack:
        value, level = stack.pop()
        if isinstance(value, dict):
            children: Any = value.values()
        elif isinstance(value, list):
            children = value
        else:
            continue
        deepest = max(deepest, level)
        if level > MAX_JSON_DEPTH:
            break
        stack.extend((child, level + 1) for child in children)
    return deepest


def _located(exc: InputError, source: str, line: int) -> InputError:
    return InputError(exc.message, source=source, key=exc.key, line=line)


def read_strokes(path: str | Path, *, allow_truncated: bool = True) -> StrokeFile:
    """Load and validate the stroke file ``path``.

    Raises :class:`InputError` with the line number and the field for a malformed header or
    record, a time running backwards, or a NaN, infinite or out-of-range value. An unfinished
    last line (no newline at its end and not valid JSON, or only NUL bytes) is dropped with
    ``truncated=True``, unless ``allow_truncated`` is False, when it is an error too.
    """
    source = str(path)
    try:
        data = Path(path).read_bytes()
    except FileNotFoundError:
        raise InputError("no such stroke file", source=source) from None
    except OSError as exc:
        raise InputError(f"cannot read the stroke file: {exc}", source=source) from None
    if data.startswith(_BOM):
        data = data[len(_BOM) :]
    header: StrokeHeader | None = None
    records: list[StrokeRecord] = []
    lines: list[int] = []
    warning = None
    for number, raw, unfinished in _lines(data):
        if unfinished and not raw.strip(b"\x00"):
            warning = f"line {number} holds only NUL bytes (the recording was cut short); dropped"
            break
        if not raw.strip():
            continue
        try:
            obj = _parse_json(raw)
        except _TooDeep as exc:
            raise InputError(str(exc), source=source, line=number) from None
        except ValueError as exc:  # JSONDecodeError and UnicodeDecodeError are ValueErrors
            if unfinished and header is not None and allow_truncated:
                warning = f"line {number} is unfinished (the recording was cut short); dropped"
                break
            what = "cut short" if unfinished else "not valid JSON"
            raise InputError(f"{what}: {exc}", source=source, line=number) from None
        try:
            if header is None:
                header = StrokeHeader.from_dict(obj)
                continue
            records.append(_record(obj, header, records[-1].t_s if records else None))
            lines.append(number)
        except InputError as exc:
            raise _located(exc, source, number) from None
    if header is None:
        raise InputError("empty file; expected the header line", source=source, line=1)
    if warning is not None and not allow_truncated:
        raise InputError(warning, source=source)
    return StrokeFile(header, tuple(records), warning is not None, warning, source, tuple(lines))


def _record(obj: Any, header: StrokeHeader, last_t_s: float | None) -> StrokeRecord:
    if not isinstance(obj, Mapping):
        raise InputError(f"expected a JSON object (a sample or an event), got {obj!r}")
    if "event" in obj:
        record: StrokeRecord = event_from_dict(obj, header.pigments)
    else:
        record = sample_from_dict(obj)
    if last_t_s is not None and record.t_s < last_t_s:
        raise InputError(
            f"time went backwards ({record.t_s} s after {last_t_s} s); "
            "times must be non-decreasing",
            key="t",
        )
    return record
