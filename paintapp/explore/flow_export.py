"""Writing flows for exploration: our solver's state as node-centred arrays, to ``.npz`` (the
format :mod:`paintapp.explore.flow_files` reads) or VTK image data (``.vti``, for ParaView and
other CFD tools).

The MAC grid's face velocities are averaged to the cell centres, which become the data set's
nodes; cells inside a probe or a static solid are marked ``fluid = False`` and hold the solid's
velocity as the solver set it. Pressure is in Pa.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from paintapp.atomic import atomic_path
from solver import FLUID, Simulation


@dataclass
class FlowFrames:
    """Frames of one grid: times (T,), pressure (T, *nodes), velocity (T, dim, *nodes)."""

    origin_m: np.ndarray
    spacing_m: np.ndarray
    times_s: list[float]
    pressure_pa: list[np.ndarray]
    velocity_m_s: list[np.ndarray]
    fluid: np.ndarray
    density_kg_m3: float
    viscosity_pa_s: float
    period_s: float | None = None

    @classmethod
    def start(cls, sim: Simulation) -> FlowFrames:
        """An empty series on ``sim``'s grid and fluid."""
        g = sim.grid
        dim = g.dim
        h = g.cell_size_m
        origin = np.array(g.origin_m[:dim], dtype=float) + 0.5 * h
        return cls(
            origin,
            np.full(dim, h),
            [],
            [],
            [],
            np.ones(g.cells[:dim], dtype=bool),
            sim.fluid.density_kg_m3,
            sim.fluid.dynamic_viscosity_pa_s,
        )

    def add(self, sim: Simulation) -> None:
        """Append ``sim``'s current state as a frame."""
        dim = sim.grid.dim
        st = sim.state
        cells = sim.grid.cells[:dim]
        self.times_s.append(float(sim.time_s))
        self.pressure_pa.append(np.asarray(st.pressure, dtype=float).reshape(cells).copy())
        self.velocity_m_s.append(sim.cell_velocity().reshape(dim, *cells))
        self.fluid = np.asarray(st.label).reshape(cells) == FLUID

    def arrays(self) -> dict[str, np.ndarray]:
        """The ``.npz`` keys (see :mod:`paintapp.explore.flow_files`)."""
        out = {
            "p": np.stack(self.pressure_pa).astype(np.float32),
            "u": np.stack(self.velocity_m_s).astype(np.float32),
            "origin": self.origin_m,
            "spacing": self.spacing_m,
            "times": np.array(self.times_s),
            "density": np.array(self.density_kg_m3),
            "viscosity": np.array(self.viscosity_pa_s),
            "fluid": self.fluid,
            "pressure_units": np.array("Pa"),
        }
        if self.period_s is not None:
            out["period"] = np.array(self.period_s)
        return out


def write_flow_npz(path: str | Path, frames: FlowFrames) -> None:
    """Write ``frames`` as a compressed ``.npz`` (atomically)."""
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as handle:
            np.savez_compressed(handle, allow_pickle=False, **frames.arrays())


def write_flow_vti(path: str | Path, frames: FlowFrames, index: int = -1) -> None:
    """Write frame ``index`` as VTK image data with point arrays ``p``, ``U`` (3 components) and
    ``fluid``, and field data ``density``, ``viscosity``, ``TimeValue`` (needs the vtk package)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonCore import vtkDoubleArray
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

    dim = len(frames.origin_m)
    nodes = frames.fluid.shape
    image = vtkImageData()
    image.SetDimensions(*nodes, *([1] * (3 - dim)))
    image.SetOrigin(*frames.origin_m, *([0.0] * (3 - dim)))
    image.SetSpacing(*frames.spacing_m, *([1.0] * (3 - dim)))

    def flat(a: np.ndarray) -> np.ndarray:  # x fastest, as VTK orders points
        return np.ascontiguousarray(a.transpose(*reversed(range(a.ndim))).reshape(-1))

    u = frames.velocity_m_s[index]
    u3 = np.stack([flat(u[a]) if a < dim else np.zeros(u[0].size) for a in range(3)], axis=1)
    for name, values in (
        ("p", flat(frames.pressure_pa[index])),
        ("U", u3),
        ("fluid", flat(frames.fluid.astype(np.float64))),
    ):
        array = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.float64), deep=True)
        array.SetName(name)
        image.GetPointData().AddArray(array)
    for name, value in (
        ("density", frames.density_kg_m3),
        ("viscosity", frames.viscosity_pa_s),
        ("TimeValue", frames.times_s[index]),
    ):
        field = vtkDoubleArray()
        field.SetName(name)
        field.InsertNextValue(float(value))
        image.GetFieldData().AddArray(field)
    with atomic_path(path) as tmp:
        writer = vtkXMLImageDataWriter()
        writer.SetFileName(str(tmp))
        writer.SetInputData(image)
        if writer.Write() != 1:
            raise OSError(f"could not write {path}")
