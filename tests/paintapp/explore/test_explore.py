"""Exploring stored flows: files in and out, the probe's force against the solver's, the command."""

from __future__ import annotations

import json
import tomllib

import numpy as np
import pytest

from common.errors import InputError
from paintapp.cli import main
from paintapp.explore.exploration import Exploration, ProbeSpec
from paintapp.explore.flow_export import FlowFrames, write_flow_npz, write_flow_vti
from paintapp.explore.flow_files import FluidOverrides, load_flow
from paintapp.explore.force_trace import read_explore_forces_csv
from paintapp.resources import asset_path
from solver.scenes.scene import parse_scene


@pytest.fixture(scope="module")
def channel_flow():
    """The Schaefer-Turek 2D-1 cylinder at D/h = 20 in a shortened channel, 1 s of flow: a body
    at rest in a stored result."""
    data = tomllib.loads(
        asset_path("scenes", "schaefer_turek_2d1.toml").read_text(encoding="utf-8")
    )
    data["domain"] = {"size": [0.8, 0.41], "cells": [160, 82]}
    data["solver"]["force_model"] = "stress"
    data["run"] = {"dt": 0.01, "duration": 1.0}
    data.pop("output", None)
    scene = parse_scene(data, "st")
    sim = scene.build()
    for _ in range(100):
        sim.step(0.01)
    frames = FlowFrames.start(sim)
    frames.add(sim)
    return sim, frames


@pytest.mark.slow
def test_the_probe_feels_what_the_solver_computed_for_a_body_at_rest_there(tmp_path, channel_flow):
    """Round trip through both file formats. Measured: pressure drag 4.9 % and total drag 11 %
    below the (staircase) solver's; the stored grid samples the wall's shear layer with one
    node per 0.05 D, so the viscous part is the one that differs (22 % low)."""
    sim, frames = channel_flow
    solver = sim.forces["cylinder"]
    solver_force = solver.force
    write_flow_npz(tmp_path / "flow.npz", frames)
    write_flow_vti(tmp_path / "flow.vti", frames)
    for name in ("flow.npz", "flow.vti"):
        flow = load_flow([tmp_path / name])
        assert flow.dim == 2 and flow.nodes == (160, 82)
        probe = Exploration(flow, ProbeSpec("circle", (0.1,), depth_m=1.0))
        felt = probe.force_at(0.0, np.array([0.2, 0.2]), 0.0)
        # the same drag within the two boundary treatments' difference (a staircase solver
        # against the smooth surface), and hardly any lift in this symmetric flow
        assert felt.pressure_force[0] == pytest.approx(solver.pressure_force[0], rel=0.07)
        assert felt.force[0] == pytest.approx(solver_force[0], rel=0.15)
        assert abs(felt.force[1]) < 0.03 * abs(felt.force[0])
        assert felt.outside_fraction == 0.0


def test_npz_series_is_read_with_its_times_and_units(tmp_path):
    n = 6
    p = np.stack([np.full((n, n), 1.0), np.full((n, n), 3.0)])
    u = np.zeros((2, 2, n, n))
    np.savez(tmp_path / "s.npz", p=p, u=u, origin=[0, 0], spacing=[0.1, 0.1],
             density=2.0, viscosity=1e-3, times=[0.0, 1.0], pressure_units="m2/s2")  # fmt: skip
    flow = load_flow([tmp_path / "s.npz"])
    assert flow.times_s.tolist() == [0.0, 1.0]
    assert flow.pressure_pa[1, 0, 0] == pytest.approx(6.0)  # kinematic * density


