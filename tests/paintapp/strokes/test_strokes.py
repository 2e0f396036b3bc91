"""Stroke files: reading, validation with line numbers, truncated files, recording."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from brushes.presets import find_preset
from brushes.stylus import StylusSample
from common.errors import InputError
from paintapp.strokes.files import (
    CanvasSpec,
    CleanBrush,
    LoadPigment,
    Marker,
    StrokeHeader,
    SwitchBrush,
    read_strokes,
)
from paintapp.strokes.recorder import StrokeRecorder

ASSETS = Path(__file__).resolve().parents[3] / "assets"
HEADER = {
    "format": "paintapp-strokes",
    "version": 1,
    "canvas": {"pixels": [256, 128], "size_m": [0.2, 0.1]},
    "brush": "round_small",
    "pigments": ["ultramarine_blue", "titanium_white"],
    "scene": None,
    "device": {"kind": "tablet", "model": "test"},
    "seed": 42,
}
SAMPLE = {
    "t": 0.0,
    "pos": [0.01, 0.02, 0.0],
    "pressure": 0.5,
    "tilt": [0.1, -0.2],
    "twist": 0.3,
    "buttons": 1,
}


def write_lines(path: Path, objs: list, *, tail: str = "\n") -> Path:
    lines = [o if isinstance(o, str) else json.dumps(o) for o in objs]
    path.write_text("\n".join(lines) + tail, encoding="utf-8")
    return path


def samples(n: int, dt: float = 0.01) -> list[dict]:
    return [{**SAMPLE, "t": k * dt, "pos": [0.01 + 0.001 * k, 0.02, 0.0]} for k in range(n)]


def test_reads_header_samples_and_events(tmp_path):
    records = [
        {"t": 0.0, "event": "load_pigment", "pigment": "ultramarine_blue", "volume_m3": 1e-8},
        *samples(3),
        {"t": 0.05, "event": "clean"},
        {"t": 0.05, "event": "brush", "preset": "flat_wide"},
        {"t": 0.06, "event": "marker", "label": "second stroke"},
        {"t": 0.07, "pos": [0.0, 0.0, 0.0], "pressure": 0.0},  # tilt, twist, buttons default
    ]
    f = read_strokes(write_lines(tmp_path / "s.jsonl", [HEADER, *records]))
    assert not f.truncated and f.warning is None
    assert f.header.canvas == CanvasSpec((256, 128), (0.2, 0.1))
    assert f.header.brush == "round_small" and f.header.seed == 42
    assert f.header.pigments == ("ultramarine_blue", "titanium_white")
    assert f.header.input_kind == "tablet"
    assert len(f.records) == 8 and len(f.samples) == 4 and len(f.events) == 4
    assert f.events == (
        LoadPigment(0.0, "ultramarine_blue", 1e-8),
        CleanBrush(0.05),
        SwitchBrush(0.05, "flat_wide"),
        Marker(0.06, "second stroke"),
    )
    s = f.samples[1]
    assert s.t_s == 0.01 and s.pressure == 0.5 and s.twist_rad == 0.3 and s.buttons == 1
    assert np.array_equal(s.position_m, [0.011, 0.02, 0.0])
    assert np.array_equal(s.tilt_rad, [0.1, -0.2])
    last = f.samples[-1]
    assert np.array_equal(last.tilt_rad, [0.0, 0.0]) and last.buttons == 0
    arrays = f.sample_arrays()
    assert arrays.position_m.shape == (4, 3) and arrays.tilt_rad.shape == (4, 2)
    assert np.array_equal(arrays.t_s, [0.0, 0.01, 0.02, 0.07])
    assert f.duration_s == pytest.approx(0.07)


def test_blank_lines_and_crlf_are_tolerated(tmp_path):
    path = tmp_path / "s.jsonl"
    text = "\r\n".join([json.dumps(HEADER), "", *map(json.dumps, samples(2))]) + "\r\n"
    path.write_bytes(text.encode())
    assert len(read_strokes(path).samples) == 2


def test_truncated_last_line_loads_up_to_last_whole_line(tmp_path):
    path = tmp_path / "s.jsonl"
    good = [json.dumps(o) for o in [HEADER, *samples(5)]]
    path.write_text("\n".join(good) + "\n" + '{"t": 0.05, "pos": [0.01, 0.0', encoding="utf-8")
    f = read_strokes(path)
    assert f.truncated and "line 7" in f.warning
    assert len(f.samples) == 5 and f.samples[-1].t_s == 0.04
    with pytest.raises(InputError):
        read_strokes(path, allow_truncated=False)


def test_crash_leftovers_nul_bytes_and_split_utf8(tmp_path):
    path = tmp_path / "s.jsonl"
    good = "\n".join(json.dumps(o) for o in [HEADER, *samples(2)]) + "\n"
    path.write_bytes(good.encode() + b"\x00" * 40)
    assert read_strokes(path).truncated and len(read_strokes(path).samples) == 2
    half_char = b'{"t": 0.5, "event": "marker", "label": "caf' + "é".encode()[:1]
    path.write_bytes(good.encode() + half_char)
    f = read_strokes(path)
    assert f.truncated and len(f.records) == 2


def test_last_line_without_newline_but_complete_is_kept(tmp_path):
    path = write_lines(tmp_path / "s.jsonl", [HEADER, *samples(3)], tail="")
    f = read_strokes(path)
    assert not f.truncated and len(f.samples) == 3


def test_whole_but_invalid_last_line_is_an_error_not_a_truncation(tmp_path):
    bad = {**SAMPLE, "t": 1.0, "pressure": 2.0}
    path = write_lines(tmp_path / "s.jsonl", [HEADER, *samples(2), bad], tail="")
    with pytest.raises(InputError) as err:
        read_strokes(path)
    assert err.value.line == 4 and err.value.key == "pressure"


@pytest.mark.parametrize(
    ("line", "key"),
    [
        ({**SAMPLE, "pressure": 1.5}, "pressure"),
        ({**SAMPLE, "pressure": -0.1}, "pressure"),
        ('{"t": 0.5, "pos": [0.0, NaN, 0.0], "pressure": 0.5}', "pos"),
        ('{"t": 0.5, "pos": [0.0, 0.0, Infinity], "pressure": 0.5}', "pos"),
        ('{"t": NaN, "pos": [0.0, 0.0, 0.0], "pressure": 0.5}', "t"),
        ({**SAMPLE, "pressure": float("nan")}, "pressure"),
        ({**SAMPLE, "pos": [0.0, 0.0]}, "pos"),
        ({**SAMPLE, "pos": [0.0, "1", 0.0]}, "pos"),
        ({**SAMPLE, "tilt": [2.0, 0.0]}, "tilt"),
        ({**SAMPLE, "twist": "a"}, "twist"),
        ({**SAMPLE, "buttons": -1}, "buttons"),
        ({**SAMPLE, "buttons": True}, "buttons"),
        ({**SAMPLE, "presure": 0.5}, "presure"),
        ({k: v for k, v in SAMPLE.items() if k != "pos"}, "pos"),
        ({k: v for k, v in SAMPLE.items() if k != "pressure"}, "pressure"),
        ({**SAMPLE, "t": 0.005}, "t"),  # before the previous record
        ({"t": 1.0, "event": "explode"}, "event"),
        ({"t": 1.0, "event": "load_pigment", "pigment": "cobalt", "volume_m3": 1e-8}, "pigment"),
        (
            {"t": 1.0, "event": "load_pigment", "pigment": "titanium_white", "volume_m3": -1e-8},
            "volume_m3",
        ),
        ({"t": 1.0, "event": "brush", "preset": "../../etc/passwd"}, "preset"),
        ({"t": 1.0, "event": "clean", "now": True}, "now"),
        ('{"t": 1.0, "event": "clean"', None),  # whole line, bad JSON
        ('{"t": 1.0, "t": 2.0, "event": "clean"}', None),  # duplicate field
        ("[1, 2, 3]", None),
    ],
)
def test_malformed_record_names_line_and_field(tmp_path, line, key):
    path = write_lines(tmp_path / "s.jsonl", [HEADER, *samples(2), line, *samples(1)])
    with pytest.raises(InputError) as err:
        read_strokes(path)
    assert err.value.line == 4
    assert err.value.key == key
    assert err.value.source == str(path)
    assert "line 4" in str(err.value)


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"format": "something-else"}, "format"),
        ({"version": 2}, "version"),
        ({"canvas": {"pixels": [0, 10], "size_m": [0.1, 0.1]}}, "canvas.pixels"),
        ({"canvas": {"pixels": [10, 10], "size_m": [0.1, -0.1]}}, "canvas.size_m"),
        ({"canvas": {"pixels": [10, 10.5], "size_m": [0.1, 0.1]}}, "canvas.pixels"),
        ({"canvas": None}, "canvas"),
        ({"brush": "a/b"}, "brush"),
        ({"pigments": ["red", "red"]}, "pigments"),
        ({"seed": -1}, "seed"),
        ({"device": {"kind": "joystick"}}, "device.kind"),
        ({"device": "wacom"}, "device"),
        ({"extra": 1}, "extra"),
    ],
)
def test_malformed_header_names_field_on_line_1(tmp_path, change, key):
    path = write_lines(tmp_path / "s.jsonl", [{**HEADER, **change}, *samples(1)])
    with pytest.raises(InputError) as err:
        read_strokes(path)
    assert err.value.line == 1 and err.value.key == key


def test_empty_missing_and_cut_header(tmp_path):
    empty = tmp_path / "empty.jsonl"
    empty.write_text("")
    with pytest.raises(InputError, match="header"):
        read_strokes(empty)
    with pytest.raises(InputError, match="no such"):
        read_strokes(tmp_path / "missing.jsonl")
    cut = tmp_path / "cut.jsonl"
    cut.write_text(json.dumps(HEADER)[:40])
    with pytest.raises(InputError) as err:
        read_strokes(cut)
    assert err.value.line == 1


def make_records() -> list:
    rng = np.random.default_rng(5)
    out: list = [LoadPigment(0.0, "titanium_white", 2e-8)]
    for k in range(50):
        out.append(
            StylusSample(
                t_s=0.001 * k + rng.uniform(0, 1e-4),
                position_m=rng.uniform(0, 0.1, 3),
                pressure=float(rng.uniform()),
                tilt_rad=rng.uniform(-1, 1, 2),
                twist_rad=float(rng.normal()),
                buttons=int(rng.integers(0, 4)),
            )
        )
    out += [CleanBrush(1.0), SwitchBrush(1.0, "flat_wide"), Marker(1.5, "end ✓")]
    return out


def test_recorder_round_trip_is_exact(tmp_path):
    path = tmp_path / "rec.jsonl"
    header = StrokeHeader.from_dict(HEADER)
    records = make_records()
    with StrokeRecorder(path, header) as rec:
        for r in records:
            rec.write(r)
        assert rec.count == len(records)
    f = read_strokes(path)
    assert f.header == header and not f.truncated
    assert len(f.records) == len(records)
    for got, want in zip(f.records, records, strict=True):
        if isinstance(want, StylusSample):
            assert got.t_s == want.t_s and got.pressure == want.pressure
            assert np.array_equal(got.position_m, want.position_m)
            assert np.array_equal(got.tilt_rad, want.tilt_rad)
            assert (got.twist_rad, got.buttons) == (want.twist_rad, want.buttons)
        else:
            assert got == want


def test_recorder_refuses_to_clobber_and_validates(tmp_path):
    path = tmp_path / "rec.jsonl"
    path.write_text("precious\n")
    with pytest.raises(InputError, match="refusing to overwrite"):
        StrokeRecorder(path, HEADER)
    assert path.read_text() == "precious\n"
    with StrokeRecorder(path, HEADER, overwrite=True, fsync=True) as rec:
        rec.write(StylusSample(1.0, np.zeros(3), 0.5))
        with pytest.raises(InputError):
            rec.write(StylusSample(0.5, np.zeros(3), 0.5))  # backwards in time
        with pytest.raises(InputError):
            rec.write(LoadPigment(1.0, "cobalt", 1e-8))  # not in the header
        with pytest.raises(InputError):
            rec.write(LoadPigment(1.0, "titanium_white", float("nan")))
    with pytest.raises(InputError):
        StrokeHeader(CanvasSpec((10, 10), (0.1, 0.1)), brush="bad name")
    assert len(read_strokes(path).records) == 1


def test_each_record_is_on_disk_before_the_next_is_written(tmp_path):
    path = tmp_path / "rec.jsonl"
    rec = StrokeRecorder(path, HEADER)
    for k, sample in enumerate(make_records()[1:6]):
        rec.write(sample)
        assert len(read_strokes(path).samples) == k + 1  # flushed, file still open
    rec.close()


def test_a_killed_recording_process_keeps_every_written_record(tmp_path):
    path = tmp_path / "crash.jsonl"
    script = f"""
import os, numpy as np
from brushes.stylus import StylusSample
from paintapp.strokes.recorder import StrokeRecorder
rec = StrokeRecorder({str(path)!r}, {HEADER!r})
for k in range(20):
    rec.write(StylusSample(0.01 * k, np.array([0.001 * k, 0.0, 0.0]), 0.5))
rec._file.write('{{"t": 0.2, "pos": [0.0')  # a record half-written when the crash comes
rec._file.flush()
os._exit(3)
"""
    done = subprocess.run([sys.executable, "-c", script], check=False)
    assert done.returncode == 3
    f = read_strokes(path)
    assert f.truncated and len(f.samples) == 20 and f.samples[-1].t_s == pytest.approx(0.19)


def test_bundled_example_strokes_load_and_name_bundled_brushes():
    for path in sorted((ASSETS / "strokes").glob("*.jsonl")):
        f = read_strokes(path)
        assert not f.truncated and f.samples
        brushes = {f.header.brush} | {e.preset for e in f.events if isinstance(e, SwitchBrush)}
        for name in brushes:
            assert find_preset(name, ASSETS / "brushes").exists()
        for pigment in f.header.pigments:
            assert (ASSETS / "pigments" / f"{pigment}.toml").exists(), pigment
