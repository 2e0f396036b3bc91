"""The sizes an unstructured data file claims, checked before a reader allocates them.

VTK's and OpenFOAM's readers trust the counts in a file's headers (``POINTS 1000000000000``,
``NumberOfPoints="..."``, an OpenFOAM list's leading count) and allocate what they claim. These
checks parse the counts themselves and refuse, with one line naming the file and the field:

- any count beyond the memory budget (:data:`common.limits.MEMORY_BUDGET_BYTES`);
- in a legacy ``.vtk`` or an uncompressed OpenFOAM file, a count the file is too small to hold
  (every value takes at least 2 bytes in ASCII, 4 in binary);
- components per tuple beyond :data:`MAX_COMPONENTS`.

Files are scanned through a memory map (nothing is read into memory at once); compressed
OpenFOAM files (``.gz``) only as far as their first :data:`HEAD_BYTES` inflated bytes.
"""

from __future__ import annotations

import gzip
import mmap
import re
import zlib
from pathlib import Path

from common.errors import InputError
from common.limits import check_elements

#: Bytes a point may take while read and resampled: its coordinates, pressure, velocity and
#: velocity gradient as float64, in VTK's arrays and in ours.
BYTES_PER_POINT = 2 * 16 * 8
#: Bytes a cell may take: its connectivity (8 ids), offset, type, bounding box and size.
BYTES_PER_CELL = 12 * 8
#: The most components a data array may claim.
MAX_COMPONENTS = 64
#: How much of a compressed file's start is inflated to read its counts.
HEAD_BYTES = 64 * 1024
#: Fewest bytes a value takes in a file (ASCII: a digit and a separator).
MIN_VALUE_BYTES = 2

_LEGACY = re.compile(
    rb"(?m)^[ \t]*(POINTS|CELLS|CELL_TYPES|POINT_DATA|CELL_DATA)"
    rb"[ \t]+(\S{1,40})(?:[ \t]+(\S{1,40}))?"
)
_LEGACY_ARRAY = re.compile(rb"(?m)^[ \t]*(?:SCALARS|COLOR_SCALARS)[ \t]+\S+[ \t]+\S+[ \t]+(\S+)")
_XML_COUNT = re.compile(
    rb"\b(NumberOfPoints|NumberOfCells|NumberOfComponents)\s*=\s*[\"'](.{0,40}?)[\"']"
)


def _whole(text: bytes, source: str, key: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise InputError(f"expected a whole number, got {text[:40]!r}", source, key) from None
    if value < 0:
        raise InputError(f"expected a count >= 0, got {value}", source, key)
    return value


def _scan(path: Path, pattern: re.Pattern[bytes]) -> list[tuple[bytes, ...]]:
    source = str(path)
    try:
        with open(path, "rb") as fh:
            if path.stat().st_size == 0:
                raise InputError("the file is empty", source)
            with mmap.mmap(fh.fileno(), 0, access=mmap.ACCESS_READ) as view:
                return [m.groups() for m in pattern.finditer(view)]  # type: ignore[arg-type]
    except OSError as exc:
        raise InputError(f"cannot read the file: {exc.strerror}", source) from None


def check_legacy(path: Path) -> None:
    """A legacy ``.vtk`` file's ``POINTS``, ``CELLS``, ``*_DATA`` and array counts."""
    source = str(path)
    size = path.stat().st_size
    for name, first, second in _scan(path, _LEGACY):
        key = name.decode()
        count = _whole(first, source, key)
        per = BYTES_PER_POINT if key in ("POINTS", "POINT_DATA") else BYTES_PER_CELL
        check_elements(count, per, source, key)
        values = count * (3 if key == "POINTS" else 1)
        if key == "CELLS" and second is not None:
            values = max(values, _whole(second, source, key))
            check_elements(values, 8, source, key)
        if values * MIN_VALUE_BYTES > size and key not in ("POINT_DATA", "CELL_DATA"):
            raise InputError(
                f"claims {values} values but the file holds only {size} bytes", source, key
            )
    for (components,) in _scan(path, _LEGACY_ARRAY):
        if components.strip().isdigit():
            _components(int(components), source)


def check_xml(path: Path) -> None:
    """A VTK XML file's ``NumberOfPoints``, ``NumberOfCells`` (summed over its pieces) and
    ``NumberOfComponents``."""
    source = str(path)
    totals = {"NumberOfPoints": 0, "NumberOfCells": 0}
    for name, value in _scan(path, _XML_COUNT):
        key = name.decode()
        count = _whole(value, source, key)
        if key == "NumberOfComponents":
            _components(count, source)
        else:
            totals[key] += count
    check_elements(totals["NumberOfPoints"], BYTES_PER_POINT, source, "NumberOfPoints")
    check_elements(totals["NumberOfCells"], BYTES_PER_CELL, source, "NumberOfCells")


def _components(count: int, source: str) -> None:
    if not 1 <= count <= MAX_COMPONENTS:
        raise InputError(
            f"claims {count} components per value; expected 1 to {MAX_COMPONENTS}",
            source,
            "NumberOfComponents",
        )


_FOAM_COUNT = re.compile(rb"(?:^|\n|>\s*|List<\w+>\s*)[ \t]*(\d{1,40})[ \t]*\r?\n?[ \t]*[(\[{]")


def check_openfoam_file(path: Path) -> None:
    """The list counts near the start of an OpenFOAM file (``points``, ``faces``, ``owner``,
    ``neighbour``, a field's ``internalField``), plain or ``.gz``."""
    source = str(path)
    try:
        if path.suffix == ".gz":
            with gzip.open(path, "rb") as fh:
                head = fh.read(HEAD_BYTES)
            size = None
        else:
            with open(path, "rb") as fh:
                head = fh.read(HEAD_BYTES)
            size = path.stat().st_size
    except (OSError, EOFError, zlib.error) as exc:
        raise InputError(f"cannot read the OpenFOAM file ({exc})", source) from None
    body = head.split(b"FoamFile", 1)[-1]
    body = body.split(b"}", 1)[-1] if b"FoamFile" in head else body
    for match in _FOAM_COUNT.finditer(body):
        count = _whole(match.group(1), source, "list size")
        check_elements(count, BYTES_PER_POINT, source, "list size")
        if size is not None and count * MIN_VALUE_BYTES > size:
            raise InputError(
                f"claims a list of {count} values but the file holds only {size} bytes",
                source,
                "list size",
            )