@pytest.mark.parametrize(
    ("change", "field", "message"),
    [
        ({"p": None}, "p", "missing field"),
        ({"density": None}, "density", "does not state"),
        ({"viscosity": None}, "viscosity", "does not state"),
        ({"density": -1.0}, "density", "> 0"),
        ({"spacing": [0.1, 0.0]}, "spacing", "> 0"),
        ({"u": np.zeros((3, 6, 6))}, "u", "expected p of shape"),
        ({"p": np.full((6, 6), np.nan)}, "p", "non-finite"),
        ({"times": [0.0, 1.0]}, "times", "expected 1 frame"),
        ({"pressure_units": "bar"}, "pressure_units", "expected one of"),
        ({"extra": 1}, "extra", "unknown key"),
    ],
)
def test_malformed_npz_names_the_field(tmp_path, change, field, message):
    arrays = {"p": np.zeros((6, 6)), "u": np.zeros((2, 6, 6)), "origin": [0, 0],
              "spacing": [0.1, 0.1], "density": 1.0, "viscosity": 1e-3}  # fmt: skip
    for k, v in change.items():
        if v is None:
            arrays.pop(k)
        else:
            arrays[k] = v
    np.savez(tmp_path / "bad.npz", **arrays)
    with pytest.raises(InputError) as err:
        load_flow([tmp_path / "bad.npz"])
    assert err.value.key == field and message in str(err.value)
    assert str(tmp_path / "bad.npz") in str(err.value)


