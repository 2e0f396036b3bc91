"""Fidelity presets: what they change, deterministic replays at each, and the bench families."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from common.errors import InputError
from paintapp.canvas.exr import read_canvas_exr
from paintapp.cli import main
from paintapp.paint.fidelity import FIDELITY_NAMES, apply_fidelity, get_fidelity
from paintapp.paint.paint_scene import load_paint_scene
from paintapp.session.compare import compare_replays, snapshot
from paintapp.session.outputs import read_forces_csv
from paintapp.session.painting import paint_inventory
from paintapp.session.playback import replay
from paintapp.strokes.files import CanvasSpec, LoadPigment, StrokeFile, StrokeHeader, read_strokes
from tests.support.demo_strokes import StrokeSpec, stroke_samples
from tests.support.goldens import compare_canvas, compare_forces

GOLDEN = Path(__file__).parent / "golden"
BLUE = "ultramarine_blue"


def short_strokes() -> StrokeFile:
    """A quarter-second stroke of a loaded small round brush on a 24 mm canvas."""
    header = StrokeHeader(
        canvas=CanvasSpec((96, 96), (0.024, 0.024)),
        brush="round_small",
        pigments=(BLUE,),
        scene=None,
        device={"kind": "tablet", "name": "test", "rate_hz": 60},
        seed=1,
    )
    samples = stroke_samples(StrokeSpec((0.008, 0.012), (0.016, 0.013), 0.25, 0.9), 0.0)
    return StrokeFile(header, (LoadPigment(0.0, BLUE, 1e-8), *samples))


def small_scene(name: str = "default"):
    return dataclasses.replace(load_paint_scene(name), cells=(16, 16, 6), margin_cells=5)


def test_standard_is_the_scene_as_written():
    for name in ("default", "thin_glaze", "no_fluid", "auto"):
        scene = load_paint_scene(name)
        assert apply_fidelity(scene, "standard") is scene


def test_draft_and_high_change_the_knobs():
    scene = load_paint_scene("default")
    draft, high = apply_fidelity(scene, "draft"), apply_fidelity(scene, "high")
    assert draft.cells == (24, 24, 9) and high.cells == (48, 48, 18)
    assert draft.margin_cells < scene.margin_cells < high.margin_cells
    # the default grid re-centres on the tip at every step, and so does each fidelity's
    assert [s.margin_cells for s in (draft, scene, high)] == [11, 15, 23]
    thin = dataclasses.replace(scene, margin_cells=8)  # a scene that re-centres less often
    assert apply_fidelity(thin, "high").margin_cells == 12
    assert draft.solver.pressure_tolerance > scene.solver.pressure_tolerance
    assert high.solver.pressure_tolerance < scene.solver.pressure_tolerance
    assert high.solver.viscosity_tolerance < scene.solver.viscosity_tolerance
    assert (draft.solver.advection, high.solver.advection) == ("linear", "maccormack")
    assert draft.solver.viscosity_tolerance > scene.solver.viscosity_tolerance
    # draft leaves the advection out of creeping paint; high always advects, even where the
    # scene would not
    assert (scene.choose.stokes_below_re, draft.choose.stokes_below_re) == (0.0, 0.1)
    creeping = dataclasses.replace(
        scene, choose=dataclasses.replace(scene.choose, stokes_below_re=0.5)
    )
    assert apply_fidelity(creeping, "high").choose.stokes_below_re == 0.0
    assert high.max_step_s < scene.max_step_s == draft.max_step_s
    glaze = apply_fidelity(load_paint_scene("thin_glaze"), "high")
    assert glaze.cells == (72, 72, 1)  # a 2D grid stays one cell deep


def test_an_unknown_fidelity_is_an_input_error(tmp_path, capsys):
    with pytest.raises(InputError, match="unknown fidelity"):
        get_fidelity("ultra")
    strokes = GOLDEN / "glaze_cross.jsonl"
    with pytest.raises(SystemExit) as exc:
        main(["replay", str(strokes), "--out", str(tmp_path / "c.exr"), "--fidelity", "ultra"])
    assert exc.value.code == 2
    assert FIDELITY_NAMES == ("draft", "standard", "high")


@pytest.mark.parametrize("fidelity", FIDELITY_NAMES)
def test_each_fidelity_replays_deterministically(fidelity):
    strokes, scene = short_strokes(), small_scene()
    first = replay(strokes, scene, fidelity=fidelity)
    second = replay(strokes, scene, fidelity=fidelity)
    assert np.array_equal(first.canvas.paint_m, second.canvas.paint_m)
    assert np.array_equal(first.forces, second.forces)
    assert first.session.stats.solver_steps > 0 and first.canvas.paint_m.sum() > 0.0
    if fidelity == "high":  # 120 Hz steps: two solver steps per 60 Hz sample
        assert first.session.stats.solver_steps > first.session.stats.paint_steps


def test_fidelities_differ_a_little_and_conserve_paint():
    strokes, scene = short_strokes(), small_scene()
    shots = {f: replay(strokes, scene, fidelity=f) for f in ("draft", "high")}
    diff = compare_replays(*(snapshot(r.canvas, r.forces) for r in shots.values()))
    assert 0.0 < diff["colour_rms"] < 0.2
    assert diff["force_rms_rel"] is not None and diff["force_rms_rel"] > 0.0
    for r in shots.values():  # each replay conserves paint: canvas + brush = loaded - removed
        s = r.session
        inventory = paint_inventory(r.canvas, s.reservoir)
        for name, volume in inventory.items():
            booked = s.loaded_m3.get(name, 0.0) - s.removed_m3.get(name, 0.0)
            assert volume == pytest.approx(booked, rel=1e-6, abs=1e-15)
    # and the same strokes lay about the same paint (measured: draft lays 7 % more than high)
    totals = [r.canvas.paint_m.sum(dtype=np.float64) for r in shots.values()]
    assert totals[0] == pytest.approx(totals[1], rel=0.12)


def test_standard_fidelity_reproduces_the_golden_replay():
    result = replay(read_strokes(GOLDEN / "glaze_cross.jsonl"), fidelity="standard")
    assert compare_canvas(result.canvas, read_canvas_exr(GOLDEN / "glaze_cross.exr")) == []
    expected = read_forces_csv(GOLDEN / "glaze_cross.forces.csv")
    assert compare_forces(result.forces, expected, rel_tol=1e-6) == []


@pytest.mark.slow
def test_the_painting_bench_families_run_and_report(capsys):
    from paintapp.bench.registry import Setting
    from paintapp.commands.bench import bench_registry

    registry = bench_registry()
    names = {s.family for s in registry.quick_settings()}
    assert {"painting_models", "painting_fidelity"} <= names
    auto = registry.run_setting(Setting("painting_models", {"choice": "auto"}))
    full = registry.run_setting(Setting("painting_models", {"choice": "full3d"}))
    assert "failed" not in auto and "failed" not in full
    assert full["errors"]["colour_rms"] == 0.0
    assert auto["cost"]["solver_steps"] > 0 and auto["measured"]["what_ran"]["steps_by_model"]
    draft = registry.run_setting(Setting("painting_fidelity", {"fidelity": "draft"}))
    assert draft["errors"]["colour_rms"] > 0.0
    registry.cleanup()
