"""Feeling a flow someone else computed (``paintapp explore``): reading CFD data sets
(:mod:`.flow_files`: ``.npz`` and VTK grids, :mod:`.vtk_files`; OpenFOAM cases,
:mod:`.openfoam_case`, and unstructured VTK, :mod:`.vtk_unstructured`, loaded by
:mod:`.load_unstructured` into an :class:`~.unstructured.UnstructuredFlow`; a frame as a reader
found it, :mod:`.flow_frame`), the local grid resampled around a probe in a mesh
(:mod:`.local_resample`), writing ours (:mod:`.flow_export`), scripted probe paths
(:mod:`.probe_paths`), the probe whose force reaches the servo loop (:mod:`.exploration`) and
the force trace it writes (:mod:`.force_trace`). The force itself is the solver's stress integral
over the probe's exact surface (:mod:`solver.sampled.forces`).

The names below load lazily (``from paintapp.explore import load_flow``)::

    flow = load_flow(["case.foam"], FluidOverrides(density_kg_m3=998.0), CaseSelection())
    probe = Exploration(flow, ProbeSpec("circle", (0.1,)), resample=ResampleSpec(refine=2))
    force, torque = probe.felt(probe.force_at(flow.times_s[-1], centre, 0.0))
"""

from __future__ import annotations

import importlib
from typing import Any

_NAMES = {
    "load_flow": "paintapp.explore.flow_files",
    "FluidOverrides": "paintapp.explore.fluid_properties",
    "CaseSelection": "paintapp.explore.openfoam_case",
    "UnstructuredFlow": "paintapp.explore.unstructured",
    "ResampleSpec": "paintapp.explore.local_resample",
    "Exploration": "paintapp.explore.exploration",
    "ProbeSpec": "paintapp.explore.exploration",
    "run_scripted": "paintapp.explore.exploration",
    "read_probe_path": "paintapp.explore.probe_paths",
    "write_explore_forces_csv": "paintapp.explore.force_trace",
    "read_explore_forces_csv": "paintapp.explore.force_trace",
}
__all__ = sorted(_NAMES)


def __getattr__(name: str) -> Any:
    if name not in _NAMES:
        raise AttributeError(f"module 'paintapp.explore' has no attribute {name!r}")
    return getattr(importlib.import_module(_NAMES[name]), name)
