"""Fidelity presets: paint fast at ``draft``, finish at ``high`` (``paintapp replay --fidelity``).

A preset is a small table of knobs applied on top of a painting scene (:func:`apply_fidelity`);
``standard`` is the scene exactly as written:

============  ==========  ========  ==========  ===========  ===========  ===========
preset        cell scale  nz scale  pressure    viscosity    advection    max step
============  ==========  ========  ==========  ===========  ===========  ===========
``draft``     0.75        0.75      tol 1e-4    tol 1e-3     Stokes       the scene's
``high``      1.5         1.5       tol 1e-7    tol 1e-8     maccormack   1/120 s
============  ==========  ========  ==========  ===========  ===========  ===========

``draft`` leaves out momentum advection while the tip's Reynolds number is below 0.1
(``choose.stokes_below_re``; linear advection above). The cell scale multiplies the grid's cells
(the same span, smaller cells, as near as whole texels per cell allow: ``--explain`` shows it)
and the re-centring margin; the nz scale the 3D grid's height in cells. Tolerances are relative
residuals of the pressure and viscosity solves; ``max_iterations`` caps them (draft 200, high
1000, standard the scene's). A smaller max step splits a gap between samples into more steps.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Literal

from common.errors import InputError
from paintapp.paint.paint_scene import MAX_CELLS, PaintScene


@dataclass(frozen=True)
class Fidelity:
    """One fidelity preset (None: keep the scene's value).

    Attributes:
        name: ``draft``, ``standard`` or ``high``.
        cell_scale: multiplies the grid's lateral cells (and the margin).
        nz_scale: multiplies the 3D grid's cells in z.
        pressure_tolerance, viscosity_tolerance: relative residuals of the PCG solves.
        max_iterations: iteration cap of each solve.
        advection: ``linear`` or ``maccormack`` (the fluid velocity's self-advection).
        stokes_below_re: replaces the scene's ``choose.stokes_below_re`` (0: always advect).
        max_step_s: longest solver step, s (never longer than the scene's).
        description: one line for ``--help`` and ``--explain``.
    """

    name: str
    cell_scale: float = 1.0
    nz_scale: float = 1.0
    pressure_tolerance: float | None = None
    viscosity_tolerance: float | None = None
    max_iterations: int | None = None
    advection: Literal["linear", "maccormack"] | None = None
    max_step_s: float | None = None
    stokes_below_re: float | None = None
    description: str = ""


FIDELITIES: dict[str, Fidelity] = {
    f.name: f
    for f in (
        Fidelity(
            "draft",
            cell_scale=0.75,
            nz_scale=0.75,
            pressure_tolerance=1e-4,
            viscosity_tolerance=1e-3,
            max_iterations=200,
            advection="linear",
            stokes_below_re=0.1,
            description="interactive: 0.75x cells, loose tolerances, Stokes flow below Re 0.1",
        ),
        Fidelity("standard", description="the scene as written"),
        Fidelity(
            "high",
            cell_scale=1.5,
            nz_scale=1.5,
            pressure_tolerance=1e-7,
            viscosity_tolerance=1e-8,
            max_iterations=1000,
            advection="maccormack",
            max_step_s=1.0 / 120.0,
            stokes_below_re=0.0,
            description="final render: 1.5x cells, tight tolerances, MacCormack, 120 Hz steps",
        ),
    )
}
FIDELITY_NAMES = tuple(FIDELITIES)


def get_fidelity(name: str) -> Fidelity:
    """The preset called ``name``; :class:`InputError` for an unknown one."""
    if name not in FIDELITIES:
        raise InputError(
            f"unknown fidelity {name!r}; expected one of {', '.join(FIDELITY_NAMES)}",
            key="fidelity",
        )
    return FIDELITIES[name]


def _scaled(n: int, scale: float, lowest: int) -> int:
    return max(lowest, round(n * scale)) if scale != 1.0 else n


def apply_fidelity(scene: PaintScene, fidelity: str | Fidelity) -> PaintScene:
    """``scene`` with the knobs of ``fidelity`` (``standard``: ``scene`` itself)."""
    f = get_fidelity(fidelity) if isinstance(fidelity, str) else fidelity
    nx, ny, nz = scene.cells
    flat = scene.fluid_model in ("depth_averaged", "none")
    cells = (
        _scaled(nx, f.cell_scale, 8),
        _scaled(ny, f.cell_scale, 8),
        nz if flat else _scaled(nz, f.nz_scale, 3),
    )
    if math.prod(cells) > MAX_CELLS:
        raise InputError(
            f"fidelity {f.name!r} would give {cells} cells, more than {MAX_CELLS}", key="fidelity"
        )
    widest = min(cells[0], cells[1]) // 2 - 1
    every_step = scene.margin_cells >= min(nx, ny) // 2 - 1  # re-centred at every step: stays so
    margin = widest if every_step else min(_scaled(scene.margin_cells, f.cell_scale, 0), widest)
    s = scene.solver
    solver = replace(
        s,
        pressure_tolerance=f.pressure_tolerance or s.pressure_tolerance,
        viscosity_tolerance=f.viscosity_tolerance or s.viscosity_tolerance,
        max_iterations=f.max_iterations or s.max_iterations,
        advection=f.advection or s.advection,
    )
    step = min(scene.max_step_s, f.max_step_s) if f.max_step_s else scene.max_step_s
    choose = scene.choose
    if f.stokes_below_re is not None:
        choose = replace(choose, stokes_below_re=f.stokes_below_re)
    if solver == s and cells == scene.cells and step == scene.max_step_s and choose == scene.choose:
        return scene
    return replace(
        scene, cells=cells, margin_cells=margin, max_step_s=step, solver=solver, choose=choose
    )
