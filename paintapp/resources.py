"""Locating the data that ships with the application (assets and shaders)."""

from __future__ import annotations

from importlib import resources
from pathlib import Path


def asset_path(*parts: str) -> Path:
    """Path of a bundled asset, e.g. ``asset_path("scenes", "lid_cavity_re100.toml")``."""
    base = resources.files("paintapp.assets")
    return Path(str(base.joinpath(*parts)))


def shader_source(name: str) -> str:
    """Source text of the GLSL program file ``shaders/<name>``."""
    return resources.files("paintapp.shaders").joinpath(name).read_text(encoding="utf-8")
