"""Fuzzing the stroke-file reader: near-valid files mutated as a careless or hostile user would.

Each example starts from a valid file (a header, samples and every kind of event) and applies a
few mutations: a field set to a hostile JSON value (huge or tiny numbers, NaN and Infinity tokens,
wrong types, nesting), a field dropped or added, a line replaced by raw text (deep nesting, cut
JSON, junk), a byte order mark, CRLF endings, or the file cut at a random byte. The reader must
either return a file whose every value is finite and in range, or raise an :class:`InputError`
naming the file and the line; never any other exception. About 400 examples, a few seconds
(``FUZZ_EXAMPLES=N`` runs N).
"""

from __future__ import annotations

import copy
import json
import math
import os
import tempfile
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from brushes.stylus import StylusSample
from common.errors import InputError
from paintapp.strokes.files import MAX_JSON_DEPTH, LoadPigment, Marker, SwitchBrush, read_strokes

HEADER = {
    "format": "paintapp-strokes",
    "version": 1,
    "canvas": {"pixels": [64, 48], "size_m": [0.02, 0.015]},
    "brush": "round_small",
    "pigments": ["ultramarine_blue", "titanium_white"],
    "scene": None,
    "device": {"kind": "tablet", "name": "fuzz", "rate_hz": 60},
    "seed": 3,
}
RECORDS = [
    {"t": 0.0, "event": "load_pigment", "pigment": "ultramarine_blue", "volume_m3": 1e-8},
    {"t": 0.0, "pos": [0.005, 0.005, 0.0], "pressure": 0.4, "tilt": [0.1, 0.0], "twist": 0.0},
    {"t": 0.01, "pos": [0.006, 0.005, 0.0], "pressure": 0.5, "buttons": 1},
    {"t": 0.02, "event": "marker", "label": "middle"},
    {"t": 0.02, "event": "brush", "preset": "flat_wide"},
    {"t": 0.03, "event": "clean"},
    {"t": 0.04, "pos": [0.007, 0.006, 0.0], "pressure": 0.0},
]
FIELDS = sorted({k for r in [HEADER, *RECORDS] for k in r} | {"canvas.pixels", "canvas.size_m"})

NUMBERS = st.sampled_from(
    [
        10**400, -(10**400), 2**63, 2**64, -1, 0, 1, 1e308, -1e308, 1e300, 5e-324, -0.0,
        float("nan"), float("inf"), float("-inf"),
    ]
)  # fmt: skip
HOSTILE = st.sampled_from(
    [
        "", "1", "nan", "round_small",
        "x" * 300, "é\u0000", None, True, False, [], {}, [0.0], [1e300, 1e300, 1e300],
        [0.0, 0.0, 0.0, 0.0], [[0.0]], {"kind": "haptic"}, {"kind": "tablet", "x": [[[1]]]},
    ]
)  # fmt: skip
SCALARS = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(2**70), max_value=2**70),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=20),
)
VALUES = st.one_of(
    NUMBERS,
    HOSTILE,
    st.lists(NUMBERS, min_size=1, max_size=4),
    st.recursive(
        SCALARS,
        lambda inner: (
            st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=6), inner, max_size=4)
        ),
        max_leaves=8,
    ),
)
RAW_LINES = st.one_of(
    st.sampled_from(
        [
            "[" * 5000 + "]" * 5000,
            '{"t": 0.5, "pos": ' + "[" * 100_000,
            '{"t": 0.5, "pos": ' + "[" * (MAX_JSON_DEPTH + 2) + "]" * (MAX_JSON_DEPTH + 2) + "}",
            '{"t": NaN, "pos": [0, 0, 0], "pressure": 0}',
            '{"t": Infinity, "pos": [0, 0, 0], "pressure": 0}',
            '{"t": 1e999, "pos": [0, 0, 0], "pressure": 0}',
            '{"t": 0.5, "t": 0.6, "pos": [0, 0, 0], "pressure": 0}',
            '{"t": 1' + "0" * 5000 + ', "pos": [0, 0, 0], "pressure": 0}',
            "\ufeff{}",
            "null",
            "42",
            '"text"',
            "{",
        ]
    ),
    st.text(max_size=40),
)


