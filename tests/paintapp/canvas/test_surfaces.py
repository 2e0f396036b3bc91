"""Canvas surfaces: seamless tiles at their real scale, the stated relief, saved with the canvas."""

from __future__ import annotations

import json

import numpy as np
import OpenImageIO as oiio
import pytest

from common.errors import InputError
from paintapp.canvas.exr import META_KEY, TOOTH, read_canvas_exr, write_canvas_exr
from paintapp.canvas.model import Canvas
from paintapp.canvas.surfaces import (
    SURFACES,
    block_mean,
    sample_tile,
    surface_names,
    surface_spec,
    surface_tile,
    tooth_on_texels,
)

TOOTHED = [name for name in surface_names() if not surface_spec(name).flat]


@pytest.mark.parametrize("name", TOOTHED)
def test_tiles_have_the_stated_relief_zero_mean_and_are_deterministic(name):
    tile = surface_tile(name)
    spec = SURFACES[name]
    assert np.ptp(tile) == pytest.approx(spec.relief_um * 1e-6, rel=1e-9)
    assert abs(tile.mean()) < 1e-12
    np.testing.assert_array_equal(tile, surface_tile.__wrapped__(name))


@pytest.mark.parametrize("name", TOOTHED)
def test_tiles_repeat_seamlessly(name):
    tile = surface_tile(name)
    period = SURFACES[name].tile_mm * 1e-3
    # across the seam the height changes no more than between neighbours inside the tile
    inner = np.abs(np.diff(tile, axis=1)).max()
    seam = np.abs(tile[:, 0] - tile[:, -1]).max()
    assert seam <= 1.01 * inner
    x = np.linspace(0.0, 3 * period, 1001)
    a = sample_tile(tile, period, x, np.full_like(x, 0.001))
    b = sample_tile(tile, period, x + period, np.full_like(x, 0.001 - 2 * period))
    np.testing.assert_allclose(a, b, atol=1e-12)


@pytest.mark.parametrize(("name", "pitch_mm"), [("fine_linen", 0.35), ("cotton_duck", 1.0)])
def test_woven_surfaces_have_their_thread_pitch(name, pitch_mm):
    tile = surface_tile(name)
    spectrum = np.abs(np.fft.rfft(tile - tile.mean(), axis=1)).mean(axis=0)
    freq = np.fft.rfftfreq(tile.shape[1], d=SURFACES[name].tile_mm / tile.shape[1])
    k = int(np.argmax(spectrum[1:])) + 1
    wavelength = 1.0 / freq[k]
    assert min(abs(wavelength - pitch_mm), abs(wavelength - 2 * pitch_mm)) < 0.05 * pitch_mm


def test_tooth_on_texels_matches_the_tile_at_scale_and_smooth_is_flat():
    canvas = Canvas((300, 200), (0.03, 0.02), surface="cotton_duck")
    tooth = canvas.tooth_m
    assert tooth.shape == (200, 300) and tooth.dtype == np.float32
    assert 0.5 * 120e-6 < np.ptp(tooth) <= 120e-6
    # the duck's tile is 24 mm: 240 texels at 0.1 mm, so the texels repeat with it
    np.testing.assert_allclose(tooth[:, :60], tooth[:, 240:300], atol=1e-9)
    part = tooth_on_texels("cotton_duck", canvas.pixels, canvas.texel_size_m, (10, 20, 50, 40))
    np.testing.assert_array_equal(part, tooth[20:40, 10:50])
    assert not Canvas((30, 20), (0.03, 0.02)).tooth_m.any()


def test_block_mean_averages_partial_blocks_over_what_they_hold():
    heights = np.arange(15, dtype=float).reshape(3, 5)
    out = block_mean(heights, 2, (3, 2))
    np.testing.assert_allclose(out, [[3.0, 5.0, 6.5], [10.5, 12.5, 14.0]])


def test_unknown_surfaces_are_refused():
    with pytest.raises(InputError, match="unknown surface"):
        Canvas((10, 10), (0.01, 0.01), surface="velvet")


def test_exr_keeps_the_surface_and_its_tooth_layer(tmp_path):
    canvas = Canvas((120, 80), (0.012, 0.008), ("cadmium_red",), surface="fine_linen")
    canvas.paint_m[0, 10:20, 10:30] = 2e-5
    path = tmp_path / "linen.exr"
    write_canvas_exr(path, canvas)
    inp = oiio.ImageInput.open(str(path))
    spec = inp.spec()
    inp.close()
    assert TOOTH in spec.channelnames
    assert json.loads(spec.getattribute(META_KEY))["surface"] == "fine_linen"
    back = read_canvas_exr(path)
    assert back.surface == "fine_linen"
    np.testing.assert_array_equal(back.tooth_m, canvas.tooth_m)
    np.testing.assert_allclose(back.paint_m, canvas.paint_m, rtol=1e-3)


def test_a_smooth_canvas_file_has_no_tooth_layer_and_reads_as_smooth(tmp_path):
    path = tmp_path / "smooth.exr"
    write_canvas_exr(path, Canvas((20, 10), (0.002, 0.001), ("cadmium_red",)))
    inp = oiio.ImageInput.open(str(path))
    names, meta = inp.spec().channelnames, json.loads(inp.spec().getattribute(META_KEY))
    inp.close()
    assert TOOTH not in names and "surface" not in meta  # as files were before surfaces
    assert read_canvas_exr(path).surface == "smooth"


def _rewrite(path, info_change=None, tooth_scale=1.0):
    inp = oiio.ImageInput.open(str(path))
    spec = inp.spec()
    pixels = inp.read_image(0, 0, 0, spec.nchannels, "float")
    inp.close()
    info = json.loads(spec.getattribute(META_KEY))
    info.update(info_change or {})
    spec.attribute(META_KEY, json.dumps(info))
    channels = list(spec.channelnames)
    if TOOTH in channels:
        pixels[..., channels.index(TOOTH)] *= tooth_scale
    out = oiio.ImageOutput.create(str(path))
    out.open(str(path), spec)
    out.write_image(pixels)
    out.close()


def test_a_surface_file_with_a_foreign_name_or_layer_is_refused(tmp_path):
    path = tmp_path / "duck.exr"
    write_canvas_exr(
        path, Canvas((40, 30), (0.004, 0.003), ("cadmium_red",), surface="cotton_duck")
    )
    _rewrite(path, tooth_scale=10.0)  # not the surface's heights: far beyond its relief
    with pytest.raises(InputError, match="relief"):
        read_canvas_exr(path)
    _rewrite(path, {"surface": "velvet"})
    with pytest.raises(InputError, match="unknown surface"):
        read_canvas_exr(path)
    _rewrite(path, {"surface": 3})
    with pytest.raises(InputError, match="surface name"):
        read_canvas_exr(path)
