"""The paper's square-probe sweep (Figs. 4-6) at any resolution, in 2D or as a 3D slab.

The bundled scene ``paper_square_sweep.toml`` (unit square, 64 x 64, Re ~ 1000) is re-gridded to
``cells`` per side; every other setting comes from the file unless overridden. The 3D variant
makes the domain a slab ``SLAB_DEPTH_M`` deep (no-slip walls all round) and the square a cube of
the same side at mid-depth, spinning about z: a brush tip in a thin layer rather than an infinite
prism, so its relative noise compares with the 2D run but its force (N, not N/m) does not.
"""

from __future__ import annotations

import tomllib
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from paintapp.bench.noise import DEFAULT_WINDOW_S, relative_noise, smooth
from paintapp.resources import asset_path
from solver import Scene, Simulation, StepStats, parse_scene

SCENE_FILE = "paper_square_sweep.toml"
PROBE = "square"
SLAB_DEPTH_M = 0.25
MOTION_END_S = 2.0  # the path's last move ends here; the probe rests after


@dataclass
class SweepTrace:
    """Forces recorded along one sweep, one row per step.

    Attributes:
        time_s: end time of each step, shape (n,).
        force: force in the xy plane, shape (n, 2) (2D: N/m; 3D: N).
        torque: torque about z, shape (n,) (2D: N m/m; 3D: N m).
        velocity: the probe's velocity over each step, shape (n, 2), m/s.
        omega: the probe's spin about z over each step, shape (n,), rad/s.
        stats: the solver's report of every step.
        dt_s: time step, s.
        cells: cells per axis.
    """

    time_s: np.ndarray
    force: np.ndarray
    torque: np.ndarray
    velocity: np.ndarray
    omega: np.ndarray
    stats: list[StepStats]
    dt_s: float
    cells: tuple[int, ...]

    def moving(self, fraction: float = 0.2) -> np.ndarray:
        """Mask of the steps where the speed exceeds ``fraction`` of its peak, shape (n,)."""
        speed = np.linalg.norm(self.velocity, axis=1)
        return speed > fraction * speed.max() if speed.max() > 0 else np.zeros(len(speed), bool)

    def components(self) -> tuple[np.ndarray, np.ndarray]:
        """Drag (along the motion; negative when it opposes it) and perpendicular force.

        Both shape (n,), NaN where the probe is at rest (no direction of motion). The
        perpendicular direction is the motion direction turned 90 degrees counter-clockwise.
        """
        speed = np.linalg.norm(self.velocity, axis=1)
        ok = speed > 1e-6 * max(speed.max(), 1e-300)
        tangent = np.full_like(self.velocity, np.nan)
        tangent[ok] = self.velocity[ok] / speed[ok, None]
        drag = np.sum(self.force * tangent, axis=1)
        perp = self.force[:, 1] * tangent[:, 0] - self.force[:, 0] * tangent[:, 1]
        return drag, perp


def sweep_scene(
    cells: int = 64,
    *,
    dim: int = 2,
    dt_s: float | None = None,
    solver: dict[str, Any] | None = None,
    duration_s: float | None = None,
) -> Scene:
    """The sweep scene on ``cells`` per side (3D: a slab ``cells/4`` deep), with ``solver`` keys
    (scene-file ``[solver]`` names) and the time step or duration overridden when given."""
    with open(asset_path("scenes", SCENE_FILE), "rb") as fh:
        data = tomllib.load(fh)
    data["domain"]["cells"] = [cells, cells]
    data["solver"].update(solver or {})
    if dt_s is not None:
        data["run"]["dt"] = dt_s
    if duration_s is not None:
        data["run"]["duration"] = duration_s
    if dim == 3:
        _extrude(data, cells)
    return parse_scene(data, f"{SCENE_FILE} ({dim}D, {cells} cells)")


