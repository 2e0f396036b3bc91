"""One frame of a VTK structured data set (``.vti``, ``.vtr``, legacy ``.vtk``) as arrays, read
with the ``vtk`` package (imported here only: it is large and only this reader needs it)."""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import numpy as np

from common.errors import InputError
from common.limits import check_elements
from paintapp.explore.flow_frame import Frame

PRESSURE_NAMES = ("p", "pressure", "P")
VELOCITY_NAMES = ("U", "u", "velocity", "Velocity")
#: Bytes a point may take while read: pressure, three velocity components and the fluid mask as
#: float64, once in VTK's arrays and once in ours.
BYTES_PER_POINT = 2 * 5 * 8
#: How much of a file's start is searched for its header.
HEADER_BYTES = 64 * 1024
_XML_ATTRIBUTE = r'\b{}\s*=\s*"([^"]*)"'


def read_vtk_frame(path: Path) -> Frame:
    """The :class:`~paintapp.explore.flow_frame.Frame` in ``path``."""
    source = str(path)
    data = _read(path)
    dims = np.array(data.GetDimensions(), dtype=int)
    origin, spacing = _geometry(data, source)
    arrays, on_cells = _arrays(data)
    if on_cells:  # cell data: the samples sit at the cell centres
        dims = np.maximum(dims - 1, 1)
        origin = origin + 0.5 * spacing
    dim = 2 if dims[2] == 1 else 3
    nodes = tuple(int(n) for n in dims[:dim])
    p = _field(arrays, PRESSURE_NAMES, 1, dims, source, "p")[..., 0]
    u = _field(arrays, VELOCITY_NAMES, 3, dims, source, "U")
    velocity = np.moveaxis(u[..., :dim], -1, 0)
    pressure = p.reshape(nodes) if dim == 2 else p
    fluid = None
    if "fluid" in arrays:
        fluid = _field(arrays, ("fluid",), 1, dims, source, "fluid")[..., 0] > 0.5
        fluid = fluid.reshape(nodes)
    fields = _field_data(data)
    return Frame(
        source,
        origin[:dim],
        spacing[:dim],
        pressure.reshape(1, *nodes),
        velocity.reshape(1, dim, *nodes),
        fluid,
        fields.get("TimeValue"),
        fields.get("density"),
        fields.get("viscosity"),
        fields.get("pressure_units"),
    )


def _read(path: Path) -> Any:
    try:
        from vtkmodules.vtkCommonCore import vtkLogger, vtkObject
        from vtkmodules.vtkIOLegacy import vtkDataSetReader
        from vtkmodules.vtkIOXML import vtkXMLImageDataReader, vtkXMLRectilinearGridReader
    except ImportError:
        raise InputError(
            "reading VTK files needs the vtk package: pip install 'haptic-fluid-paint[cfd]' "
            "(or convert the data to .npz)",
            source=str(path),
        ) from None
    vtkObject.GlobalWarningDisplayOff()  # our own message says what is wrong
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
    check_header(path)
    suffix = path.suffix.lower()
    readers: dict[str, Any] = {".vti": vtkXMLImageDataReader, ".vtr": vtkXMLRectilinearGridReader}
    reader: Any = readers.get(suffix, vtkDataSetReader)()
    reader.SetFileName(str(path))
    reader.Update()
    data = reader.GetOutput()
    if data is None or data.GetNumberOfPoints() == 0:
        raise InputError(
            "not a readable VTK structured data set (image data or rectilinear grid)", str(path)
        )
    kind = data.GetClassName()
    if kind not in ("vtkImageData", "vtkStructuredPoints", "vtkRectilinearGrid"):
        raise InputError(
            f"holds a {kind}; expected image data or a rectilinear grid (resample first)", str(path)
        )
    return data


