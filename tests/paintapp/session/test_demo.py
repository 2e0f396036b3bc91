"""The bundled demo strokes, and the demo run end to end (slow)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from brushes import StylusSample
from paintapp.canvas.exr import read_canvas_exr
from paintapp.canvas.lattice import count_holes
from paintapp.cli import main
from paintapp.resources import asset_path
from paintapp.session.comb import period_depths, stroke_paths, tooth_depth
from paintapp.session.outputs import read_forces_csv
from paintapp.strokes.files import read_strokes
from paintapp.strokes.records import LoadPigment, StrokeRecord, SwitchBrush, record_to_dict
from tests.support.demo_strokes import demo_recording

DEMO = asset_path("strokes", "demo.jsonl")


def as_dicts(records: tuple[StrokeRecord, ...] | list[StrokeRecord]) -> list[dict]:
    return [record_to_dict(r) for r in records]


def test_bundled_demo_is_what_the_generator_writes():
    header, records = demo_recording()
    bundled = read_strokes(DEMO, allow_truncated=False)
    assert bundled.header == header
    assert as_dicts(bundled.records) == as_dicts(records)


def test_demo_has_several_brushes_and_pigments():
    strokes = read_strokes(DEMO)
    brushes = {strokes.header.brush} | {
        e.preset for e in strokes.events if isinstance(e, SwitchBrush)
    }
    pigments = {e.pigment for e in strokes.events if isinstance(e, LoadPigment)}
    assert len(brushes) >= 4 and "square_probe" in brushes
    assert len(pigments) >= 4
    assert sum(isinstance(r, StylusSample) for r in strokes.records) > 300


def test_the_demo_strokes_are_centred_on_a_larger_sheet_and_kept_on_a_smaller_one():
    from paintapp.commands.demo import on_canvas

    strokes = read_strokes(DEMO)
    own = strokes.header.canvas.size_m
    placed = on_canvas(strokes, "a4", 0.1)
    assert placed.header.canvas.pixels == (2100, 2970)
    assert len(placed.records) == len(strokes.records) and placed.events == strokes.events
    shifts = np.array(
        [b.position_m - a.position_m for a, b in zip(strokes.samples, placed.samples, strict=True)]
    )
    expected = [(0.210 - own[0]) / 2, (0.297 - own[1]) / 2, 0.0]
    assert np.allclose(shifts, expected, atol=1e-12)
    for a, b in zip(strokes.samples, placed.samples, strict=True):
        assert (a.t_s, a.pressure) == (b.t_s, b.pressure)
    small = on_canvas(strokes, "100x200", 0.25)  # narrower than the file's: kept at x = 0
    assert np.allclose(small.samples[5].position_m - strokes.samples[5].position_m,
                       [0.0, (0.2 - own[1]) / 2, 0.0], atol=1e-12)  # fmt: skip


@pytest.mark.slow
def test_demo_paints_mixes_and_records_forces(tmp_path):
    out = tmp_path / "demo"
    assert main(["demo", "--out", str(out), "--flat"]) == 0
    canvas = read_canvas_exr(out / "canvas.exr")
    assert canvas.pixels == (2100, 2970)  # an A4 sheet at 0.1 mm
    painted = read_strokes(out / "strokes.jsonl")
    assert painted.header.canvas.pixels == canvas.pixels
    ys, xs = np.nonzero(canvas.height_m > 0.0)
    dx = canvas.texel_size_m[0]
    # the paint lies round the sheet's centre, where the strokes were moved
    assert abs(0.5 * (xs.min() + xs.max()) * dx - 0.105) < 0.03
    assert abs(0.5 * (ys.min() + ys.max()) * dx - 0.1485) < 0.03
    conc = canvas.concentration
    blue, yellow = canvas.pigment_index("ultramarine_blue"), canvas.pigment_index("cadmium_yellow")
    assert np.count_nonzero((conc[blue] > 0.2) & (conc[yellow] > 0.2)) > 1000  # they mixed
    red = conc[canvas.pigment_index("cadmium_red")] > 0.5
    assert canvas.height_m[red].max() > 5e-4  # impasto: over half a millimetre
    assert count_holes(canvas.height_m) == (0, 0)  # no unpainted texel inside the painting
    # The probe's trail through the impasto carries a shallow comb at most: at its step (12.6
    # texels) and at its sub-step (6.3) the height varies by a few hundredths of itself; at 50
    # texels by no more than with each step's phase dealt at random (the whole-cells window of
    # the past varied by 0.38 there, several times that floor).
    height = canvas.height_m.astype(np.float64)
    probe = next(p for p in stroke_paths(painted) if "probe" in p.label)
    step_depth, _ = tooth_depth(height, dx, probe.points_m)
    step = np.median(np.hypot(*np.diff(probe.points_m, axis=0).T)) / dx
    half, long = period_depths(height, dx, probe.points_m, np.array([step / 2, 50.2]))
    assert step_depth < 0.035 and half.depth < 0.04 and long.depth <= long.floor
    forces = read_forces_csv(out / "forces.csv")
    assert np.all(np.isfinite(forces)) and np.linalg.norm(forces[:, 1:4], axis=1).max() > 0.01


def test_the_demo_paints_with_the_window_s_scene_unless_one_is_named():
    from paintapp.commands.demo import DEMO_SCENE, scene_for

    strokes = read_strokes(DEMO)
    assert strokes.header.scene is None and DEMO_SCENE == "live"
    assert scene_for(strokes, None) == "live"
    assert scene_for(strokes, "default") == "default"
    named = dataclasses.replace(
        strokes, header=dataclasses.replace(strokes.header, scene="thin_glaze")
    )
    assert scene_for(named, None) is None  # the file's own scene
