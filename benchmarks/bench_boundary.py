"""Staircase vs cut-cell boundaries: every row of the README's cut-cell table.

    python benchmarks/bench_boundary.py [--only SECTION ...] [--methods staircase cutcell]
        [--cells 72 96 160] [--steps 400] [--dh 20] [--dh2 10] [--cfl2 0.5] [--t2 8]

Sections (all by default, each selectable with --only):

towed     Towed disk: radius 0.04 m at 0.3 m/s through fluid at rest in a closed unit box,
          slightly off the centre line, nu = 1e-3, dt = 0.004 s, on each --cells grid (72, 96, 160:
          D/h 5.8, 7.7, 12.8). After the wake has formed (the first 0.6 s, 2.25 D of travel, are
          dropped) the drag's high-frequency part (the signal minus a cubic Savitzky-Golay fit
          over 0.25 s) is reported as an RMS and as the largest single-step jump, both in % of the
          mean drag; the lift's likewise (still in % of the mean drag).
sphere    The same for a 3D sphere, radius 0.05 m at a/h = 4 (64 x 32 x 32 in 0.8 x 0.4 x 0.4 m),
          0.3 m/s, nu = 1e-3, dt = 0.004 s, 250 steps, the first 0.4 s dropped.
st        Schaefer-Turek 2D-1 (Re 20): steady c_D from the surface (stress) force, MacCormack,
          dt 0.01 s, t 5 s, at D/h = --dh; reference 5.5795.
st2       Schaefer-Turek 2D-2 (Re 100: inflow peak 1.5 m/s, U_mean 1): Strouhal from the lift's
          upward zero crossings (with hysteresis), c_D max and c_L max over the last 3 s (and
          c_L max over the 3 s before, to show whether the shedding has saturated), scaled by
          2 / (rho U_mean^2 D), at D/h = --dh2 (a multiple of 10), MacCormack, dt = --cfl2 h /
          (1.5 m/s) (CFL 0.5 by default), t = --t2 (8 s: the lift amplitude has saturated).
          References: St 0.295-0.305, c_D max 3.22-3.24, c_L max 0.99-1.01.
couette   Circular Couette: a disk (R1 0.15) spinning at 1.5 rad/s inside a fixed (voxelized)
          ring (R2 0.45), mu 1, 64^2, dt 0.05 s, t 1.5 s; torque error against
          -4 pi mu omega R1^2 R2^2 / (R2^2 - R1^2).
stokes    Stokes drag (32^2, disk radius 0.15 in a 0.01 m/s parabolic channel inflow, t 4 s):
          ratio of the drag at 2 nu to that at nu, once at the same nu dt / h^2 (dt halved) and
          once at the same dt. Linear and dt independent: both 2.
cost      Per-step cost on the same grid: the towed disk at --cost-cells (96^2), both methods'
          steps interleaved, median step time of 200 warm steps (the first 20, which include numba
          compilation, are dropped); ratio cut/staircase.
sweep     The paper's square-probe sweep (paintapp/bench/sweep_force.py) at 64^2: force and
          torque noise (no reference run); cut cells with sharp corners (the default) and
          with the square's corners rounded by 0.75 cell (corner_radius_cells).

Prints markdown tables.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy.signal import savgol_filter

from solver import Ball, DomainBoundary, Fluid, Grid, Probe, Side, Simulation, SolverSettings

METHODS = ("staircase", "cutcell")
SECTIONS = ("towed", "sphere", "st", "st2", "couette", "stokes", "cost", "sweep")
WARM_STEPS = 20
ROUNDED_CELLS = 0.75  # the sweep's corner radius beside the default's, cells


def noise(f: np.ndarray, dt: float) -> dict[str, float]:
    """HF RMS and largest jump of drag and lift, % of the mean drag (f: steps x dim)."""
    mean = abs(f[:, 0].mean())
    window = round(0.25 / dt) | 1
    out = {}
    for c, name in ((0, "drag"), (1, "lift")):
        hf = f[:, c] - savgol_filter(f[:, c], window, 3)
        out[f"{name}_rms"] = 100 * float(np.sqrt(np.mean(hf**2))) / mean
        out[f"{name}_jump"] = 100 * float(np.abs(np.diff(f[:, c])).max()) / mean
    return out


def _towed(sim: Simulation, steps: int, dt: float, skip_s: float) -> dict[str, float]:
    forces, times = [], []
    for _ in range(steps):
        stats = sim.step(dt)
        times.append(stats.step_ms)
        forces.append(sim.forces["p"].force.copy())
    out = noise(np.array(forces)[round(skip_s / dt) :], dt)
    out["step_ms"] = float(np.median(times[WARM_STEPS:]))
    return out


def towed_disk(method: str, cells: int, steps: int = 400, dt: float = 0.004) -> dict[str, float]:
    """Noise figures of the towed disk (percent of the mean drag) and the warm median step time."""
    grid = Grid.from_size((1.0, 1.0), (cells, cells))
    probe = Probe("p", Ball(0.04), 2, np.array([0.2, 0.51]), velocity_m_s=np.array([0.3, 0.0]))
    settings = SolverSettings(boundary_method=method, pressure_tolerance=1e-6)
    sim = Simulation(grid, Fluid(1.0, 1e-3), probes=[probe], settings=settings)
    return {"dh": 0.08 / grid.cell_size_m, **_towed(sim, steps, dt, 0.6)}


def towed_sphere(method: str, steps: int = 250, dt: float = 0.004) -> dict[str, float]:
    """The towed disk's noise figures for a sphere at a/h = 4."""
    grid = Grid.from_size((0.8, 0.4, 0.4), (64, 32, 32))
    probe = Probe("p", Ball(0.05), 3, np.array([0.2, 0.205, 0.2025]),
                  velocity_m_s=np.array([0.3, 0.0, 0.0]))  # fmt: skip
    settings = SolverSettings(boundary_method=method, pressure_tolerance=1e-6)
    sim = Simulation(grid, Fluid(1.0, 1e-3), probes=[probe], settings=settings)
    return {"ah": 0.05 / grid.cell_size_m, **_towed(sim, steps, dt, 0.4)}