def _extrude(data: dict, cells: int) -> None:
    """Turn the 2D sweep into a slab of depth ``SLAB_DEPTH_M`` with a cube probe spinning about z."""
    depth_cells = max(3, round(cells * SLAB_DEPTH_M))
    depth = depth_cells / cells
    data["domain"]["size"] = [1.0, 1.0, depth]
    data["domain"]["cells"] = [cells, cells, depth_cells]
    probe = data["probes"][0]
    side = probe["size"][0]
    probe["size"] = [side, side, side]
    probe["center"] = [*probe["center"], 0.5 * depth]
    probe["path"] = [
        [t, x, y, 0.5 * depth, float(np.cos(a / 2)), 0.0, 0.0, float(np.sin(a / 2))]
        for t, x, y, a in probe["path"]
    ]


def run_sweep(
    scene: Scene, on_step: Callable[[], None] | None = None, sim: Simulation | None = None
) -> SweepTrace:
    """Run the sweep scene to its end, recording force, torque and the probe's motion.

    ``sim`` may be a fresh ``scene.build()`` the caller keeps (e.g. to measure it afterwards).
    """
    sim = sim if sim is not None else scene.build()
    probe = sim.probes[0]
    n = scene.run.steps
    out = {k: np.zeros((n, 2)) for k in ("force", "velocity")}
    torque, omega, times = np.zeros(n), np.zeros(n), np.zeros(n)
    stats = []
    for i in range(n):
        stats.append(sim.step(scene.run.dt_s))
        times[i] = sim.time_s
        f = sim.forces.get(PROBE)
        if f is not None:
            out["force"][i] = f.force[:2]
            torque[i] = float(np.asarray(f.torque).reshape(-1)[-1])
        out["velocity"][i] = probe.velocity_m_s[:2]
        omega[i] = float(probe.omega3()[2])
        if on_step:
            on_step()
    cells = tuple(scene.grid.cells[: scene.grid.dim])
    return SweepTrace(
        times, out["force"], torque, out["velocity"], omega, stats, scene.run.dt_s, cells
    )


def sweep_summary(trace: SweepTrace, window_s: float = DEFAULT_WINDOW_S) -> dict[str, float]:
    """Noise and the signs of the forces along a sweep (all over the moving part, t <= 2 s).

    * ``force_noise``, ``torque_noise``: :func:`~paintapp.bench.noise.relative_noise` of the xy
      force and of the torque;
    * ``force_velocity_corr``: Pearson correlation of the smoothed force with the velocity (x and
      y components pooled) where the probe moves; negative when the fluid resists the motion;
    * ``torque_spin_corr``: the same for the smoothed torque and the spin;
    * ``opposing_fraction``: share of moving steps whose drag component is negative;
    * ``force_work_j``, ``torque_work_j``: work of the fluid force and torque on the probe,
      ``sum F.v dt`` and ``sum tau omega dt`` (J, per metre of depth in 2D); negative when the
      fluid takes energy from the probe.
    """
    dt = trace.dt_s
    on = trace.time_s <= MOTION_END_S + 1e-9
    moving = trace.moving()
    sf = smooth(trace.force, dt, window_s)
    st = smooth(trace.torque, dt, window_s)
    drag, _ = trace.components()
    return {
        "force_noise": relative_noise(trace.force[on], dt, window_s),
        "torque_noise": relative_noise(trace.torque[on], dt, window_s),
        "force_velocity_corr": _corr(sf[moving].ravel(), trace.velocity[moving].ravel()),
        "torque_spin_corr": _corr(st[moving], trace.omega[moving]),
        "opposing_fraction": float(np.mean(drag[moving] < 0)) if moving.any() else 0.0,
        "force_work_j": float(np.sum(trace.force * trace.velocity) * dt),
        "torque_work_j": float(np.sum(trace.torque * trace.omega) * dt),
    }


def _corr(a: np.ndarray, b: np.ndarray) -> float:
    if len(a) < 2 or np.std(a) == 0 or np.std(b) == 0:
        return 0.0
    return float(np.corrcoef(a, b)[0, 1])
