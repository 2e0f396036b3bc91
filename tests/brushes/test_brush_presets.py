"""Brush preset files: the bundled ones load; bad ones fail naming the file and the key."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from brushes.presets import (
    find_preset,
    list_presets,
    load_preset,
    load_preset_named,
)
from brushes.tips import RoundCone, RoundedBox
from common.errors import InputError

BUNDLED = Path(__file__).resolve().parents[2] / "assets" / "brushes"

GOOD = """\
shape = "round"
stiffness = 0.4
capacity_m3 = 3.0e-8

[size]
tip_radius_m = 0.0004
belly_radius_m = 0.002
length_m = 0.012

[pressure]
depth_m = 0.0015
exponent = 2.0
spread = 0.8
"""


def write(tmp_path: Path, text: str, name: str = "brush") -> Path:
    path = tmp_path / f"{name}.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_bundled_presets_load_with_millimetre_sizes():
    presets = list_presets(BUNDLED)
    assert {"round_small", "round_large", "flat_wide", "square_probe"} <= set(presets)
    for name, path in presets.items():
        preset = load_preset(path)
        assert preset.name == name
        assert 5e-3 <= preset.length_m <= 30e-3
        assert 0.0 < preset.capacity_m3 <= 1e-6
        tip = preset.tip()
        assert tip.sdf(np.array([0.0, 0.0, -1e-3])) == pytest.approx(1e-3)  # apex at the origin
        assert tip.sdf(np.array([0.0, 0.0, 0.5 * preset.length_m])) < 0.0
    assert isinstance(load_preset_named("round_small", BUNDLED).tip(), RoundCone)
    square = load_preset_named("square_probe", BUNDLED)
    assert isinstance(square.tip(), RoundedBox) and square.stiffness == 1.0
    assert square.tip(square.splay_for_depth(1.0)) == square.tip()  # rigid: never splays


def test_good_preset_values_and_defaults(tmp_path):
    preset = load_preset(write(tmp_path, GOOD, "soft_round"))
    assert preset.name == "soft_round" and preset.shape == "round"
    assert preset.size_m["belly_radius_m"] == 0.002
    assert preset.tilt.gain == 1.0 and preset.description == ""
    assert preset.pressure.depth_for(0.5) == pytest.approx(0.0015 * 0.25)
    for p in (0.0, 0.3, 1.0):
        assert preset.pressure.pressure_for(preset.pressure.depth_for(p)) == pytest.approx(p)
    assert preset.splay_for_depth(0.0) == 1.0
    assert preset.splay_for_depth(1.0) == pytest.approx(1.0 + 0.8 * 0.6)


def test_flat_corner_radius_defaults_to_half_thickness(tmp_path):
    text = GOOD.replace('"round"', '"flat"').replace(
        "tip_radius_m = 0.0004\nbelly_radius_m = 0.002", "width_m = 0.01\nthickness_m = 0.002"
    )
    preset = load_preset(write(tmp_path, text))
    assert preset.size_m["corner_radius_m"] == pytest.approx(0.001)


@pytest.mark.parametrize(
    ("old", "new", "key"),
    [
        ("stiffness = 0.4", "stiffness = 0.4\ncolour = 1", "colour"),
        ("length_m = 0.012", "length_m = 0.012\nradius_m = 0.001", "size.radius_m"),
        ("stiffness = 0.4", 'stiffness = "soft"', "stiffness"),
        ("stiffness = 0.4", "stiffness = true", "stiffness"),
        ("stiffness = 0.4", "stiffness = 1.5", "stiffness"),
        ("capacity_m3 = 3.0e-8", "capacity_m3 = 0.0", "capacity_m3"),
        ("capacity_m3 = 3.0e-8", "capacity_m3 = -1e-8", "capacity_m3"),
        ("tip_radius_m = 0.0004", "tip_radius_m = -0.0004", "size.tip_radius_m"),
        ("tip_radius_m = 0.0004", "tip_radius_m = 0", "size.tip_radius_m"),
        ("length_m = 0.012", "length_m = 12", "size.length_m"),
        ("length_m = 0.012", "length_m = 0.003", "size.length_m"),
        ("length_m = 0.012", "", "size.length_m"),
        ('shape = "round"', 'shape = "oval"', "shape"),
        ("depth_m = 0.0015", "depth_m = 0.05", "pressure.depth_m"),
        ("exponent = 2.0", "exponent = nan", "pressure.exponent"),
        ("spread = 0.8", "spread = -1", "pressure.spread"),
        ("[pressure]\ndepth_m = 0.0015", "[push]\ndepth_m = 0.0015", "push"),
        ("spread = 0.8", "spread = 0.8\n[tilt]\nmax_rad = 2.0", "tilt.max_rad"),
        ("stiffness = 0.4", "stiffness = 0.4\ntilt = 1", "tilt"),
        ("spread = 0.8", "spread = 0.8\n[bristles]\nclumps = 1", "bristles.clumps"),
        ("spread = 0.8", "spread = 0.8\n[bristles]\nclumps = 12.5", "bristles.clumps"),
        ("spread = 0.8", "spread = 0.8\n[bristles]\ncontrast = 1.5", "bristles.contrast"),
        ("spread = 0.8", 'spread = 0.8\n[bristles]\nridge = "high"', "bristles.ridge"),
        ("spread = 0.8", "spread = 0.8\n[bristles]\nseed = -1", "bristles.seed"),
        ("spread = 0.8", "spread = 0.8\n[bristles]\nhairs = 40", "bristles.hairs"),
        ("stiffness = 0.4", "stiffness = 0.4\nbristles = 3", "bristles"),
    ],
)
def test_bad_presets_name_file_and_key(tmp_path, old, new, key):
    assert old in GOOD
    path = write(tmp_path, GOOD.replace(old, new))
    with pytest.raises(InputError) as err:
        load_preset(path)
    assert err.value.source == str(path)
    assert err.value.key == key
    assert str(path) in str(err.value) and f"'{key}'" in str(err.value)


def test_size_hint_for_millimetres_written_as_metres(tmp_path):
    with pytest.raises(InputError, match="metres"):
        load_preset(write(tmp_path, GOOD.replace("length_m = 0.012", "length_m = 12.0")))


def test_flat_must_be_thin(tmp_path):
    text = GOOD.replace('"round"', '"flat"').replace(
        "tip_radius_m = 0.0004\nbelly_radius_m = 0.002", "width_m = 0.002\nthickness_m = 0.004"
    )
    with pytest.raises(InputError) as err:
        load_preset(write(tmp_path, text))
    assert err.value.key == "size.thickness_m"


def test_toml_syntax_error_gives_line(tmp_path):
    path = write(tmp_path, GOOD.replace("stiffness = 0.4", "stiffness = = 0.4"))
    with pytest.raises(InputError) as err:
        load_preset(path)
    assert err.value.line == 2


def test_missing_file_and_unknown_or_unsafe_names(tmp_path):
    with pytest.raises(InputError, match="no such"):
        load_preset(tmp_path / "nothing.toml")
    write(tmp_path, GOOD, "mine")
    assert find_preset("mine", tmp_path) == tmp_path / "mine.toml"
    with pytest.raises(InputError, match="known presets: mine"):
        find_preset("yours", tmp_path)
    with pytest.raises(InputError):
        find_preset("../mine", tmp_path)


def test_bristles_are_optional_per_preset_and_refused_on_a_rigid_probe(tmp_path):
    assert load_preset(write(tmp_path, GOOD)).bristles is None
    text = GOOD + "\n[bristles]\nclumps = 10\ncontrast = 0.6\n"
    bristles = load_preset(write(tmp_path, text)).bristles
    assert bristles is not None and (bristles.clumps, bristles.contrast) == (10, 0.6)
    assert (bristles.ridge, bristles.seed) == (0.5, 0)  # the defaults
    box = text.replace('"round"', '"box"').replace(
        "tip_radius_m = 0.0004\nbelly_radius_m = 0.002", "width_m = 0.004\nthickness_m = 0.004"
    )
    path = write(tmp_path, box)
    with pytest.raises(InputError) as err:
        load_preset(path)
    assert err.value.key == "bristles" and "rigid" in str(err.value) and str(path) in str(err.value)
    for name in ("round_small", "round_large", "flat_wide"):
        assert load_preset_named(name, BUNDLED).bristles is not None
    assert load_preset_named("square_probe", BUNDLED).bristles is None


def test_bristle_profiles_stay_in_range_and_streak_across_the_width():
    bristles = load_preset_named("flat_wide", BUNDLED).bristles
    assert bristles is not None
    u = np.linspace(-1.5, 1.5, 3001)
    gain, loss = bristles.gain_weight(u), bristles.loss_weight(u)
    assert gain.min() > 0.0 and 0.0 <= loss.min() and loss.max() <= 1.0
    inner = np.abs(u) < 0.8
    assert gain[inner].max() / gain[inner].min() > 3.0  # streaks: strong variation across
    peaks = np.count_nonzero(np.diff(np.sign(np.diff(bristles.tracks(u[inner])))) < 0)
    assert peaks >= bristles.clumps // 3  # several separate streaks, not one hump
    assert bristles.edge(np.array([0.0]))[0] == 0.0 and bristles.edge(np.array([1.0]))[0] == 1.0


def test_a_preset_nested_too_deeply_or_too_large_is_refused(tmp_path, monkeypatch):
    import brushes.presets as presets

    deep = tmp_path / "deep.toml"
    deep.write_text("name = 'x'\nshape = " + "[" * 1000 + "]" * 1000 + "\n", "utf-8")
    with pytest.raises(InputError, match="nested more than") as err:
        presets.load_preset(deep)
    assert err.value.source == str(deep) and err.value.line == 2
    monkeypatch.setattr(presets, "MAX_TOML_BYTES", 100)
    big = tmp_path / "big.toml"
    big.write_text("# " + "x" * 200 + "\n", "utf-8")
    with pytest.raises(InputError, match="larger than 100 bytes") as err:
        presets.load_preset(big)
    assert err.value.source == str(big)