def check_header(path: Path) -> None:
    """Refuse a file whose header claims more points than the memory budget allows, or a grid
    origin or spacing that is not finite, before VTK reads (and allocates) anything."""
    source = str(path)
    try:
        with open(path, "rb") as fh:
            head = fh.read(HEADER_BYTES).decode("latin-1")
    except OSError as exc:
        raise InputError(f"cannot read the VTK file: {exc.strerror}", source) from None
    if path.suffix.lower() in (".vti", ".vtr"):
        extent = _numbers(head, _XML_ATTRIBUTE.format("WholeExtent"), source, "WholeExtent", 6)
        if extent is not None:
            counts = [int(extent[2 * a + 1] - extent[2 * a] + 1) for a in range(3)]
            check_elements(
                math.prod(max(c, 0) for c in counts), BYTES_PER_POINT, source, "WholeExtent"
            )
        for key in ("Origin", "Spacing"):
            _numbers(head, _XML_ATTRIBUTE.format(key), source, key, 3)
        return
    dims = _numbers(head, r"(?im)^\s*DIMENSIONS\s+(\S+\s+\S+\s+\S+)", source, "DIMENSIONS", 3)
    if dims is not None:
        check_elements(
            math.prod(max(int(d), 0) for d in dims), BYTES_PER_POINT, source, "DIMENSIONS"
        )
    for key in ("POINT_DATA", "CELL_DATA"):
        count = _numbers(head, rf"(?im)^\s*{key}\s+(\S+)", source, key, 1)
        if count is not None:
            check_elements(int(count[0]), BYTES_PER_POINT, source, key)
    for key in ("ORIGIN", "SPACING", "ASPECT_RATIO"):
        _numbers(head, rf"(?im)^\s*{key}\s+(\S+\s+\S+\s+\S+)", source, key, 3)


def _numbers(head: str, pattern: str, source: str, key: str, count: int) -> list[float] | None:
    """The ``count`` finite numbers of the header field ``key`` (None where it is absent)."""
    found = re.search(pattern, head)
    if found is None:
        return None
    given = found.group(1)[:80]
    try:
        values = [float(v) for v in found.group(1).split()]
    except ValueError:
        values = []
    if len(values) != count or not all(math.isfinite(v) for v in values):
        raise InputError(f"expected {count} finite numbers, got {given!r}", source, key)
    if key in ("WholeExtent", "DIMENSIONS", "POINT_DATA", "CELL_DATA") and not all(
        v.is_integer() and abs(v) < 2**62 for v in values
    ):
        raise InputError(f"expected {count} whole numbers, got {given!r}", source, key)
    return values


def _geometry(data: Any, source: str) -> tuple[np.ndarray, np.ndarray]:
    if data.GetClassName() != "vtkRectilinearGrid":
        return np.array(data.GetOrigin(), dtype=float), np.array(data.GetSpacing(), dtype=float)
    from vtkmodules.util.numpy_support import vtk_to_numpy

    origin, spacing = np.zeros(3), np.ones(3)
    for axis, coords in enumerate(
        (data.GetXCoordinates(), data.GetYCoordinates(), data.GetZCoordinates())
    ):
        c = vtk_to_numpy(coords).astype(float)
        origin[axis] = c[0]
        if len(c) > 1:
            steps = np.diff(c)
            if not np.allclose(steps, steps[0], rtol=1e-6, atol=0.0):
                raise InputError(
                    f"axis {'xyz'[axis]} is not uniformly spaced; resample onto a regular grid",
                    source,
                    "coordinates",
                )
            spacing[axis] = steps[0]
    return origin, spacing


def _arrays(data: Any) -> tuple[dict[str, Any], bool]:
    from vtkmodules.util.numpy_support import vtk_to_numpy

    for on_cells, attrs in ((False, data.GetPointData()), (True, data.GetCellData())):
        arrays = {}
        for i in range(attrs.GetNumberOfArrays()):
            array = attrs.GetArray(i)
            if array is not None and array.GetName():
                arrays[array.GetName()] = vtk_to_numpy(array)
        if any(n in arrays for n in PRESSURE_NAMES):
            return arrays, on_cells
    return {}, False


def _field(
    arrays: dict[str, Any],
    names: tuple[str, ...],
    components: int,
    dims: np.ndarray,
    source: str,
    key: str,
) -> np.ndarray:
    name = next((n for n in names if n in arrays), None)
    if name is None:
        raise InputError(
            f"missing field; expected a point array named one of {', '.join(names)}", source, key
        )
    values = np.asarray(arrays[name], dtype=np.float64).reshape(int(np.prod(dims)), -1)
    if values.shape[1] != components:
        raise InputError(f"expected {components} component(s), got {values.shape[1]}", source, name)
    # VTK orders points x fastest: reshape to (z, y, x, c), then to (x, y, z, c)
    return values.reshape(dims[2], dims[1], dims[0], components).transpose(2, 1, 0, 3)


def _field_data(data: Any) -> dict[str, Any]:
    out: dict[str, Any] = {}
    fields = data.GetFieldData()
    for i in range(fields.GetNumberOfArrays()):
        array = fields.GetAbstractArray(i)
        if array is None or not array.GetName():
            continue
        name = array.GetName()
        if array.IsA("vtkStringArray"):
            out[name] = array.GetValue(0) if array.GetNumberOfValues() else None
        elif array.GetNumberOfTuples() >= 1:
            value = float(array.GetTuple(0)[0])
            out[name] = value
    return out
