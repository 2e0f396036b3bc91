"""Canvas files: OpenEXR with the picture and the paint, written atomically with OpenEXR's
library and read with OpenImageIO.

Channels of a canvas EXR (image rows top to bottom, i.e. canvas row H-1 first):

=====================  ========================================================================
``R``, ``G``, ``B``    linear scene-referred colour, sRGB/Rec.709 primaries, D65 white
``A``                  1 on the canvas
``paint.height``       total paint thickness, metres (always 32-bit float: thin paint is ~1e-5 m)
``paint.wetness``      wetness in [0, 1]
``pigment.<name>``     volume fraction of each pigment, in the canvas's channel order
``surface.tooth``      the canvas surface's height, metres, zero-mean (32-bit float; only on a
                       canvas with tooth: :mod:`paintapp.canvas.surfaces`)
=====================  ========================================================================

Attributes: ``chromaticities`` (Rec.709 primaries, D65 white), ``compression`` zip, and
``paintapp:canvas``, a JSON object ``{"format": "paintapp-canvas", "version": 1,
"pixels": [W, H], "size_m": [w, h], "pigments": [...], "surface": NAME}`` (plus any
``paintapp:<key>`` strings passed as ``metadata``). ``half`` files store every channel but the
heights as 16-bit floats. ``surface`` names the canvas surface; a file without it (written before
surfaces existed) reads as ``smooth``. The name is what a reader keeps: the heights are rebuilt
from it (deterministically), and the ``surface.tooth`` layer, written for other tools, is only
checked to lie within the named surface's relief (a layer that does not is refused).
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import OpenEXR
import OpenImageIO as oiio

from common.errors import InputError
from common.limits import check_nesting
from paintapp.atomic import atomic_path
from paintapp.canvas.exr_rows import FLOAT, HALF, file_rows
from paintapp.canvas.model import MAX_PAINT_M, MAX_PIXELS, Canvas
from paintapp.canvas.surfaces import SMOOTH, relief_m, surface_spec
from paintapp.pigments.bands import canvas_band_table, canvas_linear_rgb
from paintapp.pigments.library import PigmentLibrary, load_pigment_library

FORMAT_NAME = "paintapp-canvas"
FORMAT_VERSION = 1
META_KEY = "paintapp:canvas"
#: Rec.709 / sRGB primaries and D65 white: (xr, yr, xg, yg, xb, yb, xw, yw).
REC709_CHROMATICITIES = (0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290)
HEIGHT, WETNESS = "paint.height", "paint.wetness"
TOOTH = "surface.tooth"


def pigment_channel(name: str) -> str:
    """EXR channel name of a pigment's concentration."""
    return f"pigment.{name}"


