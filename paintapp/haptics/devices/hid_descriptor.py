"""A small HID report descriptor parser: where each field lives in which report.

Enough of the HID 1.11 item grammar (section 6.2.2) to locate fields: short items with the
global state (usage page, logical range, report size/count/ID, push/pop), local usages and usage
ranges, and Input/Output/Feature main items inside collections. The drivers use it to find a
joystick's axes and buttons in its input report and the byte size of each report.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from common.errors import InputError

INPUT, OUTPUT, FEATURE = "input", "output", "feature"
_MAIN_KINDS = {0x8: INPUT, 0x9: OUTPUT, 0xB: FEATURE}
PAGE_GENERIC_DESKTOP = 0x01
PAGE_BUTTON = 0x09
PAGE_PID = 0x0F


@dataclass(frozen=True)
class HidField:
    """One main item: ``count`` values of ``size`` bits starting at ``bit_offset`` of the report
    payload (after the report ID byte, if the device numbers its reports).

    ``usages`` has one (page, usage) per value for variable items (the last usage repeats when
    there are fewer usages than values); ``constant`` fields are padding.
    """

    kind: str
    report_id: int
    bit_offset: int
    size: int
    count: int
    usages: tuple[tuple[int, int], ...]
    logical_min: int
    logical_max: int
    constant: bool
    variable: bool

    def usage_index(self, page: int, usage: int) -> int | None:
        """Index of the value with this usage, or None."""
        for i in range(self.count):
            if self.usages and self.usages[min(i, len(self.usages) - 1)] == (page, usage):
                return i
        return None


@dataclass
class ReportDescriptor:
    """The parsed descriptor: every field, and whether reports carry an ID byte."""

    fields: list[HidField] = field(default_factory=list)
    numbered: bool = False

    def report_bytes(self, kind: str, report_id: int) -> int:
        """Payload size in bytes of a report (without the ID byte); 0 if it is not declared."""
        bits = [
            f.bit_offset + f.size * f.count
            for f in self.fields
            if f.kind == kind and f.report_id == report_id
        ]
        return (max(bits) + 7) // 8 if bits else 0

    def find(self, kind: str, page: int, usage: int) -> tuple[HidField, int] | None:
        """The first variable field with this usage and the value's index in it."""
        for f in self.fields:
            if f.kind == kind and f.variable and not f.constant:
                index = f.usage_index(page, usage)
                if index is not None:
                    return f, index
        return None

    def uses_page(self, page: int) -> bool:
        """Whether any field carries a usage on ``page`` (e.g. 0x0F: force feedback)."""
        return any(p == page for f in self.fields for p, _ in f.usages)


def _value(data: bytes, signed: bool) -> int:
    return int.from_bytes(data, "little", signed=signed) if data else 0


@dataclass
class _State:
    page: int = 0
    logical_min: int = 0
    logical_max: int = 0
    logical_max_raw: bytes = b""
    size: int = 0
    count: int = 0
    report_id: int = 0


def _local_usages(state: _State, usages: list[int], lo: int | None, hi: int | None) -> list:
    full = [(u >> 16, u & 0xFFFF) if u > 0xFFFF else (state.page, u) for u in usages]
    if lo is not None and hi is not None and hi >= lo and hi - lo < 4096:
        full += [(state.page, u) for u in range(lo, hi + 1)]
    return full


def _global_item(
    state: _State, stack: list[_State], tag: int, raw: bytes, out: ReportDescriptor
) -> tuple[_State, list[_State]]:
    if tag == 0:
        state.page = _value(raw, False)
    elif tag == 1:
        state.logical_min = _value(raw, True)
    elif tag == 2:
        state.logical_max, state.logical_max_raw = _value(raw, True), raw
    elif tag == 7:
        state.size = _value(raw, False)
    elif tag == 8:
        state.report_id = _value(raw, False)
        out.numbered = True
    elif tag == 9:
        state.count = _value(raw, False)
    elif tag == 0xA:
        stack.append(_State(**vars(state)))
    elif tag == 0xB and stack:
        state = stack.pop()
    return state, stack


class _Parser:
    """Walks the items, keeping the global state, its push/pop stack and the local usages."""

    def __init__(self) -> None:
        self.out = ReportDescriptor()
        self.state = _State()
        self.stack: list[_State] = []
        self.offsets: dict[tuple[str, int], int] = {}
        self._clear_locals()

    def _clear_locals(self) -> None:
        self.usages: list[int] = []
        self.usage_lo: int | None = None
        self.usage_hi: int | None = None

    def main_item(self, tag: int, raw: bytes) -> None:
        if tag in _MAIN_KINDS:
            st = self.state
            flags = _value(raw, False)
            key = (_MAIN_KINDS[tag], st.report_id)
            lmax = st.logical_max
            if st.logical_min >= 0 and lmax < 0:
                lmax = _value(st.logical_max_raw, False)
            usages = tuple(_local_usages(st, self.usages, self.usage_lo, self.usage_hi))
            offset = self.offsets.get(key, 0)
            self.out.fields.append(
                HidField(
                    key[0],
                    st.report_id,
                    offset,
                    st.size,
                    st.count,
                    usages,
                    st.logical_min,
                    lmax,
                    bool(flags & 1),
                    bool(flags & 2),
                )
            )
            self.offsets[key] = offset + st.size * st.count
        self._clear_locals()  # every main item (collections too) clears the local state

    def local_item(self, tag: int, raw: bytes) -> None:
        if tag == 0:
            self.usages.append(_value(raw, False))
        elif tag == 1:
            self.usage_lo = _value(raw, False)
        elif tag == 2:
            self.usage_hi = _value(raw, False)

    def global_item(self, tag: int, raw: bytes) -> None:
        self.state, self.stack = _global_item(self.state, self.stack, tag, raw, self.out)


def parse_report_descriptor(data: bytes) -> ReportDescriptor:
    """Parse a report descriptor; raises :class:`InputError` if it is truncated."""
    parser = _Parser()
    data = bytes(data)
    i = 0
    while i < len(data):
        prefix = data[i]
        if prefix == 0xFE:  # long item: data size, tag, data; no meaning for fields
            i += 3 + (data[i + 1] if i + 1 < len(data) else 0)
            continue
        size = (0, 1, 2, 4)[prefix & 3]
        kind, tag = (prefix >> 2) & 3, prefix >> 4
        if i + 1 + size > len(data):
            raise InputError("HID report descriptor is truncated", key="report_descriptor")
        raw = data[i + 1 : i + 1 + size]
        i += 1 + size
        if kind == 0:
            parser.main_item(tag, raw)
        elif kind == 1:
            parser.global_item(tag, raw)
        elif kind == 2:
            parser.local_item(tag, raw)
    return parser.out


def read_field(payload: bytes, f: HidField, index: int = 0) -> int:
    """The integer value ``index`` of field ``f`` in a report payload (ID byte removed)."""
    start = f.bit_offset + index * f.size
    nbytes = (start % 8 + f.size + 7) // 8
    chunk = int.from_bytes(payload[start // 8 : start // 8 + nbytes], "little")
    value = (chunk >> (start % 8)) & ((1 << f.size) - 1)
    if f.logical_min < 0 and value & (1 << (f.size - 1)):
        value -= 1 << f.size
    return value


def normalize(value: int, f: HidField) -> float:
    """Map a logical value linearly from [logical_min, logical_max] to [-1, 1]."""
    lo, hi = f.logical_min, f.logical_max
    if hi <= lo:
        return 0.0
    return 2.0 * (value - lo) / (hi - lo) - 1.0
