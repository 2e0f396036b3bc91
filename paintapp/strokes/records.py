"""Records of the stroke file format (``paintapp-strokes`` version 1): the header, stylus samples
and events, with conversion from and to the JSON objects of one line each.

Every ``*_from_dict`` function validates its input and raises :class:`InputError` naming the
field (``key``); the reader adds the file and the line number.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

from brushes.stylus import StylusSample
from common.errors import InputError
from common.names import check_pigment_name, check_preset_name
from paintapp.canvas.model import MAX_PIXELS

FORMAT_NAME = "paintapp-strokes"
FORMAT_VERSION = 1
MAX_CANVAS_M = 10.0
MAX_LOAD_M3 = 1e-3
DEVICE_KINDS = ("tablet", "mouse", "haptic")
SAMPLE_KEYS = ("t", "pos", "pressure", "tilt", "twist", "buttons")


def _fail(message: str, key: str) -> InputError:
    return InputError(message, key=key)


def _shown(value: Any, limit: int = 60) -> str:
    """``repr(value)``, cut to ``limit`` characters (a hostile value can be huge)."""
    text = repr(value) if not isinstance(value, int) or abs(value) < 10**30 else "a huge integer"
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _number(data: Mapping[str, Any], key: str, *, required: bool = True, default: float = 0.0):
    if key not in data:
        if required:
            raise _fail("missing field; expected a number", key)
        return default
    value = data[key]
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise _fail(f"expected a number, got {_shown(value)}", key)
    try:
        value = float(value)
    except OverflowError:  # an integer beyond floating point's range
        raise _fail("expected a finite number, got a huge integer", key) from None
    if not math.isfinite(value):
        raise _fail(f"expected a finite number, got {value}", key)
    return value


def _name(data: Mapping[str, Any], key: str, what: str, *, nullable: bool = False) -> str | None:
    if key not in data:
        if nullable:
            return None
        raise _fail(f"missing field; expected a {what} name", key)
    value = data[key]
    if value is None and nullable:
        return None
    try:
        return check_pigment_name(value) if what == "pigment" else check_preset_name(value, what)
    except ValueError as exc:
        raise _fail(str(exc), key) from None


def _check_keys(data: Mapping[str, Any], allowed: tuple[str, ...], prefix: str = "") -> None:
    for key in data:
        if key not in allowed:
            raise _fail(
                f"unknown field; expected {', '.join(allowed)}", f"{prefix}{key}" if prefix else key
            )


@dataclass(frozen=True)
class CanvasSpec:
    """Canvas size: ``pixels`` (width, height) and ``size_m`` (width, height) in metres."""

    pixels: tuple[int, int]
    size_m: tuple[float, float]

    @classmethod
    def from_dict(cls, data: Any) -> CanvasSpec:
        """Validate ``{"pixels": [W, H], "size_m": [w, h]}``."""
        if not isinstance(data, Mapping):
            raise _fail("expected an object with pixels and size_m", "canvas")
        _check_keys(data, ("pixels", "size_m"), "canvas.")
        pixels = data.get("pixels")
        if (
            not isinstance(pixels, list | tuple)
            or len(pixels) != 2
            or not all(type(n) is int and 1 <= n <= MAX_PIXELS for n in pixels)
        ):
            raise _fail(f"expected [width, height] integers in [1, {MAX_PIXELS}]", "canvas.pixels")
        size = data.get("size_m")
        if (
            not isinstance(size, list | tuple)
            or len(size) != 2
            or not all(type(x) in (int, float) and 0.0 < x <= MAX_CANVAS_M for x in size)
        ):
            raise _fail(
                f"expected [width, height] metres in (0, {MAX_CANVAS_M:g}]", "canvas.size_m"
            )
        return cls((pixels[0], pixels[1]), (float(size[0]), float(size[1])))

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of this canvas spec."""
        return {"pixels": list(self.pixels), "size_m": list(self.size_m)}


