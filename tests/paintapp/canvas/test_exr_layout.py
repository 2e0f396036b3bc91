"""The canvas EXR as OpenEXR's library writes it (every channel converted by numpy a block of rows
at a time): the same file, channel by channel and bit for bit, as OpenImageIO writes from the
whole image in float32, converting each channel to its stored type itself (the way before)."""

from __future__ import annotations

import json

import numpy as np
import OpenImageIO as oiio
import pytest

from paintapp.canvas import exr as canvas_io
from paintapp.canvas.exr import read_canvas_exr, stored_channels, write_canvas_exr
from paintapp.canvas.model import Canvas

PIGMENTS = ("ultramarine_blue", "cadmium_yellow", "titanium_white", "cadmium_red")


def painted(pixels: tuple[int, int], surface: str = "smooth", seed: int = 0) -> Canvas:
    """Random paint with bare texels, paint thinner than half's smallest normal fraction can
    tell apart, and full wetness."""
    rng = np.random.default_rng(seed)
    w, h = pixels
    canvas = Canvas(pixels, (w * 1e-4, h * 1e-4), PIGMENTS, surface=surface)
    paint = rng.uniform(0.0, 2e-4, canvas.paint_m.shape).astype(np.float32)
    paint[rng.uniform(size=paint.shape) < 0.3] = 0.0
    paint[0, :5] = 1e-12  # one pigment's fraction far below the others'
    paint[:, -3:, :7] = 0.0  # bare canvas
    canvas.paint_m[:] = paint
    canvas.wetness[:] = rng.uniform(0.0, 1.0, canvas.wetness.shape)
    canvas.wetness[:2] = 1.0
    return canvas


def picture(canvas: Canvas, seed: int = 1) -> np.ndarray:
    """Linear RGBA with the values a conversion to half could get wrong: NaN, infinities, values
    past half's largest, half's subnormals, ties between two halves, negatives."""
    rng = np.random.default_rng(seed)
    rgba = rng.uniform(-0.1, 1.2, (canvas.height, canvas.width, 4)).astype(np.float32)
    special = np.array(
        [np.nan, np.inf, -np.inf, 7e4, 65504.0, 65520.0, -7e4, 3e-8, 6e-5, 1.0 + 2**-11, 0.0],
        np.float32,
    )
    flat = rgba.reshape(-1)
    step = min(7, flat.size // special.size)
    flat[: special.size * step : step] = special
    flat[-special.size :] = special
    return rgba


def old_pixels(canvas: Canvas, rgba: np.ndarray) -> np.ndarray:
    """The pixels as the whole-image way built them (the picture's values within half's range):
    (H, W, C) float32, top row first."""
    rgba = np.clip(np.nan_to_num(rgba, nan=0.0, posinf=65504.0, neginf=-65504.0), -65504, 65504)
    channels = [rgba[..., i] for i in range(4)] + [canvas.height_m, canvas.wetness]
    channels += list(canvas.concentration)
    if canvas.has_tooth:
        channels.append(canvas.tooth_m)
    pixels = np.empty((canvas.height, canvas.width, len(channels)), np.float32)
    for i, channel in enumerate(channels):
        pixels[..., i] = channel[::-1]
    return pixels


def write_whole(path, canvas, rgba, half) -> None:
    """Write ``canvas`` the whole-image way: OpenImageIO's ``write_image`` of the old pixels,
    converting them to each channel's stored type, with the spec the module wrote before."""
    names = ["R", "G", "B", "A", "paint.height", "paint.wetness"]
    names += [f"pigment.{p}" for p in canvas.pigment_names]
    if canvas.has_tooth:
        names.append("surface.tooth")
    spec = oiio.ImageSpec(canvas.width, canvas.height, len(names), "float")
    spec.channelnames = names
    small = oiio.HALF if half else oiio.FLOAT
    spec.channelformats = tuple(
        oiio.FLOAT if "height" in n or "tooth" in n else small for n in names
    )
    spec.attribute("compression", "zip")
    spec.attribute("chromaticities", oiio.TypeDesc("float[8]"), canvas_io.REC709_CHROMATICITIES)
    info = {"format": "paintapp-canvas", "version": 1, "pixels": list(canvas.pixels)}
    info |= {"size_m": list(canvas.size_m), "pigments": list(canvas.pigment_names)}
    if canvas.has_tooth:
        info["surface"] = canvas.surface
    spec.attribute("paintapp:canvas", json.dumps(info))
    spec.attribute("paintapp:stroke_file", "demo.jsonl")
    out = oiio.ImageOutput.create(str(path))
    assert out is not None
    assert out.open(str(path), spec)
    assert out.write_image(old_pixels(canvas, rgba)), out.geterror()
    out.close()


def attributes(spec: oiio.ImageSpec) -> dict[str, object]:
    """A spec's attributes, by name, but the time of writing (OpenImageIO stamps one)."""
    return {a.name: a.value for a in spec.extra_attribs if a.name != "DateTime"}


@pytest.mark.parametrize(
    ("pixels", "surface", "half"),
    [
        ((37, 50), "smooth", True),
        ((37, 50), "fine_linen", True),  # with the tooth layer
        ((64, 81), "gesso", False),  # 32-bit everywhere, with the tooth
        ((5, 3), "smooth", True),
    ],
)
def test_openexr_writes_the_same_file_as_openimageio_from_the_whole_image(
    tmp_path, pixels, surface, half
):
    canvas = painted(pixels, surface)
    rgba = picture(canvas)
    old, new = tmp_path / "old.exr", tmp_path / "new.exr"
    write_whole(old, canvas, rgba, half)
    write_canvas_exr(new, canvas, rgba, half=half, metadata={"stroke_file": "demo.jsonl"})

    old_spec, old_channels = stored_channels(old)
    new_spec, new_channels = stored_channels(new)
    assert list(new_spec.channelnames) == list(old_spec.channelnames)
    assert [str(f) for f in new_spec.channelformats] == [str(f) for f in old_spec.channelformats]
    assert (new_spec.width, new_spec.height, new_spec.tile_width) == (*canvas.pixels, 0)
    assert attributes(new_spec) == attributes(old_spec)
    for name, values in old_channels.items():
        assert new_channels[name].dtype == values.dtype, name
        np.testing.assert_array_equal(
            new_channels[name].view(np.uint8), values.view(np.uint8), err_msg=name
        )
    if half:
        assert new_channels["R"].dtype == np.float16
    assert new_channels["paint.height"].dtype == np.float32
    for name, values in new_channels.items():  # nothing non-finite in the file
        assert np.isfinite(values).all(), name

    back, before = read_canvas_exr(new), read_canvas_exr(old)
    assert back.surface == before.surface == surface
    np.testing.assert_array_equal(back.paint_m, before.paint_m)
    np.testing.assert_array_equal(back.wetness, before.wetness)


def test_a_write_openexr_refuses_is_an_oserror_and_leaves_no_file(tmp_path, monkeypatch):
    canvas = painted((30, 90))

    class Refusing:
        def __init__(self, header, channels):
            assert all(c.shape == (90, 30) for c in channels.values())

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            return False

        def write(self, path):
            raise RuntimeError("Cannot write image file: disk full")

    monkeypatch.setattr(canvas_io.OpenEXR, "File", Refusing)
    with pytest.raises(OSError, match=r"cannot write .*disk full"):
        write_canvas_exr(tmp_path / "c.exr", canvas, picture(canvas))
    assert list(tmp_path.iterdir()) == []
