"""Fuzzing the scene-file reader: valid scenes mutated as a careless or hostile user would.

Each example starts from a valid 2D or 3D scene that uses every section (boundaries, probes with a
path, solver settings, outputs) and applies a few mutations: a value replaced by a hostile one
(huge integers, nan and inf, which TOML allows, wrong types, nesting, huge counts), a key dropped
or added, a section replaced; the result is written as TOML, sometimes with a byte order mark, cut
short or with junk bytes. :func:`load_scene` must return a scene whose every number is finite and
whose every size is bounded, or raise an :class:`InputError` naming the file; never any other
exception. About 400 examples, a few seconds
(``FUZZ_EXAMPLES=N`` runs N).
"""

from __future__ import annotations

import copy
import json
import math
import os
import re
import tempfile
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from common.errors import InputError
from solver.scenes.budget import estimate_bytes, estimate_step_s
from solver.scenes.scene import MAX_CELLS, MAX_ITERATIONS, MAX_LINE_POINTS, MAX_STEPS, load_scene

SCENE_2D = {
    "version": 1,
    "name": "fuzz_2d",
    "description": "a channel with two probes",
    "domain": {"size": [2.0, 1.0], "cells": [32, 16]},
    "fluid": {"density": 1.0, "viscosity": 1e-3, "body_force": [0.0, -1.0]},
    "boundary": {
        "x_min": {"kind": "inflow", "profile": "parabolic", "velocity": [0.3, 0.0]},
        "x_max": {"kind": "outflow"},
        "y_max": {"kind": "wall", "velocity": [1.0, 0.0]},
    },
    "probes": [
        {"name": "cylinder", "shape": "circle", "center": [0.5, 0.5], "radius": 0.1},
        {
            "name": "square",
            "shape": "box",
            "center": [1.2, 0.5],
            "size": [0.2, 0.2],
            "angle": 0.3,
            "velocity": [0.1, 0.0],
            "angular_velocity": 1.0,
            "reference": [0.0, 0.0],
            "path": [[0.0, 1.2, 0.5, 0.0], [1.0, 1.4, 0.5, 0.5]],
        },
    ],
    "solver": {
        "advection": "maccormack",
        "pressure_tolerance": 1e-6,
        "viscosity_tolerance": 1e-8,
        "max_iterations": 500,
        "force_model": "control_volume",
        "drag_coefficient": 1.0,
    },
    "run": {"dt": 0.01, "duration": 1.0},
    "output": {
        "lines": [{"name": "u", "start": [0.5, 0.0], "end": [0.5, 1.0], "points": 17}],
        "points": [{"name": "front", "at": [0.3, 0.5]}],
    },
}
SCENE_3D = {
    "domain": {"size": [1.0, 1.0, 1.0], "cells": [8, 8, 8]},
    "fluid": {"density": 1.0, "viscosity": 1e-2},
    "boundary": {"z_max": {"kind": "slip"}},
    "probes": [
        {
            "name": "sphere",
            "shape": "sphere",
            "center": [0.5, 0.5, 0.5],
            "radius": 0.2,
            "orientation": [1.0, 0.0, 0.0, 0.0],
            "angular_velocity": [0.0, 0.0, 1.0],
            "path": [[0.0, 0.5, 0.5, 0.5, 1, 0, 0, 0], [1.0, 0.6, 0.5, 0.5, 0, 0, 0, 1]],
        }
    ],
    "run": {"dt": 0.01, "steps": 10},
    "output": {"points": [{"name": "p", "at": [0.1, 0.1, 0.1]}]},
}

NUMBERS = st.sampled_from(
    [
        10**30, -(10**30), 2**63 - 1, -(2**63), 10**9, 10**8, 64_000_001, 0, 1, 2, 3, -1,
        1e308, -1e308, 1e-308, 5e-324, -0.0, 0.5, float("nan"), float("inf"), float("-inf"),
    ]
)  # fmt: skip
OTHERS = st.sampled_from(
    ["", "1", "nan", "wall", "box", "x" * 200, True, False, [], {}, [[]], [1, 2], [1.0, 2.0, 3.0],
     [[0.0, 0.1, 0.1, 0.0]], {"kind": "wall"}, [{"name": "a"}]]
)  # fmt: skip
SCALARS = st.one_of(
    st.booleans(),
    st.integers(min_value=-(2**63), max_value=2**63 - 1),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=12),
)
VALUES = st.one_of(
    NUMBERS,
    OTHERS,
    st.lists(NUMBERS, min_size=1, max_size=4),
    st.recursive(
        SCALARS,
        lambda inner: (
            st.lists(inner, max_size=4)
            | st.dictionaries(st.from_regex(r"[a-z_]{1,8}", fullmatch=True), inner, max_size=3)
        ),
        max_leaves=6,
    ),
)