@dataclass(frozen=True)
class StrokeHeader:
    """The first line of a stroke file.

    Attributes:
        canvas: canvas size in pixels and metres.
        brush: name of the brush preset in use at the start.
        pigments: names of the pigments the file may load (an event may only load these).
        scene: scene name, or None for the default painting scene.
        device: description of the input device (JSON object), or None (a tablet). Its optional
            ``kind`` is ``"tablet"``, ``"mouse"`` or ``"haptic"``; other keys are free-form.
        seed: random seed of the session (integer >= 0).
    """

    FORMAT: ClassVar[str] = FORMAT_NAME
    VERSION: ClassVar[int] = FORMAT_VERSION

    canvas: CanvasSpec
    brush: str
    pigments: tuple[str, ...] = ()
    scene: str | None = None
    device: dict[str, Any] | None = None
    seed: int = 0

    def __post_init__(self) -> None:
        fields = _header_fields(self.to_dict())  # validates (and normalizes) every field
        for key, value in fields.items():
            object.__setattr__(self, key, value)

    @classmethod
    def from_dict(cls, data: Any) -> StrokeHeader:
        """Validate a parsed header line; raises :class:`InputError` naming the field."""
        return cls(**_header_fields(data))

    @property
    def input_kind(self) -> str:
        """How to map samples to tip poses: ``"haptic"`` when ``device.kind`` is ``"haptic"``
        (z is the tip height), else ``"tablet"`` (pressure sets the depth)."""
        kind = (self.device or {}).get("kind", "tablet")
        return "haptic" if kind == "haptic" else "tablet"

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of the header line (format and version first)."""
        return {
            "format": FORMAT_NAME,
            "version": FORMAT_VERSION,
            "canvas": self.canvas.to_dict() if isinstance(self.canvas, CanvasSpec) else self.canvas,
            "brush": self.brush,
            "pigments": list(self.pigments),
            "scene": self.scene,
            "device": self.device,
            "seed": self.seed,
        }


def _header_fields(data: Any) -> dict[str, Any]:
    if not isinstance(data, Mapping):
        raise _fail("expected the header: a JSON object with format and version", "format")
    _check_keys(
        data, ("format", "version", "canvas", "brush", "pigments", "scene", "device", "seed")
    )
    if data.get("format") != FORMAT_NAME:
        raise _fail(
            f"not a stroke file: expected format {FORMAT_NAME!r}, got {_shown(data.get('format'))}",
            "format",
        )
    version = data.get("version")
    if type(version) is not int:
        raise _fail(
            f"expected an integer (the format version, 1), got {_shown(version)}", "version"
        )
    if version != FORMAT_VERSION:
        raise _fail(f"unsupported version {version}; this reader reads version 1", "version")
    pigments = data.get("pigments", [])
    if not isinstance(pigments, list | tuple):
        raise _fail("expected a list of pigment names", "pigments")
    names = tuple(_name({"pigments": p}, "pigments", "pigment") or "" for p in pigments)
    if len(set(names)) != len(names):
        raise _fail(f"pigment names must be unique, got {list(names)}", "pigments")
    seed = data.get("seed", 0)
    if type(seed) is not int or not 0 <= seed < 2**64:
        raise _fail(f"expected an integer in [0, 2^64), got {_shown(seed)}", "seed")
    canvas = data.get("canvas")
    if isinstance(canvas, CanvasSpec):
        canvas = canvas.to_dict()
    return {
        "canvas": CanvasSpec.from_dict(canvas),
        "brush": _name(data, "brush", "brush preset") or "",
        "pigments": names,
        "scene": _name(data, "scene", "scene", nullable=True),
        "device": _device(data.get("device")),
        "seed": seed,
    }


def _device(device: Any) -> dict[str, Any] | None:
    if device is None:
        return None
    if not isinstance(device, Mapping):
        raise _fail("expected a JSON object describing the device, or null", "device")
    kind = device.get("kind", "tablet")
    if kind not in DEVICE_KINDS:
        raise _fail(f"expected one of {', '.join(DEVICE_KINDS)}, got {_shown(kind)}", "device.kind")
    try:
        json.dumps(device, allow_nan=False)
    except (TypeError, ValueError) as exc:
        raise _fail(f"expected plain JSON values: {exc}", "device") from None
    return dict(device)


@dataclass(frozen=True)
class LoadPigment:
    """Event ``load_pigment``: the brush dips into ``pigment`` on the palette and takes up
    ``volume_m3`` (m^3, > 0; the brush keeps what fits its capacity)."""

    EVENT: ClassVar[str] = "load_pigment"
    t_s: float
    pigment: str
    volume_m3: float


@dataclass(frozen=True)
class SwitchBrush:
    """Event ``brush``: from now on paint with the brush preset ``preset`` (a clean brush)."""

    EVENT: ClassVar[str] = "brush"
    t_s: float
    preset: str


@dataclass(frozen=True)
class CleanBrush:
    """Event ``clean``: the brush is wiped; it carries no paint afterwards."""

    EVENT: ClassVar[str] = "clean"
    t_s: float


@dataclass(frozen=True)
class Marker:
    """Event ``marker``: a label at a time (annotation for tests and figures; replay ignores it)."""

    EVENT: ClassVar[str] = "marker"
    t_s: float
    label: str


StrokeEvent = LoadPigment | SwitchBrush | CleanBrush | Marker
StrokeRecord = StylusSample | StrokeEvent
EVENT_TYPES: dict[str, type] = {
    cls.EVENT: cls for cls in (LoadPigment, SwitchBrush, CleanBrush, Marker)
}
_EVENT_FIELDS = {
    "load_pigment": ("t", "event", "pigment", "volume_m3"),
    "brush": ("t", "event", "preset"),
    "clean": ("t", "event"),
    "marker": ("t", "event", "label"),
}


def _time(data: Mapping[str, Any]) -> float:
    t = _number(data, "t")
    if t < 0.0:
        raise _fail(f"expected a time >= 0 s, got {t}", "t")
    return t


def sample_from_dict(data: Mapping[str, Any]) -> StylusSample:
    """A stylus sample from its line's object (``tilt``, ``twist``, ``buttons`` default to 0)."""
    _check_keys(data, SAMPLE_KEYS)
    if "pos" not in data:
        raise _fail("missing field; expected [x, y, z] in metres", "pos")
    fields = {
        "t_s": _time(data),
        "position_m": data["pos"],
        "pressure": _number(data, "pressure"),
        "tilt_rad": data.get("tilt", [0.0, 0.0]),
        "twist_rad": _number(data, "twist", required=False),
        "buttons": data.get("buttons", 0),
    }
    names = {"position_m": "pos", "tilt_rad": "tilt", "twist_rad": "twist", "t_s": "t"}
    for vector in ("position_m", "tilt_rad"):
        value = fields[vector]
        if not isinstance(value, list) or any(isinstance(x, bool | str) for x in value):
            raise _fail(f"expected a list of numbers, got {_shown(value)}", names[vector])
    try:
        return StylusSample(**fields)
    except InputError as exc:
        raise _fail(exc.message, names.get(exc.key or "", exc.key or "")) from None


