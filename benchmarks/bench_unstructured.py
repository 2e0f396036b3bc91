"""Unstructured flows in ``paintapp explore``: load, local resample and per-tick force cost.

    python benchmarks/bench_unstructured.py [--cells 1000000] [--ticks 2000] [--moves 9]
                                            [--keep DIR]

Writes a synthetic hexahedral box of about ``--cells`` cells as a binary ``.vtu`` in a temporary
folder (a 3D flow: p = 1000 x Pa, u = (y, -x, 0) m/s), then reports:

- load: ``load_flow`` on it (reading, the velocity gradient on the mesh, the cells' boxes);
- resample: the median time to resample the local grid around a sphere (4 median cells across)
  each time it moves out of its box (``--moves`` positions), what the worker thread does off the
  servo path;
- tick: the median cost of one force evaluation on the resampled grid (``--ticks`` evaluations
  at small moves inside the box), what the servo path pays.

and checks them against the targets: a tick <= 1 ms, a resample <= 50 ms on 1M cells. The
default run takes well under two minutes.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

TICK_TARGET_S = 1e-3
RESAMPLE_TARGET_S = 50e-3


def write_box(path: Path, cells: int) -> float:
    """A box of about ``cells`` hexahedra, 1 m a side, as .vtu; returns its cell size (m)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import VTK_HEXAHEDRON, vtkCellArray, vtkUnstructuredGrid
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

    n = max(round(cells ** (1.0 / 3.0)), 2)
    h = 1.0 / n
    idx = np.arange(n + 1)
    z, y, x = np.meshgrid(idx, idx, idx, indexing="ij")
    points = np.column_stack([x.ravel(), y.ravel(), z.ravel()]).astype(np.float64) * h
    i, j, k = (
        a.ravel() for a in np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij")
    )

    def node(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
        return (c * (n + 1) + b) * (n + 1) + a

    hexes = np.column_stack([node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k),
                             node(i, j + 1, k), node(i, j, k + 1), node(i + 1, j, k + 1),
                             node(i + 1, j + 1, k + 1), node(i, j + 1, k + 1)])  # fmt: skip
    grid = vtkUnstructuredGrid()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(points, deep=True))
    grid.SetPoints(vtk_points)
    cell_array = vtkCellArray()
    offsets = np.arange(0, 8 * len(hexes) + 1, 8, dtype=np.int64)
    cell_array.SetData(
        numpy_to_vtk(offsets, deep=True), numpy_to_vtk(hexes.ravel().astype(np.int64), deep=True)
    )
    grid.SetCells(VTK_HEXAHEDRON, cell_array)
    for name, values in (
        ("p", 1000.0 * points[:, 0]),
        ("U", np.column_stack([points[:, 1], -points[:, 0], np.zeros(len(points))])),
    ):
        array = numpy_to_vtk(np.ascontiguousarray(values), deep=True)
        array.SetName(name)
        grid.GetPointData().AddArray(array)
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(grid)
    writer.SetDataModeToAppended()
    writer.EncodeAppendedDataOff()
    writer.Write()
    return h


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cells", type=int, default=1_000_000)
    parser.add_argument("--ticks", type=int, default=2000)
    parser.add_argument("--moves", type=int, default=9)
    parser.add_argument("--keep", type=Path, help="write the mesh here instead of a temp folder")
    args = parser.parse_args(argv)
    from paintapp.explore.exploration import Exploration, ProbeSpec
    from paintapp.explore.flow_files import FluidOverrides, load_flow
    from paintapp.explore.local_resample import resample_box

    with tempfile.TemporaryDirectory() as tmp:
        folder = args.keep or Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / "box.vtu"
        start = time.perf_counter()
        h = write_box(path, args.cells)
        print(
            f"wrote {path} ({path.stat().st_size / 1e6:.0f} MB) in {time.perf_counter() - start:.1f} s"
        )
        start = time.perf_counter()
        flow = load_flow([path], FluidOverrides(1000.0, 1e-3))
        load_s = time.perf_counter() - start
        print(f"load: {flow.describe()} in {load_s:.2f} s")
        probe = Exploration(flow, ProbeSpec("sphere", (4 * h,)))
        assert probe.resampler is not None
        radius, spec = probe.resampler.radius_m, probe.resampler.spec
        rng = np.random.default_rng(1)
        resample = []
        for _ in range(args.moves):
            centre = rng.uniform(0.2, 0.8, 3)
            start = time.perf_counter()
            box = resample_box(flow, centre, radius, spec)
            resample.append(time.perf_counter() - start)
        print(f"resample: local grid {'x'.join(map(str, box.flow.nodes))} nodes, median "
              f"{1e3 * statistics.median(resample):.1f} ms over {args.moves} moves "
              f"(target <= {1e3 * RESAMPLE_TARGET_S:.0f} ms, off the servo path)")  # fmt: skip
        centre = np.full(3, 0.5)
        probe.force_at(0.0, centre, np.array([1.0, 0, 0, 0]))  # the first box
        ticks = []
        for k in range(args.ticks):
            at = centre + 0.05 * h * np.sin(np.array([k, 1.3 * k, 1.7 * k]) * 0.01)
            start = time.perf_counter()
            probe.force_at(0.0, at, np.array([1.0, 0, 0, 0]))
            ticks.append(time.perf_counter() - start)
        result = probe.force_at(0.0, centre, np.array([1.0, 0, 0, 0]))
        volume = np.pi / 6.0 * (4 * h) ** 3
        print(f"tick: median {1e6 * statistics.median(ticks):.0f} us, p99 "
              f"{1e6 * float(np.percentile(ticks, 99)):.0f} us over {args.ticks} evaluations "
              f"(target <= {1e6 * TICK_TARGET_S:.0f} us); {len(probe.rule.weights)} surface "
              f"points; F_x {result.force[0]:.4g} N (exact -1000 V = {-1000 * volume:.4g} N)")  # fmt: skip
        ok = statistics.median(ticks) <= TICK_TARGET_S and statistics.median(resample) <= (
            RESAMPLE_TARGET_S * max(flow.cells / 1e6, 1.0)
        )
        print("targets met" if ok else "targets NOT met")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
