"""Model only what the scene requires: dry brush, air, auto model, outputs, grid fit, channels."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from brushes import StylusSample
from brushes.presets import load_preset_named
from common.errors import InputError
from paintapp.canvas.model import Canvas
from paintapp.cli import main
from paintapp.haptics.channel import ForceChannel
from paintapp.paint.fit import fit_grid, full_grid
from paintapp.paint.paint_scene import FULL_MODEL, ModelChoice, load_paint_scene, parse_paint_scene
from paintapp.resources import asset_path
from paintapp.session.painting import PaintingSession
from paintapp.session.playback import ServoForcePath
from paintapp.session.replay_devices import REPLAY_DEVICES
from tests.support.demo_strokes import StrokeSpec, stroke_samples

BLUE, YELLOW = "ultramarine_blue", "cadmium_yellow"
SMALL = dict(cells=(20, 20, 8), margin_cells=6)


def scene(name: str = "default", **choose) -> object:
    """A bundled scene on a small grid, with ``choose`` overrides."""
    s = load_paint_scene(name)
    return dataclasses.replace(s, **SMALL, choose=dataclasses.replace(s.choose, **choose))


def covered(thickness_m: float, pigments=(BLUE,)) -> Canvas:
    """A 24 mm canvas evenly covered with wet blue paint (other pigments as empty channels)."""
    paint = np.zeros((len(pigments), 96, 96), np.float32)
    paint[0] = thickness_m
    return Canvas((96, 96), (0.024, 0.024), pigments, paint, np.ones((96, 96), np.float32))


def stroke(duration_s: float = 0.2) -> list[StylusSample]:
    return stroke_samples(StrokeSpec((0.008, 0.012), (0.016, 0.012), duration_s, 0.9), 0.0)


def paint(session: PaintingSession, samples) -> list:
    return [session.sample(s) for s in samples]


def test_a_dry_brush_over_dry_canvas_takes_no_solver_steps_and_feels_nothing():
    canvas = Canvas((96, 96), (0.024, 0.024), (BLUE,))
    session = PaintingSession(canvas, "round_small", scene())
    steps = paint(session, stroke())
    assert session.stats.dry_steps > 5
    assert session.stats.solver_steps == 0 and session.stats.paint_steps == 0
    assert all(not np.any(s.force_n) for s in steps)
    assert not canvas.paint_m.any()
    assert any("touch-down: dry" in str(d) for d in session.decisions)


def test_the_fluid_starts_once_the_brush_holds_paint():
    canvas = Canvas((96, 96), (0.024, 0.024), (BLUE,))
    session = PaintingSession(canvas, "round_small", scene())
    samples = stroke(0.3)
    paint(session, samples[:6])
    assert session.stats.solver_steps == 0
    session.load_pigment(BLUE, 1e-8)
    paint(session, samples[6:])
    assert session.stats.solver_steps > 0 and canvas.paint_m.sum() > 0.0
    assert session.choices.switches == 1


def test_with_dry_brush_off_the_fluid_runs_for_a_dry_brush_too():
    canvas = Canvas((96, 96), (0.024, 0.024), (BLUE,))
    session = PaintingSession(canvas, "round_small", scene(dry_brush=False))
    paint(session, stroke())
    assert session.stats.dry_steps == 0 and session.stats.solver_steps > 5


def test_a_brush_in_the_air_takes_no_steps_and_is_counted():
    session = PaintingSession(covered(0.2e-3), "round_small", scene())
    air = [StylusSample(0.01 * i, np.array([0.01, 0.01, 0.0]), 0.0) for i in range(5)]
    paint(session, air)
    assert session.stats.air_samples == 5
    assert session.stats.solver_steps == 0 and not session.choices.steps


@pytest.mark.parametrize(("thickness_m", "model"), [(0.05e-3, "depth_averaged"), (1e-3, "grid3d")])
def test_auto_picks_depth_averaged_for_thin_paint_and_grid3d_for_thick(thickness_m, model):
    session = PaintingSession(covered(thickness_m), "round_small", scene("auto"))
    paint(session, stroke(0.15))
    assert set(session.choices.steps) == {model}
    assert session.model.name == model
    assert session.stats.solver_steps > 0


def test_auto_switches_with_hysteresis():
    canvas = covered(0.3e-3)  # between thin_below (0.2 mm) and thick_above (0.4 mm)
    session = PaintingSession(canvas, "round_small", scene("auto"))
    samples = stroke(0.6)
    paint(session, samples[:3])  # before the tip has carved its trough
    assert session.selector.plan.fluid == "grid3d"  # at touch-down: not thinner than 0.2 mm
    canvas.paint_m[0] = 0.1e-3  # thin: over to the depth-averaged grid
    paint(session, samples[3:14])
    assert session.selector.plan.fluid == "depth_averaged"
    canvas.paint_m[0] = 0.3e-3  # inside the band: stays
    paint(session, samples[14:20])
    assert session.selector.plan.fluid == "depth_averaged"
    canvas.paint_m[0] = 1e-3  # thick: back to 3D
    paint(session, samples[20:26])
    assert session.selector.plan.fluid == "grid3d"
    assert session.choices.switches == 2


@pytest.mark.parametrize("device", ["3dof", "tablet"])
def test_a_device_without_torque_gets_zero_torque_and_no_torque_work(device):
    info = REPLAY_DEVICES[device]
    channel = ForceChannel()
    session = PaintingSession(covered(0.3e-3), "flat_wide", scene(), forces=channel, device=info)
    steps = [s for s in paint(session, stroke()) if s.paint is not None]
    assert all(not np.any(s.torque_nm) for s in steps)
    assert not np.any(channel.latest()[1].torque)
    force_seen = any(np.any(s.force_n) for s in steps)
    assert force_seen == (device == "3dof")
    assert session.model.sim.settings.probe_forces == (device == "3dof")
    path = ServoForcePath(stroke(), ForceChannel(), info=info)
    assert path.servo.fluid.filter.dim == (3 if device == "3dof" else 6) or device == "tablet"


def test_a_six_dof_device_gets_torque():
    session = PaintingSession(covered(0.3e-3), "flat_wide", scene(), device=REPLAY_DEVICES["6dof"])
    steps = [s for s in paint(session, stroke()) if s.paint is not None]
    assert any(np.any(s.torque_nm) for s in steps)


def test_the_fitted_grid_follows_the_brush():
    s = load_paint_scene("auto")
    texel = 0.12 / 480
    large = load_preset_named("round_large", asset_path("brushes"))
    small = load_preset_named("round_small", asset_path("brushes"))
    upright = fit_grid(s, large, texel, "grid3d", 0.0)
    leaning = fit_grid(s, large, texel, "grid3d", 0.8)
    assert upright.cells[0] < s.cells[0] and upright.cells[2] < s.cells[2]  # smaller than full
    assert leaning.cells[0] > upright.cells[0]  # a leaning brush sweeps wider
    deeper = dataclasses.replace(large, pressure=dataclasses.replace(large.pressure, depth_m=6e-3))
    assert fit_grid(s, deeper, texel, "grid3d", 0.0).cells[2] > upright.cells[2]  # taller
    assert fit_grid(s, small, texel, "depth_averaged", 0.0).cells[2] == s.cells[2]
    assert full_grid(s).cells == s.cells


def test_a_fitted_model_keeps_the_cell_size_and_uses_fewer_cells():
    canvas = covered(0.5e-3)  # thick: the tip's trough stays above thin_below (0.2 mm)
    fitted = PaintingSession(canvas, "round_large", scene("auto", fit_grid=True))
    full = PaintingSession(covered(0.5e-3), "round_large", scene("auto", fit_grid=False))
    for session in (fitted, full):
        paint(session, stroke(0.1))
    assert fitted.model.cell_size_m == full.model.cell_size_m
    assert fitted.model.window.cells[0] < full.model.window.cells[0]
    (label,) = fitted.choices.grids  # e.g. "grid3d 12x12x5"
    nx, _, nz = (int(c) for c in label.split()[1].split("x"))
    assert label.startswith("grid3d") and nx < 20 and nz < 8
    assert set(full.choices.grids) == {"grid3d 20x20x8"}


def test_carrying_only_the_pigments_in_use_changes_nothing():
    results = []
    for used in (True, False):
        canvas = covered(0.3e-3, pigments=(BLUE, YELLOW, "cadmium_red"))
        session = PaintingSession(canvas, "round_small", scene(used_pigments=used))
        session.load_pigment(YELLOW, 5e-9)
        steps = paint(session, stroke())
        results.append((canvas.paint_m.copy(), [s.force_n for s in steps]))
        assert set(session.choices.channels) == ({2} if used else {3})
    assert np.array_equal(results[0][0], results[1][0])
    assert all(np.array_equal(a, b) for a, b in zip(results[0][1], results[1][1], strict=True))


def test_creeping_paint_steps_as_stokes_flow_and_fast_thin_paint_advects():
    """Below ``stokes_below_re`` a step leaves the momentum advection out; the count says so.
    The default paint (20 Pa s) under a 4 cm/s stroke is at Re ~ 0.01; a paint 2000 times
    thinner at the same speed is at Re ~ 20."""
    for mu, stokes in ((20.0, True), (0.01, False)):
        canvas = covered(0.3e-3)
        s = dataclasses.replace(scene(stokes_below_re=0.1), viscosity_pa_s=mu)
        session = PaintingSession(canvas, "round_small", s)
        paint(session, stroke())
        model = session.model
        assert bool(model.reynolds < 0.1) is stokes
        solver = session.choices.solver_steps["grid3d"]
        assert solver > 5
        assert session.choices.stokes_steps["grid3d"] == (solver if stokes else 0)
        assert (model.step_settings().advection == "none") is stokes
    off = PaintingSession(covered(0.3e-3), "round_small", scene())
    paint(off, stroke())
    assert off.choices.stokes_steps["grid3d"] == 0  # the bundled scenes always advect


def test_the_choose_table_is_validated():
    with pytest.raises(InputError, match="thick_above_m"):
        parse_paint_scene({"choose": {"thin_below_m": 5e-4, "thick_above_m": 1e-4}}, "x")
    with pytest.raises(InputError, match="true or false"):
        parse_paint_scene({"choose": {"fit_grid": "yes"}}, "x")
    with pytest.raises(InputError, match="not a known key"):
        parse_paint_scene({"choose": {"thin": 1e-4}}, "x")
    with pytest.raises(InputError, match="stokes_below_re"):  # Stokes flow is for Re < 1
        parse_paint_scene({"choose": {"stokes_below_re": 5.0}}, "x")
    assert (
        parse_paint_scene({"choose": {"stokes_below_re": 0.1}}, "x").choose.stokes_below_re == 0.1
    )
    assert FULL_MODEL == ModelChoice(dry_brush=False, fit_grid=False, used_pigments=False)
    assert load_paint_scene("auto").fluid_model == "auto"


def test_replay_explain_prints_decisions_and_counts(tmp_path, capsys):
    strokes = tmp_path / "s.jsonl"
    from tests.support.demo_strokes import write_recording
    from tests.support.goldens import golden_recordings

    header, records = golden_recordings()["glaze_cross"]
    write_recording(strokes, header, records[:12])
    code = main(["replay", str(strokes), "--out", str(tmp_path / "c.exr"), "--flat",
                 "--scene", "auto", "--explain", "--device", "3dof"])  # fmt: skip
    out = capsys.readouterr().out
    assert code == 0
    assert "touch-down:" in out and "outputs: force only" in out
    assert "in the air, no steps" in out and "grids used" in out
    assert "paint still below 0.3 of a column a second" in out


def test_the_solver_table_takes_the_preconditioners_and_names_a_bad_one():
    scene = parse_paint_scene(
        {"solver": {"preconditioner": "mic0", "viscosity_preconditioner": "jacobi"}}, "x"
    )
    assert scene.solver.preconditioner == "mic0"
    assert scene.solver.viscosity_preconditioner == "jacobi"
    assert parse_paint_scene({}, "x").solver.preconditioner == "multigrid"
    with pytest.raises(InputError, match=r"solver\.preconditioner") as info:
        parse_paint_scene({"solver": {"preconditioner": "ilu"}}, "x")
    assert "multigrid" in str(info.value) and "mic0" in str(info.value)


def test_the_solver_table_takes_threads_and_names_a_bad_count():
    assert parse_paint_scene({}, "x").solver.threads == 0  # auto
    assert parse_paint_scene({"solver": {"threads": 2}}, "x").solver.threads == 2
    with pytest.raises(InputError, match=r"solver\.threads"):
        parse_paint_scene({"solver": {"threads": 100}}, "x")


def test_the_solver_table_takes_the_warm_start_on_by_default():
    assert parse_paint_scene({}, "x").solver.warm_start  # the paint grid rides with the tip
    assert not parse_paint_scene({"solver": {"warm_start": False}}, "x").solver.warm_start
    with pytest.raises(InputError, match=r"solver\.warm_start"):
        parse_paint_scene({"solver": {"warm_start": "yes"}}, "x")


def test_the_solver_table_takes_the_boundary_method_and_names_a_bad_one():
    assert parse_paint_scene({}, "x").solver.boundary_method == "cutcell"
    scene = parse_paint_scene({"solver": {"boundary_method": "staircase"}}, "x")
    assert scene.solver.boundary_method == "staircase"
    assert not scene.solver.incremental_pressure  # auto: Chorin on the staircase
    with pytest.raises(InputError, match=r"solver\.boundary_method") as info:
        parse_paint_scene({"solver": {"boundary_method": "voxels"}}, "x")
    assert "cutcell" in str(info.value) and "staircase" in str(info.value)


def test_the_paint_table_takes_the_transfer_kernel_and_names_a_bad_one():
    assert parse_paint_scene({}, "x").transfer == "bspline"
    assert parse_paint_scene({"paint": {"transfer": "tent"}}, "x").transfer == "tent"
    with pytest.raises(InputError, match=r"paint\.transfer") as info:
        parse_paint_scene({"paint": {"transfer": "box"}}, "x")
    assert "bspline" in str(info.value) and "tent" in str(info.value)