def _paths(node, prefix=()):
    """Every path to a value in a nested dict/list scene."""
    out = [prefix] if prefix else []
    if isinstance(node, dict):
        for key, value in node.items():
            out += _paths(value, (*prefix, key))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            out += _paths(value, (*prefix, i))
    return out


def _key(name: str) -> str:
    return name if re.fullmatch(r"[A-Za-z0-9_-]+", name) else json.dumps(name, ensure_ascii=False)


def _toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float) and math.isnan(value):
        return "nan"
    if isinstance(value, float) and math.isinf(value):
        return "inf" if value > 0 else "-inf"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)  # TOML has no surrogate-pair escapes
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    return "{" + ", ".join(f"{_key(k)} = {_toml_value(v)}" for k, v in value.items()) + "}"


def to_toml(scene: dict) -> str:
    """A TOML document of ``scene`` (every table inline: TOML allows it)."""
    return "".join(f"{_key(k)} = {_toml_value(v)}\n" for k, v in scene.items())


def value(draw):
    """A hostile value, copied: the strategies' own lists and tables must never be mutated."""
    return copy.deepcopy(draw(VALUES))


@st.composite
def scene_files(draw) -> bytes:
    scene = copy.deepcopy(draw(st.sampled_from([SCENE_2D, SCENE_3D])))
    for _ in range(draw(st.integers(0, 4))):
        paths = _paths(scene)
        kind = draw(st.sampled_from(["set"] * 8 + ["drop", "add"]))
        if kind == "add" or not paths:
            where = scene
            for part in draw(st.sampled_from([(), ("domain",), ("run",), ("solver",)])):
                where = where.setdefault(part, {})
            if isinstance(where, dict):
                where[draw(st.from_regex(r"[a-z_]{1,10}", fullmatch=True))] = value(draw)
            continue
        path = draw(st.sampled_from(paths))
        parent = scene
        for part in path[:-1]:
            parent = parent[part]
        if kind == "drop":
            del parent[path[-1]]
        else:
            parent[path[-1]] = value(draw)
    data = to_toml(scene).encode("utf-8", "surrogatepass")
    if draw(st.integers(0, 4)) == 0:
        data = b"\xef\xbb\xbf" + data
    if draw(st.integers(0, 5)) == 0:
        data = data[: max(0, len(data) - draw(st.integers(1, 300)))]
    if draw(st.integers(0, 8)) == 0:
        at = draw(st.integers(0, len(data)))
        data = data[:at] + draw(st.binary(min_size=1, max_size=6)) + data[at:]
    return data


def _finite(*values) -> bool:
    return all(np.all(np.isfinite(np.asarray(v, dtype=float))) for v in values)


def _check_scene(scene) -> None:
    """Everything a scene hands to the solver is finite and bounded."""
    g = scene.grid
    assert g.dim in (2, 3) and 3 <= min(g.cells[: g.dim]) and math.prod(g.cells) <= MAX_CELLS
    assert _finite(g.cell_size_m, g.size_m) and g.cell_size_m > 0
    f = scene.fluid
    assert _finite(f.density_kg_m3, f.viscosity_m2_s, f.body_force_m_s2)
    assert f.density_kg_m3 > 0 and f.viscosity_m2_s >= 0
    assert _finite(scene.run.dt_s) and scene.run.dt_s > 0 and 1 <= scene.run.steps <= MAX_STEPS
    for p in scene.probes:
        assert _finite(p.centre_m, p.orientation, p.velocity_m_s, p.angular_velocity_rad_s)
        assert p.path is None or _finite(p.path)
    for line in scene.lines:
        assert _finite(line.start_m, line.end_m) and 2 <= line.points <= MAX_LINE_POINTS
    for point in scene.points:
        assert _finite(point.at_m)
    s = scene.settings
    assert _finite(s.pressure_tolerance, s.viscosity_tolerance, s.drag_coefficient)
    assert 1 <= s.max_iterations <= MAX_ITERATIONS
    assert estimate_bytes(g, scene.run.steps, len(scene.probes)) > 0  # the budget can be told
    assert math.isfinite(estimate_step_s(g))


@settings(
    max_examples=int(os.environ.get("FUZZ_EXAMPLES", "400")),
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(data=scene_files())
def test_scene_reader_returns_a_finite_scene_or_a_located_input_error(data: bytes) -> None:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "fuzz.toml"
        path.write_bytes(data)
        try:
            scene = load_scene(path)
        except InputError as exc:
            assert exc.source == str(path)
            assert exc.key or exc.line is not None, str(exc)
        else:
            _check_scene(scene)


def test_the_unmutated_scenes_load():
    with tempfile.TemporaryDirectory() as folder:
        for i, scene in enumerate([SCENE_2D, SCENE_3D]):
            path = Path(folder) / f"s{i}.toml"
            path.write_text(to_toml(scene), encoding="utf-8")
            _check_scene(load_scene(path))
