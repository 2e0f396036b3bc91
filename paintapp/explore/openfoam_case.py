"""An OpenFOAM case as a flow: the case folder, or a ``.foam``/``.OpenFOAM`` marker file in it,
read with VTK's ``vtkOpenFOAMReader`` (its internal mesh; the boundary patches' values are what
it writes at the mesh's boundary points).

What the case states is taken from it: the kinematic viscosity ``nu`` from
``constant/transportProperties`` (or ``constant/physicalProperties``), and whether the pressure
is kinematic (``p`` with dimensions ``[0 2 -2 ...]``, m^2/s^2, as incompressible solvers such as
simpleFoam, pimpleFoam and icoFoam write it) or in Pa (``[1 -1 -2 ...]``). The density is not in
an incompressible case: it is given (``--density``); the dynamic viscosity is then ``rho nu``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from common.errors import InputError
from common.limits import read_bytes_capped
from paintapp.explore.claimed_sizes import check_openfoam_file
from paintapp.explore.load_progress import Progress
from paintapp.explore.unstructured import UnstructuredFrame

MARKER_SUFFIXES = (".foam", ".openfoam")
#: Largest dictionary file read for ``nu`` or a field's dimensions.
MAX_DICT_BYTES = 1024 * 1024
_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_NU = re.compile(rf"(?m)^\s*nu\s+(?:nu\s+)?(?:\[[^\]]*\]\s*)?({_NUMBER})\s*;")
_DIMENSIONS = re.compile(r"dimensions\s*\[([^\]]*)\]")


@dataclass(frozen=True)
class CaseSelection:
    """Which times to read: ``time_s`` (None: the latest), or ``all_times``."""

    time_s: float | None = None
    all_times: bool = False


def case_folder(path: Path) -> Path | None:
    """The case folder ``path`` names (the folder, or a marker file in it), or None."""
    if path.is_dir() and (path / "system" / "controlDict").is_file():
        return path
    if (
        path.suffix.lower() in MARKER_SUFFIXES
        and (path.parent / "system" / "controlDict").is_file()
    ):
        return path.parent
    return None


def read_case(
    case: Path, selection: CaseSelection, progress: Progress | None = None
) -> tuple[list[UnstructuredFrame], list[float]]:
    """The frames the selection names, and their times (s)."""
    source = str(case)
    reader = _reader(case)
    values = reader.GetTimeValues()
    available = [values.GetValue(i) for i in range(values.GetNumberOfTuples())] if values else []
    if not available:
        raise InputError("the case has no time folders", source)
    if selection.all_times:
        times = [t for t in available if t > 0] or available
    elif selection.time_s is None:
        times = [available[-1]]
    else:
        near = [t for t in available if abs(t - selection.time_s) <= 1e-9 * max(1.0, abs(t))]
        if not near:
            listed = ", ".join(f"{t:g}" for t in available[:20])
            raise InputError(
                f"no time {selection.time_s:g} in the case; it has {listed}", source, "--time"
            )
        times = near
    for t in times:
        _check_time_folder(case, t)
    frames = []
    nu = kinematic_viscosity(case)
    units = pressure_units(case, times[-1])
    if progress is not None:
        progress.watch(reader, "reading")
    for k, t in enumerate(times):
        if progress is not None:
            progress.show(f"reading time {t:g} ({k + 1} of {len(times)})")
        reader.UpdateTimeStep(t)
        reader.Update()
        mesh = _internal(reader.GetOutput(), source)
        copy = mesh.NewInstance()
        copy.DeepCopy(mesh)
        frames.append(UnstructuredFrame(f"{source} (time {t:g})", copy, t, None, None, units, nu))
    return frames, times


def _reader(case: Path) -> Any:
    from vtkmodules.vtkIOGeometry import vtkOpenFOAMReader

    from paintapp.explore.vtk_unstructured import quiet_vtk

    quiet_vtk()

    mesh = case / "constant" / "polyMesh"
    for name in ("points", "faces", "owner", "neighbour"):
        found = [mesh / (name + s) for s in ("", ".gz") if (mesh / (name + s)).is_file()]
        if not found:
            raise InputError(f"no mesh: constant/polyMesh/{name} is missing", str(case))
        check_openfoam_file(found[0])
    reader = vtkOpenFOAMReader()
    reader.SetFileName(str(case / "system" / "controlDict"))
    reader.UpdateInformation()
    for i in range(reader.GetNumberOfPatchArrays()):
        name = reader.GetPatchArrayName(i)
        reader.SetPatchArrayStatus(name, 1 if name == "internalMesh" else 0)
    return reader


def _time_folders(case: Path, t: float) -> list[Path]:
    """The case's folders whose names are the time ``t`` (``0.5`` and ``0.50`` both)."""
    found = []
    for folder in case.iterdir():
        try:
            if folder.is_dir() and abs(float(folder.name) - t) <= 1e-9 * max(1.0, abs(t)):
                found.append(folder)
        except ValueError:
            continue
    return found


def _check_time_folder(case: Path, t: float) -> None:
    for folder in _time_folders(case, t):
        for name in ("p", "U", "p.gz", "U.gz"):
            if (folder / name).is_file():
                check_openfoam_file(folder / name)


def _internal(output: Any, source: str) -> Any:
    block = output.GetBlock(0) if output is not None else None  # type: ignore[attr-defined]
    if (
        block is None
        or block.GetClassName() != "vtkUnstructuredGrid"
        or not block.GetNumberOfCells()
    ):
        raise InputError("the case's internal mesh could not be read", source)
    return block


def kinematic_viscosity(case: Path) -> float | None:
    """``nu`` (m^2/s) from ``constant/transportProperties`` or ``physicalProperties``."""
    for name in ("transportProperties", "physicalProperties"):
        path = case / "constant" / name
        if not path.is_file():
            continue
        text = read_bytes_capped(path, MAX_DICT_BYTES, name).decode("latin-1")
        found = _NU.search(_strip_comments(text))
        if found:
            return float(found.group(1))
    return None


def pressure_units(case: Path, t: float) -> str | None:
    """``"m2/s2"`` or ``"Pa"`` from the dimensions of ``p`` at time ``t``, or None."""
    import gzip

    for folder in _time_folders(case, t):
        for name in ("p", "p.gz"):
            path = folder / name
            if not path.is_file():
                continue
            try:
                with (gzip.open if name.endswith(".gz") else open)(path, "rb") as fh:
                    head = fh.read(4096).decode("latin-1")
            except (OSError, EOFError) as exc:
                raise InputError(f"cannot read the pressure field ({exc})", str(path)) from None
            found = _DIMENSIONS.search(head)
            if found:
                dims = found.group(1).split()[:3]
                if dims == ["0", "2", "-2"]:
                    return "m2/s2"
                if dims == ["1", "-1", "-2"]:
                    return "Pa"
    return None


def _strip_comments(text: str) -> str:
    return re.sub(r"//[^\n]*|/\*.*?\*/", "", text, flags=re.S)


def enclosing_case(path: Path) -> Path | None:
    """The OpenFOAM case a ``foamToVTK`` output lies in (``CASE/VTK/...``), or None."""
    for parent in list(path.resolve().parents)[:4]:
        if parent.name == "VTK" and case_folder(parent.parent) is not None:
            return parent.parent
    return None