def test_truncated_and_foreign_files_are_refused(tmp_path):
    good = tmp_path / "g.npz"
    np.savez(good, p=np.zeros((4, 4)), u=np.zeros((2, 4, 4)), origin=[0, 0], spacing=[1, 1],
             density=1.0, viscosity=1.0)  # fmt: skip
    cut = tmp_path / "cut.npz"
    cut.write_bytes(good.read_bytes()[: good.stat().st_size // 2])
    junk = tmp_path / "junk.vti"
    junk.write_text("<VTKFile> not really", encoding="utf-8")
    for path, what in ((cut, "not a readable .npz"), (junk, "not a readable VTK"),
                       (tmp_path / "none.npz", "no such file"), (good.with_suffix(".h5"), "no such")):  # fmt: skip
        with pytest.raises(InputError, match=what):
            load_flow([path])
    pickled = tmp_path / "obj.npz"
    np.savez(pickled, p=np.array([{"a": 1}], dtype=object), u=np.zeros(2), origin=[0, 0],
             spacing=[1, 1], density=1.0, viscosity=1.0)  # fmt: skip
    with pytest.raises(InputError, match="not a readable"):
        load_flow([pickled])


def test_nan_inside_a_marked_body_never_reaches_the_force(tmp_path):
    n = 21
    p = np.zeros((n, n))
    u = np.zeros((2, n, n))
    fluid = np.ones((n, n), dtype=bool)
    fluid[8:13, 8:13] = False
    p[~fluid] = np.nan
    u[:, ~fluid] = np.nan
    np.savez(tmp_path / "body.npz", p=p, u=u, origin=[0, 0], spacing=[0.05, 0.05], density=1.0,
             viscosity=1e-3, fluid=fluid)  # fmt: skip
    flow = load_flow([tmp_path / "body.npz"])
    probe = Exploration(flow, ProbeSpec("circle", (0.3,)))
    for x in np.linspace(0.0, 1.0, 11):
        r = probe.force_at(0.0, np.array([x, 0.5]), 0.0)
        assert np.all(np.isfinite(r.force)) and np.isfinite(r.torque)
    np.savez(tmp_path / "nomask.npz", p=p, u=u, origin=[0, 0], spacing=[0.05, 0.05],
             density=1.0, viscosity=1e-3)  # fmt: skip
    with pytest.raises(InputError, match="non-finite"):
        load_flow([tmp_path / "nomask.npz"])


def test_scripted_exploration_writes_a_finite_force_trace(tmp_path):
    n = 21
    x = np.meshgrid(np.arange(n) * 0.05, np.arange(n) * 0.05, indexing="ij")[0]
    p = 100.0 * x  # a pressure gradient of 100 Pa/m along x
    np.savez(tmp_path / "grad.npz", p=p, u=np.zeros((2, n, n)), origin=[0, 0],
             spacing=[0.05, 0.05], density=1000.0, viscosity=1e-3)  # fmt: skip
    path = tmp_path / "path.csv"
    path.write_text("t_s,x_m,y_m\n0,0.3,0.5\n1,0.7,0.5\n", encoding="utf-8")
    out = tmp_path / "forces.csv"
    args = ["explore", str(tmp_path / "grad.npz"), "--path", str(path), "--forces", str(out),
            "--size", "0.2", "--depth", "0.1", "--force-scale", "1"]  # fmt: skip
    assert main(args) == 0
    trace, fluid = read_explore_forces_csv(out)
    assert len(trace) > 900 and len(fluid) == len(trace) and np.all(np.isfinite(trace))
    # the force settles at -grad p * area * depth = -100 * pi 0.01 * 0.1 N
    settled = trace[(trace[:, 0] > 0.6) & (trace[:, 0] < 0.95)]
    assert settled[:, 1].mean() == pytest.approx(-100 * np.pi * 0.01 * 0.1, rel=0.02)
    assert np.all(np.abs(settled[:, 2]) < 1e-6)


@pytest.mark.parametrize(
    ("path_text", "message"),
    [
        ("t_s,x_m\n0,1\n", "'y_m': missing column"),
        ("t_s,x_m,y_m\n0,1,nan\n", "finite"),
        ("t_s,x_m,y_m\n1,0,0\n0,0,0\n", "backwards"),
        ("t_s,x_m,y_m,w\n0,0,0,1\n", "unknown column"),
        ("t_s,x_m,y_m\n0,0\n", "expected 3 values"),
        ("", "empty"),
    ],
)
def test_a_bad_path_is_a_clear_error(tmp_path, capsys, path_text, message):
    np.savez(tmp_path / "f.npz", p=np.zeros((4, 4)), u=np.zeros((2, 4, 4)), origin=[0, 0],
             spacing=[1, 1], density=1.0, viscosity=1.0)  # fmt: skip
    (tmp_path / "p.csv").write_text(path_text, encoding="utf-8")
    assert main(["explore", str(tmp_path / "f.npz"), "--path", str(tmp_path / "p.csv")]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


def test_the_bundled_example_loads_and_is_unsteady():
    flow = load_flow([asset_path("flows", "schaefer_turek_2d2.npz")], FluidOverrides())
    assert flow.dim == 2 and len(flow.times_s) >= 10
    probe = Exploration(flow, ProbeSpec("circle", (0.1,), depth_m=0.1))
    lifts = [probe.force_at(t, np.array([0.6, 0.2]), 0.0).force[1] for t in flow.times_s]
    assert np.ptp(lifts) > 0.0 and np.all(np.isfinite(lifts))
    json.dumps([float(v) for v in lifts])
    # the frames cover one shedding period: looping it is seamless (no jump at the wrap)
    assert flow.period_s is not None
    t0, step = float(flow.times_s[0]), 0.002
    ts = t0 + flow.period_s + np.arange(-0.05, 0.05, step)
    fy = np.array([probe.force_at(t, np.array([0.6, 0.2]), 0.0).force[1] for t in ts])
    assert np.abs(np.diff(fy)).max() < 0.05 * np.ptp(lifts)


def test_explore_outputs_are_checked_before_any_work(tmp_path, capsys):
    np.savez(tmp_path / "f.npz", p=np.zeros((4, 4)), u=np.zeros((2, 4, 4)), origin=[0, 0],
             spacing=[1, 1], density=1.0, viscosity=1.0)  # fmt: skip
    (tmp_path / "p.csv").write_text("t_s,x_m,y_m\n0,1,1\n1,2,2\n", encoding="utf-8")
    base = ["explore", str(tmp_path / "f.npz"), "--path", str(tmp_path / "p.csv")]
    assert main([*base, "--forces", str(tmp_path)]) == 2
    assert "is an existing folder" in capsys.readouterr().err
    same = str(tmp_path / "out.csv")
    assert main([*base, "--forces", same, "--plot", same]) == 2
    assert "its own file" in capsys.readouterr().err
    assert main(["explore", str(tmp_path / "f.npz"), "--forces", same]) == 2
    assert "needs a scripted --path" in capsys.readouterr().err
    assert not (tmp_path / "out.csv").exists()