def unlit_rgba(canvas: Canvas, library: PigmentLibrary | None = None) -> np.ndarray:
    """Unlit Kubelka-Munk colour of a canvas (CPU), (H, W, 4) float32, row 0 = bottom."""
    table = canvas_band_table(canvas, library or load_pigment_library())
    rgba = np.ones((canvas.height, canvas.width, 4), np.float32)
    step = max(1, (1 << 20) // canvas.width)
    for r0 in range(0, canvas.height, step):
        rows = slice(r0, min(canvas.height, r0 + step))
        rgba[rows, :, :3] = canvas_linear_rgb(canvas, table, rows)
    return rgba


#: Channels stored as 32-bit floats in a half file too: heights (thin paint is ~1e-5 m).
WIDE = (HEIGHT, TOOTH)

#: Threads OpenEXR compresses a file's blocks on (its library's global pool; 0, its default,
#: compresses on the calling thread): 1.46 -> 1.17 s for a demo-sized canvas on 2 cores
#: (docs/performance.md, the canvas EXR through OpenEXR).
EXR_THREADS = min(8, os.cpu_count() or 1)


def file_channels(
    canvas: Canvas, rgba: np.ndarray, names: tuple[str, ...], half: bool
) -> dict[str, np.ndarray]:
    """Each channel of the file by name, (H, W) in the type it is stored in (float16 where
    ``half``, but the heights; else float32), image rows top first: ``names`` are the layout's
    (R, G, B, A, height, wetness, the pigments[, tooth]), built in one pass over the texels by
    :func:`~paintapp.canvas.exr_rows.file_rows` (numpy's values and its IEEE round to nearest
    even, as OpenEXR converts)."""
    if len(names) != 6 + len(canvas.pigment_names) + int(canvas.has_tooth):
        raise ValueError(f"expected the canvas's channels, got {names}")
    h, w = canvas.height, canvas.width
    kinds = np.array([HALF if half and n not in WIDE else FLOAT for n in names], np.int64)
    slots = np.zeros(len(names), np.int64)
    for kind in (HALF, FLOAT):
        slots[kinds == kind] = np.arange(np.count_nonzero(kinds == kind))
    halves = np.empty((np.count_nonzero(kinds == HALF), h, w), np.float16)
    floats = np.empty((np.count_nonzero(kinds == FLOAT), h, w), np.float32)
    tooth = canvas.tooth_m if canvas.has_tooth else np.zeros((0, 0), np.float32)
    file_rows(
        np.ascontiguousarray(rgba, np.float32),
        np.ascontiguousarray(canvas.paint_m, np.float32),
        np.ascontiguousarray(canvas.wetness, np.float32),
        np.ascontiguousarray(tooth, np.float32),
        (kinds, slots),
        halves.view(np.uint16),
        floats,
    )
    stores = (halves, floats)
    return {name: stores[kinds[c]][slots[c]] for c, name in enumerate(names)}


def write_canvas_exr(
    path: str | Path,
    canvas: Canvas,
    rgba: np.ndarray | None = None,
    *,
    half: bool = True,
    library: PigmentLibrary | None = None,
    metadata: Mapping[str, str] | None = None,
) -> None:
    """Write a canvas EXR atomically (see the module docstring for the layout) with OpenEXR's
    own library: every channel is handed over in its stored type (:func:`file_channels`), and
    OpenEXR compresses them. The channels are held at once: 2 bytes a texel a half channel, 4 a
    float one (137 MB at A4 with four pigments, about what the canvas itself holds).

    Args:
        path: output file (``.exr``).
        canvas: the canvas.
        rgba: the picture, linear RGBA (H, W, 4), row 0 = canvas bottom (e.g. a lit render);
            default the unlit Kubelka-Munk colour computed on the CPU.
        half: 16-bit float channels (the height stays 32-bit); False writes 32-bit everywhere.
        library: pigments for the default picture.
        metadata: extra string attributes, stored as ``paintapp:<key>``.
    """
    if rgba is None:
        rgba = unlit_rgba(canvas, library)
    rgba = np.asarray(rgba, np.float32)
    if rgba.shape != (canvas.height, canvas.width, 4):
        raise ValueError(
            f"rgba must have shape {(canvas.height, canvas.width, 4)}, got {rgba.shape}"
        )
    names = ("R", "G", "B", "A", HEIGHT, WETNESS, *map(pigment_channel, canvas.pigment_names))
    if canvas.has_tooth:
        names = (*names, TOOTH)
    info = {
        "format": FORMAT_NAME,
        "version": FORMAT_VERSION,
        "pixels": list(canvas.pixels),
        "size_m": list(canvas.size_m),
        "pigments": list(canvas.pigment_names),
    }
    if canvas.has_tooth:
        info["surface"] = canvas.surface
    header: dict[str, object] = {
        "compression": OpenEXR.ZIP_COMPRESSION,
        "type": OpenEXR.scanlineimage,
        "chromaticities": REC709_CHROMATICITIES,
        META_KEY: json.dumps(info, allow_nan=False),
    }
    for key, value in (metadata or {}).items():
        header[f"paintapp:{key}"] = str(value)
    channels = file_channels(canvas, rgba, names, half)
    with atomic_path(path) as tmp:
        _write_image(tmp, header, channels)


def _write_image(path: Path, header: dict[str, object], channels: dict[str, np.ndarray]) -> None:
    """Write one scanline image with OpenEXR: ``header`` its attributes, ``channels`` (H, W)
    arrays by name, image rows top first, compressed on :data:`EXR_THREADS` threads; raises
    OSError with OpenEXR's message on failure."""
    if OpenEXR.global_thread_count() != EXR_THREADS:
        OpenEXR.set_global_thread_count(EXR_THREADS)
    try:
        with OpenEXR.File(header, channels) as image:
            image.write(str(path))
    except (RuntimeError, ValueError, TypeError) as exc:
        raise OSError(f"cannot write {path}: {exc}") from exc


def stored_channels(path: str | Path) -> tuple[oiio.ImageSpec, dict[str, np.ndarray]]:
    """The spec of an EXR and each of its channels by name, (H, W, 1) in the type it is stored
    in (float16 or float32, image rows top first), for comparing files bit for bit."""
    inp = oiio.ImageInput.open(str(path))
    if inp is None:
        raise OSError(f"cannot open {path}: {oiio.geterror()}")
    try:
        spec = inp.spec()
        channels = {}
        for c, name in enumerate(spec.channelnames):
            pixels = inp.read_image(0, 0, c, c + 1, spec.channelformat(c))
            channels[name] = np.asarray(pixels).copy()
    finally:
        inp.close()
    return spec, channels


def _read_info(spec: oiio.ImageSpec, source: str) -> dict:
    raw = spec.getattribute(META_KEY)
    if not isinstance(raw, str):
        raise InputError("not a paintapp canvas: no paintapp:canvas metadata", source, META_KEY)
    check_nesting(raw, source, toml=False, key=META_KEY)
    try:
        info = json.loads(raw)
    except json.JSONDecodeError as exc:
        raise InputError(f"malformed JSON: {exc}", source, META_KEY) from exc
    if not isinstance(info, dict) or info.get("format") != FORMAT_NAME:
        raise InputError(f"expected format {FORMAT_NAME!r}", source, META_KEY)
    if info.get("version") != FORMAT_VERSION:
        raise InputError(f"unsupported version {info.get('version')!r}", source, META_KEY)
    size = info.get("size_m")
    pigments = info.get("pigments")
    if not (isinstance(size, list) and len(size) == 2 and isinstance(pigments, list)):
        raise InputError("expected size_m [w, h] and a pigments list", source, META_KEY)
    return info


def _channel_data(spec, pixels: np.ndarray, names: list[str], source: str) -> list[np.ndarray]:
    present = list(spec.channelnames)
    out = []
    for name in names:
        if name not in present:
            raise InputError(f"missing channel; expected channels {names}", source, key=name)
        out.append(pixels[::-1, :, present.index(name)])
    return out


def read_canvas_exr(path: str | Path) -> Canvas:
    """Load a canvas written by :func:`write_canvas_exr`; malformed files raise InputError."""
    source = str(path)
    spec, pixels = _read_image(Path(path))
    info = _read_info(spec, source)
    if info.get("pixels") != [spec.width, spec.height]:
        raise InputError(
            f"metadata says {info.get('pixels')} pixels, image is {spec.width}x{spec.height}",
            source,
            META_KEY,
        )
    names = [str(n) for n in info["pigments"]]
    height, wetness, *conc = _channel_data(
        spec, pixels, [HEIGHT, WETNESS, *map(pigment_channel, names)], source
    )
    bad = int(np.count_nonzero(~np.isfinite(pixels[..., 4:])))
    if bad:
        raise InputError(f"{bad} non-finite value(s) in the paint channels", source)
    if np.any(height < 0) or any(np.any((c < 0) | (c > 1.001)) for c in conc):
        raise InputError("paint height must be >= 0 and concentrations in [0, 1]", source, HEIGHT)
    if np.any(height > MAX_PAINT_M):  # on bare texels too: no height is dropped unseen
        raise InputError(f"paint height must be at most {MAX_PAINT_M} m", source, HEIGHT)
    if np.any((wetness < 0) | (wetness > 1.001)):
        raise InputError("wetness must be in [0, 1]", source, WETNESS)
    surface = _surface(info, source)
    fractions = np.stack(conc).reshape(len(names), spec.height, spec.width)
    total = fractions.sum(axis=0)
    # Renormalise (16-bit fractions need not sum to 1) so the 32-bit height survives exactly.
    paint = fractions * np.where(total > 0, height / np.where(total > 0, total, 1.0), 0.0)
    try:
        canvas = Canvas(
            pixels=(spec.width, spec.height),
            size_m=(float(info["size_m"][0]), float(info["size_m"][1])),
            pigment_names=tuple(names),
            paint_m=paint.astype(np.float32),
            wetness=np.minimum(wetness, 1.0),
            surface=surface,
        )
    except InputError as exc:
        raise InputError(exc.message, source, exc.key) from exc
    _check_tooth(canvas, spec, pixels, source)
    return canvas


def _surface(info: dict, source: str) -> str:
    """The canvas surface a file names (``smooth`` if none)."""
    name = info.get("surface", SMOOTH)
    if not isinstance(name, str):
        raise InputError("expected a surface name", source, META_KEY)
    try:
        return surface_spec(name, key=META_KEY).name
    except InputError as exc:
        raise InputError(exc.message, source, META_KEY) from exc


def _check_tooth(canvas: Canvas, spec, pixels: np.ndarray, source: str) -> None:
    """A stored tooth layer must lie within the relief of the surface the file names (its
    heights are zero-mean, peak to valley the relief: none is farther than that from 0)."""
    present = list(spec.channelnames)
    if TOOTH not in present:
        return
    stored = pixels[::-1, :, present.index(TOOTH)]
    relief = relief_m(canvas.surface)
    if np.any(np.abs(stored) > relief * (1.0 + 1e-3)):
        raise InputError(
            f"the {TOOTH} layer exceeds the {canvas.surface!r} surface's relief of "
            f"{relief * 1e6:g} um",
            source,
            TOOTH,
        )


def read_exr_rgba(path: str | Path) -> np.ndarray:
    """The RGBA picture of an EXR, (H, W, 4) float32, row 0 = bottom (A = 1 if absent)."""
    spec, pixels = _read_image(Path(path))
    present = list(spec.channelnames)
    rgba = np.ones((spec.height, spec.width, 4), np.float32)
    for i, name in enumerate("RGBA"):
        if name in present:
            rgba[..., i] = pixels[::-1, :, present.index(name)]
        elif name != "A":
            raise InputError(f"missing channel; expected R, G, B (got {present})", str(path), name)
    return rgba


def _one_line(text: str) -> str:
    """OpenImageIO's message on one line, without its advice on raising its own limits."""
    lines = [s.strip() for s in text.splitlines() if s.strip() and "limits:" not in s]
    return " ".join(lines)


def _read_image(path: Path) -> tuple[oiio.ImageSpec, np.ndarray]:
    """(spec, pixels (H, W, C) float32, top row first) of the first subimage of an EXR."""
    source = str(path)
    if not path.is_file():
        raise InputError("no such file", source)
    inp = oiio.ImageInput.open(source)
    if inp is None:
        raise InputError(f"cannot read image: {_one_line(oiio.geterror())}", source)
    try:
        spec = inp.spec()
        if inp.format_name() != "openexr":
            raise InputError(f"expected an OpenEXR file, got {inp.format_name()}", source)
        if spec.x != 0 or spec.y != 0 or spec.deep:
            raise InputError("expected a flat image with its data window at (0, 0)", source)
        if not (1 <= spec.width <= MAX_PIXELS and 1 <= spec.height <= MAX_PIXELS):
            raise InputError(
                f"image is {spec.width}x{spec.height}; canvases are at most {MAX_PIXELS}", source
            )
        pixels = inp.read_image(0, 0, 0, spec.nchannels, "float")
        if pixels is None:
            raise InputError(f"cannot decode pixels: {_one_line(inp.geterror())}", source)
    finally:
        inp.close()
    return spec, np.asarray(pixels, np.float32).reshape(spec.height, spec.width, spec.nchannels)
