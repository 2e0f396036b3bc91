"""Replays: determinism, golden canvases and force traces, the replay and demo commands."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from paintapp.canvas.exr import read_canvas_exr
from paintapp.cli import main
from paintapp.session.outputs import read_forces_csv
from paintapp.session.playback import FORCE_COLUMNS, replay
from paintapp.strokes.files import read_strokes
from tests.support.goldens import compare_canvas, compare_forces

GOLDEN = Path(__file__).parent / "golden"
GOLDEN_NAMES = sorted(p.stem for p in GOLDEN.glob("*.jsonl"))


def test_goldens_exist():
    assert GOLDEN_NAMES == ["glaze_cross", "grid3d_drag"]


def test_the_same_file_gives_the_same_canvas_and_force_trace():
    strokes = read_strokes(GOLDEN / "grid3d_drag.jsonl")
    first, second = replay(strokes), replay(strokes)
    assert np.array_equal(first.canvas.paint_m, second.canvas.paint_m)
    assert np.array_equal(first.canvas.wetness, second.canvas.wetness)
    assert np.array_equal(first.forces, second.forces)
    assert first.forces.shape[1] == len(FORCE_COLUMNS)
    np.testing.assert_allclose(np.diff(first.forces[:, 0]), 1e-3)  # one row per 1 ms tick
    assert np.abs(first.forces[:, 1:4]).max() > 0.0


@pytest.mark.parametrize("name", GOLDEN_NAMES)
def test_replay_matches_its_golden_canvas_and_forces(name):
    result = replay(read_strokes(GOLDEN / f"{name}.jsonl"))
    expected = read_canvas_exr(GOLDEN / f"{name}.exr")
    assert compare_canvas(result.canvas, expected) == []
    forces = read_forces_csv(GOLDEN / f"{name}.forces.csv")
    assert compare_forces(result.forces, forces) == []


def test_replay_command_writes_canvas_preview_and_forces(tmp_path, capsys):
    out, preview, forces = tmp_path / "c.exr", tmp_path / "p.png", tmp_path / "f.csv"
    status = main(["replay", str(GOLDEN / "glaze_cross.jsonl"), "--out", str(out),
                   "--preview", str(preview), "--forces", str(forces), "--flat"])  # fmt: skip
    assert status == 0
    assert out.stat().st_size > 0 and preview.stat().st_size > 0
    lines = forces.read_text().splitlines()
    assert lines[0] == ",".join(FORCE_COLUMNS)
    assert len(lines) > 100 and all(len(line.split(",")) == 7 for line in lines[1:])
    canvas = read_canvas_exr(out)
    assert canvas.pigment_names == ("ultramarine_blue", "cadmium_yellow")
    assert canvas.height_m.max() > 0.0
    assert "replayed" in capsys.readouterr().out


def test_a_malformed_stroke_file_is_a_clear_error_and_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.jsonl"
    lines = (GOLDEN / "grid3d_drag.jsonl").read_text().splitlines()
    lines[3] = lines[3].replace('"pressure": ', '"pressure": 7')
    bad.write_text("\n".join(lines) + "\n")
    status = main(["replay", str(bad), "--out", str(tmp_path / "c.exr")])
    err = capsys.readouterr().err
    assert status == 2
    assert "bad.jsonl" in err and "line 4" in err and "pressure" in err
    assert not (tmp_path / "c.exr").exists()
    assert main(["replay", str(bad), "--out", str(tmp_path / "c.png")]) == 2


def test_demo_command_writes_its_four_files(tmp_path, capsys):
    out = tmp_path / "demo"
    status = main(["demo", "--out", str(out), "--strokes", str(GOLDEN / "glaze_cross.jsonl"),
                   "--flat"])  # fmt: skip
    assert status == 0
    for name in ("canvas.exr", "preview.png", "forces.csv", "forces.png"):
        assert (out / name).stat().st_size > 0
    assert "wrote" in capsys.readouterr().out
