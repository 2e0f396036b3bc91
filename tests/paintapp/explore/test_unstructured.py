"""Unstructured flows: an OpenFOAM case and its foamToVTK output against OpenFOAM's own wall
force, a hand-written legacy VTK hydrostatic case, and files that lie."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("vtkmodules")

from common.errors import InputError
from paintapp.cli import main
from paintapp.explore.exploration import Exploration, ProbeSpec
from paintapp.explore.flow_files import FluidOverrides, load_flow
from paintapp.explore.force_trace import read_explore_forces_csv
from paintapp.explore.local_resample import ResampleSpec
from paintapp.explore.openfoam_case import CaseSelection
from paintapp.explore.unstructured import UnstructuredFlow

CASE = Path(__file__).parents[2] / "data" / "openfoam_cylinder"
VTU = CASE / "VTK" / "openfoam_cylinder_152" / "internal.vtu"
WATER = FluidOverrides(density_kg_m3=1.0)


def openfoam_force() -> np.ndarray:
    """OpenFOAM's total force on the cylinder (N, over the mesh's 0.01 m depth) at the last
    iteration of its forces function object."""
    last = (CASE / "postProcessing" / "forces" / "0" / "force.dat").read_text().splitlines()[-1]
    total = last.split("(")[1].split(")")[0]
    return np.array([float(v) for v in total.split()])


@pytest.mark.parametrize(
    "data",
    [
        CASE,
        CASE / "case.foam",
        VTU,
        CASE / "VTK" / "openfoam_cylinder_152.vtm",
        CASE / "VTK" / "openfoam_cylinder.vtm.series",
    ],
    ids=["case", "marker", "vtu", "vtm", "series"],
)
def test_a_probe_where_the_cylinder_is_feels_openfoams_own_force(data):
    """Measured (drag error, lift error / drag) at refine 1, 2, 4: case -1.9 %, -0.9 %,
    -0.4 %; foamToVTK's .vtu -1.9 %, -0.9 %, -0.5 %; lift within 0.2 % of the drag."""
    flow = load_flow([data], WATER)
    assert isinstance(flow, UnstructuredFlow) and flow.dim == 2
    assert flow.thickness_m == pytest.approx(0.01)
    assert flow.viscosity_pa_s == pytest.approx(1e-3)  # nu from the case, times rho
    reference = openfoam_force()
    errors = []
    for refine in (1.0, 2.0, 4.0):
        probe = Exploration(flow, ProbeSpec("circle", (0.1,)), resample=ResampleSpec(refine))
        assert probe.depth_m == pytest.approx(0.01)  # the mesh's thickness
        force, _ = probe.felt(probe.force_at(152.0, np.array([0.2, 0.2]), 0.0))
        drag = (force[0] - reference[0]) / reference[0]
        assert abs(drag) < 0.05
        assert abs(force[1] - reference[1]) < 0.05 * abs(reference[0])
        errors.append(abs(drag))
    assert errors[2] < errors[0]  # the gap shrinks as the resampling refines


def converted(tmp_path: Path, legacy: bool, cells_only: bool) -> Path:
    """foamToVTK's .vtu written again: as legacy .vtk, or with its point data dropped."""
    from vtkmodules.vtkIOLegacy import vtkUnstructuredGridWriter
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter

    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(VTU))
    reader.Update()
    mesh = reader.GetOutput()
    if cells_only:
        mesh.GetPointData().Initialize()
    out = tmp_path / ("cylinder.vtk" if legacy else "cylinder.vtu")
    writer = vtkUnstructuredGridWriter() if legacy else vtkXMLUnstructuredGridWriter()
    writer.SetFileName(str(out))
    writer.SetInputData(mesh)
    writer.Write()
    return out


@pytest.mark.parametrize("legacy", [True, False], ids=["legacy-vtk", "vtu"])
def test_cell_data_alone_and_legacy_files_give_openfoams_force(tmp_path, legacy):
    """Cell data alone (no point values) is interpolated between the cell centres and the walls
    (the finite-volume wall shear). Measured drag error at refine 1, 2, 4: -1.5 %, +0.1 %,
    +0.4 %; lift within 0.1 % of the drag."""
    data = converted(tmp_path, legacy, cells_only=True)
    flow = load_flow([data], FluidOverrides(1.0, 1e-3, None, "m2/s2"))
    assert isinstance(flow, UnstructuredFlow) and flow.on_cells and flow.samples is not None
    reference = openfoam_force()
    for refine in (1.0, 2.0, 4.0):
        probe = Exploration(flow, ProbeSpec("circle", (0.1,)), resample=ResampleSpec(refine))
        force, _ = probe.felt(probe.force_at(0.0, np.array([0.2, 0.2]), 0.0))
        assert force[0] == pytest.approx(reference[0], rel=0.05)
        assert abs(force[1] - reference[1]) < 0.05 * abs(reference[0])


