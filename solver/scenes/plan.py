"""What a simulation will compute, and why: the model is no bigger than the scene requires.

:func:`explain` reads a built :class:`~solver.simulation.Simulation` (and the time step it will
take) and returns one :class:`Decision` per choice: the grid, whether a viscosity solve runs, the
advection scheme, the pressure solve, whether and how probe forces are computed, torque, body
force and boundaries. It only describes; the simulation already skips what is not needed (no
viscosity solve for an inviscid fluid, no force work without probes or with
``SolverSettings.probe_forces = False``). Layers above add their own decisions (the device's
torque output, a dry brush) to the same list.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from solver.boundary import SIDE_NAMES
from solver.compiled.threads import AUTO_MIN_SAMPLES, usable_cores
from solver.linalg.multigrid import PARALLEL_MIN_CELLS
from solver.probes import Probe
from solver.settings import JACOBI_LIMIT
from solver.shapes import Box
from solver.simulation import Simulation

MIB = 1024.0 * 1024.0


@dataclass(frozen=True)
class Decision:
    """One modelling choice: ``topic`` (e.g. ``viscosity``), what was ``chosen``, and ``reason``."""

    topic: str
    chosen: str
    reason: str

    def __str__(self) -> str:
        return f"{self.topic}: {self.chosen} -- {self.reason}"


def explain(sim: Simulation, dt_s: float) -> list[Decision]:
    """The decisions behind ``sim`` stepping with ``dt_s`` seconds, in step order."""
    return [
        _grid(sim),
        _time_step(sim, dt_s),
        _advection(sim),
        _body_force(sim),
        _viscosity(sim, dt_s),
        _threads(sim),
        _pressure(sim),
        _boundaries(sim),
        _probe_boundary(sim),
        _forces(sim),
        _torque(sim),
    ]


def _grid(sim: Simulation) -> Decision:
    g = sim.grid
    shape = "x".join(str(c) for c in g.cells[: g.dim])
    n = int(np.prod(g.cells))
    mib = sum(a.nbytes for a in (*sim.state.comps, sim.state.pressure, sim.state.label)) / MIB
    chosen = f"{g.dim}D {shape} = {n} cells, h = {g.cell_size_m:.4g} m, {mib:.2f} MiB of fields"
    if g.dim == 2:
        reason = "the scene's domain is 2D: one cell deep, no z faces and no w velocity"
    else:
        reason = "the scene's domain is 3D: three velocity components, 7-point stencils"
    return Decision("grid", chosen, reason + "; cost grows with the cell count")


def max_boundary_speed(sim: Simulation) -> float:
    """The fastest moving boundary: probe surface (linear + spin) or domain side, m/s."""
    speeds = [float(np.abs(sim.boundary.velocities()).max())]
    speeds += [_probe_speed(p) for p in sim.probes]
    return max(speeds)


def _probe_speed(p: Probe) -> float:
    reach = p.shape.bounding_radius_m
    if p.path is not None and len(p.path) > 1:
        d = p.dim
        dt = np.diff(p.path[:, 0])
        lin = np.linalg.norm(np.diff(p.path[:, 1 : 1 + d], axis=0), axis=1) / dt
        spin = np.abs(np.diff(p.path[:, 1 + d])) / dt if d == 2 else np.zeros_like(dt)
        return float(np.max(lin + spin * reach))
    spin_rad_s = float(np.linalg.norm(p.omega3()))
    return float(np.linalg.norm(p.velocity_m_s)) + spin_rad_s * reach


def _time_step(sim: Simulation, dt_s: float) -> Decision:
    cells = max_boundary_speed(sim) * dt_s / sim.grid.cell_size_m
    reason = (
        "semi-Lagrangian advection and implicit viscosity are stable at any step; "
        f"the fastest boundary moves {cells:.2g} cells per step"
    )
    if cells > 1.0:
        reason += " (above 1 the flow near it loses accuracy, not stability)"
    return Decision("time step", f"dt = {dt_s:g} s", reason)


def _advection(sim: Simulation) -> Decision:
    if sim.settings.advection == "none":
        return Decision(
            "advection",
            "none (Stokes flow)",
            "solver.advection = none: the velocity's self-advection is left out, valid only where "
            "the Reynolds number is far below 1 (creeping flow)",
        )
    if sim.settings.advection == "maccormack":
        return Decision(
            "advection",
            "bounded MacCormack (second order)",
            "solver.advection = maccormack: less numerical diffusion for about 1.5x the "
            "advection cost (two extra interpolation passes)",
        )
    return Decision(
        "advection",
        "semi-Lagrangian, linear interpolation (first order)",
        "solver.advection = linear: the cheapest scheme; more numerical diffusion",
    )


def _body_force(sim: Simulation) -> Decision:
    f = np.asarray(sim.fluid.body_force_m_s2[: sim.grid.dim])
    if not np.any(f):
        return Decision("body force", "none", "fluid.body_force is zero or absent")
    return Decision("body force", f"{f.tolist()} m/s^2", "added to the velocity after advection")


def _viscosity(sim: Simulation, dt_s: float) -> Decision:
    nu = sim.fluid.viscosity_m2_s
    d = sim.grid.dim
    if nu <= 0.0:
        return Decision(
            "viscosity",
            "no viscosity solve",
            "the fluid is inviscid (viscosity = 0): no diffusion and no viscous stress",
        )
    number = nu * dt_s / sim.grid.cell_size_m**2
    limit = 1.0 / (2 * d)
    reason = f"nu = {nu:g} m^2/s, nu dt / h^2 = {number:.3g}"
    if number > limit:
        reason += f" (an explicit step would need < {limit:.3g}; the implicit one is stable)"
    cfg = sim.settings
    coupling = 2 * d * number
    kind = cfg.viscosity_solver(coupling)
    names = {"jacobi": "diagonally preconditioned CG", "multigrid": "MGPCG", "mic0": "MIC(0)-PCG"}
    start = "the last step's solution (warm_start)" if cfg.warm_start else "the advected velocity"
    chosen = (
        f"implicit, {d} {names[kind]} solves per step (tolerance {cfg.viscosity_tolerance:g}, "
        f"at most {cfg.max_iterations} iterations), each from {start}"
    )
    if cfg.viscosity_preconditioner == "auto":
        side = "<=" if kind == "jacobi" else ">"
        reason += f"; 2 dim nu dt / h^2 = {coupling:.3g} {side} {JACOBI_LIMIT:g} picks {kind}"
    return Decision("viscosity", chosen, reason)


def _threads(sim: Simulation) -> Decision:
    g = sim.grid
    threads = sim.component_threads()
    samples = sim.component_samples  # the smallest component's
    chosen = f"the {g.dim} velocity components' advection and viscosity solves on " + (
        f"{threads} threads at once" if threads > 1 else "one thread, one after the other"
    )
    if sim.pressure_on_threads():
        levels = f"the pressure solve's levels of {PARALLEL_MIN_CELLS}+ cells"
        if sim.pressure_threads_adaptive():
            chosen += (
                f"; {levels} on {sim.pressure_threads()} threads or one, whichever has cost less "
                "per iteration lately (measured as it runs)"
            )
        else:
            chosen += f"; {levels} on {sim.pressure_threads()}"
    if sim.settings.threads:
        reason = f"the scene sets threads = {sim.settings.threads}"
    elif samples < AUTO_MIN_SAMPLES[g.dim]:
        reason = (
            f"auto: {samples} samples a component < {AUTO_MIN_SAMPLES[g.dim]} ({g.dim}D), where "
            "handing work to another thread costs more than it saves"
        )
    else:
        reason = f"auto: {samples} samples a component, {usable_cores()} usable cores"
    return Decision("threads", chosen, reason)


def _pressure(sim: Simulation) -> Decision:
    cfg = sim.settings
    solver = "MGPCG (multigrid V-cycle)" if cfg.preconditioner == "multigrid" else "MIC(0)-PCG"
    scheme = "incremental pressure correction" if cfg.incremental_pressure else "Chorin projection"
    outflow = sim.boundary.has_outflow()
    if not cfg.incremental_pressure:
        start = "the last pressure"
    elif cfg.warm_start and outflow:
        start = "the last step's increment (warm_start)"
    else:
        start = "a zero increment"
    chosen = (
        f"{scheme}, {solver} to relative residual {cfg.pressure_tolerance:g}, at most "
        f"{cfg.max_iterations} iterations, from {start}"
    )
    if outflow:
        reason = "outflow sides hold the pressure at zero"
    else:
        reason = "closed domain: pressure is defined up to a constant (the mean is removed)"
        if cfg.warm_start and cfg.incremental_pressure:
            reason += "; its increment starts cold (a warm start would carry the constant along)"
    return Decision("pressure", chosen, reason)


def _boundaries(sim: Simulation) -> Decision:
    parts = []
    for a in range(sim.grid.dim):
        for e in range(2):
            side = sim.boundary.side(a, e)
            moving = any(side.velocity) if side.velocity else False
            text = side.kind + (" (moving)" if moving and side.kind == "wall" else "")
            parts.append(f"{SIDE_NAMES[2 * a + e]} {text}")
    return Decision("boundaries", ", ".join(parts), "from the scene's [boundary] (default: wall)")


def _probe_boundary(sim: Simulation) -> Decision:
    if not sim.probes:
        return Decision("probe surfaces", "none", "no probes")
    if sim.settings.boundary_method == "cutcell":
        why = (
            "a moving surface changes the pressure matrix continuously (no cells switching "
            "between solid and fluid, so no force spikes as it crosses them)"
        )
        boxes = sum(isinstance(p.shape, Box) for p in sim.probes)
        radius = sim.settings.corner_radius_cells
        if boxes and radius > 0:
            why += (
                f"; {boxes} box probe(s) with corners rounded by {radius:g} cell(s) "
                f"({radius * sim.grid.cell_size_m:.3g} m, solver.corner_radius_cells): a corner "
                "sharper than the grid makes the force jump at every cell it crosses"
            )
        return Decision(
            "probe surfaces",
            "cut cells: face fractions from each probe's signed distance, every step",
            why,
        )
    return Decision(
        "probe surfaces",
        "staircase: the cells whose centres lie inside a probe are solid",
        "solver.boundary_method = staircase (the paper's; its force jumps as cells switch)",
    )


def _forces(sim: Simulation) -> Decision:
    n = len(sim.probes)
    if n == 0:
        return Decision("probe forces", "none", "no probes: no voxelizing and no force work")
    if not sim.settings.probe_forces:
        return Decision(
            "probe forces",
            "not computed",
            "nothing reads them (SolverSettings.probe_forces = False)",
        )
    model = sim.settings.force_model
    reasons = {
        "stress": (
            "the stress integral over each probe's cut surface"
            if sim.settings.boundary_method == "cutcell"
            else "the paper's stress integral over each probe's staircase surface (eqs. 9-18)"
        ),
        "control_volume": (
            f"momentum balance over a box {sim.settings.control_volume_margin} cells around "
            "each probe (less staircase noise and bias; keeps the previous state each step; "
            "the stress integral where no box fits)"
        ),
        "drag": "the paper's quadratic drag F = -C rho |v| v A: no flow field needed, no torque",
        "viscous_drag": "the paper's viscous drag F = -C mu v A: no flow field needed, no torque",
    }
    return Decision("probe forces", f"{model} on {n} probe(s)", reasons[model])


def _torque(sim: Simulation) -> Decision:
    if not sim.computes_forces():
        return Decision("torque", "none", "no probe forces are computed")
    if sim.settings.force_model in ("drag", "viscous_drag"):
        return Decision("torque", "none", "the drag formulas give no torque")
    kind = "scalar about z (N m/m)" if sim.grid.dim == 2 else "vector (N m)"
    return Decision(
        "torque",
        f"computed, {kind}, about each probe's reference point",
        "part of the same surface sum (no extra cost); a device without torque output drops it",
    )
