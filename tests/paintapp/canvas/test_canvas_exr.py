"""Canvas files: EXR round trips, metadata, atomic writes, malformed input, PNG previews."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import numpy as np
import OpenImageIO as oiio
import pytest

from common.errors import InputError
from paintapp.canvas import exr as canvas_io
from paintapp.canvas.exr import (
    REC709_CHROMATICITIES,
    read_canvas_exr,
    read_exr_rgba,
    unlit_rgba,
    write_canvas_exr,
)
from paintapp.canvas.model import Canvas
from paintapp.canvas.preview import (
    _srgb8_tables,
    encode_preview,
    srgb8,
    srgb8_reference,
    write_preview_png,
)


def painted_canvas(seed: int = 0) -> Canvas:
    rng = np.random.default_rng(seed)
    canvas = Canvas((20, 12), (0.02, 0.012))
    for name in ("ultramarine_blue", "cadmium_yellow", "titanium_white"):
        canvas.add_pigment(name)
    canvas.paint_m[:] = rng.uniform(0.0, 1e-3, canvas.paint_m.shape)
    canvas.paint_m[:, :3, :4] = 0.0  # some bare canvas
    canvas.wetness[:] = rng.uniform(0.0, 1.0, canvas.wetness.shape)
    return canvas


def test_float_round_trip_is_exact(tmp_path):
    canvas = painted_canvas()
    path = tmp_path / "c.exr"
    write_canvas_exr(path, canvas, half=False)
    back = read_canvas_exr(path)
    assert back.pixels == canvas.pixels and back.size_m == canvas.size_m
    assert back.pigment_names == canvas.pigment_names
    np.testing.assert_allclose(back.paint_m, canvas.paint_m, rtol=1e-6, atol=1e-12)
    np.testing.assert_array_equal(back.wetness, canvas.wetness)
    assert not back.paint_m[:, :3, :4].any()


def test_half_round_trip_within_half_precision(tmp_path):
    canvas = painted_canvas()
    path = tmp_path / "c.exr"
    write_canvas_exr(path, canvas, half=True)
    back = read_canvas_exr(path)
    # Concentrations are 16-bit (11-bit mantissa), the height 32-bit.
    np.testing.assert_allclose(back.paint_m, canvas.paint_m, rtol=2e-3, atol=1e-9)
    np.testing.assert_allclose(back.height_m, canvas.height_m, rtol=1e-6)
    np.testing.assert_allclose(back.wetness, canvas.wetness, atol=5e-4)


def test_file_layout_channels_and_chromaticities(tmp_path):
    canvas = painted_canvas()
    path = tmp_path / "c.exr"
    write_canvas_exr(path, canvas, half=True, metadata={"stroke_file": "demo.jsonl"})
    inp = oiio.ImageInput.open(str(path))
    spec = inp.spec()
    inp.close()
    assert sorted(spec.channelnames) == sorted(
        [
            *("R", "G", "B", "A", "paint.height", "paint.wetness"),
            *("pigment.ultramarine_blue", "pigment.cadmium_yellow", "pigment.titanium_white"),
        ]
    )
    formats = dict(zip(spec.channelnames, (str(f) for f in spec.channelformats), strict=True))
    assert formats["R"] == "half" and formats["paint.height"] == "float"
    assert spec.getattribute("chromaticities") == pytest.approx(REC709_CHROMATICITIES)
    assert spec.getattribute("paintapp:stroke_file") == "demo.jsonl"
    assert spec.getattribute("compression") == "zip"


def test_default_picture_is_the_unlit_colour_top_row_first(tmp_path):
    canvas = painted_canvas()
    path = tmp_path / "c.exr"
    write_canvas_exr(path, canvas, half=False)
    expected = unlit_rgba(canvas)
    np.testing.assert_allclose(read_exr_rgba(path), expected, rtol=1e-6, atol=1e-7)
    inp = oiio.ImageInput.open(str(path))
    top_row = inp.read_image(0, 0, 0, 4, "float")[0]
    inp.close()
    np.testing.assert_allclose(top_row, expected[-1], rtol=1e-6, atol=1e-7)  # canvas top row


def test_failed_write_leaves_the_old_file_intact(tmp_path, monkeypatch):
    path = tmp_path / "c.exr"
    old = painted_canvas(seed=1)
    write_canvas_exr(path, old, half=False)
    old_bytes = path.read_bytes()
    real_write = canvas_io._write_image

    def crash_mid_write(tmp, spec, pixels):
        real_write(tmp, spec, pixels)
        with open(tmp, "r+b") as f:  # a half-written file...
            f.truncate(os.path.getsize(tmp) // 2)
        raise OSError("disk full")  # ...then the writer dies

    monkeypatch.setattr(canvas_io, "_write_image", crash_mid_write)
    with pytest.raises(OSError, match="disk full"):
        write_canvas_exr(path, painted_canvas(seed=2), half=False)
    assert path.read_bytes() == old_bytes
    assert [p.name for p in tmp_path.iterdir()] == ["c.exr"]  # no temporary left behind
    np.testing.assert_allclose(read_canvas_exr(path).paint_m, old.paint_m, rtol=1e-6)


WRITER = """
import sys, numpy as np
from paintapp.canvas.model import Canvas
from paintapp.canvas.exr import write_canvas_exr
canvas = Canvas((512, 512), (0.1, 0.1))
canvas.add_pigment("cadmium_red")
rgba = np.ones((512, 512, 4), np.float32)
i = 0
while True:
    canvas.paint_m[0] = np.random.default_rng(i).uniform(0, 1e-3, (512, 512))
    write_canvas_exr(sys.argv[1], canvas, rgba, half=False)
    print(i, flush=True)
    i += 1