def test_a_case_time_is_chosen_or_refused():
    flow = load_flow([CASE], WATER, CaseSelection(time_s=152.0))
    assert list(flow.times_s) == [152.0]
    with pytest.raises(InputError, match="no time 7 in the case") as err:
        load_flow([CASE], WATER, CaseSelection(time_s=7.0))
    assert err.value.key == "--time"
    with pytest.raises(InputError, match="density"):
        load_flow([CASE])


def test_a_probe_moving_away_gets_a_new_local_grid():
    flow = load_flow([CASE], WATER)
    probe = Exploration(flow, ProbeSpec("circle", (0.05,)))
    first = probe.field_at(np.array([0.6, 0.2]))
    assert probe.field_at(np.array([0.601, 0.2])) is first  # still inside its box
    moved = probe.field_at(np.array([1.0, 0.2]))
    assert moved is not first and probe.resampler.resamples == 2
    force, _ = probe.felt(probe.force_at(152.0, np.array([1.0, 0.2]), 0.0))
    assert np.all(np.isfinite(force))


def test_background_resampling_keeps_the_old_grid_until_the_new_one_is_ready():
    flow = load_flow([CASE], WATER)
    probe = Exploration(flow, ProbeSpec("circle", (0.05,)))
    first = probe.field_at(np.array([0.6, 0.2]))
    probe.use_background_resampling()
    try:
        assert probe.field_at(np.array([1.0, 0.2])) is first  # returned at once
        deadline = time.monotonic() + 30.0
        while probe.resampler.resamples < 2 and time.monotonic() < deadline:
            time.sleep(0.01)
        assert probe.field_at(np.array([1.0, 0.2])) is not first
    finally:
        probe.close()


def hydrostatic_legacy(path: Path, n: int = 12, side_m: float = 0.6) -> None:
    """Water at rest in a box of hexahedra, written by hand as a legacy unstructured .vtk:
    p = rho g (side - z), U = 0, no field data (density and viscosity come from the command)."""
    h = side_m / n
    idx = np.arange(n + 1)
    z, y, x = np.meshgrid(idx, idx, idx, indexing="ij")
    points = np.column_stack([x.ravel(), y.ravel(), z.ravel()]) * h

    def node(i, j, k):
        return (k * (n + 1) + j) * (n + 1) + i

    cells = []
    for k in range(n):
        for j in range(n):
            for i in range(n):
                cells.append([node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k),
                              node(i, j + 1, k), node(i, j, k + 1), node(i + 1, j, k + 1),
                              node(i + 1, j + 1, k + 1), node(i, j + 1, k + 1)])  # fmt: skip
    p = 1000.0 * 9.81 * (side_m - points[:, 2])
    lines = ["# vtk DataFile Version 3.0", "water at rest", "ASCII", "DATASET UNSTRUCTURED_GRID",
             f"POINTS {len(points)} double"]  # fmt: skip
    lines += [" ".join(f"{v:.9g}" for v in pt) for pt in points]
    lines.append(f"CELLS {len(cells)} {9 * len(cells)}")
    lines += ["8 " + " ".join(map(str, c)) for c in cells]
    lines.append(f"CELL_TYPES {len(cells)}")
    lines += ["12"] * len(cells)
    lines += [f"POINT_DATA {len(points)}", "SCALARS p double 1", "LOOKUP_TABLE default"]
    lines += [f"{v:.12g}" for v in p]
    lines += ["VECTORS U double"] + ["0 0 0"] * len(points)
    path.write_text("\n".join(lines) + "\n", encoding="ascii")


def test_a_sphere_in_water_at_rest_as_cell_data_feels_rho_g_v(tmp_path):
    """The same water with its pressure at the cells (interpolated between cell centres)."""
    from vtkmodules.vtkFiltersCore import vtkPointDataToCellData
    from vtkmodules.vtkIOLegacy import vtkUnstructuredGridReader, vtkUnstructuredGridWriter

    hydrostatic_legacy(tmp_path / "points.vtk")
    reader = vtkUnstructuredGridReader()
    reader.SetFileName(str(tmp_path / "points.vtk"))
    to_cells = vtkPointDataToCellData()  # exact for a linear field at a hexahedron's centre
    to_cells.SetInputConnection(reader.GetOutputPort())
    writer = vtkUnstructuredGridWriter()
    writer.SetFileName(str(tmp_path / "cells.vtk"))
    writer.SetInputConnection(to_cells.GetOutputPort())
    writer.Write()
    flow = load_flow([tmp_path / "cells.vtk"], FluidOverrides(1000.0, 1e-3))
    assert isinstance(flow, UnstructuredFlow) and flow.on_cells and flow.dim == 3
    probe = Exploration(flow, ProbeSpec("sphere", (0.2,)))
    force, _ = probe.felt(probe.force_at(0.0, np.array([0.3, 0.3, 0.3]), np.array([1.0, 0, 0, 0])))
    buoyancy = 1000.0 * 9.81 * 4.0 / 3.0 * np.pi * 0.1**3
    assert force[2] == pytest.approx(buoyancy, rel=0.02)


