"""Model only what a scene requires: the solver skips work nothing needs, and says why."""

from __future__ import annotations

import numpy as np
import pytest

from paintapp.cli import main
from solver.boundary import Side
from solver.scenes.plan import Decision, explain, max_boundary_speed
from solver.simulation import SolverSettings


def _decisions(sim, dt: float = 0.01) -> dict[str, Decision]:
    return {d.topic: d for d in explain(sim, dt)}


def test_inviscid_fluid_takes_no_viscosity_solve(build):
    probe = build.circle(2, velocity=(0.5, 0.0), spin=2.0)
    sim = build.sim(16, 2, nu=0.0, probes=[probe])
    stats = [sim.step(0.01) for _ in range(3)]
    assert all(s.viscosity == () for s in stats)
    assert "no viscosity solve" in _decisions(sim)["viscosity"].chosen
    viscous = build.sim(16, 2, nu=1e-3, probes=[build.circle(2)])
    assert len(viscous.step(0.01).viscosity) == 2
    assert "2 diagonally preconditioned CG solves" in _decisions(viscous)["viscosity"].chosen
    thick = build.sim(16, 2, nu=10.0, probes=[build.circle(2)])  # 2 dim nu dt / h^2 = 102
    assert "2 MGPCG solves" in _decisions(thick)["viscosity"].chosen


def test_explain_names_the_probe_surfaces_and_the_pressure_solver(build):
    cut = _decisions(build.sim(16, 2, probes=[build.circle(2)]))
    assert cut["probe surfaces"].chosen.startswith("cut cells")
    assert "incremental" in cut["pressure"].chosen and "MGPCG" in cut["pressure"].chosen
    settings = SolverSettings(boundary_method="staircase", preconditioner="mic0")
    stair = _decisions(build.sim(16, 2, probes=[build.circle(2)], settings=settings))
    assert stair["probe surfaces"].chosen.startswith("staircase")
    assert "Chorin" in stair["pressure"].chosen and "MIC(0)" in stair["pressure"].chosen


def test_explain_says_where_each_solve_starts(build):
    cold = _decisions(build.sim(16, 2, probes=[build.circle(2)]))
    assert "each from the advected velocity" in cold["viscosity"].chosen
    assert "from a zero increment" in cold["pressure"].chosen
    warm = SolverSettings(warm_start=True)
    closed = _decisions(build.sim(16, 2, probes=[build.circle(2)], settings=warm))
    assert "each from the last step's solution" in closed["viscosity"].chosen
    assert "from a zero increment" in closed["pressure"].chosen  # the closed box's
    assert "starts cold" in closed["pressure"].reason
    opened = _decisions(build.sim(16, 2, probes=[build.circle(2)], settings=warm,
                                  sides={"y_max": Side("outflow")}))  # fmt: skip
    assert "from the last step's increment" in opened["pressure"].chosen
    chorin = SolverSettings(warm_start=True, pressure_scheme="chorin")
    last = _decisions(build.sim(16, 2, probes=[build.circle(2)], settings=chorin))
    assert "from the last pressure" in last["pressure"].chosen


def test_probe_forces_off_skips_the_force_work_and_leaves_the_flow_unchanged(build):
    def run(forces: bool):
        probe = build.box(velocity=(0.6, 0.2), spin=3.0)
        settings = SolverSettings(probe_forces=forces, force_model="control_volume")
        sim = build.sim(20, 2, nu=1e-3, probes=[probe], settings=settings)
        for _ in range(4):
            sim.step(0.01)
        return sim

    with_forces, without = run(True), run(False)
    assert "box" in with_forces.forces and without.forces == {}
    assert not without.computes_forces()
    assert without._previous is None  # no copy of the old state is kept for the balance
    for a in range(2):
        np.testing.assert_array_equal(with_forces.state.comps[a], without.state.comps[a])
    assert _decisions(without)["probe forces"].chosen == "not computed"
    assert _decisions(without)["torque"].chosen == "none"


def test_only_the_momentum_balance_keeps_the_previous_state(build):
    stress = build.sim(12, 2, probes=[build.circle(2)])
    stress.step(0.01)
    assert stress._previous is None
    balance = build.sim(
        12, 2, probes=[build.circle(2)], settings=SolverSettings(force_model="control_volume")
    )
    balance.step(0.01)
    assert balance._previous is not None


def test_no_probes_means_no_force_work(build):
    sim = build.sim(12, 2)
    sim.step(0.01)
    assert sim.forces == {} and not sim.computes_forces()
    d = _decisions(sim)
    assert d["probe forces"].chosen == "none" and "no probes" in d["probe forces"].reason


@pytest.mark.parametrize(
    ("model", "expected"),
    [("stress", "stress integral"), ("control_volume", "momentum balance"), ("drag", "rho")],
)
def test_force_model_and_torque_are_explained(build, model, expected):
    sim = build.sim(12, 2, probes=[build.circle(2)], settings=SolverSettings(force_model=model))
    d = _decisions(sim)
    assert expected in d["probe forces"].reason
    assert (d["torque"].chosen == "none") == (model == "drag")


def test_explain_reports_grid_advection_and_time_step(build):
    probe = build.circle(3, velocity=(2.0, 0.0, 0.0), radius=0.1, spin=10.0)
    sim = build.sim(8, 3, probes=[probe], settings=SolverSettings(advection="maccormack"))
    d = _decisions(sim, 0.1)
    assert d["grid"].chosen.startswith("3D 8x8x8 = 512 cells")
    assert "MacCormack" in d["advection"].chosen
    assert max_boundary_speed(sim) == pytest.approx(2.0 + 10.0 * 0.1)
    assert "2.4 cells per step" in d["time step"].reason  # 3 m/s * 0.1 s / 0.125 m


def test_simulate_explain_prints_each_decision_before_the_run(tmp_path, capsys):
    scene = tmp_path / "inviscid.toml"
    scene.write_text(
        '[domain]\nsize = [1.0, 1.0]\ncells = [8, 8]\n[fluid]\ndensity = 1.0\nviscosity = 0.0\n'
        '[run]\ndt = 0.01\nsteps = 2\n',
        encoding="utf-8",
    )  # fmt: skip
    assert main(["simulate", str(scene), "--explain"]) == 0
    out = capsys.readouterr().out
    for topic in ("grid", "time step", "advection", "viscosity", "pressure", "probe forces"):
        assert f"  {topic}: " in out
    assert "no viscosity solve" in out and "inviscid" in out
    assert out.index("viscosity:") < out.index("median step")
