"""Time a full solver step, and each sub-step, with a moving probe; or, with ``--peer``, our step
against PhiFlow's on one scene.

Grids: 2D 64x64 and 128x128, 3D 32^3 and 64^3; a box probe 0.12 m a side sweeps back and forth
through the fluid between x = 0.3 and 0.7 m at 0.8 m/s while spinning at 3 rad/s (the paper's
setting: unit domain, Re ~ 100), 0.4 cells a step, and stays inside for every step timed.
Prints the median over many steps (after a warm-up that compiles the kernels) and the PCG
iterations.

``--peer``: PhiFlow 3.4 with its JAX backend (``phiflow_peer.py``) and our solver on the same
scene, 2D 64x64 and 128x128: a 0.1 m square box moving at 0.5 m/s back and forth between
x = 0.3 and 0.7 m (y = 0.5 m) in a closed unit box, nu = 0.01 m^2/s, density 1, dt = 1/60 s,
pressure to a relative residual of 1e-5. The two steps are timed alternately, in rounds whose
order alternates, each step waited for; prints both medians, their ratio (PhiFlow / ours: above 1,
ours is faster), the iterations of the solves, and a check that the two runs are comparable (the
distance the boxes travelled, the fluid's kinetic energy at the end). It takes minutes, compiles
JAX and needs PhiFlow, which is no dependency of the package: not part of the default run.

    python benchmarks/bench_solver.py [--steps N] [--only 2d|3d] [--advection linear|maccormack]
    ~/phiflow-venv/bin/python benchmarks/bench_solver.py --peer [--steps N] [--rounds R]
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import os
import statistics
import sys
import time

import numpy as np
from tqdm import tqdm

from solver import MAX_THREADS, Box, Fluid, Grid, Probe, Simulation, SolverSettings

CASES = [("2D 64x64", 2, 64), ("2D 128x128", 2, 128), ("3D 32^3", 3, 32), ("3D 64^3", 3, 64)]

PEER_CASES = [("2D 64x64", 64), ("2D 128x128", 128)]
PEER_BOX_M = 0.1
PEER_SPEED_M_S = 0.5
PEER_X_M = (0.3, 0.7)  # the box's centre moves back and forth between these, at y = 0.5
PEER_NU_M2_S = 0.01
PEER_DT_S = 1.0 / 60.0
PEER_TOLERANCE = 1e-5
PEER_WARMUP = 3  # PhiFlow traces twice (the first state differs in structure), then compiled
PEER_INSTALL = (
    "--peer needs PhiFlow and JAX, not importable here; from the repository root: "
    "python3 -m venv ~/phiflow-venv && ~/phiflow-venv/bin/pip install phiflow==3.4.0 jax && "
    "~/phiflow-venv/bin/pip install -e . && "
    "~/phiflow-venv/bin/python benchmarks/bench_solver.py --peer"
)


BENCH_X_M = (0.3, 0.7)  # the box's centre moves back and forth between these
BENCH_SPEED_M_S = 0.8
BENCH_SPIN_RAD_S = 3.0
BENCH_KEY_S = 0.05  # keyframe spacing (a slerp between keyframes turns at most 0.15 rad)


def bench_path(dim: int, duration_s: float) -> np.ndarray:
    """Keyframes ``[t, position, angle or quaternion]`` of the benchmark's box: back and forth
    along x between ``BENCH_X_M`` at ``BENCH_SPEED_M_S`` (the rest of the centre at 0.5 m),
    spinning about z at ``BENCH_SPIN_RAD_S``, for ``duration_s`` seconds and a keyframe more; the
    turning points are keyframes, so the linear path is exact."""
    leg_s = (BENCH_X_M[1] - BENCH_X_M[0]) / BENCH_SPEED_M_S
    times = np.arange(0.0, duration_s + 2 * BENCH_KEY_S, BENCH_KEY_S)
    turns = np.arange(leg_s, times[-1], leg_s)
    rows = []
    for t in np.unique(np.concatenate([times, turns])):
        phase = (t / leg_s) % 2.0
        x = BENCH_X_M[0] + (BENCH_X_M[1] - BENCH_X_M[0]) * (phase if phase <= 1.0 else 2.0 - phase)
        angle = BENCH_SPIN_RAD_S * t
        if dim == 2:
            rows.append([t, x, 0.5, angle])
        else:
            rows.append([t, x, 0.5, 0.5, math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2)])
    return np.array(rows)


def make(
    dim: int, n: int, advection: str, duration_s: float = 10.0, threads: int = 0
) -> Simulation:
    """The benchmark's scene on an ``n``-cell-a-side unit box: a box probe, 0.12 m a side, on
    :func:`bench_path` for ``duration_s``; nu = 1e-3 m^2/s, pressure to 1e-5."""
    grid = Grid.from_size((1.0,) * dim, (n,) * dim)
    path = bench_path(dim, duration_s)
    probe = Probe("box", Box((0.12,) * dim), dim, path[0, 1 : 1 + dim].copy(), path=path)
    settings = SolverSettings(advection=advection, pressure_tolerance=1e-5, threads=threads)
    return Simulation(grid, Fluid(1.0, 1e-3), probes=[probe], settings=settings)


def bench(dim: int, n: int, steps: int, advection: str, threads: int = 0) -> dict[str, float]:
    dt = 0.5 / n  # the probe moves 0.4 cells per step
    sim = make(dim, n, advection, (steps + 3) * dt, threads)
    for _ in range(3):
        sim.step(dt)
    rows = []
    for _ in tqdm(range(steps), desc=f"{dim}D {n}", leave=False, file=sys.stderr, disable=None):
        rows.append(sim.step(dt))
    out = {"step": statistics.median(r.step_ms for r in rows)}
    for key in rows[0].substep_ms:
        out[key] = statistics.median(r.substep_ms[key] for r in rows)
    out["pcg_it"] = statistics.median(r.pressure.iterations for r in rows)
    out["threads"] = sim.component_threads()
    return out


# -- --peer: our step against PhiFlow's ------------------------------------------------------------
def peer_keyframes(duration_s: float) -> np.ndarray:
    """The box's path, rows ``[t, x, y, angle]``: legs between ``PEER_X_M`` at ``PEER_SPEED_M_S``
    (0.8 s, 48 steps of 1/60 s each), enough of them to cover ``duration_s``."""
    leg_s = (PEER_X_M[1] - PEER_X_M[0]) / PEER_SPEED_M_S
    legs = math.ceil(duration_s / leg_s) + 1
    return np.array([[k * leg_s, PEER_X_M[k % 2], 0.5, 0.0] for k in range(legs + 1)])


def make_peer(n: int, keyframes: np.ndarray) -> Simulation:
    grid = Grid.from_size((1.0, 1.0), (n, n))
    probe = Probe("box", Box((PEER_BOX_M, PEER_BOX_M)), 2, keyframes[0, 1:3].copy(), path=keyframes)
    settings = SolverSettings(pressure_tolerance=PEER_TOLERANCE)
    return Simulation(grid, Fluid(1.0, PEER_NU_M2_S), probes=[probe], settings=settings)


def peer_available() -> bool:
    return all(importlib.util.find_spec(name) is not None for name in ("phi", "jax"))


def bench_peer(n: int, steps: int, rounds: int) -> dict[str, float]:
    """Our step and PhiFlow's on the same scene, ``rounds`` rounds of ``steps`` steps each,
    alternating which goes first. Milliseconds are wall clock per step."""
    import phiflow_peer

    keyframes = peer_keyframes((PEER_WARMUP + rounds * steps + 1) * PEER_DT_S)
    ours = make_peer(n, keyframes)
    peer = phiflow_peer.PeerScene(
        n,
        keyframes,
        PEER_BOX_M,
        PEER_NU_M2_S,
        PEER_DT_S,
        PEER_TOLERANCE,
        ours.settings.viscosity_tolerance,
    )
    probe = ours.probes[0]
    travel = {"ours": 0.0, "peer": 0.0}
    ms: dict[str, list[float]] = {"ours": [], "peer": []}
    round_ms: dict[str, list[float]] = {"ours": [], "peer": []}
    pressure_it: list[int] = []
    viscosity_it: list[float] = []

    def ours_step() -> float:
        c0 = probe.centre_m.copy()
        t0 = time.perf_counter()
        stats = ours.step(PEER_DT_S)
        t1 = time.perf_counter()
        travel["ours"] += float(np.linalg.norm(probe.centre_m - c0))
        pressure_it.append(stats.pressure.iterations)
        viscosity_it.append(statistics.mean(r.iterations for r in stats.viscosity))
        return 1e3 * (t1 - t0)

    def peer_step() -> float:
        c0 = peer.centre_m.copy()
        t0 = time.perf_counter()
        peer.step()
        t1 = time.perf_counter()
        travel["peer"] += float(np.linalg.norm(peer.centre_m - c0))
        return 1e3 * (t1 - t0)

    run = {"ours": ours_step, "peer": peer_step}
    for _ in range(PEER_WARMUP):
        ours_step()
        peer_step()
    pressure_it.clear()
    viscosity_it.clear()
    bar = tqdm(
        total=2 * rounds * steps, desc=f"peer {n}", leave=False, file=sys.stderr, disable=None
    )
    for r in range(rounds):
        for side in ("ours", "peer") if r % 2 == 0 else ("peer", "ours"):
            times = [run[side]() for _ in range(steps)]
            bar.update(steps)
            ms[side] += times
            round_ms[side].append(statistics.median(times))
    bar.close()
    peer_visc_x, peer_visc_y, peer_pressure = peer.solve_iterations()
    return {
        "ours": statistics.median(ms["ours"]),
        "peer": statistics.median(ms["peer"]),
        "ours_lo": min(round_ms["ours"]),
        "ours_hi": max(round_ms["ours"]),
        "peer_lo": min(round_ms["peer"]),
        "peer_hi": max(round_ms["peer"]),
        "ours_p_it": statistics.median(pressure_it),
        "ours_v_it": statistics.median(viscosity_it),
        "peer_p_it": peer_pressure,
        "peer_v_it": 0.5 * (peer_visc_x + peer_visc_y),
        "ours_travel": travel["ours"],
        "peer_travel": travel["peer"],
        "ours_x": float(probe.centre_m[0]),
        "peer_x": float(peer.centre_m[0]),
        "ours_ke": ours.kinetic_energy(),
        "peer_ke": peer.kinetic_energy(),
        "time_s": ours.time_s,
    }


def main_peer(steps: int, rounds: int) -> int:
    if not peer_available():
        print(PEER_INSTALL)
        return 0
    import phiflow_peer

    load = " ".join(f"{x:.2f}" for x in os.getloadavg())
    print(
        f"ours vs {phiflow_peer.versions()} (float64, jit-compiled step); {os.cpu_count()} CPUs, "
        f"load average {load}"
    )
    print(
        f"box {PEER_BOX_M} m at {PEER_SPEED_M_S} m/s back and forth in a closed unit box, "
        f"nu {PEER_NU_M2_S} m^2/s, dt 1/{round(1 / PEER_DT_S)} s, pressure to {PEER_TOLERANCE:g}; "
        f"{rounds} alternating rounds of {steps} steps"
    )
    head = ["ours ms", "PhiFlow ms", "ratio", "ours it p/v", "PhiFlow it p/v"]
    print(f"{'grid':<12}" + "".join(f"{h:>16}" for h in head))
    for name, n in PEER_CASES:
        r = bench_peer(n, steps, rounds)
        cells = [
            f"{r['ours']:.2f}",
            f"{r['peer']:.2f}",
            f"{r['peer'] / r['ours']:.2f}",
            f"{r['ours_p_it']:.0f}/{r['ours_v_it']:.0f}",
            f"{r['peer_p_it']:.0f}/{r['peer_v_it']:.0f}",
        ]
        print(f"{name:<12}" + "".join(f"{c:>16}" for c in cells))
        print(
            f"{'':<12}rounds' medians: ours {r['ours_lo']:.2f}-{r['ours_hi']:.2f}, PhiFlow "
            f"{r['peer_lo']:.2f}-{r['peer_hi']:.2f} ms; after {r['time_s']:.2f} s the boxes "
            f"travelled {r['ours_travel']:.3f} / {r['peer_travel']:.3f} m to x = "
            f"{r['ours_x']:.3f} / {r['peer_x']:.3f} m; fluid kinetic energy {r['ours_ke']:.3e} / "
            f"{r['peer_ke']:.3e} J/m (PhiFlow / ours {r['peer_ke'] / r['ours_ke']:.2f})"
        )
    load = " ".join(f"{x:.2f}" for x in os.getloadavg())
    print(f"load average at the end {load}")
    return 0


def thread_setting(text: str) -> int:
    """``--threads``: a whole number in [0, MAX_THREADS] (0: auto)."""
    try:
        value = int(text)
    except ValueError:
        value = -1
    if not 0 <= value <= MAX_THREADS:
        raise argparse.ArgumentTypeError(
            f"expected a whole number in [0, {MAX_THREADS}] (0: auto), got {text!r}"
        )
    return value


def positive_int(text: str) -> int:
    """An argument that must be a whole number of at least 1."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got {text!r}")
    return value


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--steps",
        type=positive_int,
        help="timed steps for 2D (default 200; 3D: fewer); with --peer, steps per round (48)",
    )
    parser.add_argument("--only", choices=["2d", "3d"])
    parser.add_argument("--advection", default="linear", choices=["linear", "maccormack"])
    parser.add_argument(
        "--peer", action="store_true", help="our step against PhiFlow 3.4's (JAX) on one scene"
    )
    parser.add_argument("--rounds", type=positive_int, default=5,
                        help="with --peer: rounds per solver")  # fmt: skip
    parser.add_argument("--threads", type=thread_setting, default=0,
                        help="threads for the velocity components (default 0: auto; 1: one)")  # fmt: skip
    args = parser.parse_args()
    if args.peer:
        return main_peer(args.steps or 48, args.rounds)
    steps_2d = args.steps or 200
    cols = ["step", "advect", "boundaries", "viscosity", "projection", "forces"]
    print(f"median milliseconds per step ({args.advection} advection, moving spinning box)")
    print(f"{'grid':<12}" + "".join(f"{c:>12}" for c in cols) + f"{'PCG it':>8}{'threads':>9}")
    for name, dim, n in CASES:
        if args.only and args.only != f"{dim}d":
            continue
        steps = steps_2d if dim == 2 else max(5, steps_2d // (4 if n <= 32 else 20))
        r = bench(dim, n, steps, args.advection, args.threads)
        print(
            f"{name:<12}"
            + "".join(f"{r[c]:>12.3f}" for c in cols)
            + f"{r['pcg_it']:>8.0f}{r['threads']:>9.0f}"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
