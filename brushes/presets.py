"""Brush presets: TOML files (one brush each, named by the file stem) validated into
:class:`BrushPreset`.

A preset file::

    description = "Small round sable"   # optional
    shape = "round"                     # round | flat | box
    stiffness = 0.4                     # 0..1: 1 = rigid (never splays), 0 = floppy
    capacity_m3 = 3.0e-8                # paint the brush holds (30 mm^3)

    [size]                              # metres; keys depend on the shape (see SIZE_KEYS)
    tip_radius_m = 0.0004
    belly_radius_m = 0.002
    length_m = 0.012

    [pressure]
    depth_m = 0.0015   # full pressure presses the apex this far below the paint surface
    exponent = 1.0     # press depth = depth_m * pressure**exponent
    spread = 0.8       # footprint widens by spread * (1 - stiffness) at full depth

    [tilt]             # optional
    gain = 1.0         # fraction of the stylus tilt given to the brush axis
    max_rad = 1.0      # the axis leans at most this far from the canvas normal
    twist_gain = 1.0   # fraction of the stylus twist turning the tip about its axis

    [bristles]         # optional (round and flat only): the bristle texture, brushes.bristles
    clumps = 24        # bristle clumps across the footprint, 2-400
    contrast = 0.5     # 0-1: how strongly the clumps streak the paint along the stroke
    ridge = 0.5        # 0-2: paint heaped along the stroke's sides
    seed = 0           # integer >= 0: which clump positions
"""

from __future__ import annotations

import re
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from brushes.bristles import MAX_CLUMPS, MAX_CONTRAST, Bristles
from brushes.tips import RoundCone, RoundedBox, Splayed, TipShape
from common.errors import InputError
from common.limits import MAX_TOML_BYTES, check_nesting, read_text_capped
from common.names import check_preset_name, is_preset_name
from common.tables import Table

SHAPES = ("round", "flat", "box")
SIZE_KEYS: dict[str, tuple[str, ...]] = {
    "round": ("tip_radius_m", "belly_radius_m", "length_m"),
    "flat": ("width_m", "thickness_m", "length_m", "corner_radius_m"),
    "box": ("width_m", "thickness_m", "length_m", "corner_radius_m"),
}
MIN_SIZE_M = 1e-5
MAX_SIZE_M = 0.1
MAX_CAPACITY_M3 = 1e-4
_SIZE_HINT = " (sizes are in metres: 4 mm is 0.004)"


@dataclass(frozen=True)
class PressureResponse:
    """What stylus pressure does: press depth below the paint surface, and footprint spread."""

    depth_m: float
    exponent: float = 1.0
    spread: float = 0.0

    def depth_for(self, pressure: float) -> float:
        """Press depth (m) of the apex below the paint surface at ``pressure`` in [0, 1]."""
        return self.depth_m * min(max(pressure, 0.0), 1.0) ** self.exponent

    def pressure_for(self, depth_m: float) -> float:
        """Inverse of :meth:`depth_for`, clamped to [0, 1] (deeper than full depth gives 1)."""
        ratio = min(max(depth_m / self.depth_m, 0.0), 1.0)
        return ratio ** (1.0 / self.exponent)


@dataclass(frozen=True)
class TiltResponse:
    """What stylus tilt and twist do to the brush axis."""

    gain: float = 1.0
    max_rad: float = 1.2
    twist_gain: float = 1.0


