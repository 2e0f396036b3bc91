"""Pigments: named paints with a masstone reflectance spectrum, loaded from TOML files.

A pigment file (``assets/pigments/<name>.toml``) looks like::

    name = "ultramarine_blue"        # [a-z0-9_], unique; used in canvas files (pigment.<name>)
    label = "Ultramarine Blue"       # optional, for people
    colour_index = "PB29"            # optional Colour Index name
    scattering_per_m = 20000.0       # optional Kubelka-Munk S, 1/m (default 20000)
    srgb = "#1d2f95"                 # masstone as sRGB: "#rrggbb" or [r, g, b] in [0, 1]

or, instead of ``srgb``, a measured masstone::

    [reflectance]
    wavelengths_nm = [400, 450, 500, ...]
    values = [0.05, 0.12, 0.30, ...]     # fractions in (0, 1]

An sRGB masstone is upsampled to a spectrum (see :mod:`paintapp.pigments.spectra`); K and S
follow from the masstone (see :mod:`paintapp.pigments.kubelka_munk`). Errors name the file and the key.
"""

from __future__ import annotations

import functools
import math
import re
import tomllib
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from common.errors import InputError
from common.limits import MAX_TOML_BYTES, check_nesting, read_text_capped
from common.names import is_pigment_name
from paintapp.pigments.kubelka_munk import masstone_ks
from paintapp.pigments.spectra import (
    reflectance_to_linear_rgb,
    resample_reflectance,
    srgb_to_reflectance,
)
from paintapp.resources import asset_path

DEFAULT_SCATTERING_PER_M = 20000.0
_KEYS = {"name", "label", "colour_index", "scattering_per_m", "srgb", "reflectance", "notes"}


@dataclass(frozen=True, eq=False)
class Pigment:
    """One pigment.

    Attributes:
        name: identifier, ``[a-z][a-z0-9_]*``.
        reflectance: masstone reflectance on ``WAVELENGTHS_NM``, shape (L,), in (0, 1).
        scattering_per_m: Kubelka-Munk scattering S, 1/m, flat over wavelength.
        label: human-readable name.
        colour_index: Colour Index code (e.g. "PB29"), may be empty.
        source: where it was defined (a file path), may be empty.
    """

    name: str
    reflectance: np.ndarray
    scattering_per_m: float = DEFAULT_SCATTERING_PER_M
    label: str = ""
    colour_index: str = ""
    source: str = field(default="", compare=False)

    @property
    def k_per_m(self) -> np.ndarray:
        """Absorption K per wavelength, 1/m, shape (L,)."""
        return masstone_ks(self.reflectance, self.scattering_per_m)[0]

    @property
    def s_per_m(self) -> np.ndarray:
        """Scattering S per wavelength, 1/m, shape (L,)."""
        return masstone_ks(self.reflectance, self.scattering_per_m)[1]

    def masstone_linear_rgb(self) -> np.ndarray:
        """Linear sRGB (D65) colour of an opaque layer of the pure pigment, shape (3,)."""
        return reflectance_to_linear_rgb(self.reflectance)


class PigmentLibrary(Mapping[str, Pigment]):
    """Pigments by name (read-only mapping)."""

    def __init__(self, pigments: Iterable[Pigment]) -> None:
        self._by_name: dict[str, Pigment] = {}
        for pigment in pigments:
            self._by_name[pigment.name] = pigment

    def __getitem__(self, name: str) -> Pigment:
        return self._by_name[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._by_name)

    def __len__(self) -> int:
        return len(self._by_name)

    def require(self, names: Iterable[str], source: str | None = None) -> list[Pigment]:
        """The named pigments; an unknown name raises :class:`InputError` listing the known ones."""
        found = []
        for name in names:
            if name not in self._by_name:
                known = ", ".join(sorted(self._by_name)) or "none"
                raise InputError(f"unknown pigment {name!r}; known: {known}", source=source)
            found.append(self._by_name[name])
        return found

    def merged(self, other: PigmentLibrary) -> PigmentLibrary:
        """A library with this one's pigments, overridden by ``other``'s of the same name."""
        return PigmentLibrary([*self.values(), *other.values()])


def _parse_srgb(value: object, source: str) -> tuple[float, float, float]:
    if isinstance(value, str):
        if not re.fullmatch(r"#[0-9a-fA-F]{6}", value):
            raise InputError(f"expected '#rrggbb', got {value!r}", source=source, key="srgb")
        return tuple(int(value[i : i + 2], 16) / 255.0 for i in (1, 3, 5))  # type: ignore[return-value]
    if (
        isinstance(value, list)
        and len(value) == 3
        and all(isinstance(c, int | float) and 0.0 <= c <= 1.0 for c in value)
    ):
        return (float(value[0]), float(value[1]), float(value[2]))
    raise InputError(
        f"expected '#rrggbb' or three numbers in [0, 1], got {value!r}", source=source, key="srgb"
    )


