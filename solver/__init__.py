"""Numerics for incompressible viscous flow on a staggered MAC grid (2D and 3D).

Knows nothing of brushes, rendering or devices. The names below are the package's public API: the
application and the brushes import them from ``solver`` itself (an import-linter contract says so),
never from the modules that hold them. Each is loaded on first use, so that importing one light
name (a scene reader, the cell labels) does not load every numerical kernel.

Layout: the model at the top (:mod:`solver.grid`, :mod:`solver.boundary`, :mod:`solver.labels`,
:mod:`solver.shapes`, :mod:`solver.probes`, :mod:`solver.settings`, :mod:`solver.simulation`,
:mod:`solver.interp`, :mod:`solver.field_shift`), the typed bundles of arrays the kernels take
(:mod:`solver.bundles`), and one subpackage per part of the method: :mod:`solver.advection`,
:mod:`solver.cutcell`, :mod:`solver.staircase`, :mod:`solver.linalg`, :mod:`solver.forces`,
:mod:`solver.sampled`, :mod:`solver.scenes`, and the numba plumbing in :mod:`solver.compiled`.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from solver.advection.scalars import substeps_for, transport
    from solver.boundary import DomainBoundary, Side
    from solver.compiled.jit import inline_kernel, kernel
    from solver.compiled.threads import MAX_THREADS, BesideJob
    from solver.grid import Grid
    from solver.labels import BOUNDARY, FLUID, FREE, INTERIOR, STATIC_SOLID
    from solver.probes import Probe
    from solver.sampled.flow import SampledFlow, frame_pair
    from solver.sampled.forces import FieldForce, surface_force
    from solver.sampled.quadrature import SurfaceRule, surface_rule
    from solver.scenes.budget import check_memory, slow_step_warning
    from solver.scenes.plan import Decision, explain
    from solver.scenes.runner import NonFiniteError, run_scene
    from solver.scenes.scene import Scene, load_scene, method_keys, parse_scene
    from solver.settings import (
        Advection,
        BoundaryMethod,
        ForceModel,
        Preconditioner,
        PressureScheme,
        SolverSettings,
        ViscosityPreconditioner,
    )
    from solver.shapes import Ball, Box, FilletedBox, Shape, with_rounded_corners
    from solver.simulation import Fluid, FluidState, ProbeForce, Simulation, StepStats

#: Where each public name lives.
_HOME: dict[str, str] = {
    "Grid": "solver.grid",
    "DomainBoundary": "solver.boundary",
    "Side": "solver.boundary",
    "BOUNDARY": "solver.labels",
    "FLUID": "solver.labels",
    "FREE": "solver.labels",
    "INTERIOR": "solver.labels",
    "STATIC_SOLID": "solver.labels",
    "Ball": "solver.shapes",
    "Box": "solver.shapes",
    "FilletedBox": "solver.shapes",
    "Shape": "solver.shapes",
    "with_rounded_corners": "solver.shapes",
    "Probe": "solver.probes",
    "Advection": "solver.settings",
    "BoundaryMethod": "solver.settings",
    "ForceModel": "solver.settings",
    "Preconditioner": "solver.settings",
    "PressureScheme": "solver.settings",
    "SolverSettings": "solver.settings",
    "ViscosityPreconditioner": "solver.settings",
    "Fluid": "solver.simulation",
    "FluidState": "solver.simulation",
    "ProbeForce": "solver.simulation",
    "Simulation": "solver.simulation",
    "StepStats": "solver.simulation",
    "substeps_for": "solver.advection.scalars",
    "transport": "solver.advection.scalars",
    "inline_kernel": "solver.compiled.jit",
    "kernel": "solver.compiled.jit",
    "BesideJob": "solver.compiled.threads",
    "MAX_THREADS": "solver.compiled.threads",
    "Scene": "solver.scenes.scene",
    "load_scene": "solver.scenes.scene",
    "method_keys": "solver.scenes.scene",
    "parse_scene": "solver.scenes.scene",
    "NonFiniteError": "solver.scenes.runner",
    "run_scene": "solver.scenes.runner",
    "Decision": "solver.scenes.plan",
    "explain": "solver.scenes.plan",
    "check_memory": "solver.scenes.budget",
    "slow_step_warning": "solver.scenes.budget",
    "SampledFlow": "solver.sampled.flow",
    "frame_pair": "solver.sampled.flow",
    "FieldForce": "solver.sampled.forces",
    "surface_force": "solver.sampled.forces",
    "SurfaceRule": "solver.sampled.quadrature",
    "surface_rule": "solver.sampled.quadrature",
}

__all__ = [
    "BOUNDARY",
    "FLUID",
    "FREE",
    "INTERIOR",
    "MAX_THREADS",
    "STATIC_SOLID",
    "Advection",
    "Ball",
    "BesideJob",
    "BoundaryMethod",
    "Box",
    "Decision",
    "DomainBoundary",
    "FieldForce",
    "FilletedBox",
    "Fluid",
    "FluidState",
    "ForceModel",
    "Grid",
    "NonFiniteError",
    "Preconditioner",
    "PressureScheme",
    "Probe",
    "ProbeForce",
    "SampledFlow",
    "Scene",
    "Shape",
    "Side",
    "Simulation",
    "SolverSettings",
    "StepStats",
    "SurfaceRule",
    "ViscosityPreconditioner",
    "check_memory",
    "explain",
    "frame_pair",
    "inline_kernel",
    "kernel",
    "load_scene",
    "method_keys",
    "parse_scene",
    "run_scene",
    "slow_step_warning",
    "substeps_for",
    "surface_force",
    "surface_rule",
    "transport",
    "with_rounded_corners",
]


def __getattr__(name: str) -> Any:
    """Load a public name from its module on first use (PEP 562)."""
    home = _HOME.get(name)
    if home is None:
        raise AttributeError(f"module 'solver' has no attribute {name!r}")
    value = getattr(importlib.import_module(home), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
