"""Agreement with published reference solutions (slow: seconds to a minute each).

* Lid-driven cavity, Re = 100, against Ghia, Ghia & Shin (1982), at 128 x 128.
* Schaefer & Turek (1996) benchmark 2D-1 (cylinder in a channel, Re = 20), at D/h = 20.

Each tolerance is the value measured in the test's own configuration (noted beside it) with a
margin of about 1.3x, so a regression of a few tenths of a percent fails.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from paintapp.resources import asset_path
from solver.boundary import DomainBoundary, Side
from solver.grid import Grid
from solver.probes import Probe
from solver.scenes.runner import run_scene
from solver.scenes.scene import load_scene
from solver.shapes import Ball
from solver.simulation import Fluid, Simulation, SolverSettings

GHIA_U = {  # y: u along the vertical centreline x = 0.5
    0.9766: 0.84123, 0.9688: 0.78871, 0.9609: 0.73722, 0.9531: 0.68717, 0.8516: 0.23151,
    0.7344: 0.00332, 0.6172: -0.13641, 0.5000: -0.20581, 0.4531: -0.21090, 0.2813: -0.15662,
    0.1719: -0.10150, 0.1016: -0.06434, 0.0703: -0.04775, 0.0625: -0.04192, 0.0547: -0.03717,
}  # fmt: skip
GHIA_V = {  # x: v along the horizontal centreline y = 0.5
    0.9688: -0.05906, 0.9531: -0.08864, 0.9063: -0.16914, 0.8594: -0.22445, 0.8047: -0.24533,
    0.5000: 0.05454, 0.2344: 0.17527, 0.1563: 0.16077, 0.0938: 0.12317, 0.0625: 0.09233,
}  # fmt: skip


@pytest.mark.slow
def test_lid_driven_cavity_matches_ghia_at_128():
    scene = load_scene(asset_path("scenes", "lid_cavity_re100.toml"))
    scene.run = dataclasses.replace(scene.run, steps=2000)  # 20 s: steady to 1e-4
    result = run_scene(scene)
    line = result["lines"]["u_vertical_centreline"]
    pts, vel = np.array(line["points"]), np.array(line["velocity"])
    u = np.interp(list(GHIA_U), pts[:, 1], vel[:, 0])
    line = result["lines"]["v_horizontal_centreline"]
    pts, vel = np.array(line["points"]), np.array(line["velocity"])
    v = np.interp(list(GHIA_V), pts[:, 0], vel[:, 1])
    err_u = np.abs(u - np.array(list(GHIA_U.values()))).max()
    err_v = np.abs(v - np.array(list(GHIA_V.values()))).max()
    # 128 x 128, MacCormack, dt = 0.01 s, t = 20 s: measured 0.00241 and 0.00719
    assert err_u < 0.0032 and err_v < 0.0094


@pytest.mark.slow
def test_schaefer_turek_2d1_drag_and_pressure_difference():
    scene = load_scene(asset_path("scenes", "schaefer_turek_2d1.toml"))
    assert scene.settings.force_model == "stress"
    assert scene.settings.boundary_method == "cutcell"
    scene.run = dataclasses.replace(scene.run, steps=400)  # dt = 0.01 s, t = 4 s
    result = run_scene(scene)
    force = np.array(result["probes"]["cylinder"]["force"])
    scale = 2.0 / (1.0 * 0.2**2 * 0.1)  # 2 / (rho U_mean^2 D)
    c_d, c_l = scale * force[-1, 0], scale * force[-1, 1]
    # 440 x 82 (D/h = 20), cut-cell surface integral, measured at t = 4 s: c_D 5.5430 (-0.65 %),
    # changing by -5.8e-4 over the last 0.49 s; c_L 0.00792 (-25 %: the lift is 500 times smaller
    # than the drag, and the one figure here far from its reference; the staircase's control
    # volume gave 0.01035); dp 0.11386 (-3.1 %). The staircase surface integral was +7.7 % high.
    assert abs(scale * (force[-1, 0] - force[-50, 0])) < 1e-3  # steady
    assert c_d == pytest.approx(5.5795, rel=0.01)
    assert 0.5 * 0.010619 < c_l < 1.5 * 0.010619
    dp = result["points"]["front"]["pressure"] - result["points"]["back"]["pressure"]
    assert dp == pytest.approx(0.11752, rel=0.04)


@pytest.mark.slow
def test_schaefer_turek_2d2_sheds_vortices_within_2_percent_of_the_published_figures():
    """Benchmark 2D-2 (Re 100: parabolic inflow peaking at 1.5 m/s, U_mean 1 m/s), D/h 30 (660 x
    123), cut cells, MacCormack, dt = h / (7.5 m/s) (CFL 0.2 on the peak), t = 8 s; over the
    last 3 s. Published: St 0.295-0.305, c_D max 3.22-3.24, c_L max 0.99-1.01; the target is each
    within 2 % of its range. Measured: St 0.2965, c_D max 3.1865 (1.0 % below), c_L max 0.9714
    (1.9 % below: the closest). At CFL 0.25 c_L max saturates at 0.9702 (t = 10 s), 2.0 % below;
    at D/h 20 and CFL 0.5 the figures were 0.2866 / 3.258 / 0.926 (first-order time splitting:
    the Strouhal number rises as dt falls; c_L max grows with the resolution)."""
    grid = Grid.from_size((2.2, 0.41), (660, 123))
    sides = {"x_min": Side("inflow", (1.5, 0.0), "parabolic"), "x_max": Side("outflow")}
    probe = Probe("cylinder", Ball(0.05), 2, np.array([0.2, 0.2]))
    settings = SolverSettings(advection="maccormack")
    sim = Simulation(grid, Fluid(1.0, 1e-3), DomainBoundary(grid, sides), [probe], settings)
    dt = grid.cell_size_m / 7.5
    forces = []
    for _ in range(round(8.0 / dt)):
        sim.step(dt)
        forces.append(sim.forces["cylinder"].force.copy())
    c = 2.0 * np.array(forces)[-round(3.0 / dt) :] / (1.0**2 * 0.1)
    lift = c[:, 1] - c[:, 1].mean()
    low, armed, up = -0.3 * float(np.abs(lift).max()), False, []
    for i in range(len(lift) - 1):  # upward zero crossings, with hysteresis against jitter
        armed = armed or lift[i] < low
        if armed and lift[i] < 0 <= lift[i + 1]:
            up.append(i)
            armed = False
    t_up = (np.array(up) + lift[up] / (lift[up] - lift[np.array(up) + 1])) * dt
    strouhal = 0.1 / float(np.diff(t_up).mean())
    print(
        f"ST 2D-2 D/h 30: St {strouhal:.4f}, c_D max {c[:, 0].max():.4f}, c_L max {c[:, 1].max():.4f}"
    )
    assert len(t_up) >= 6
    assert 0.98 * 0.295 <= strouhal <= 1.02 * 0.305
    assert 0.98 * 3.22 <= c[:, 0].max() <= 1.02 * 3.24
    assert 0.98 * 0.99 <= c[:, 1].max() <= 1.02 * 1.01