@st.composite
def stroke_files(draw) -> bytes:
    """A valid stroke file with a few mutations, as bytes."""
    lines: list[object] = [json.loads(json.dumps(o)) for o in [HEADER, *RECORDS]]
    for _ in range(draw(st.integers(0, 4))):
        index = draw(st.integers(0, len(lines) - 1))
        line = lines[index]
        kind = draw(
            st.sampled_from(["set"] * 12 + ["drop"] * 2 + ["raw"] * 3 + ["time"] * 2 + ["add"])
        )
        if kind == "raw" or not isinstance(line, dict):
            lines[index] = ("raw", draw(RAW_LINES))
        elif kind == "time":
            line["t"] = draw(st.sampled_from([1e6, 1e300, -1.0, 0.015, 2.5, 10**30]))
        elif kind == "drop" and line:
            line.pop(draw(st.sampled_from(sorted(line))))
        else:
            if kind == "add":
                key = draw(st.text(max_size=8))
            elif line and draw(st.integers(0, 3)):
                key = draw(st.sampled_from(sorted(line)))  # one of the line's own fields
            else:
                key = draw(st.sampled_from(FIELDS))
            if "." in key and isinstance(line.get(key.split(".")[0]), dict):
                line[key.split(".")[0]][key.split(".")[1]] = copy.deepcopy(draw(VALUES))
            else:
                line[key] = copy.deepcopy(draw(VALUES))
    texts = [o[1] if isinstance(o, tuple) else json.dumps(o) for o in lines]  # NaN tokens too
    newline = draw(st.sampled_from(["\n", "\r\n"]))
    data = (newline.join(texts) + newline).encode("utf-8", "surrogatepass")
    if draw(st.booleans()):
        data = b"\xef\xbb\xbf" + data
    if draw(st.integers(0, 3)) == 0:  # cut short, most often in the last lines
        data = data[: max(0, len(data) - draw(st.integers(1, 400)))]
    if draw(st.integers(0, 5)) == 0:
        at = draw(st.integers(0, len(data)))
        data = data[:at] + draw(st.binary(min_size=1, max_size=8)) + data[at:]
    return data


def _check_loaded(f) -> None:
    """Everything a reader hands on is finite and in range."""
    header = f.header
    assert all(1 <= n <= 4096 for n in header.canvas.pixels)
    assert all(math.isfinite(x) and 0.0 < x <= 10.0 for x in header.canvas.size_m)
    assert isinstance(header.brush, str) and header.brush
    assert len(set(header.pigments)) == len(header.pigments)
    assert len(f.lines) == len(f.records)
    last = -math.inf
    for record in f.records:
        assert math.isfinite(record.t_s) and record.t_s >= max(last, 0.0)
        last = record.t_s
        if isinstance(record, StylusSample):
            assert np.all(np.isfinite(record.position_m)) and record.position_m.shape == (3,)
            assert np.all(np.isfinite(record.tilt_rad)) and record.tilt_rad.shape == (2,)
            assert 0.0 <= record.pressure <= 1.0 and math.isfinite(record.twist_rad)
        elif isinstance(record, LoadPigment):
            assert record.pigment in header.pigments
            assert math.isfinite(record.volume_m3) and record.volume_m3 > 0
        elif isinstance(record, SwitchBrush):
            assert isinstance(record.preset, str) and record.preset
        elif isinstance(record, Marker):
            assert isinstance(record.label, str)
    for line, gap in f.gaps:
        assert line is not None and gap > 0


@settings(
    max_examples=int(os.environ.get("FUZZ_EXAMPLES", "400")),
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(data=stroke_files())
def test_stroke_reader_returns_finite_records_or_a_located_input_error(data: bytes) -> None:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "fuzz.jsonl"
        path.write_bytes(data)
        try:
            loaded = read_strokes(path)
        except InputError as exc:
            assert exc.source == str(path)
            assert exc.line is not None, str(exc)
            assert exc.message
        else:
            _check_loaded(loaded)


def test_the_unmutated_file_loads():
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "ok.jsonl"
        path.write_text("\n".join(json.dumps(o) for o in [HEADER, *RECORDS]) + "\n")
        loaded = read_strokes(path)
    _check_loaded(loaded)
    assert len(loaded.records) == len(RECORDS)
