"""Unstructured VTK files as frames: XML ``.vtu``, ``.vtm`` multiblock (its internal mesh),
legacy ``.vtk`` unstructured grids, and the time series ``.pvd`` (ParaView's collection) and
``.series`` (the JSON ``file-series-version`` list that foamToVTK and ParaView write).

Sizes are checked before a reader allocates anything (:mod:`.claimed_sizes`). A ``.vtp`` (a
surface: polygons with no volume) is refused: a surface is not a flow.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path
from typing import Any

from common.errors import InputError
from common.limits import read_bytes_capped
from paintapp.explore.claimed_sizes import check_legacy, check_xml
from paintapp.explore.load_progress import Progress
from paintapp.explore.unstructured import UnstructuredFrame

UNSTRUCTURED_SUFFIXES = (".vtu", ".vtm", ".pvd", ".series", ".vtp")
SERIES_SUFFIXES = (".pvd", ".series")
#: Largest series index file read.
MAX_INDEX_BYTES = 4 * 1024 * 1024
#: Names foamToVTK and ParaView give the volume mesh in a multiblock set.
INTERNAL_NAMES = ("internal", "internalMesh", "internalmesh")
NOT_A_FLOW = (
    "holds a surface (polygons), not a volume: a surface is not a flow; give the volume mesh "
    "(.vtu, .vtm, or the OpenFOAM case)"
)


def is_legacy_unstructured(path: Path) -> bool:
    """True for a legacy ``.vtk`` file whose header says ``DATASET UNSTRUCTURED_GRID``."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(4096)
    except OSError:
        return False
    return re.search(rb"(?m)^\s*DATASET\s+UNSTRUCTURED_GRID", head) is not None


def series_members(path: Path) -> list[tuple[Path, float | None]]:
    """The files of a ``.pvd`` or ``.series`` index and their times (s), in order."""
    source = str(path)
    try:
        text = read_bytes_capped(path, MAX_INDEX_BYTES, "series index").decode("utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read the series index ({exc})", source) from None
    members: list[tuple[Path, float | None]] = []
    if path.suffix.lower() == ".series":
        try:
            listed = json.loads(text)["files"]
            pairs = [(str(f["name"]), f.get("time")) for f in listed]
        except (ValueError, KeyError, TypeError) as exc:
            raise InputError(
                f"expected JSON with a 'files' list of name and time ({exc})", source, "files"
            ) from None
    else:
        pairs = []
        for tag in re.findall(r"<DataSet\b[^>]*>", text):
            file = re.search(r'\bfile\s*=\s*["\']([^"\']*)["\']', tag)
            step = re.search(r'\btimestep\s*=\s*["\']([^"\']*)["\']', tag)
            if file is None:
                raise InputError("a DataSet without a file", source, "DataSet")
            pairs.append((file.group(1), step.group(1) if step else None))
    for name, time in pairs:
        value = None
        if time is not None:
            try:
                value = float(time)
            except (TypeError, ValueError):
                raise InputError(
                    f"expected a number, got {str(time)[:40]!r}", source, "time"
                ) from None
            if not math.isfinite(value):
                raise InputError("expected a finite time", source, "time")
        member = (path.parent / name).resolve()
        members.append((member, value))
    if not members:
        raise InputError("the series lists no files", source)
    return members


def read_unstructured(path: Path, progress: Progress | None = None) -> UnstructuredFrame:
    """One frame from a ``.vtu``, ``.vtm`` or legacy unstructured ``.vtk`` file."""
    source = str(path)
    suffix = path.suffix.lower()
    if suffix == ".vtp":
        raise InputError(NOT_A_FLOW, source)
    if suffix not in (".vtu", ".vtm", ".vtk"):
        raise InputError(
            f"a {suffix or 'suffix-less'} file in a series of meshes; expected .vtu, .vtm or a "
            "legacy unstructured .vtk",
            source,
        )
    quiet_vtk()
    if suffix == ".vtm":
        mesh = _multiblock(path, progress)
    else:
        if suffix == ".vtk":
            check_legacy(path)
            from vtkmodules.vtkIOLegacy import vtkUnstructuredGridReader

            reader: Any = vtkUnstructuredGridReader()
        else:
            check_xml(path)
            from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

            reader = vtkXMLUnstructuredGridReader()
        mesh = _read(reader, source, progress)
    if mesh is None or mesh.GetClassName() != "vtkUnstructuredGrid" or not mesh.GetNumberOfCells():
        raise InputError("not a readable unstructured grid (no cells were read)", source)
    return UnstructuredFrame(source, mesh, *_field_data(mesh))