def event_from_dict(data: Mapping[str, Any], pigments: tuple[str, ...]) -> StrokeEvent:
    """An event from its line's object; ``pigments`` are the header's (the ones it may load)."""
    kind = data.get("event")
    if not isinstance(kind, str) or kind not in EVENT_TYPES:
        raise _fail(
            f"unknown event {_shown(kind)}; expected one of {', '.join(EVENT_TYPES)}", "event"
        )
    _check_keys(data, _EVENT_FIELDS[kind])
    t = _time(data)
    if kind == "load_pigment":
        pigment = _name(data, "pigment", "pigment") or ""
        if pigment not in pigments:
            raise _fail(
                f"pigment {pigment!r} is not in the header's pigments {list(pigments)}", "pigment"
            )
        volume = _number(data, "volume_m3")
        if not 0.0 < volume <= MAX_LOAD_M3:
            raise _fail(f"expected a volume in (0, {MAX_LOAD_M3:g}] m^3, got {volume}", "volume_m3")
        return LoadPigment(t, pigment, volume)
    if kind == "brush":
        return SwitchBrush(t, _name(data, "preset", "brush preset") or "")
    if kind == "clean":
        return CleanBrush(t)
    label = data.get("label")
    if not isinstance(label, str) or len(label) > 200:
        raise _fail("expected a string label of at most 200 characters", "label")
    return Marker(t, label)


def record_to_dict(record: StrokeRecord) -> dict[str, Any]:
    """The JSON object of one sample or event line."""
    if isinstance(record, StylusSample):
        return {
            "t": record.t_s,
            "pos": [float(x) for x in record.position_m],
            "pressure": record.pressure,
            "tilt": [float(x) for x in record.tilt_rad],
            "twist": record.twist_rad,
            "buttons": record.buttons,
        }
    out: dict[str, Any] = {"t": float(record.t_s), "event": record.EVENT}
    if isinstance(record, LoadPigment):
        out.update(pigment=record.pigment, volume_m3=float(record.volume_m3))
    elif isinstance(record, SwitchBrush):
        out["preset"] = record.preset
    elif isinstance(record, Marker):
        out["label"] = record.label
    return out


def to_json_line(data: Mapping[str, Any]) -> str:
    """One JSON line (no newline); refuses NaN and infinities."""
    try:
        return json.dumps(data, allow_nan=False, ensure_ascii=False)
    except (TypeError, ValueError) as exc:
        raise InputError(f"cannot write as JSON: {exc}") from None
