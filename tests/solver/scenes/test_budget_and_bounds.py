"""A run's memory and time estimated before it starts, bounded counts in scene files, and results
that stay finite JSON."""

from __future__ import annotations

import json

import pytest

from common.errors import InputError
from solver.scenes.budget import (
    available_memory_bytes,
    check_memory,
    estimate_bytes,
    estimate_step_s,
    slow_step_warning,
)
from solver.scenes.runner import run_scene
from solver.scenes.scene import MAX_ITERATIONS, MAX_LINE_POINTS, load_scene, parse_scene


def scene_dict(cells=(16, 16), **extra):
    size = [1.0] * len(cells)
    return {
        "domain": {"size": size, "cells": list(cells)},
        "fluid": {"density": 1.0, "viscosity": 0.01},
        "run": {"dt": 0.01, "steps": 2},
        **extra,
    }


def test_memory_estimate_scales_with_cells_and_is_refused_over_what_is_available():
    small = parse_scene(scene_dict((64, 64)), "s.toml")
    big = parse_scene(scene_dict((8000, 8000)), "big.toml")
    assert estimate_bytes(big.grid) == 15_625 * estimate_bytes(small.grid)
    assert 10e9 < estimate_bytes(big.grid) < 20e9  # ~170 B per cell measured
    assert check_memory(small, available=10**9) == estimate_bytes(small.grid, 2, 0)
    with pytest.raises(InputError) as err:
        check_memory(big, available=2 * 10**9)
    assert (err.value.source, err.value.key) == ("big.toml", "domain.cells")
    assert "needs about 12.8 GB of memory; this machine has 2.0 GB available" in str(err.value)


def test_the_recorded_results_count_towards_the_memory():
    scene = parse_scene(scene_dict(run={"dt": 1e-6, "steps": 10**9}), "long.toml")
    with pytest.raises(InputError, match="with the results of 1,000,000,000 steps") as err:
        check_memory(scene, available=10**9)
    assert err.value.key == "run"


def test_available_memory_is_known_on_this_machine():
    have = available_memory_bytes()
    assert have is None or have > 0


def test_a_slow_grid_is_announced_and_a_small_one_is_not():
    assert estimate_step_s(parse_scene(scene_dict((64, 64))).grid) < 0.05
    slow = parse_scene(scene_dict((2000, 2000)), "slow.toml")
    assert estimate_step_s(slow.grid) > 60  # measured: over a minute per step
    message = slow_step_warning(slow)
    assert message is not None and message.startswith("warning: slow.toml: a 2D 2000x2000 grid")
    assert slow_step_warning(parse_scene(scene_dict((128, 128)))) is None


def test_counts_a_file_asks_for_are_bounded():
    line = {"name": "l", "start": [0.0, 0.5], "end": [1.0, 0.5], "points": 10**9}
    with pytest.raises(InputError, match=f"expected an integer <= {MAX_LINE_POINTS}") as err:
        parse_scene(scene_dict(output={"lines": [line]}), "s.toml")
    assert err.value.key == "output.lines[0].points"
    with pytest.raises(InputError, match=f"<= {MAX_ITERATIONS}"):
        parse_scene(scene_dict(solver={"max_iterations": 10**12}))
    with pytest.raises(InputError, match="huge integer"):
        parse_scene(scene_dict(fluid={"density": 10**400, "viscosity": 0.0}))
    probe = {"name": "p", "shape": "circle", "center": [0.5, 0.5], "radius": 0.1}
    probe["path"] = [[0, 0.5, 0.5, 0.0], [10**30, 0.5, 0.5, 0.0]]
    parse_scene(scene_dict(probes=[probe]))  # large but finite: fine
    probe["path"][1][0] = 10**400
    with pytest.raises(InputError, match=r"path\[1\]"):
        parse_scene(scene_dict(probes=[probe]))


def test_a_byte_order_mark_is_skipped_and_toml_errors_have_a_line(tmp_path):
    path = tmp_path / "s.toml"
    path.write_bytes(b"\xef\xbb\xbf[domain]\nsize = [1.0, 1.0]\ncells = [8, 8]\n[fluid]\n")
    path.write_bytes(path.read_bytes() + b"density = 1.0\nviscosity = 0.0\n[run]\ndt = 0.1\n")
    path.write_bytes(path.read_bytes() + b"steps = 1\n")
    assert load_scene(path).grid.cells[:2] == (8, 8)
    path.write_bytes(b"[domain]\nsize = [1.0,\n")
    with pytest.raises(InputError, match="not valid TOML") as err:
        load_scene(path)
    assert err.value.line is not None


def test_a_probe_over_the_whole_domain_is_refused_and_over_a_point_gives_finite_json():
    probe = {"name": "all", "shape": "box", "center": [0.5, 0.5], "size": [3.0, 3.0]}
    with pytest.raises(InputError, match="no fluid is left") as err:
        parse_scene(scene_dict(probes=[probe]))
    assert err.value.key == "probes[0].size"
    probe["size"] = [0.9, 0.9]  # the corners stay fluid
    points = [{"name": "p", "at": [0.5, 0.5]}]
    lines = [{"name": "l", "start": [0.0, 0.5], "end": [1.0, 0.5], "points": 5}]
    scene = parse_scene(scene_dict(probes=[probe], output={"points": points, "lines": lines}))
    results = run_scene(scene)
    text = json.dumps(results, allow_nan=False)  # raises on NaN or infinity
    point = json.loads(text)["points"]["p"]
    assert point["pressure"] is None and "inside a probe" in point["note"]


def test_a_quaternion_too_long_for_floating_point_is_an_input_error():
    probe = {"name": "s", "shape": "sphere", "center": [0.5, 0.5, 0.5], "radius": 0.1}
    probe["orientation"] = [1e308, 1e308, 1e308, 1e308]  # its length overflows (found by fuzzing)
    with pytest.raises(InputError, match="non-zero quaternion") as err:
        parse_scene(scene_dict((8, 8, 8), probes=[probe]))
    assert err.value.key == "probes[0].orientation"
    probe["orientation"] = [1.0, 0.0, 0.0, 0.0]
    probe["path"] = [[0.0, 0.5, 0.5, 0.5, 1e308, 1e308, 1e308, 1e308]]
    with pytest.raises(InputError, match=r"path\[0\]"):
        parse_scene(scene_dict((8, 8, 8), probes=[probe]))
