"""Reading flows that a CFD tool (or our solver) wrote: NumPy ``.npz`` and VTK structured data
here; OpenFOAM cases and unstructured VTK (``.vtu``, ``.vtm``, legacy unstructured ``.vtk``,
``.pvd`` and ``.series`` time series) through :mod:`.load_unstructured`.

Units are SI throughout: metres, seconds, kg/m^3, Pa s, and pressure in Pa (``pressure_units =
"Pa"``) or, as incompressible solvers such as OpenFOAM write it, kinematic pressure p/rho in
m^2/s^2 (``pressure_units = "m2/s2"``), converted here with the density.

``.npz`` keys (plain arrays; pickled objects are refused):

========================  =============================================================
``p``                     pressure, shape ``(*nodes)`` or ``(T, *nodes)``
``u``                     velocity (m/s), shape ``(dim, *nodes)`` or ``(T, dim, *nodes)``
``origin``, ``spacing``   position of node 0 and the node spacing, ``(dim,)`` metres
``density``               kg/m^3 (required: without it a pressure is not a force)
``viscosity``             dynamic viscosity, Pa s (required)
``times``                 frame times, s, ``(T,)`` increasing (required for T > 1)
``fluid``                 optional bool ``(*nodes)``: False inside the data set's own bodies
``pressure_units``        optional: ``"Pa"`` (default) or ``"m2/s2"``
``period``                optional, s: the frames cover one period of a periodic flow
========================  =============================================================

VTK files (``.vti`` image data, ``.vtr`` rectilinear grids with uniform spacing, legacy ``.vtk``
structured points or rectilinear grids) are read with the ``vtk`` package: point (or, failing
that, cell) arrays named ``p``/``pressure`` and ``U``/``u``/``velocity`` (3 components; a grid one
node deep is 2D), an optional ``fluid`` array, and field data ``density``, ``viscosity``,
``pressure_units`` and ``TimeValue`` (as ParaView writes it) -- or the command's ``--density``,
``--viscosity`` and ``--frame-dt``. Several VTK files make a time series.

Every problem is an :class:`~common.errors.InputError` naming the file and the field: a missing
field, a wrong shape, non-finite values in the fluid, units that are not stated.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from common.errors import InputError
from common.limits import ARCHIVE_ERRORS, brief, npz_headers
from paintapp.explore.flow_frame import Frame, series_times
from paintapp.explore.fluid_properties import PRESSURE_UNITS, FluidOverrides
from paintapp.explore.fluid_properties import given as _given
from solver import SampledFlow

if TYPE_CHECKING:
    from paintapp.explore.load_progress import Progress
    from paintapp.explore.openfoam_case import CaseSelection
    from paintapp.explore.unstructured import UnstructuredFlow

#: Most nodes a data set may have (a 512^3 grid); more would not fit a haptic session's memory.
MAX_NODES = 512**3
#: Most frames in a time series.
MAX_FRAMES = 10_000
#: Most values of the small ``.npz`` members, checked on their headers before anything is inflated.
_MOST_VALUES = {
    "origin": 3,
    "spacing": 3,
    "density": 1,
    "viscosity": 1,
    "period": 1,
    "pressure_units": 1,
    "times": MAX_FRAMES,
}
VTK_SUFFIXES = (".vti", ".vtr", ".vtk")


KNOWN = ".npz, .vti, .vtr, .vtk, .vtu, .vtm, .pvd, .series or an OpenFOAM case"


def load_flow(
    paths: Sequence[str | Path],
    overrides: FluidOverrides | None = None,
    selection: CaseSelection | None = None,
    progress: Progress | None = None,
) -> SampledFlow | UnstructuredFlow:
    """The flow in ``paths``: one ``.npz`` (one frame or a series), one or more VTK files, an
    OpenFOAM case (its folder or ``.foam`` marker; ``selection`` picks its times, or a series'
    frame), or unstructured VTK. A grid gives a :class:`~solver.SampledFlow`, a mesh an
    :class:`~paintapp.explore.unstructured.UnstructuredFlow`; ``progress`` reports long loads."""
    overrides = overrides or FluidOverrides()
    files = [Path(p) for p in paths]
    if not files:
        raise InputError(f"no data file given; expected {KNOWN}")
    from paintapp.explore.load_unstructured import is_unstructured, load_unstructured

    if len(files) == 1 and files[0].is_dir() and not is_unstructured(files):
        raise InputError(
            "is a folder but not an OpenFOAM case (no system/controlDict); expected a data file "
            "(.npz, .vti, .vtr, .vtk, .vtu, .vtm, .pvd, .series) or a case",
            str(files[0]),
        )
    for f in files:
        if not (f.is_file() or (len(files) == 1 and f.is_dir())):
            raise InputError("no such file", source=str(f))
    if is_unstructured(files):
        _check_vtk_package(str(files[0]))
        return load_unstructured(files, overrides, selection, progress)
    if selection is not None and (selection.time_s is not None or selection.all_times):
        raise InputError(
            "--time and --all-times apply to an OpenFOAM case or a .pvd/.series time series",
            str(files[0]),
        )
    suffixes = {f.suffix.lower() for f in files}
    if suffixes == {".npz"}:
        if len(files) > 1:
            raise InputError("give one .npz file (it holds every frame)", source=str(files[1]))
        return _from_npz(files[0], overrides)
    if suffixes <= set(VTK_SUFFIXES):
        from paintapp.explore.vtk_files import read_vtk_frame

        frames = [read_vtk_frame(f) for f in files]
        return _from_frames(frames, overrides, str(files[0]))
    raise InputError(f"unknown data file type {sorted(suffixes)}; expected {KNOWN}", str(files[0]))


def _check_vtk_package(source: str) -> None:
    try:
        import vtkmodules  # noqa: F401
    except ImportError:
        raise InputError(
            "reading meshes and OpenFOAM cases needs the vtk package: pip install "
            "'haptic-fluid-paint[cfd]'",
            source=source,
        ) from None


def _from_npz(path: Path, overrides: FluidOverrides) -> SampledFlow:
    source = str(path)
    try:
        for key, (shape, _) in npz_headers(path).items():
            most = _MOST_VALUES.get(key)
            if most is not None and math.prod(shape) > most:
                raise InputError(
                    f"holds {math.prod(shape)} values of shape {shape}; expected at most {most}",
                    source,
                    key,
                )
        with np.load(path, allow_pickle=False) as data:
            arrays = {k: data[k] for k in data.files}
    except ARCHIVE_ERRORS as exc:
        if isinstance(exc, InputError):
            raise
        raise InputError(f"not a readable .npz file ({brief(exc)})", source=source) from None
    known = {
        "p",
        "u",
        "origin",
        "spacing",
        "density",
        "viscosity",
        "times",
        "fluid",
        "pressure_units",
        "period",
    }
    unknown = sorted(set(arrays) - known)
    if unknown:
        raise InputError(
            f"unknown key; expected some of {', '.join(sorted(known))}", source, unknown[0]
        )
    for key in ("p", "u", "origin", "spacing"):
        if key not in arrays:
            raise InputError("missing field", source, key)
    origin = _vector(arrays["origin"], source, "origin")
    spacing = _vector(arrays["spacing"], source, "spacing")
    dim = len(origin)
    p = _numeric(arrays["p"], source, "p")
    u = _numeric(arrays["u"], source, "u")
    if p.ndim == dim:
        p, u = p[None], u[None]
    if p.ndim != dim + 1 or u.shape != (p.shape[0], dim, *p.shape[1:]):
        raise InputError(
            f"expected p of shape (T, *nodes) or (*nodes) with {dim} node axes and u of shape "
            f"(T, {dim}, *nodes); got p {arrays['p'].shape}, u {arrays['u'].shape}",
            source,
            "u",
        )
    times = _numeric(arrays["times"], source, "times").reshape(-1) if "times" in arrays else None
    fluid = _fluid(arrays.get("fluid"), p.shape[1:], source)
    period = _scalar(arrays, "period", source)
    frame = Frame(
        source,
        origin,
        spacing,
        p,
        u,
        fluid,
        None,
        _scalar(arrays, "density", source),
        _scalar(arrays, "viscosity", source),
        str(arrays["pressure_units"]) if "pressure_units" in arrays else None,
    )
    return _build(frame, times, overrides, period)


def _from_frames(frames: list[Frame], overrides: FluidOverrides, source: str) -> SampledFlow:
    first = frames[0]
    for f in frames[1:]:
        if f.pressure.shape != first.pressure.shape or not (
            np.allclose(f.origin, first.origin) and np.allclose(f.spacing, first.spacing)
        ):
            raise InputError("every frame of a series needs the same grid", source=f.source)
    times: np.ndarray | None = None
    if len(frames) > 1:
        times = series_times([f.time_s for f in frames], overrides.frame_dt_s, source)
    pressure = np.concatenate([f.pressure for f in frames])
    velocity = np.concatenate([f.velocity for f in frames])
    merged = replace(first, source=source, pressure=pressure, velocity=velocity, time_s=None)
    return _build(merged, times, overrides)


def _build(
    frame: Frame, times: np.ndarray | None, overrides: FluidOverrides, period: float | None = None
) -> SampledFlow:
    source = frame.source
    count = frame.pressure.shape[0]
    nodes = frame.pressure.shape[1:]
    if int(np.prod(nodes)) > MAX_NODES or count > MAX_FRAMES:
        raise InputError(
            f"the data set has {count} frames of {'x'.join(map(str, nodes))} nodes; at most "
            f"{MAX_FRAMES} frames of {MAX_NODES} nodes are read",
            source,
            "p",
        )
    if min(nodes) < 2:
        raise InputError("expected at least 2 nodes along every axis", source, "p")
    if times is None:
        times = np.zeros(1) if count == 1 else None
    if times is None or len(times) != count:
        raise InputError(f"expected {count} frame times", source, "times")
    if not (np.all(np.isfinite(times)) and (count == 1 or np.all(np.diff(times) > 0))):
        raise InputError("expected finite, strictly increasing frame times", source, "times")
    if not (np.all(np.isfinite(frame.spacing)) and np.all(frame.spacing > 0)):
        raise InputError("expected finite node spacings > 0 (metres)", source, "spacing")
    if not np.all(np.isfinite(frame.origin)):
        raise InputError("expected a finite origin (metres)", source, "origin")
    density = _given(overrides.density_kg_m3, frame.density, source, "density", "kg/m^3")
    viscosity = _given(overrides.viscosity_pa_s, frame.viscosity, source, "viscosity", "Pa s")
    units = overrides.pressure_units or frame.pressure_units or "Pa"
    if units not in PRESSURE_UNITS:
        raise InputError(
            f"expected one of {', '.join(PRESSURE_UNITS)}, got {units!r}", source, "pressure_units"
        )
    mask = np.ones(nodes, dtype=bool) if frame.fluid is None else frame.fluid
    for key, values in (("p", frame.pressure), ("u", frame.velocity)):
        inside = values[..., mask] if key == "p" else values[:, :, mask]
        if not np.all(np.isfinite(inside)):
            raise InputError(
                "non-finite values in the fluid (mark bodies with a 'fluid' mask instead)",
                source,
                key,
            )
    if period is not None and not (
        count > 1 and np.isfinite(period) and period > times[-1] - times[0]
    ):
        raise InputError(
            "expected a period longer than the frames' span (a series of 2 or more frames)",
            source,
            "period",
        )
    pressure = frame.pressure * (density if units == "m2/s2" else 1.0)
    return SampledFlow(
        frame.origin,
        frame.spacing,
        times,
        pressure,
        frame.velocity,
        density,
        viscosity,
        frame.fluid,
        period,
    )


def _numeric(value: Any, source: str, key: str) -> np.ndarray:
    array = np.asarray(value)
    if array.dtype.kind not in "fiu":
        raise InputError(f"expected numbers, got {array.dtype}", source, key)
    return array.astype(np.float64)


def _vector(value: Any, source: str, key: str) -> np.ndarray:
    array = _numeric(value, source, key).reshape(-1)
    if len(array) not in (2, 3):
        raise InputError(f"expected 2 or 3 numbers (metres), got {len(array)}", source, key)
    return array


def _scalar(arrays: dict[str, np.ndarray], key: str, source: str) -> float | None:
    if key not in arrays:
        return None
    array = _numeric(arrays[key], source, key)
    if array.size != 1:
        raise InputError("expected one number", source, key)
    return float(array.reshape(-1)[0])


def _fluid(value: Any, nodes: tuple[int, ...], source: str) -> np.ndarray | None:
    if value is None:
        return None
    mask = np.asarray(value)
    if mask.shape != nodes or mask.dtype.kind not in "bui":
        raise InputError(f"expected a boolean mask of shape {nodes}", source, "fluid")
    mask = mask.astype(bool)
    if not mask.any():
        raise InputError("no node is fluid", source, "fluid")
    return mask