"""


def test_killed_writer_never_leaves_a_broken_file(tmp_path):
    path = tmp_path / "c.exr"
    proc = subprocess.Popen(
        [sys.executable, "-c", WRITER, str(path)], stdout=subprocess.PIPE, text=True
    )
    try:
        assert proc.stdout.readline().strip() == "0"  # one complete file exists
        time.sleep(0.05)
        proc.send_signal(signal.SIGKILL)  # most likely in the middle of the next write
        proc.wait(timeout=10)
    finally:
        if proc.poll() is None:
            proc.kill()
    canvas = read_canvas_exr(path)
    assert canvas.pixels == (512, 512) and canvas.paint_m.max() > 0


def write_plain_exr(path, names, pixels, attributes=()):
    spec = oiio.ImageSpec(pixels.shape[1], pixels.shape[0], len(names), "float")
    spec.channelnames = names
    for key, value in attributes:
        spec.attribute(key, value)
    out = oiio.ImageOutput.create(str(path))
    out.open(str(path), spec)
    assert out.write_image(np.ascontiguousarray(pixels))
    out.close()


def test_missing_channel_names_the_file_and_the_channel(tmp_path):
    path = tmp_path / "c.exr"
    write_canvas_exr(path, painted_canvas(), half=False)
    inp = oiio.ImageInput.open(str(path))
    spec, pixels = inp.spec(), inp.read_image(0, 0, 0, 9, "float")
    inp.close()
    names = list(spec.channelnames)
    keep = [i for i, n in enumerate(names) if n != "pigment.cadmium_yellow"]
    broken = tmp_path / "broken.exr"
    meta = spec.getattribute("paintapp:canvas")
    write_plain_exr(
        broken, [names[i] for i in keep], pixels[..., keep], [("paintapp:canvas", meta)]
    )
    with pytest.raises(InputError, match="missing channel") as info:
        read_canvas_exr(broken)
    assert info.value.source == str(broken) and info.value.key == "pigment.cadmium_yellow"


def test_plain_exr_garbage_and_other_formats_are_input_errors(tmp_path):
    plain = tmp_path / "plain.exr"
    write_plain_exr(plain, ["R", "G", "B"], np.zeros((4, 4, 3), np.float32))
    with pytest.raises(InputError, match="paintapp:canvas"):
        read_canvas_exr(plain)
    garbage = tmp_path / "garbage.exr"
    garbage.write_bytes(b"\x76\x2f\x31\x01" + b"not really an exr" * 10)
    with pytest.raises(InputError) as info:
        read_canvas_exr(garbage)
    assert info.value.source == str(garbage)
    png = tmp_path / "p.png"
    write_preview_png(png, np.zeros((4, 4, 4), np.float32))
    with pytest.raises(InputError, match="OpenEXR"):
        read_canvas_exr(png)
    with pytest.raises(InputError, match="no such file"):
        read_canvas_exr(tmp_path / "missing.exr")


def test_non_finite_paint_in_a_file_is_rejected(tmp_path):
    path = tmp_path / "c.exr"
    write_canvas_exr(path, painted_canvas(), half=False)
    inp = oiio.ImageInput.open(str(path))
    spec, pixels = inp.spec(), inp.read_image(0, 0, 0, 9, "float")
    inp.close()
    pixels[2, 3, 4] = np.nan  # paint.height
    meta = spec.getattribute("paintapp:canvas")
    write_plain_exr(path, list(spec.channelnames), pixels, [("paintapp:canvas", meta)])
    with pytest.raises(InputError, match="1 non-finite"):
        read_canvas_exr(path)


def test_preview_is_srgb_encoded_8_bit_with_the_top_row_first(tmp_path):
    rgba = np.zeros((2, 3, 4), np.float32)
    rgba[0, :, :3] = 0.18  # bottom row: middle grey
    rgba[1, :, :3] = [1.0, 0.0, 2.0]  # top row: clipping above 1
    pixels = encode_preview(rgba)
    assert pixels.dtype == np.uint8 and pixels.shape == (2, 3, 3)
    assert list(pixels[1, 0]) == [118, 118, 118]  # sRGB(0.18) = 0.461
    assert list(pixels[0, 0]) == [255, 0, 255]
    path = tmp_path / "p.png"
    write_preview_png(path, rgba)
    inp = oiio.ImageInput.open(str(path))
    assert inp.spec().format == oiio.UINT8
    np.testing.assert_array_equal(inp.read_image(0, 0, 0, 3, "uint8"), pixels)
    inp.close()


def test_the_preview_s_codes_are_the_srgb_transfer_function_s():
    """The table lookup gives the codes of encoding in float64 and rounding, at every step
    between two codes (and three float32s either side), on a sweep of the float32s in [0, 1],
    and on what is clipped or replaced."""
    _, step_bits = _srgb8_tables()
    steps = step_bits[step_bits < np.iinfo(np.int32).max]
    assert len(steps) == 255
    near = (steps[:, None] + np.arange(-3, 4)[None, :]).ravel().astype(np.int32)
    one = int(np.float32(1.0).view(np.int32))
    sweep = np.arange(0, one + 1, 997, dtype=np.int32)
    special = np.array(
        [np.nan, -np.nan, np.inf, -np.inf, -0.0, 0.0, 1.0, 2.0, -1.0, 1e-45, 0.0031308, 0.18],
        np.float32,
    )
    for values in (near.view(np.float32), sweep.view(np.float32), special):
        np.testing.assert_array_equal(srgb8(values), srgb8_reference(values))
    assert list(srgb8(special[:5])) == [0, 0, 255, 0, 0]


def _claim_size(path, out, width: int, height: int) -> None:
    """Copy an EXR, its header claiming ``width`` x ``height`` pixels."""
    import struct

    raw = bytearray(path.read_bytes())
    for name in (b"dataWindow\0box2i\0", b"displayWindow\0box2i\0"):
        at = raw.index(name) + len(name) + 4
        raw[at + 8 : at + 16] = struct.pack("<ii", width - 1, height - 1)
    out.write_bytes(bytes(raw))


def test_a_header_claiming_a_huge_image_is_one_line(tmp_path):
    path = tmp_path / "c.exr"
    write_canvas_exr(path, painted_canvas(), half=False)
    big = tmp_path / "big.exr"
    _claim_size(path, big, 100_000, 100_000)
    with pytest.raises(InputError) as info:
        read_canvas_exr(big)
    assert info.value.source == str(big) and "\n" not in str(info.value)


def test_deeply_nested_metadata_is_refused_before_parsing(tmp_path):
    path = tmp_path / "c.exr"
    write_canvas_exr(path, painted_canvas(), half=False)
    inp = oiio.ImageInput.open(str(path))
    spec, pixels = inp.spec(), inp.read_image(0, 0, 0, 9, "float")
    inp.close()
    deep = tmp_path / "deep.exr"
    meta = "[" * 5000 + "]" * 5000
    write_plain_exr(deep, list(spec.channelnames), pixels, [("paintapp:canvas", meta)])
    with pytest.raises(InputError, match="nested more than") as info:
        read_canvas_exr(deep)
    assert info.value.source == str(deep) and info.value.key == "paintapp:canvas"


def test_a_huge_height_on_a_bare_texel_is_rejected_not_dropped(tmp_path):
    path = tmp_path / "c.exr"
    write_canvas_exr(path, painted_canvas(), half=False)
    inp = oiio.ImageInput.open(str(path))
    spec, pixels = inp.spec(), inp.read_image(0, 0, 0, 9, "float")
    inp.close()
    row = spec.height - 1  # the file's top row is the canvas's row 0: bare canvas there
    assert np.all(pixels[row, 0, 6:] == 0.0)
    pixels[row, 0, 4] = 1e30  # paint.height
    meta = spec.getattribute("paintapp:canvas")
    write_plain_exr(path, list(spec.channelnames), pixels, [("paintapp:canvas", meta)])
    with pytest.raises(InputError, match="at most") as info:
        read_canvas_exr(path)
    assert info.value.key == "paint.height" and info.value.source == str(path)


@pytest.mark.parametrize("exposure", [0.0, 1.5, -3.0])
def test_the_preview_s_one_pass_gives_the_codes_of_the_array_form(exposure):
    """:func:`encode_preview`'s kernel: the rows flipped, the exposure's float32 product, and
    :func:`srgb8`'s codes, for RGB and RGBA pictures with what is clipped or replaced."""
    rng = np.random.default_rng(5)
    rgba = rng.uniform(-0.2, 1.3, (37, 23, 4)).astype(np.float32)
    special = [np.nan, -np.nan, np.inf, -np.inf, -0.0, 1.0, 2.0, -1.0, 1e-45, 0.0031308]
    rgba.reshape(-1)[: len(special) * 9 : 9] = special
    for picture in (rgba, rgba[..., :3].copy()):
        scaled = picture[::-1, :, :3] * np.float32(2.0**exposure)
        np.testing.assert_array_equal(encode_preview(picture, exposure), srgb8(scaled))
    with pytest.raises(ValueError, match="expected a picture"):
        encode_preview(rgba[..., :2])