@dataclass(frozen=True)
class BrushPreset:
    """A validated brush: its tip geometry and how it answers pressure and tilt.

    Attributes:
        name: the preset name (the file stem), as referenced by stroke files.
        shape: ``"round"``, ``"flat"`` or ``"box"``.
        size_m: the ``[size]`` table (metres), keys from :data:`SIZE_KEYS`.
        stiffness: 0..1; 1 is rigid (no splay), 0 splays the most.
        capacity_m3: paint volume the brush holds (m^3).
        pressure, tilt: the responses.
        description: free text.
        bristles: the bristle texture (:class:`brushes.bristles.Bristles`), or None for an even
            footprint (a rigid probe, or a preset without ``[bristles]``).
    """

    name: str
    shape: str
    size_m: Mapping[str, float]
    stiffness: float
    capacity_m3: float
    pressure: PressureResponse
    tilt: TiltResponse = field(default_factory=TiltResponse)
    description: str = ""
    bristles: Bristles | None = None

    @property
    def length_m(self) -> float:
        """Length (m) of the tip along its axis."""
        return self.size_m["length_m"]

    def base_tip(self) -> TipShape:
        """The undeformed tip shape in its body frame (apex at origin, handle along +z)."""
        s = self.size_m
        if self.shape == "round":
            return RoundCone(s["tip_radius_m"], s["belly_radius_m"], s["length_m"])
        return RoundedBox(s["width_m"], s["thickness_m"], s["length_m"], s["corner_radius_m"])

    def tip(self, splay: float = 1.0) -> TipShape:
        """The tip shape widened laterally by the factor ``splay`` (>= 1; 1 is undeformed)."""
        base = self.base_tip()
        return base if splay == 1.0 else Splayed(base, splay)

    def splay_for_depth(self, depth_m: float) -> float:
        """Lateral splay factor (>= 1) when the stylus presses ``depth_m`` below the surface.

        Grows linearly from 1 at zero depth to ``1 + spread * (1 - stiffness)`` at the preset's
        full press depth, and stays there beyond it.
        """
        ratio = min(max(depth_m / self.pressure.depth_m, 0.0), 1.0)
        return 1.0 + self.pressure.spread * (1.0 - self.stiffness) * ratio

    @classmethod
    def from_dict(
        cls, data: Mapping[str, Any], name: str, source: str | None = None
    ) -> BrushPreset:
        """Validate a parsed preset table; raises :class:`InputError` naming ``source`` and key."""
        top = Table(data, source or "", "")
        top.expect(
            (
                "description",
                "shape",
                "stiffness",
                "capacity_m3",
                "size",
                "pressure",
                "tilt",
                "bristles",
            )
        )
        shape = top.string("shape", choices=SHAPES)
        size = _size_table(top.table("size"), shape)
        capacity = top.number(
            "capacity_m3",
            minimum=0.0,
            exclusive=True,
            maximum=MAX_CAPACITY_M3,
            hint=" (m^3: 30 mm^3 is 3e-8)",
        )
        preset = cls(
            name=name,
            shape=shape,
            size_m=size,
            stiffness=top.number("stiffness", minimum=0.0, maximum=1.0),
            capacity_m3=capacity,
            pressure=_pressure(top.table("pressure"), size["length_m"]),
            tilt=_tilt(top.table("tilt", {})),
            description=top.string("description", ""),
            bristles=_bristles(top, shape),
        )
        top.finish()
        return preset


def _size_table(table: Table, shape: str) -> dict[str, float]:
    table.expect(SIZE_KEYS[shape])
    size: dict[str, float] = {}
    for key in SIZE_KEYS[shape]:
        if key == "corner_radius_m":
            default = 0.5 * size["thickness_m"] if shape == "flat" else 0.0
            size[key] = table.number(key, default, minimum=0.0)
        else:
            size[key] = table.number(key, minimum=MIN_SIZE_M, maximum=MAX_SIZE_M, hint=_SIZE_HINT)
    table.finish()
    _check_geometry(size, shape, table)
    return size


def _check_geometry(size: dict[str, float], shape: str, table: Table) -> None:
    def fail(key: str, message: str) -> None:
        raise table.error(key, message)

    if shape == "round":
        widest = max(size["tip_radius_m"], size["belly_radius_m"])
        if size["length_m"] <= 2.0 * widest:
            fail("length_m", f"expected more than twice the larger radius ({2 * widest:g} m)")
        return
    if shape == "flat" and size["thickness_m"] >= size["width_m"]:
        fail("thickness_m", "a flat brush is thin in y: expected thickness_m < width_m")
    smallest = min(size["width_m"], size["thickness_m"], size["length_m"])
    if size["corner_radius_m"] > 0.5 * smallest:
        fail("corner_radius_m", f"expected at most half the smallest size ({0.5 * smallest:g} m)")


