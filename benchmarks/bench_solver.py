"""Time a full solver step, and each sub-step, with a moving probe.

Grids: 2D 64x64 and 128x128, 3D 32^3 and 64^3; a box probe sweeps through the fluid while
spinning (the paper's setting: unit domain, Re ~ 1000). Prints the median over many steps
(after a warm-up that compiles the kernels) and the PCG iterations.

    python benchmarks/bench_solver.py [--steps N] [--only 2d|3d]
"""

from __future__ import annotations

import argparse
import statistics
import sys

import numpy as np
from tqdm import tqdm

from solver.grid import Grid
from solver.probes import Probe
from solver.shapes import Box
from solver.simulation import Fluid, Simulation, SolverSettings

CASES = [("2D 64x64", 2, 64), ("2D 128x128", 2, 128), ("3D 32^3", 3, 32), ("3D 64^3", 3, 64)]


def make(dim: int, n: int, advection: str) -> Simulation:
    grid = Grid.from_size((1.0,) * dim, (n,) * dim)
    size = (0.12,) * dim
    if dim == 2:
        probe = Probe("box", Box(size), 2, np.array([0.3, 0.5]), 0.0, np.array([0.8, 0.2]), 3.0)
    else:
        probe = Probe(
            "box",
            Box(size),
            3,
            np.array([0.3, 0.5, 0.5]),
            None,
            np.array([0.8, 0.2, 0.1]),
            np.array([0.0, 0.0, 3.0]),
        )
    settings = SolverSettings(advection=advection, pressure_tolerance=1e-5)
    return Simulation(grid, Fluid(1.0, 1e-3), probes=[probe], settings=settings)


def bench(dim: int, n: int, steps: int, advection: str) -> dict[str, float]:
    sim = make(dim, n, advection)
    dt = 0.5 / n  # the probe moves ~0.4 cells per step
    for _ in range(3):
        sim.step(dt)
    rows = []
    for _ in tqdm(range(steps), desc=f"{dim}D {n}", leave=False, file=sys.stderr, disable=None):
        rows.append(sim.step(dt))
    out = {"step": statistics.median(r.step_ms for r in rows)}
    for key in rows[0].substep_ms:
        out[key] = statistics.median(r.substep_ms[key] for r in rows)
    out["pcg_it"] = statistics.median(r.pressure.iterations for r in rows)
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=200, help="timed steps for 2D (3D: fewer)")
    parser.add_argument("--only", choices=["2d", "3d"])
    parser.add_argument("--advection", default="linear", choices=["linear", "maccormack"])
    args = parser.parse_args()
    cols = ["step", "advect", "boundaries", "viscosity", "projection", "forces"]
    print(f"median milliseconds per step ({args.advection} advection, moving spinning box)")
    print(f"{'grid':<12}" + "".join(f"{c:>12}" for c in cols) + f"{'PCG it':>8}")
    for name, dim, n in CASES:
        if args.only and args.only != f"{dim}d":
            continue
        steps = args.steps if dim == 2 else max(5, args.steps // (4 if n <= 32 else 20))
        r = bench(dim, n, steps, args.advection)
        print(f"{name:<12}" + "".join(f"{r[c]:>12.3f}" for c in cols) + f"{r['pcg_it']:>8.0f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
