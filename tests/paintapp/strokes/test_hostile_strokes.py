"""Stroke files from careless or hostile hands: nesting, byte order marks, types, huge numbers,
time jumps."""

from __future__ import annotations

import json

import pytest

from common.errors import InputError
from paintapp.strokes.files import MAX_GAP_S, MAX_JSON_DEPTH, read_strokes

HEADER = {
    "format": "paintapp-strokes",
    "version": 1,
    "canvas": {"pixels": [32, 32], "size_m": [0.01, 0.01]},
    "brush": "round_small",
    "pigments": ["ultramarine_blue"],
}
SAMPLES = [{"t": 0.01 * k, "pos": [0.005, 0.005, 0.0], "pressure": 0.5} for k in range(3)]


def write(path, lines, prefix=b""):
    text = "\n".join(x if isinstance(x, str) else json.dumps(x) for x in lines) + "\n"
    path.write_bytes(prefix + text.encode())
    return path


@pytest.mark.parametrize("line", [1, 3])
def test_deep_nesting_is_refused_with_its_line(tmp_path, line):
    deep = "[" * 100_000 + "]" * 100_000
    lines: list = [HEADER, *SAMPLES]
    if line == 1:
        lines[0] = json.dumps(HEADER)[:-1] + f', "device": {deep}}}'
    else:
        lines[2] = '{"t": 0.5, "pos": ' + deep + "}"
    with pytest.raises(InputError) as err:
        read_strokes(write(tmp_path / "s.jsonl", lines))
    assert err.value.line == line and f"nested more than {MAX_JSON_DEPTH} levels" in str(err.value)


def test_nesting_below_the_recursion_limit_is_refused_too(tmp_path):
    device = {"kind": "tablet", "x": json.loads("[" * 40 + "]" * 40)}
    with pytest.raises(InputError, match="nested more than") as err:
        read_strokes(write(tmp_path / "s.jsonl", [{**HEADER, "device": device}, *SAMPLES]))
    assert err.value.line == 1


def test_a_utf8_byte_order_mark_is_accepted(tmp_path):
    f = read_strokes(write(tmp_path / "s.jsonl", [HEADER, *SAMPLES], prefix=b"\xef\xbb\xbf"))
    assert len(f.samples) == 3 and f.lines == (2, 3, 4)


def test_a_string_version_asks_for_an_integer(tmp_path):
    with pytest.raises(InputError, match="'version': expected an integer") as err:
        read_strokes(write(tmp_path / "s.jsonl", [{**HEADER, "version": "1"}, *SAMPLES]))
    assert err.value.line == 1
    with pytest.raises(InputError, match="unsupported version 2"):
        read_strokes(write(tmp_path / "s.jsonl", [{**HEADER, "version": 2}, *SAMPLES]))


@pytest.mark.parametrize(
    "record, key",
    [
        ('{"t": 1' + "0" * 400 + ', "pos": [0, 0, 0], "pressure": 0}', "t"),
        ('{"t": 0.5, "pos": [1' + "0" * 400 + ', 0, 0], "pressure": 0}', "pos"),
        ('{"t": 0.5, "pos": [0, 0, 0], "pressure": 0, "twist": 1' + "0" * 400 + "}", "twist"),
        ('{"t": 0.5, "event": [], "pigment": "ultramarine_blue", "volume_m3": 1e-9}', "event"),
    ],
)
def test_huge_integers_and_unhashable_types_are_input_errors(tmp_path, record, key):
    with pytest.raises(InputError) as err:
        read_strokes(write(tmp_path / "s.jsonl", [HEADER, *SAMPLES, record]))
    assert err.value.line == 5 and err.value.key == key and len(str(err.value)) < 300


def test_time_jumps_are_kept_and_listed_with_their_lines(tmp_path):
    jump = [{**SAMPLES[0], "t": 1e6}, {**SAMPLES[0], "t": 1e300, "pressure": 0.0}]
    f = read_strokes(write(tmp_path / "s.jsonl", [HEADER, *SAMPLES, *jump]))
    assert [line for line, _ in f.gaps] == [5, 6]
    assert all(gap > MAX_GAP_S for _, gap in f.gaps)
    assert f.samples[-1].t_s == 1e300


def test_an_absurd_position_is_refused_with_its_line(tmp_path):
    far = {**SAMPLES[0], "t": 0.5, "pos": [1e18, 0.005, 0.0]}
    with pytest.raises(InputError, match=r"within \+-1e\+06 m") as err:
        read_strokes(write(tmp_path / "s.jsonl", [HEADER, *SAMPLES, far]))
    assert err.value.line == 5 and err.value.key == "pos"
