"""Replays of hostile stroke files: long pauses cost bounded work, unknown names are found before
any work and located in the file."""

from __future__ import annotations

import json
import time

import numpy as np
import pytest

from common.errors import InputError
from paintapp.cli import main
from paintapp.session.playback import check_stroke_names, replay
from paintapp.strokes.files import MAX_GAP_S, read_strokes

HEADER = {
    "format": "paintapp-strokes",
    "version": 1,
    "canvas": {"pixels": [48, 48], "size_m": [0.012, 0.012]},
    "brush": "round_small",
    "pigments": ["ultramarine_blue"],
}
LOAD = {"t": 0.0, "event": "load_pigment", "pigment": "ultramarine_blue", "volume_m3": 1e-8}
STROKE = [
    {"t": 0.02 * k, "pos": [0.004 + 0.0004 * k, 0.006, 0.0], "pressure": 0.5} for k in range(5)
]


def write(path, records, header=None):
    lines = [header or HEADER, *records]
    path.write_text("\n".join(json.dumps(x) for x in lines) + "\n", encoding="utf-8")
    return path


@pytest.mark.parametrize("t, pressure", [(1e6, 0.5), (1e300, 0.0)])
def test_a_time_jump_is_replayed_in_bounded_work(tmp_path, t, pressure):
    after = [{"t": t, "pos": [0.006, 0.006, 0.0], "pressure": pressure}]
    after.append({**after[0], "t": t + 0.02, "pos": [0.0062, 0.006, 0.0]})  # 1e300 + 0.02: 1e300
    strokes = read_strokes(write(tmp_path / "s.jsonl", [LOAD, *STROKE, *after]))
    plain = replay(read_strokes(write(tmp_path / "p.jsonl", [LOAD, *STROKE])))
    start = time.perf_counter()
    first = replay(strokes)
    assert time.perf_counter() - start < 30  # a servo tick per simulated ms would never end
    ticks_per_gap = round(MAX_GAP_S / 1e-3)
    assert len(plain.forces) < len(first.forces) <= len(plain.forces) + ticks_per_gap + 40
    assert first.skipped_ticks > 0 and first.session.stats.pauses == 1
    assert np.all(np.diff(first.forces[:, 0]) >= 0) and np.all(np.isfinite(first.forces))
    again = replay(strokes)  # still deterministic
    np.testing.assert_array_equal(first.forces, again.forces)
    np.testing.assert_array_equal(first.canvas.paint_m, again.canvas.paint_m)


def test_unknown_brushes_name_the_stroke_file_and_line(tmp_path):
    path = write(tmp_path / "s.jsonl", [LOAD, *STROKE], {**HEADER, "brush": "no_such_brush"})
    with pytest.raises(InputError) as err:
        replay(read_strokes(path))
    assert (err.value.source, err.value.line, err.value.key) == (str(path), 1, "brush")
    assert "unknown brush preset 'no_such_brush'" in str(err.value)
    switch = {"t": 0.1, "event": "brush", "preset": "nope"}
    path = write(tmp_path / "e.jsonl", [LOAD, *STROKE, switch])
    with pytest.raises(InputError) as err:
        replay(read_strokes(path))
    assert (err.value.source, err.value.line, err.value.key) == (str(path), 8, "preset")


def test_an_unknown_pigment_names_the_header_field(tmp_path):
    path = write(tmp_path / "s.jsonl", STROKE, {**HEADER, "pigments": ["no_such_pigment"]})
    strokes = read_strokes(path)
    check_stroke_names(strokes)  # without a library only the brushes are checked
    with pytest.raises(InputError, match="unknown pigment 'no_such_pigment'") as err:
        check_stroke_names(strokes, pigments={"ultramarine_blue"})
    assert (err.value.source, err.value.line, err.value.key) == (str(path), 1, "pigments")


def test_replay_command_checks_names_and_outputs_before_any_work(tmp_path, capsys):
    path = write(tmp_path / "s.jsonl", STROKE, {**HEADER, "pigments": ["no_such_pigment"]})
    out = tmp_path / "new" / "c.exr"
    assert main(["replay", str(path), "--out", str(out), "--flat"]) == 2
    err = capsys.readouterr().err
    assert f"{path}, line 1, 'pigments': unknown pigment 'no_such_pigment'" in err
    assert not (tmp_path / "new").exists()  # refused before even the folder was made
    good = write(tmp_path / "g.jsonl", [LOAD, *STROKE])
    forces = tmp_path / "f.csv"
    forces.mkdir()
    assert main(["replay", str(good), "--out", str(out), "--forces", str(forces)]) == 2
    assert "--forces" in capsys.readouterr().err and not out.exists()


def test_replay_command_warns_about_a_pause_with_its_line(tmp_path, capsys):
    jump = {"t": 500.0, "pos": [0.006, 0.006, 0.0], "pressure": 0.0}
    path = write(tmp_path / "s.jsonl", [LOAD, *STROKE, jump])
    out, forces = tmp_path / "out" / "c.exr", tmp_path / "f.csv"
    assert main(["replay", str(path), "--out", str(out), "--forces", str(forces), "--flat"]) == 0
    err = capsys.readouterr().err
    assert f"created folder {out.parent}" in err
    assert f"warning: {path}, line 8: 500 s after the record before it" in err
    assert len(forces.read_text().splitlines()) < 2000
