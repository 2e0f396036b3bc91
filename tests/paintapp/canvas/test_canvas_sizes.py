"""Canvas sizes: paper names and millimetres at a texel size; the window's new canvas is A4."""

from __future__ import annotations

import numpy as np
import pytest

from common.errors import InputError
from paintapp.canvas.exr import read_canvas_exr, write_canvas_exr
from paintapp.canvas.model import Canvas
from paintapp.canvas.sizes import canvas_size


def test_paper_sizes_and_millimetres_give_square_texels():
    pixels, size_m = canvas_size("a4", 0.1)
    assert pixels == (2100, 2970)
    assert size_m == pytest.approx((0.210, 0.297))
    assert canvas_size("A4-landscape", 0.1)[0] == (2970, 2100)
    assert canvas_size("300x200", 0.25)[0] == (1200, 800)
    assert canvas_size("120 x 120 mm", 0.25)[0] == (480, 480)
    for text, texel in (("a4", 0.1), ("a5", 0.07), ("333x111", 0.3)):
        canvas = Canvas(*canvas_size(text, texel))
        dx, dy = canvas.texel_size_m
        assert dx == pytest.approx(texel * 1e-3, rel=1e-9) and dy == pytest.approx(dx, rel=1e-9)


@pytest.mark.parametrize(
    ("text", "texel", "key"),
    [
        ("a3", 0.1, "--canvas-size"),
        ("wide", 0.1, "--canvas-size"),
        ("0x100", 0.1, "--canvas-size"),
        ("a4", 0.0, "--texel-mm"),
        ("a4", float("nan"), "--texel-mm"),
        ("a4", 0.05, "--texel-mm"),  # 4200 x 5940: more than 4096 a side
    ],
)
def test_bad_sizes_name_the_option(text, texel, key):
    with pytest.raises(InputError) as err:
        canvas_size(text, texel)
    assert err.value.key == key and key in str(err.value)


def test_the_window_starts_on_an_a4_canvas_at_a_tenth_of_a_millimetre():
    from paintapp.app.options import PaintOptions, blank_canvas

    canvas = blank_canvas(options=PaintOptions())
    assert canvas.pixels == (2100, 2970)
    assert canvas.texel_size_m[0] == pytest.approx(1e-4)


def test_a_full_a4_canvas_goes_to_exr_and_back(tmp_path):
    pixels, size_m = canvas_size("a4", 0.1)
    canvas = Canvas(pixels, size_m, ("ultramarine_blue", "cadmium_red"))
    paint = np.zeros((2, 2970, 2100), np.float32)
    paint[0, :40, :30] = 1e-4  # bottom-left corner
    paint[1, -25:, -35:] = 2e-4  # top-right corner
    canvas.write_region(0, 0, paint, np.where(paint.sum(axis=0) > 0, 1.0, 0.0))
    write_canvas_exr(tmp_path / "a4.exr", canvas, half=False)
    back = read_canvas_exr(tmp_path / "a4.exr")
    assert back.pixels == pixels and back.size_m == pytest.approx(size_m)
    np.testing.assert_array_equal(back.paint_m, canvas.paint_m)
    np.testing.assert_array_equal(back.wetness, canvas.wetness)


def test_the_commands_take_a_canvas_size_and_name_a_bad_one(tmp_path, capsys):
    from paintapp.cli import build_parser, main
    from paintapp.commands.paint import options_from_args

    args = build_parser().parse_args(
        ["paint", "--canvas-size", "a5-landscape", "--texel-mm", "0.2"]
    )
    options = options_from_args(args)
    assert options.pixels == (1050, 740) and options.size_m == pytest.approx((0.21, 0.148))
    assert options_from_args(build_parser().parse_args(["paint"])).pixels == (2100, 2970)
    bad = build_parser().parse_args(["paint", "--canvas-size", "poster"])
    with pytest.raises(InputError, match="--canvas-size"):
        options_from_args(bad)
    assert main(["demo", "--canvas-size", "a4", "--texel-mm", "0.01", "--out", str(tmp_path)]) == 2
    assert "--texel-mm" in capsys.readouterr().err
