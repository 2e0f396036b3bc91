"""Painting-scene files that are too large or nested too deeply are refused before parsing."""

from __future__ import annotations

import pytest

import paintapp.paint.paint_scene as paint_scene
from common.errors import InputError
from paintapp.paint.paint_scene import load_paint_scene, load_paint_scene_file, parse_paint_scene


def test_deep_nesting_is_one_line_naming_the_file(tmp_path):
    deep = tmp_path / "deep.toml"
    deep.write_text("a = " + "{b = " * 1000 + "1" + "}" * 1000 + "\n", encoding="utf-8")
    with pytest.raises(InputError, match="nested more than") as err:
        load_paint_scene_file(deep)
    assert err.value.source == str(deep) and err.value.line == 1


def test_a_file_beyond_the_cap_is_read_no_further(tmp_path, monkeypatch):
    monkeypatch.setattr(paint_scene, "MAX_TOML_BYTES", 100)
    big = tmp_path / "big.toml"
    big.write_text("# " + "x" * 200 + "\n", encoding="utf-8")
    with pytest.raises(InputError, match="larger than 100 bytes") as err:
        load_paint_scene_file(big)
    assert err.value.source == str(big)


def test_a_paint_scene_s_transport_is_checked():
    """The scenes' ``[paint] transport`` key: flux-corrected by default, upwind on request, any
    other value refused with the key named."""
    assert load_paint_scene("live").transport == "fct"
    assert parse_paint_scene({"paint": {"transport": "upwind"}}, "s").transport == "upwind"
    with pytest.raises(InputError, match="expected one of fct, upwind"):
        parse_paint_scene({"paint": {"transport": "muscl"}}, "s")