def _channel(method: str, dh: int, peak: float) -> Simulation:
    grid = Grid.from_size((2.2, 0.41), (22 * dh, 41 * dh // 10))
    sides = {"x_min": Side("inflow", (peak, 0.0), "parabolic"), "x_max": Side("outflow")}
    probe = Probe("cylinder", Ball(0.05), 2, np.array([0.2, 0.2]))
    settings = SolverSettings(boundary_method=method, advection="maccormack")
    return Simulation(grid, Fluid(1.0, 1e-3), DomainBoundary(grid, sides), [probe], settings)


def schaefer_turek_2d1(method: str, dh: int = 20, t_end: float = 5.0, dt: float = 0.01) -> float:
    """Steady c_D of benchmark 2D-1 from the stress (surface) model."""
    sim = _channel(method, dh, 0.3)
    for _ in range(round(t_end / dt)):
        sim.step(dt)
    return 2.0 * float(sim.forces["cylinder"].force[0]) / (0.2**2 * 0.1)


def schaefer_turek_2d2(
    method: str, dh: int = 10, t_end: float = 8.0, cfl: float = 0.5
) -> dict[str, float]:
    """Benchmark 2D-2: Strouhal number, c_D max and c_L max over the last 3 s."""
    dt = cfl * (0.1 / dh) / 1.5
    sim = _channel(method, dh, 1.5)
    f = []
    for _ in range(round(t_end / dt)):
        sim.step(dt)
        f.append(sim.forces["cylinder"].force.copy())
    n = round(3.0 / dt)
    earlier = 2.0 * float(np.array(f)[-2 * n : -n, 1].max()) / (1.0**2 * 0.1)
    c = 2.0 * np.array(f)[-n:] / (1.0**2 * 0.1)
    cl = c[:, 1] - c[:, 1].mean()
    # upward zero crossings, each counted only after the lift has been below -30 % of its
    # amplitude since the last one (hysteresis: step-to-step jitter near zero is no crossing)
    low, armed, crossings = -0.3 * float(np.abs(cl).max()), False, []
    for i in range(len(cl) - 1):
        armed = armed or cl[i] < low
        if armed and cl[i] < 0 <= cl[i + 1]:
            crossings.append(i)
            armed = False
    up = np.array(crossings, dtype=int)
    t_up = (up + cl[up] / (cl[up] - cl[up + 1])) * dt  # linear interpolation
    period = float(np.diff(t_up).mean()) if len(t_up) > 1 else float("nan")
    return {"st": 0.1 / period, "cd_max": float(c[:, 0].max()), "cl_max": float(c[:, 1].max()),
            "periods": len(t_up) - 1, "dt": dt, "cl_max_before": earlier}  # fmt: skip


def couette(method: str) -> float:
    """Relative torque error (%) of the spinning disk in a fixed ring."""
    grid = Grid.from_size((1.0, 1.0), (64, 64))
    r1, r2, mu, spin = 0.15, 0.45, 1.0, 1.5
    ring = np.linalg.norm(grid.cell_centres()[..., :2] - 0.5, axis=-1) > r2
    rotor = Probe("rotor", Ball(r1), 2, np.array([0.5, 0.5]), 0.0, np.zeros(2), spin)
    sim = Simulation(grid, Fluid(1.0, mu), probes=[rotor], static_solid=ring,
                     settings=SolverSettings(boundary_method=method))  # fmt: skip
    for _ in range(30):
        sim.step(0.05)
    exact = -4 * np.pi * mu * spin * r1**2 * r2**2 / (r2**2 - r1**2)
    return 100 * (float(sim.forces["rotor"].torque) / exact - 1)


def stokes(method: str) -> tuple[float, float]:
    """Drag ratio for 2x nu: at the same nu dt / h^2 and at the same dt (t = 4 s)."""
    res = []
    for nu, dt in ((1.0, 0.04), (2.0, 0.02), (2.0, 0.04)):
        g = Grid.from_size((1.0, 1.0), (32, 32))
        sides = {"x_min": Side("inflow", (0.01, 0.0), "parabolic"), "x_max": Side("outflow")}
        pr = Probe("probe", Ball(0.15), 2, np.array([0.4, 0.45]), 0.0, np.zeros(2), 0.3)
        settings = SolverSettings(boundary_method=method)
        sim = Simulation(g, Fluid(1.0, nu), DomainBoundary(g, sides), [pr], settings)
        for _ in range(round(4.0 / dt)):
            sim.step(dt)
        res.append(float(np.linalg.norm(sim.forces["probe"].force)))
    return res[1] / res[0], res[2] / res[0]


def step_cost(methods: list[str], cells: int = 96, steps: int = 200) -> dict[str, float]:
    """Median step time (ms) of the towed disk per method, the methods' steps interleaved (so
    that other load on the machine hits both alike), after WARM_STEPS steps of each (compile)."""
    sims = {}
    for m in methods:
        grid = Grid.from_size((1.0, 1.0), (cells, cells))
        probe = Probe("p", Ball(0.04), 2, np.array([0.2, 0.51]), velocity_m_s=np.array([0.3, 0.0]))
        settings = SolverSettings(boundary_method=m, pressure_tolerance=1e-6)
        sims[m] = Simulation(grid, Fluid(1.0, 1e-3), probes=[probe], settings=settings)
    times: dict[str, list[float]] = {m: [] for m in methods}
    for _ in range(WARM_STEPS + steps):
        for m, sim in sims.items():
            times[m].append(sim.step(0.004).step_ms)
    return {m: float(np.median(t[WARM_STEPS:])) for m, t in times.items()}


def sweep(method: str, corner_radius_cells: float) -> dict[str, float]:
    """Force and torque noise of the paper's square-probe sweep at 64^2."""
    from paintapp.bench.sweep_force import sweep_force

    m = sweep_force(cells=64, reference_cells=None, boundary_method=method,
                    corner_radius_cells=corner_radius_cells)  # fmt: skip
    return {"force_noise": float(m.errors["force_noise"] or 0.0),
            "torque_noise": float(m.errors["torque_noise"] or 0.0)}  # fmt: skip


def _timed(label: str, fn, *args):  # type: ignore[no-untyped-def]
    t0 = time.perf_counter()
    r = fn(*args)
    print(f"  ({label}: {time.perf_counter() - t0:.0f} s)", flush=True)
    return r


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", choices=SECTIONS, nargs="+", default=list(SECTIONS))
    ap.add_argument("--methods", choices=METHODS, nargs="+", default=list(METHODS))
    ap.add_argument("--cells", type=int, nargs="+", default=[72, 96, 160])
    ap.add_argument("--steps", type=int, default=400)
    ap.add_argument("--cost-cells", type=int, default=96, help="grid of the cost section")
    ap.add_argument("--dh", type=int, default=20, help="D/h of Schaefer-Turek 2D-1")
    ap.add_argument("--dh2", type=int, default=10, help="D/h of Schaefer-Turek 2D-2")
    ap.add_argument("--t2", type=float, default=8.0, help="end time of Schaefer-Turek 2D-2, s")
    ap.add_argument("--cfl2", type=float, default=0.5,
                    help="Schaefer-Turek 2D-2 time step as a CFL number on the 1.5 m/s peak")  # fmt: skip
    args = ap.parse_args()
    only, methods = set(args.only), args.methods
    towed: dict[tuple[str, int], dict[str, float]] = {}
    if "towed" in only:
        print(
            "| method | cells | D/h | drag HF RMS % | drag jump % | lift RMS % | lift jump % | step ms |"
        )
        print("|---|---|---|---|---|---|---|---|")
        for cells in args.cells:
            for m in methods:
                r = towed[m, cells] = towed_disk(m, cells, args.steps)
                print(f"| {m} | {cells} | {r['dh']:.1f} | {r['drag_rms']:.2f} | "
                      f"{r['drag_jump']:.2f} | {r['lift_rms']:.2f} | {r['lift_jump']:.2f} | "
                      f"{r['step_ms']:.2f} |", flush=True)  # fmt: skip
    if "sphere" in only:
        for m in methods:
            r = _timed("sphere", towed_sphere, m)
            print(f"sphere a/h {r['ah']:.1f} {m}: drag HF RMS {r['drag_rms']:.2f} %, jump "
                  f"{r['drag_jump']:.2f} %; lift RMS {r['lift_rms']:.2f} %, jump "
                  f"{r['lift_jump']:.2f} %; step {r['step_ms']:.1f} ms", flush=True)  # fmt: skip
    if "st" in only:
        for m in methods:
            cd = _timed("st", schaefer_turek_2d1, m, args.dh)
            print(f"ST 2D-1 D/h {args.dh} {m}: c_D {cd:.4f} ({100 * (cd / 5.5795 - 1):+.2f} %)",
                  flush=True)  # fmt: skip
    if "st2" in only:
        for m in methods:
            r = _timed("st2", schaefer_turek_2d2, m, args.dh2, args.t2, args.cfl2)
            print(f"ST 2D-2 D/h {args.dh2} {m} (dt {r['dt']:.4g}, t {args.t2:g} s): St "
                  f"{r['st']:.4f}, c_D max {r['cd_max']:.4f}, c_L max {r['cl_max']:.4f} "
                  f"({r['periods']} periods; c_L max 3 s earlier {r['cl_max_before']:.4f})", flush=True)  # fmt: skip
    if "couette" in only:
        for m in methods:
            print(f"Couette torque 64^2 {m}: {couette(m):+.2f} %", flush=True)
    if "stokes" in only:
        for m in methods:
            a, b = stokes(m)
            print(f"Stokes drag ratio 2x nu {m}: same nu dt/h^2 {a:.3f}, same dt {b:.3f}",
                  flush=True)  # fmt: skip
    if "cost" in only:
        ms = step_cost(methods, args.cost_cells)
        line = ", ".join(f"{m} {v:.2f} ms" for m, v in ms.items())
        ratio = ms["cutcell"] / ms["staircase"] if len(ms) == 2 else float("nan")
        print(f"step cost, towed disk {args.cost_cells}^2, median of warm steps: {line}; cut/staircase "
              f"{ratio:.2f}", flush=True)  # fmt: skip
    if "sweep" in only:
        runs = [(m, SolverSettings.corner_radius_cells) for m in methods]
        if "cutcell" in methods:  # the other corner setting too
            runs.append(
                ("cutcell", ROUNDED_CELLS if not SolverSettings.corner_radius_cells else 0.0)
            )
        for m, radius in runs:
            r = _timed("sweep", sweep, m, radius)
            corners = ("" if m != "cutcell" else
                       f", corners rounded by {radius:g} cell" if radius else ", sharp corners")  # fmt: skip
            print(f"sweep 64^2 {m}{corners}: force noise {r['force_noise']:.4f}, torque noise "
                  f"{r['torque_noise']:.4f}", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