def _read(reader: Any, source: str, progress: Progress | None) -> Any:
    """Run a VTK ``reader`` on the file ``source`` (its progress shown) and return its output."""
    reader.SetFileName(source)
    if progress is not None:
        progress.watch(reader, "reading")
    reader.Update()
    return reader.GetOutput()


def _multiblock(path: Path, progress: Progress | None) -> Any:
    """The volume mesh of a multiblock file: the block named ``internal`` (foamToVTK), else the
    largest unstructured grid; its pieces are checked before they are read."""
    source = str(path)
    check_xml(path)
    try:
        text = read_bytes_capped(path, MAX_INDEX_BYTES, "multiblock index").decode("utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read the multiblock index ({exc})", source) from None
    files = re.findall(r'<DataSet\b[^>]*\bfile\s*=\s*["\']([^"\']*)["\']', text)
    for name in files:
        member = path.parent / name
        if not member.is_file():
            raise InputError(f"the block file {name!r} is missing", source)
        if member.suffix.lower() in (".vtu", ".vtp", ".vti", ".vtr", ".vts"):
            check_xml(member)
    from vtkmodules.vtkIOXML import vtkXMLMultiBlockDataReader

    output = _read(vtkXMLMultiBlockDataReader(), source, progress)
    found: list[tuple[int, str, Any]] = []
    _leaves(output, "", found)
    grids = [(n, name, b) for n, name, b in found if b.GetClassName() == "vtkUnstructuredGrid"]
    if not grids:
        if any(b.GetClassName() == "vtkPolyData" for _, _, b in found):
            raise InputError(NOT_A_FLOW, source)
        raise InputError("holds no unstructured volume mesh", source)
    named = [g for g in grids if g[1].split("/")[-1] in INTERNAL_NAMES]
    return (named or sorted(grids, key=lambda g: -g[0]))[0][2]


def _leaves(data: Any, prefix: str, out: list[tuple[int, str, Any]]) -> None:
    if data is None:
        return
    if data.IsA("vtkMultiBlockDataSet"):
        for i in range(data.GetNumberOfBlocks()):
            meta = data.GetMetaData(i) if data.HasMetaData(i) else None
            name = meta.Get(data.NAME()) if meta is not None and meta.Has(data.NAME()) else str(i)
            _leaves(data.GetBlock(i), f"{prefix}/{name}", out)
        return
    if data.IsA("vtkDataSet") and data.GetNumberOfCells():
        out.append((data.GetNumberOfCells(), prefix, data))


def _field_data(mesh: Any) -> tuple[float | None, float | None, float | None, str | None]:
    """TimeValue, density, viscosity and pressure_units from the mesh's field data."""
    out: dict[str, Any] = {}
    fields = mesh.GetFieldData()
    for i in range(fields.GetNumberOfArrays()):
        array = fields.GetAbstractArray(i)
        if array is None or not array.GetName():
            continue
        if array.IsA("vtkStringArray"):
            out[array.GetName()] = array.GetValue(0) if array.GetNumberOfValues() else None
        elif array.GetNumberOfTuples() >= 1 and array.GetNumberOfComponents() >= 1:
            out[array.GetName()] = float(array.GetTuple(0)[0])
    units = out.get("pressure_units")
    return (
        out.get("TimeValue"),
        out.get("density"),
        out.get("viscosity"),
        str(units) if units is not None else None,
    )


def quiet_vtk() -> None:
    """Keep VTK's own warnings and errors off stderr: our messages say what is wrong."""
    from vtkmodules.vtkCommonCore import vtkLogger, vtkObject

    vtkObject.GlobalWarningDisplayOff()  # our own message says what is wrong
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
