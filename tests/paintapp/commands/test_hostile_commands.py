"""The commands under hostile input: one line naming what is wrong, exit 2 (1 for a write that
fails mid-run), nothing written, no traceback, no NaN in a JSON file."""

from __future__ import annotations

import json

import numpy as np
import pytest

from paintapp import atomic
from paintapp.canvas.exr import write_canvas_exr
from paintapp.canvas.model import Canvas
from paintapp.cli import main

SCENE = """
[domain]
size = [1.0, 1.0]
cells = [16, 16]
[fluid]
density = 1.0
viscosity = 0.01
[[probes]]
name = "c"
shape = "circle"
center = [0.5, 0.5]
radius = 0.2
[run]
dt = 0.01
steps = 2
[[output.points]]
name = "inside"
at = [0.5, 0.5]
[[output.points]]
name = "outside"
at = [0.1, 0.1]
"""


def strict_json(text: str):
    def refuse(token):
        raise AssertionError(f"{token} in the JSON")

    return json.loads(text, parse_constant=refuse)


@pytest.fixture
def scene_file(tmp_path):
    path = tmp_path / "scene.toml"
    path.write_text(SCENE, encoding="utf-8")
    return path


@pytest.fixture
def canvas_file(tmp_path):
    canvas = Canvas((8, 8), (0.008, 0.008), ("burnt_sienna",))
    canvas.paint_m[0] = 1e-4
    path = tmp_path / "in.exr"
    write_canvas_exr(path, canvas, np.zeros((8, 8, 4), np.float32), half=False)
    return path


def test_a_point_inside_a_probe_is_null_with_a_note_not_nan(scene_file, tmp_path, capsys):
    out = tmp_path / "r.json"
    assert main(["simulate", str(scene_file), "--json", str(out)]) == 0
    results = strict_json(out.read_text())
    inside, outside = results["points"]["inside"], results["points"]["outside"]
    assert inside["pressure"] is None and "inside a probe" in inside["note"]
    assert isinstance(outside["pressure"], float) and "note" not in outside
    assert "point inside: null: no fluid cell" in capsys.readouterr().out


def test_a_folder_as_the_json_output_is_refused_before_the_run(scene_file, tmp_path, capsys):
    assert main(["simulate", str(scene_file), "--json", str(tmp_path)]) == 2
    captured = capsys.readouterr()
    assert f"--json {tmp_path}: is an existing folder" in captured.err
    assert "median step" not in captured.out  # nothing ran


def test_more_memory_than_available_is_refused(scene_file, monkeypatch, capsys):
    monkeypatch.setattr("solver.scenes.budget.available_memory_bytes", lambda: 10_000)
    assert main(["simulate", str(scene_file)]) == 2
    err = capsys.readouterr().err
    assert "'domain.cells': a 2D 16x16 grid (256 cells) needs about" in err
    assert "this machine has 0 MB available" in err


def test_a_slow_run_is_announced_before_it_starts(scene_file, monkeypatch, capsys):
    monkeypatch.setattr("solver.scenes.budget.SLOW_STEP_S", 0.0)
    assert main(["simulate", str(scene_file), "--steps", "1"]) == 0
    assert "per step on a 2-core machine" in capsys.readouterr().err


def test_a_byte_order_mark_in_a_scene_is_accepted(scene_file, capsys):
    scene_file.write_bytes(b"\xef\xbb\xbf" + scene_file.read_bytes())
    assert main(["simulate", str(scene_file), "--steps", "1"]) == 0


@pytest.mark.parametrize(
    "option, value", [("--exposure", "nan"), ("--exposure", "inf"), ("--light-elevation", "nan")]
)
def test_export_options_must_be_finite(canvas_file, tmp_path, capsys, option, value):
    out = tmp_path / "x.png"
    assert main(["export", str(canvas_file), "--out", str(out), "--flat", option, value]) == 2
    assert f"'{option}': expected a finite number" in capsys.readouterr().err
    assert not out.exists()


def test_a_write_failing_mid_run_is_one_line_and_exit_1(canvas_file, tmp_path, monkeypatch, capsys):
    def disk_full(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(atomic, "_fsync_path", disk_full)
    out = tmp_path / "x.png"
    assert main(["export", str(canvas_file), "--out", str(out), "--flat"]) == 1
    err = capsys.readouterr().err
    assert err == f"paintapp export: error: cannot write {out}: No space left on device\n"
    assert list(tmp_path.iterdir()) == [canvas_file]


def test_demo_refuses_a_file_as_its_folder_before_painting(tmp_path, capsys):
    taken = tmp_path / "taken"
    taken.write_text("x")
    assert main(["demo", "--out", str(taken), "--flat"]) == 2
    assert f"--out {taken}: is a file; expected a folder" in capsys.readouterr().err
    assert taken.read_text() == "x"