def flat_triangles(path: Path, on_cells: bool, n: int = 24, side_m: float = 1.0) -> None:
    """A flat 2D mesh of triangles in z = 0 holding p = 100 x Pa, u = 0, as .vtu."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import VTK_TRIANGLE, vtkCellArray, vtkUnstructuredGrid
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

    idx = np.arange(n + 1)
    y, x = np.meshgrid(idx, idx, indexing="ij")
    points = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)]) * (side_m / n)
    tris = []
    for j in range(n):
        for i in range(n):
            a, b = j * (n + 1) + i, j * (n + 1) + i + 1
            c, d = a + n + 1, b + n + 1
            tris += [[a, b, d], [a, d, c]]
    grid = vtkUnstructuredGrid()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(points, deep=True))
    grid.SetPoints(vtk_points)
    cells = vtkCellArray()
    offsets = np.arange(0, 3 * len(tris) + 1, 3, dtype=np.int64)
    cells.SetData(
        numpy_to_vtk(offsets, deep=True), numpy_to_vtk(np.ravel(tris).astype(np.int64), deep=True)
    )
    grid.SetCells(VTK_TRIANGLE, cells)
    at = points if not on_cells else points[np.array(tris)].mean(axis=1)
    target = grid.GetCellData() if on_cells else grid.GetPointData()
    for name, values in (("p", 100.0 * at[:, 0]), ("U", np.zeros((len(at), 3)))):
        array = numpy_to_vtk(np.ascontiguousarray(values), deep=True)
        array.SetName(name)
        target.AddArray(array)
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(grid)
    writer.Write()


@pytest.mark.parametrize("on_cells", [False, True], ids=["points", "cells"])
def test_a_flat_2d_mesh_of_triangles_gives_the_pressure_gradients_force(tmp_path, on_cells):
    flat_triangles(tmp_path / "flat.vtu", on_cells)
    flow = load_flow([tmp_path / "flat.vtu"], FluidOverrides(1.0, 1e-3))
    assert flow.dim == 2 and flow.thickness_m is None and flow.on_cells == on_cells
    probe = Exploration(flow, ProbeSpec("circle", (0.2,), depth_m=1.0))
    result = probe.force_at(0.0, np.array([0.5, 0.5]), 0.0)
    assert result.force[0] == pytest.approx(-100.0 * np.pi * 0.1**2, rel=0.01)
    assert abs(result.force[1]) < 0.01 * abs(result.force[0])


def test_a_sphere_in_water_at_rest_feels_rho_g_v_in_the_fluid_columns(tmp_path, capsys):
    data = tmp_path / "water.vtk"
    hydrostatic_legacy(data)
    path = tmp_path / "path.csv"
    path.write_text("t_s,x_m,y_m,z_m\n0,0.3,0.3,0.3\n0.3,0.3,0.3,0.3\n", encoding="utf-8")
    out = tmp_path / "forces.csv"
    args = ["explore", str(data), "--path", str(path), "--forces", str(out), "--probe",
            "sphere", "--size", "0.2", "--density", "1000", "--viscosity", "1e-3"]  # fmt: skip
    assert main(args) == 0
    assert "3D unstructured mesh, 1728 cells" in capsys.readouterr().out
    device, fluid = read_explore_forces_csv(out)
    buoyancy = 1000.0 * 9.81 * 4.0 / 3.0 * np.pi * 0.1**3  # 41.09 N
    assert fluid[:, 2] == pytest.approx(buoyancy, rel=0.02)
    assert np.abs(fluid[:, :2]).max() < 0.02 * buoyancy
    assert np.abs(device[:, 3]).max() < buoyancy  # the device's is scaled and clamped


def test_the_case_from_the_command_line_writes_the_fluid_force(tmp_path, capsys):
    path = tmp_path / "path.csv"
    path.write_text("t_s,x_m,y_m\n0,0.2,0.2\n0.2,0.2,0.2\n", encoding="utf-8")
    out, plot = tmp_path / "forces.csv", tmp_path / "forces.png"
    args = ["explore", str(CASE), "--time", "152", "--density", "1", "--probe", "circle",
            "--size", "0.1", "--path", str(path), "--forces", str(out), "--plot", str(plot)]  # fmt: skip
    assert main(args) == 0
    _, fluid = read_explore_forces_csv(out)
    assert fluid[-1, 0] == pytest.approx(openfoam_force()[0], rel=0.05)
    assert plot.stat().st_size > 1000


HOSTILE = {
    "points.vtk": ("# vtk DataFile Version 3.0\nx\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                   "POINTS 1000000000000 float\n0 0 0\n", "POINTS"),
    "small.vtk": ("# vtk DataFile Version 3.0\nx\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                  "POINTS 100000 float\n0 0 0\n", "only"),
    "cells.vtu": ('<VTKFile type="UnstructuredGrid"><UnstructuredGrid><Piece '
                  'NumberOfPoints="4" NumberOfCells="1000000000000"></Piece>'
                  "</UnstructuredGrid></VTKFile>", "NumberOfCells"),
    "components.vtu": ('<VTKFile type="UnstructuredGrid"><UnstructuredGrid><Piece '
                       'NumberOfPoints="4" NumberOfCells="1"><PointData><DataArray '
                       'NumberOfComponents="99999999"/></PointData></Piece>'
                       "</UnstructuredGrid></VTKFile>", "components"),
    "garbage.vtu": ("this is not XML at all", "not a readable unstructured grid"),
    "empty.vtu": ("", "empty"),
    "surface.vtp": ("<VTKFile/>", "a surface is not a flow"),
    "bad.series": ('{"files": 3}', "files"),
}  # fmt: skip


@pytest.mark.parametrize("name", sorted(HOSTILE))
def test_hostile_files_get_one_clear_line_and_exit_status_2(tmp_path, capsys, name):
    text, message = HOSTILE[name]
    data = tmp_path / name
    data.write_text(text, encoding="utf-8")
    path = tmp_path / "p.csv"
    path.write_text("t_s,x_m,y_m\n0,0,0\n1,0,0\n", encoding="utf-8")
    assert main(["explore", str(data), "--density", "1", "--path", str(path)]) == 2
    err = capsys.readouterr().err
    assert message in err and str(data) in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1


def test_an_openfoam_mesh_claiming_1e12_points_is_refused_before_reading(tmp_path):
    import shutil

    case = tmp_path / "case"
    shutil.copytree(CASE, case, ignore=shutil.ignore_patterns("VTK", "postProcessing"))
    (case / "constant" / "polyMesh" / "points.gz").unlink()
    (case / "constant" / "polyMesh" / "points").write_text(
        "FoamFile\n{\n    class vectorField;\n}\n\n1000000000000\n(\n(0 0 0)\n)\n"
    )
    with pytest.raises(InputError, match="claims") as err:
        load_flow([case], WATER)
    assert "points" in str(err.value)


def test_a_folder_that_is_not_a_case_is_a_clear_error(tmp_path):
    with pytest.raises(InputError, match="not an OpenFOAM case"):
        load_flow([tmp_path])


def test_all_times_and_a_pvd_series(tmp_path):
    flow = load_flow([CASE], WATER, CaseSelection(all_times=True))
    assert list(flow.times_s) == [152.0]  # time 0 (the initial field) is not a result
    index = tmp_path / "flow.pvd"
    index.write_text(
        '<VTKFile type="Collection"><Collection>'
        f'<DataSet timestep="1" file="{VTU}"/><DataSet timestep="2" file="{VTU}"/>'
        "</Collection></VTKFile>",
        encoding="utf-8",
    )
    series = load_flow([index], FluidOverrides(1.0, 1e-3, None, "m2/s2"))
    assert list(series.times_s) == [1.0, 2.0]
    one = load_flow([index], FluidOverrides(1.0, 1e-3, None, "m2/s2"), CaseSelection(time_s=2.0))
    assert list(one.times_s) == [2.0]
    probe = Exploration(series, ProbeSpec("circle", (0.1,)))
    between = probe.felt(probe.force_at(1.5, np.array([0.2, 0.2]), 0.0))[0]
    assert between[0] == pytest.approx(openfoam_force()[0], rel=0.05)


def test_the_python_api_reaches_the_same_names():
    import paintapp.explore as api

    assert api.load_flow is load_flow and api.CaseSelection is CaseSelection


def test_progress_shows_on_a_terminal_only():
    import io

    from paintapp.explore.load_progress import Progress

    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    shown, hidden = Terminal(), io.StringIO()
    for stream in (shown, hidden):
        progress = Progress("mesh.vtu", stream)
        progress.show("reading", 0.5)
        progress.done()
    assert "mesh.vtu: reading  50 %" in shown.getvalue() and hidden.getvalue() == ""