def _pressure(table: Table, length_m: float) -> PressureResponse:
    table.expect(("depth_m", "exponent", "spread"))
    depth = table.number(
        "depth_m",
        minimum=0.0,
        exclusive=True,
        maximum=length_m,
        hint=" (metres, at most the tip length)",
    )
    response = PressureResponse(
        depth_m=depth,
        exponent=table.number("exponent", 1.0, minimum=0.1, maximum=10.0),
        spread=table.number("spread", 0.0, minimum=0.0, maximum=4.0),
    )
    table.finish()
    return response


def _tilt(table: Table) -> TiltResponse:
    table.expect(("gain", "max_rad", "twist_gain"))
    response = TiltResponse(
        gain=table.number("gain", 1.0, minimum=0.0, maximum=1.0),
        max_rad=table.number("max_rad", 1.2, minimum=0.0, maximum=1.5),
        twist_gain=table.number("twist_gain", 1.0, minimum=0.0, maximum=1.0),
    )
    table.finish()
    return response


def _bristles(top: Table, shape: str) -> Bristles | None:
    if not top.has("bristles"):
        top.raw("bristles", None)
        return None
    if shape == "box":
        raise top.error("bristles", "a box probe is rigid and has no bristles; remove [bristles]")
    table = top.table("bristles")
    table.expect(("clumps", "contrast", "ridge", "seed"))
    default = Bristles()
    bristles = Bristles(
        clumps=table.integer("clumps", default.clumps, minimum=2, maximum=MAX_CLUMPS),
        contrast=table.number("contrast", default.contrast, minimum=0.0, maximum=MAX_CONTRAST),
        ridge=table.number("ridge", default.ridge, minimum=0.0, maximum=2.0),
        seed=table.integer("seed", default.seed, minimum=0),
    )
    table.finish()
    return bristles


def load_preset(path: str | Path) -> BrushPreset:
    """Read and validate the preset file ``path``; its name is the file stem.

    Raises :class:`InputError` (with the file, the dotted key and, for TOML syntax errors, the
    line) when the file is missing, malformed or holds an unknown key or an out-of-range value.
    """
    path = Path(path)
    source = str(path)
    try:
        name = check_preset_name(path.stem, "brush preset")
    except ValueError as exc:
        raise InputError(str(exc), source=source) from None
    try:
        text = read_text_capped(path, MAX_TOML_BYTES, "brush preset", encoding="utf-8")
    except FileNotFoundError:
        raise InputError("no such brush preset file", source=source) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read the preset: {exc}", source=source) from None
    check_nesting(text, source, toml=True)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        match = re.search(r"line (\d+)", str(exc))
        line = int(match.group(1)) if match else None
        raise InputError(f"not valid TOML: {exc}", source=source, line=line) from None
    return BrushPreset.from_dict(data, name=name, source=source)


def list_presets(directory: str | Path) -> dict[str, Path]:
    """Preset name -> file for every ``*.toml`` in ``directory``, sorted by name."""
    files = sorted(Path(directory).glob("*.toml"))
    return {path.stem: path for path in files if is_preset_name(path.stem)}


def find_preset(name: str, directory: str | Path) -> Path:
    """The file of preset ``name`` in ``directory``; :class:`InputError` listing the known ones."""
    try:
        check_preset_name(name, "brush preset")
    except ValueError as exc:
        raise InputError(str(exc), key="brush") from None
    known = list_presets(directory)
    if name not in known:
        raise InputError(
            f"unknown brush preset {name!r}; known presets: {', '.join(known) or 'none'}",
            source=str(directory),
            key="brush",
        )
    return known[name]


def load_preset_named(name: str, directory: str | Path) -> BrushPreset:
    """Load preset ``name`` from ``directory`` (as stroke files refer to brushes)."""
    return load_preset(find_preset(name, directory))
