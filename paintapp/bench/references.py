"""Accuracy against published and analytic references, each at a chosen setting of the knobs.

* ``cavity``: lid-driven cavity at Re = 100, max |u - u_Ghia| over both centreline profiles of
  Ghia, Ghia & Shin (1982) (m/s, lid speed 1 m/s);
* ``schaefer_turek``: benchmark 2D-1 (Re = 20), relative error of the drag coefficient against
  c_D = 5.5795;
* ``taylor_green``: relative error of the kinetic energy decay rate against ``4 nu k^2``.

Each function takes the knobs as keyword arguments (scene-file names for the solver keys) and
returns a :class:`~paintapp.bench.measure.Measurement`. The runs are scaled down from the full
validations in the README (coarser grids, larger time steps, shorter runs); ``notes`` says how.
"""

from __future__ import annotations

import tomllib
from typing import Any

import numpy as np

from paintapp.bench.measure import SOLVER_KEYS, Measurement, step_cost
from paintapp.resources import asset_path
from solver import DomainBoundary, Fluid, Grid, Side, Simulation, SolverSettings, parse_scene

GHIA_U = {  # y: u along the vertical centreline x = 0.5, Re = 100
    0.9766: 0.84123, 0.9688: 0.78871, 0.9609: 0.73722, 0.9531: 0.68717, 0.8516: 0.23151,
    0.7344: 0.00332, 0.6172: -0.13641, 0.5000: -0.20581, 0.4531: -0.21090, 0.2813: -0.15662,
    0.1719: -0.10150, 0.1016: -0.06434, 0.0703: -0.04775, 0.0625: -0.04192, 0.0547: -0.03717,
}  # fmt: skip
GHIA_V = {  # x: v along the horizontal centreline y = 0.5, Re = 100
    0.9688: -0.05906, 0.9531: -0.08864, 0.9063: -0.16914, 0.8594: -0.22445, 0.8047: -0.24533,
    0.5000: 0.05454, 0.2344: 0.17527, 0.1563: 0.16077, 0.0938: 0.12317, 0.0625: 0.09233,
}  # fmt: skip
ST_CD = 5.5795
ST_SCALE = 2.0 / (1.0 * 0.2**2 * 0.1)  # 2 / (rho U_mean^2 D)
TG_NU = 0.05


def _scene_data(file: str, solver: dict[str, Any], cells: list[int], dt_s: float, steps: int):
    with open(asset_path("scenes", file), "rb") as fh:
        data = tomllib.load(fh)
    data["domain"]["cells"] = cells
    data.setdefault("solver", {}).update(solver)
    data["run"] = {"dt": dt_s, "steps": steps}
    data.pop("output", None)
    return parse_scene(data, file)


def _solver_keys(knobs: dict[str, Any]) -> dict[str, Any]:
    return {k: knobs[k] for k in SOLVER_KEYS if k in knobs}


def _run(sim: Simulation, dt_s: float, steps: int) -> list:
    return [sim.step(dt_s) for _ in range(steps)]


def cavity(cells: int = 32, t_end_s: float = 20.0, **knobs: Any) -> Measurement:
    """Ghia cavity at ``cells`` per side; the lid moves 1.6 cells per step (dt = 1.6 h / U)."""
    dt = knobs.pop("dt_s", 1.6 / cells)
    steps = max(1, round(t_end_s / dt))
    scene = _scene_data("lid_cavity_re100.toml", _solver_keys(knobs), [cells, cells], dt, steps)
    sim = scene.build()
    stats = _run(sim, dt, steps)
    y = np.array(list(GHIA_U))
    pts = np.column_stack([np.full_like(y, 0.5), y])
    err_u = np.abs(sim.velocity_at(pts)[:, 0] - np.array(list(GHIA_U.values()))).max()
    x = np.array(list(GHIA_V))
    pts = np.column_stack([x, np.full_like(x, 0.5)])
    err_v = np.abs(sim.velocity_at(pts)[:, 1] - np.array(list(GHIA_V.values()))).max()
    return Measurement(
        errors={
            "ghia_max_error": float(max(err_u, err_v)),
            "ghia_u_error": float(err_u),
            "ghia_v_error": float(err_v),
        },
        cost=step_cost(stats, sim, dt),
        notes=f"Re = 100 at {cells}x{cells}, dt = {dt:.4g} s, t = {steps * dt:.3g} s "
        "(reference run: 128x128, dt = 0.01 s, t = 20 s)",
    )


def schaefer_turek(dh: int = 10, t_end_s: float = 3.0, **knobs: Any) -> Measurement:
    """Schaefer-Turek 2D-1 with ``dh`` cells per cylinder diameter (10, 20, 30)."""
    if dh % 10:
        raise ValueError("cells per diameter must be a multiple of 10 (0.41 m must be whole cells)")
    dt = knobs.pop("dt_s", 0.02)
    steps = max(2, round(t_end_s / dt))
    cells = [22 * dh, round(4.1 * dh)]
    scene = _scene_data("schaefer_turek_2d1.toml", _solver_keys(knobs), cells, dt, steps)
    sim = scene.build()
    cd = []
    stats = []
    for _ in range(steps):
        stats.append(sim.step(dt))
        cd.append(ST_SCALE * float(sim.forces["cylinder"].force[0]))
    drift = abs(cd[-1] - cd[-max(2, steps // 10)])
    return Measurement(
        errors={"cd_rel_error": float(abs(cd[-1] / ST_CD - 1.0))},
        cost=step_cost(stats, sim, dt),
        notes=f"D/h = {dh} ({cells[0]}x{cells[1]}), dt = {dt:g} s, t = {steps * dt:.3g} s "
        "(reference: c_D = 5.5795; the validation tests run dt = 0.01 s to t = 4-5 s)",
        extra={"c_d": cd[-1], "c_d_drift_last_10pct": drift},
    )


def taylor_green(cells: int = 32, t_end_s: float = 2.0, **knobs: Any) -> Measurement:
    """Taylor-Green vortex on [0, pi]^2 with free-slip walls; dt = 0.64 / cells (fixed CFL)."""
    dt = knobs.pop("dt_s", 0.64 / cells)
    grid = Grid.from_size((np.pi, np.pi), (cells, cells))
    sides = {s: Side("slip") for s in ("x_min", "x_max", "y_min", "y_max")}
    settings = SolverSettings(**_solver_keys(knobs))
    sim = Simulation(grid, Fluid(1.0, TG_NU), DomainBoundary(grid, sides), settings=settings)
    fu, fv = grid.face_centres(0), grid.face_centres(1)
    sim.state.comps[0][:] = np.sin(fu[..., 0]) * np.cos(fu[..., 1])
    sim.state.comps[1][:] = -np.cos(fv[..., 0]) * np.sin(fv[..., 1])
    times, energy, stats = [0.0], [sim.kinetic_energy()], []
    for _ in range(max(2, round(t_end_s / dt))):
        stats.append(sim.step(dt))
        times.append(sim.time_s)
        energy.append(sim.kinetic_energy())
    rate = -np.polyfit(times, np.log(energy), 1)[0]
    exact = 4 * TG_NU
    return Measurement(
        errors={"decay_rate_rel_error": float(abs(rate / exact - 1.0))},
        cost=step_cost(stats, sim, dt),
        notes=f"k = 1, nu = {TG_NU} m^2/s, {cells}x{cells}, dt = {dt:.4g} s, t = {t_end_s:g} s",
        extra={"decay_rate_per_s": float(rate), "exact_per_s": exact},
    )
