"""Pigments and Kubelka-Munk colour: physics of mixing, colourimetry, pigment files."""

from __future__ import annotations

import itertools

import colour
import numpy as np
import pytest

from common.errors import InputError
from paintapp.canvas.model import Canvas
from paintapp.pigments.bands import Bands, band_table, canvas_linear_rgb, mix_linear_rgb
from paintapp.pigments.kubelka_munk import (
    GROUND_REFLECTANCE,
    reflectance_infinite,
    reflectance_layer,
)
from paintapp.pigments.library import bundled_pigments, load_pigment, load_pigment_directory
from paintapp.pigments.spectra import (
    WAVELENGTHS_NM,
    reflectance_to_linear_rgb,
    srgb_decode,
)


@pytest.fixture(scope="module")
def library():
    return bundled_pigments()


def luminance(rgb: np.ndarray) -> float:
    return float(np.dot([0.2126, 0.7152, 0.0722], rgb))


def lab_hue_deg(rgb: np.ndarray) -> float:
    xyz = colour.RGB_to_XYZ(np.clip(rgb, 1e-6, None), "sRGB", apply_cctf_decoding=False)
    lab = colour.XYZ_to_Lab(
        xyz, colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]
    )
    return float(np.degrees(np.arctan2(lab[2], lab[1])) % 360.0)


def test_bundled_library_has_the_palette(library):
    assert len(library) >= 8
    for name in ("titanium_white", "ultramarine_blue", "cadmium_yellow", "cadmium_red"):
        assert name in library
    for pigment in library.values():
        assert pigment.reflectance.shape == WAVELENGTHS_NM.shape
        assert np.all(pigment.reflectance > 0) and np.all(pigment.reflectance <= 1)


def test_perfect_white_reflector_is_rgb_one_under_d65():
    assert reflectance_to_linear_rgb(np.ones_like(WAVELENGTHS_NM)) == pytest.approx(
        [1.0, 1.0, 1.0], abs=2e-3
    )


@pytest.mark.parametrize("name", ["ultramarine_blue", "cadmium_yellow", "burnt_sienna"])
def test_upsampled_masstone_reproduces_its_srgb_colour(library, name):
    import tomllib

    srgb_hex = tomllib.loads(open(library[name].source, encoding="utf-8").read())["srgb"]
    srgb = np.array([int(srgb_hex[i : i + 2], 16) / 255 for i in (1, 3, 5)])
    expected = srgb_decode(srgb)
    assert library[name].masstone_linear_rgb() == pytest.approx(expected, abs=3e-3)
    band_masstone = mix_linear_rgb(library, {name: 1.0}, bands=Bands())
    assert band_masstone == pytest.approx(expected, abs=0.03)


@pytest.mark.parametrize(
    ("blue", "yellow"), [("ultramarine_blue", "cadmium_yellow"), ("phthalo_blue", "hansa_yellow")]
)
def test_blue_and_yellow_make_green_not_grey(library, blue, yellow):
    for bands in (None, Bands()):
        mix = mix_linear_rgb(library, {blue: 0.5, yellow: 0.5}, bands=bands)
        assert mix[1] > mix[0] and mix[1] > mix[2], mix
        chroma = (mix.max() - mix.min()) / mix.mean()
        assert chroma > 0.8  # a grey of the same mean has chroma 0
        assert 120.0 < lab_hue_deg(mix) < 220.0  # green to blue-green, CIELAB hue
    # Averaging light (additive) would have made a dull, reddish grey instead.
    naive = 0.5 * (library[blue].masstone_linear_rgb() + library[yellow].masstone_linear_rgb())
    assert naive[0] > naive[1] > naive[2]


def test_adding_white_lightens_monotonically(library):
    lum = [
        luminance(mix_linear_rgb(library, {"cadmium_red": 1 - f, "titanium_white": f}))
        for f in (0.0, 0.2, 0.5, 0.8, 1.0)
    ]
    assert all(a < b for a, b in itertools.pairwise(lum))
    tint = mix_linear_rgb(library, {"cadmium_red": 0.5, "titanium_white": 0.5})
    assert tint[0] > tint[1] and tint[0] > tint[2]  # still a red tint


def test_a_pigment_mixed_with_itself_is_itself(library):
    pigment = library["quinacridone_magenta"]
    table = band_table([pigment, pigment])
    alone = band_table([pigment]).linear_rgb(np.array([1.0]))
    for split in (0.1, 0.5, 0.9):
        assert table.linear_rgb(np.array([split, 1 - split])) == pytest.approx(alone, rel=1e-12)
        assert table.linear_rgb(np.array([split, 1 - split]), np.array(2e-5)) == pytest.approx(
            band_table([pigment]).linear_rgb(np.array([1.0]), np.array(2e-5)), rel=1e-12
        )


def test_layer_reflectance_goes_from_ground_to_masstone(library):
    table = band_table([library["ultramarine_blue"]])
    k, s = table.k_per_m[0], table.s_per_m[0]
    assert reflectance_layer(k, s, 0.0) == pytest.approx(np.full(12, GROUND_REFLECTANCE))
    assert reflectance_layer(k, s, 0.05) == pytest.approx(reflectance_infinite(k, s), rel=1e-9)
    blue_band = [reflectance_layer(k, s, x)[0] for x in (1e-6, 1e-5, 1e-4, 1e-3)]
    assert all(a > b for a, b in itertools.pairwise(blue_band))  # covers the ground


def test_reflectances_stay_in_unit_interval(library):
    rng = np.random.default_rng(1)
    table = band_table(list(library.values()))
    conc = rng.dirichlet(np.ones(len(library)) * 0.3, size=500).T
    thickness = 10 ** rng.uniform(-7, -2, size=500)
    for x in (thickness, None):
        r = table.reflectance(conc, x)
        assert np.all(r > 0) and np.all(r <= 1)


