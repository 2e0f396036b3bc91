"""``paintapp figures gallery``: before/after crops at 2x, the 'before' brushes without bristles."""

from __future__ import annotations

import dataclasses

import numpy as np
import OpenImageIO as oiio

from brushes import list_presets, load_preset
from paintapp.cli import main
from paintapp.figures.gallery import ZOOM, paint_piece, stripped_brushes
from paintapp.resources import asset_path


def test_the_before_brushes_are_the_bundled_ones_without_bristles(tmp_path):
    bundled = list_presets(asset_path("brushes"))
    stripped = list_presets(stripped_brushes(tmp_path))
    assert set(stripped) == set(bundled)
    for name, path in bundled.items():
        original, plain = load_preset(path), load_preset(stripped[name])
        assert plain.bristles is None
        assert plain == dataclasses.replace(original, bristles=None)


def test_gallery_writes_before_and_after_at_twice_the_texels(tmp_path, capsys):
    out = tmp_path / "gallery"
    assert main(["figures", "gallery", "--out", str(out), "--only", "glaze"]) == 0
    pictures = {}
    for when in ("before", "after"):
        buf = oiio.ImageBuf(str(out / f"glaze-{when}.png"))
        pictures[when] = np.asarray(buf.get_pixels(oiio.UINT8))
    after = paint_piece("glaze", before=False)
    assert pictures["after"].shape[:2] == (after.shape[0] * ZOOM, after.shape[1] * ZOOM)
    # Each texel is a ZOOM x ZOOM block.
    assert np.array_equal(pictures["after"][::ZOOM, ::ZOOM], pictures["after"][1::ZOOM, 1::ZOOM])
    assert not np.array_equal(pictures["before"], pictures["after"])
    assert "wrote" in capsys.readouterr().out


def test_gallery_refuses_a_file_where_its_folder_goes(tmp_path, capsys):
    target = tmp_path / "taken"
    target.write_text("x")
    assert main(["figures", "gallery", "--out", str(target), "--only", "glaze"]) == 2
    assert "--out" in capsys.readouterr().err