def _float_list(table: dict, key: str, source: str) -> np.ndarray:
    value = table.get(key)
    if not isinstance(value, list) or len(value) < 2:
        raise InputError("expected a list of at least 2 numbers", source=source, key=key)
    if not all(isinstance(v, int | float) and not isinstance(v, bool) for v in value):
        raise InputError("expected numbers only", source=source, key=key)
    array = np.asarray(value, np.float64)
    if not np.all(np.isfinite(array)):
        raise InputError("values must be finite", source=source, key=key)
    return array


def _parse_reflectance(value: object, source: str) -> np.ndarray:
    if not isinstance(value, dict):
        raise InputError("expected a table with wavelengths_nm and values", source, "reflectance")
    extra = set(value) - {"wavelengths_nm", "values"}
    if extra:
        raise InputError(f"unknown key(s) {sorted(extra)}", source, "reflectance")
    wl = _float_list(value, "wavelengths_nm", source)
    values = _float_list(value, "values", source)
    if len(wl) != len(values):
        raise InputError(
            f"{len(wl)} wavelengths but {len(values)} values", source, "reflectance.values"
        )
    if np.any(np.diff(wl) <= 0) or wl[0] < 300 or wl[-1] > 850:
        raise InputError(
            "wavelengths must increase strictly within 300-850 nm",
            source,
            "reflectance.wavelengths_nm",
        )
    if np.any(values <= 0) or np.any(values > 1):
        raise InputError("reflectances must be in (0, 1]", source, "reflectance.values")
    return resample_reflectance(wl, values)


def pigment_from_dict(data: dict, source: str = "") -> Pigment:
    """Build a :class:`Pigment` from parsed TOML data; errors name ``source`` and the key."""
    unknown = set(data) - _KEYS
    if unknown:
        raise InputError(f"unknown key(s) {sorted(unknown)}; allowed: {sorted(_KEYS)}", source)
    name = data.get("name")
    if not is_pigment_name(name):
        raise InputError(
            f"expected a name matching [a-z][a-z0-9_]* (at most 48 characters), got {name!r}",
            source,
            key="name",
        )
    if ("srgb" in data) == ("reflectance" in data):
        raise InputError("give exactly one of 'srgb' or '[reflectance]'", source, key="srgb")
    if "srgb" in data:
        reflectance = srgb_to_reflectance(_parse_srgb(data["srgb"], source))
    else:
        reflectance = _parse_reflectance(data["reflectance"], source)
    scattering = data.get("scattering_per_m", DEFAULT_SCATTERING_PER_M)
    if (
        not isinstance(scattering, int | float)
        or not math.isfinite(scattering)
        or not 1.0 <= scattering <= 1e8
    ):
        raise InputError(
            f"expected a number in [1, 1e8] (1/m), got {scattering!r}", source, "scattering_per_m"
        )
    for key in ("label", "colour_index", "notes"):
        if not isinstance(data.get(key, ""), str):
            raise InputError("expected a string", source, key=key)
    return Pigment(
        name=name,
        reflectance=reflectance,
        scattering_per_m=float(scattering),
        label=data.get("label", name.replace("_", " ").title()),
        colour_index=data.get("colour_index", ""),
        source=source,
    )


def load_pigment(path: str | Path) -> Pigment:
    """Load one pigment TOML file; malformed files raise :class:`InputError` naming file and key."""
    path = Path(path)
    try:
        text = read_text_capped(path, MAX_TOML_BYTES, "pigment file", encoding="utf-8")
        check_nesting(text, str(path), toml=True)
        data = tomllib.loads(text)
    except OSError as exc:
        raise InputError(f"cannot read pigment file: {exc.strerror}", source=str(path)) from exc
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise InputError(f"not valid TOML: {exc}", source=str(path)) from exc
    return pigment_from_dict(data, source=str(path))


def load_pigment_directory(directory: str | Path) -> PigmentLibrary:
    """All ``*.toml`` pigments in a directory; duplicate names are an error."""
    directory = Path(directory)
    if not directory.is_dir():
        raise InputError("not a directory of pigment files", source=str(directory))
    pigments: dict[str, Pigment] = {}
    for path in sorted(directory.glob("*.toml")):
        pigment = load_pigment(path)
        if pigment.name in pigments:
            first = pigments[pigment.name].source
            raise InputError(f"pigment name also defined in {first}", str(path), key="name")
        pigments[pigment.name] = pigment
    return PigmentLibrary(pigments.values())


@functools.cache
def bundled_pigments() -> PigmentLibrary:
    """The pigments that ship with the application (``assets/pigments/``), loaded once."""
    return load_pigment_directory(asset_path("pigments"))


def load_pigment_library(*directories: str | Path) -> PigmentLibrary:
    """The bundled pigments, extended or overridden by those in ``directories`` (in order)."""
    library = bundled_pigments()
    for directory in directories:
        library = library.merged(load_pigment_directory(directory))
    return library