def test_canvas_reference_shows_ground_where_bare_and_paint_where_thick(library):
    canvas = Canvas((3, 1), (3e-3, 1e-3))
    i = canvas.add_pigment("ivory_black")
    canvas.paint_m[i, 0, 1] = 1e-5
    canvas.paint_m[i, 0, 2] = 5e-3
    table = band_table(library.require(canvas.pigment_names))
    rgb = canvas_linear_rgb(canvas, table)
    assert rgb[0, 0] == pytest.approx([GROUND_REFLECTANCE] * 3, abs=5e-3)
    assert luminance(rgb[0, 0]) > luminance(rgb[0, 1]) > luminance(rgb[0, 2])
    assert rgb[0, 2] == pytest.approx(library["ivory_black"].masstone_linear_rgb(), abs=5e-3)


def write(tmp_path, name: str, text: str):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_measured_reflectance_file_is_resampled(tmp_path):
    path = write(
        tmp_path,
        "grey.toml",
        'name = "neutral_grey"\n[reflectance]\nwavelengths_nm = [380, 780]\nvalues = [0.5, 0.5]\n',
    )
    pigment = load_pigment(path)
    assert pigment.reflectance == pytest.approx(np.full(WAVELENGTHS_NM.shape, 0.5))
    assert pigment.masstone_linear_rgb() == pytest.approx([0.5, 0.5, 0.5], abs=2e-3)


@pytest.mark.parametrize(
    ("text", "key"),
    [
        ('name = "x"\nsrgb = "#12345"\n', "srgb"),
        ('name = "x"\nsrgb = [1.0, 0.5]\n', "srgb"),
        ('name = "Bad Name"\nsrgb = "#123456"\n', "name"),
        ('name = "x"\n', "srgb"),
        ('name = "x"\nsrgb = "#123456"\nscattering_per_m = -3\n', "scattering_per_m"),
        (
            'name = "x"\n[reflectance]\nwavelengths_nm = [400, 500, 600]\nvalues = [0.1, 0.2]\n',
            "reflectance.values",
        ),
        (
            'name = "x"\n[reflectance]\nwavelengths_nm = [400, 500]\nvalues = [0.1, 1.2]\n',
            "reflectance.values",
        ),
        (
            'name = "x"\n[reflectance]\nwavelengths_nm = [500, 400]\nvalues = [0.1, 0.2]\n',
            "reflectance.wavelengths_nm",
        ),
    ],
)
def test_load_errors_name_file_and_key(tmp_path, text, key):
    path = write(tmp_path, "bad.toml", text)
    with pytest.raises(InputError) as info:
        load_pigment(path)
    assert info.value.source == str(path)
    assert info.value.key == key
    assert str(path) in str(info.value) and key in str(info.value)


def test_load_errors_for_syntax_unknown_keys_and_duplicates(tmp_path):
    with pytest.raises(InputError, match="not valid TOML") as info:
        load_pigment(write(tmp_path, "syntax.toml", "name = \n"))
    assert info.value.source.endswith("syntax.toml")
    with pytest.raises(InputError, match="colour_idx"):
        load_pigment(write(tmp_path, "typo.toml", 'name = "x"\nsrgb = "#123456"\ncolour_idx = 1\n'))
    folder = tmp_path / "dup"
    folder.mkdir()
    write(folder, "a.toml", 'name = "same"\nsrgb = "#123456"\n')
    write(folder, "b.toml", 'name = "same"\nsrgb = "#654321"\n')
    with pytest.raises(InputError, match="also defined") as info:
        load_pigment_directory(folder)
    assert info.value.key == "name"


def test_unknown_pigment_lists_the_known_ones(library):
    with pytest.raises(InputError, match="titanium_white"):
        library.require(["unobtainium_green"])


def test_upsampling_is_cached_on_disk(tmp_path, monkeypatch):
    from paintapp.pigments import spectra as pigments_spectral
    from paintapp.pigments.spectrum_cache import cache_path

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    colour_srgb = (0.3, 0.6, 0.2)
    pigments_spectral._jakob_reflectance.cache_clear()
    fitted = pigments_spectral.srgb_to_reflectance(colour_srgb)
    assert cache_path().is_file() and str(cache_path()).startswith(str(tmp_path))
    pigments_spectral._jakob_reflectance.cache_clear()
    np.testing.assert_array_equal(pigments_spectral.srgb_to_reflectance(colour_srgb), fitted)
    cache_path().write_text("{corrupt", encoding="utf-8")  # a broken cache is ignored
    pigments_spectral._jakob_reflectance.cache_clear()
    np.testing.assert_allclose(pigments_spectral.srgb_to_reflectance(colour_srgb), fitted)
    pigments_spectral._jakob_reflectance.cache_clear()


def test_a_pigment_file_nested_too_deeply_or_too_large_is_refused(tmp_path, monkeypatch):
    import paintapp.pigments.library as library

    deep = tmp_path / "deep.toml"
    deep.write_text("name = 'x'\nreflectance = " + "[" * 1000 + "]" * 1000 + "\n", "utf-8")
    with pytest.raises(InputError, match="nested more than") as err:
        load_pigment(deep)
    assert err.value.source == str(deep) and err.value.line == 2
    monkeypatch.setattr(library, "MAX_TOML_BYTES", 100)
    big = tmp_path / "big.toml"
    big.write_text("# " + "x" * 200 + "\n", "utf-8")
    with pytest.raises(InputError, match="larger than 100 bytes") as err:
        load_pigment(big)
    assert err.value.source == str(big)
