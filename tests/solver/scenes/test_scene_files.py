"""Scene files: the bundled scenes load; malformed scenes name the file, the key and what was
expected."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from common.errors import InputError
from paintapp.cli import main
from paintapp.resources import asset_path
from solver.scenes.scene import load_scene

GOOD = """
[domain]
size = [1.0, 0.5]
cells = [20, 10]

[fluid]
density = 1.0
viscosity = 0.01

[boundary]
x_min = { kind = "inflow", profile = "parabolic", velocity = [0.2, 0.0] }
x_max = { kind = "outflow" }

[[probes]]
name = "c"
shape = "circle"
center = [0.3, 0.25]
radius = 0.05

[run]
dt = 0.05
steps = 4

[[output.lines]]
name = "mid"
start = [0.5, 0.0]
end = [0.5, 0.5]
points = 5

[[output.points]]
name = "front"
at = [0.2, 0.25]
"""


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return path


def test_bundled_scenes_load():
    names = {p.stem for p in asset_path("scenes").glob("*.toml")}
    assert {"lid_cavity_re100", "schaefer_turek_2d1", "paper_square_sweep"} <= names
    for name in names:
        scene = load_scene(asset_path("scenes", f"{name}.toml"))
        assert scene.run.steps >= 1
    sweep = load_scene(asset_path("scenes", "paper_square_sweep.toml"))
    assert sweep.build().probes[0].path_interpolation == "cubic"


@pytest.mark.parametrize(
    ("old", "new", "key", "expected"),
    [
        ("viscosity = 0.01", "viscosity = 0.01\ncolour = 3", "fluid.colour", "not a known key"),
        ("viscosity = 0.01", 'viscosity = "thick"', "fluid.viscosity", "expected a number"),
        ("viscosity = 0.01", "viscosity = -1.0", "fluid.viscosity", ">= 0"),
        ("cells = [20, 10]", "cells = [0, 10]", "domain.cells", "integers >= 1"),
        ("cells = [20, 10]", "cells = [20, 12]", "domain.cells", "equal on every axis"),
        ("center = [0.3, 0.25]", "center = [1.3, 0.25]", "probes[0].center", "outside the domain"),
        ('shape = "circle"', 'shape = "sphere"', "probes[0].shape", "circle, box"),
        ("dt = 0.05", "dt = 0", "run.dt", "> 0"),
        ("dt = 0.05", "dt = 5e-324", "run.dt", "at least 1e-09 s"),
        ("radius = 0.05", "radius = 5.0", "probes[0].radius", "no fluid is left"),
        ("radius = 0.05", "radius = 1e300", "probes[0].radius", "no fluid is left"),
        (
            'x_max = { kind = "outflow" }',
            'x_max = { kind = "drain" }',
            "boundary.x_max.kind",
            "one of",
        ),
        (
            'x_max = { kind = "outflow" }',
            'z_max = { kind = "wall" }',
            "boundary.z_max",
            "not a side",
        ),
        (
            "radius = 0.05",
            "radius = 0.05\npath = [[0.0, 0.3, 0.25, 0.0], [0.0, 0.4, 0.25, 0.0]]",
            "probes[0].path",
            "increase",
        ),
        (
            "radius = 0.05",
            'radius = 0.05\npath_interpolation = "smooth"',
            "probes[0].path_interpolation",
            "cubic",
        ),
        ("[run]", '[solver]\npreconditioner = "ilu"\n\n[run]', "solver.preconditioner", "mic0"),
        (
            "[run]",
            '[solver]\nviscosity_preconditioner = "lu"\n\n[run]',
            "solver.viscosity_preconditioner",
            "jacobi",
        ),
        ("[run]", "[solver]\ncorner_radius_cells = -1\n\n[run]", "solver.corner_radius_cells", "0"),
        ("[run]", "[solver]\nthreads = -1\n\n[run]", "solver.threads", "0"),
        ("[run]", '[solver]\nthreads = "many"\n\n[run]', "solver.threads", "integer"),
        ("[run]", "[solver]\nwarm_start = 1\n\n[run]", "solver.warm_start", "true or false"),
        (
            "[run]",
            "[solver]\ncorner_radius_cells = nan\n\n[run]",
            "solver.corner_radius_cells",
            "number",
        ),
    ],
)
def test_malformed_scene_names_key_and_expectation(tmp_path, old, new, key, expected):
    assert old in GOOD
    path = _write(tmp_path, GOOD.replace(old, new, 1))
    with pytest.raises(InputError) as info:
        load_scene(path)
    message = str(info.value)
    assert str(path) in message
    assert f"'{key}'" in message
    assert expected in message


def test_toml_syntax_error_reports_line(tmp_path):
    path = _write(tmp_path, GOOD.replace("density = 1.0", "density = = 1.0"))
    with pytest.raises(InputError, match=r"line 7"):
        load_scene(path)


def test_simulate_cli_writes_json_results(tmp_path, capsys):
    path = _write(tmp_path, GOOD)
    out = tmp_path / "out.json"
    assert main(["simulate", str(path), "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert len(data["time"]) == 4
    assert data["time"][-1] == pytest.approx(0.2)
    force = data["probes"]["c"]["force"]
    assert len(force) == 4 and len(force[0]) == 2
    assert force[-1][0] > 0  # the flow drags the cylinder downstream
    assert len(data["probes"]["c"]["torque"]) == 4
    assert len(data["lines"]["mid"]["points"]) == 5
    assert len(data["lines"]["mid"]["velocity"][0]) == 2
    assert "pressure" in data["points"]["front"]
    assert data["timing"]["median_step_ms"] > 0
    assert data["timing"]["pressure_iterations"]["max"] >= 1


def test_simulate_cli_bad_scene_exits_nonzero_without_traceback(tmp_path, capsys):
    path = _write(tmp_path, GOOD.replace("viscosity = 0.01", "viscosity = -2.0"))
    assert main(["simulate", str(path)]) == 2
    err = capsys.readouterr().err
    assert "fluid.viscosity" in err and "Traceback" not in err
    assert main(["simulate", str(tmp_path / "missing.toml")]) == 2
    assert "cannot read scene file" in capsys.readouterr().err


def test_a_scene_file_that_never_ends_is_read_no_further_than_the_cap(tmp_path, monkeypatch):
    import solver.scenes.scene as scene_module

    monkeypatch.setattr(scene_module, "MAX_TOML_BYTES", 1000)
    big = tmp_path / "big.toml"
    big.write_text("# " + "x" * 2000 + "\n", encoding="utf-8")
    with pytest.raises(InputError, match="larger than 1000 bytes") as err:
        load_scene(big)
    assert err.value.source == str(big)
    if Path("/dev/zero").exists():
        with pytest.raises(InputError, match="larger than 1000 bytes"):
            load_scene("/dev/zero")


def test_deeply_nested_toml_is_one_line_not_a_recursion_error(tmp_path, capsys):
    deep = tmp_path / "deep.toml"
    deep.write_text("version = 1\na = " + "[" * 1000 + "]" * 1000 + "\n", encoding="utf-8")
    with pytest.raises(InputError, match="nested more than 64") as err:
        load_scene(deep)
    assert err.value.source == str(deep) and err.value.line == 2
    assert main(["simulate", str(deep)]) == 2
    assert "Traceback" not in capsys.readouterr().err


def test_brackets_in_strings_and_comments_are_not_nesting():
    from common.limits import check_nesting

    text = 'a = "' + "[" * 100 + '" # ' + "{" * 100 + "\nb = '" + "[" * 100 + "'\n"
    check_nesting(text, "t.toml", toml=True)
    check_nesting(json.dumps({"k": "[" * 100, "l": [[['\\"[']]]}), "t.json", toml=False)
