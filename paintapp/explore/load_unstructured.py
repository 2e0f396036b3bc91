"""Loading an unstructured flow: an OpenFOAM case (:mod:`.openfoam_case`), unstructured VTK
files (:mod:`.vtk_unstructured`) or a ``.pvd``/``.series`` of them, settled into an
:class:`~paintapp.explore.unstructured.UnstructuredFlow` with the fluid's properties in SI.

What a file does not state comes from the command line (``--density``, ``--viscosity``,
``--pressure-units``, ``--frame-dt``); the output of ``foamToVTK`` inside a case (``CASE/VTK/``)
takes ``nu`` and the pressure's units from that case, as the case itself would.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from common.errors import InputError
from paintapp.explore.flow_frame import series_times
from paintapp.explore.fluid_properties import PRESSURE_UNITS, FluidOverrides
from paintapp.explore.fluid_properties import given as _given
from paintapp.explore.load_progress import Progress
from paintapp.explore.openfoam_case import (
    CaseSelection,
    case_folder,
    enclosing_case,
    kinematic_viscosity,
    pressure_units,
    read_case,
)
from paintapp.explore.unstructured import UnstructuredFlow, UnstructuredFrame, build_unstructured
from paintapp.explore.vtk_unstructured import SERIES_SUFFIXES, read_unstructured, series_members


def is_unstructured(files: list[Path]) -> bool:
    """True where ``files`` name an OpenFOAM case or unstructured VTK data."""
    from paintapp.explore.vtk_unstructured import UNSTRUCTURED_SUFFIXES, is_legacy_unstructured

    if len(files) == 1 and case_folder(files[0]) is not None:
        return True
    suffixes = {f.suffix.lower() for f in files}
    if suffixes <= {".vtk"}:
        return all(is_legacy_unstructured(f) for f in files)
    return bool(suffixes & set(UNSTRUCTURED_SUFFIXES))


def load_unstructured(
    files: list[Path],
    overrides: FluidOverrides,
    selection: CaseSelection | None = None,
    progress: Progress | None = None,
) -> UnstructuredFlow:
    """The flow in ``files`` (one case, one series index, or one or more mesh files)."""
    selection = selection or CaseSelection()
    source = str(files[0])
    progress = progress or Progress(source)
    try:
        case = case_folder(files[0]) if len(files) == 1 else None
        stated: list[float | None]
        if case is not None:
            frames, times = read_case(case, selection, progress)
            stated = list(times)
        else:
            if len(files) == 1 and files[0].suffix.lower() in SERIES_SUFFIXES:
                members = series_members(files[0])
            else:
                members = [(f, None) for f in files]
            members = _select(members, selection, source)
            frames = []
            for k, (member, _) in enumerate(members):
                if not member.is_file():
                    raise InputError("no such file (listed in the series)", str(member))
                progress.show(f"reading {k + 1} of {len(members)}")
                frames.append(read_unstructured(member, progress))
            stated = [
                t if t is not None else f.time_s for (_, t), f in zip(members, frames, strict=True)
            ]
            _from_case_around(files[0], frames)
        times_array = _times(stated, overrides, source)
        first = frames[0]
        density = _given(overrides.density_kg_m3, first.density, source, "density", "kg/m^3")
        viscosity = _viscosity(overrides, first, density, source)
        units = overrides.pressure_units or first.pressure_units or "Pa"
        if units not in PRESSURE_UNITS:
            raise InputError(
                f"expected one of {', '.join(PRESSURE_UNITS)}, got {units!r}",
                source,
                "pressure_units",
            )
        return build_unstructured(
            frames, times_array, density, viscosity, units == "m2/s2", progress
        )
    finally:
        progress.done()


def _select(
    members: list[tuple[Path, float | None]], selection: CaseSelection, source: str
) -> list[tuple[Path, float | None]]:
    """A series is read whole (a case's default is its latest time); ``--time`` picks a frame."""
    wanted = selection.time_s
    if selection.all_times or wanted is None:
        return members
    near = [
        m for m in members if m[1] is not None and abs(m[1] - wanted) <= 1e-9 * max(1.0, abs(m[1]))
    ]
    if not near:
        raise InputError(f"no frame at time {wanted:g} in the series", source, "--time")
    return near


def _from_case_around(path: Path, frames: list[UnstructuredFrame]) -> None:
    """``foamToVTK`` output inside a case: ``nu`` and the pressure's units from the case."""
    case = enclosing_case(path)
    if case is None:
        return
    nu = kinematic_viscosity(case)
    for frame in frames:
        frame.kinematic_viscosity = frame.kinematic_viscosity or nu
        if frame.pressure_units is None and frame.time_s is not None:
            frame.pressure_units = pressure_units(case, frame.time_s)


def _viscosity(
    overrides: FluidOverrides, frame: UnstructuredFrame, density: float, source: str
) -> float:
    if overrides.viscosity_pa_s is None and frame.viscosity is None and frame.kinematic_viscosity:
        nu = frame.kinematic_viscosity
        if not (np.isfinite(nu) and nu > 0):
            raise InputError(f"expected a finite nu > 0 (m^2/s), got {nu!r}", source, "nu")
        return density * nu
    return _given(overrides.viscosity_pa_s, frame.viscosity, source, "viscosity", "Pa s")


def _times(stated: list[float | None], overrides: FluidOverrides, source: str) -> np.ndarray:
    if len(stated) == 1:
        return np.array([stated[0] or 0.0])
    return series_times(stated, overrides.frame_dt_s, source)
