"""``paintapp figures surfaces [--out DIR]``: one dry-brush stroke on three canvas surfaces.

The same light stroke of the large round brush, loaded with a little burnt sienna, painted
through the whole painting path (the ``live`` scene's 3D paint grid, the canvas with its tooth,
the lit render) on a 40 x 24 mm canvas at 0.1 mm texels of each of ``fine_linen``,
``cotton_duck`` and ``cold_press`` (``--surface`` picks others, repeatable), and rendered headless
at two zooms: ``<surface>-100.png``, a 30 x 16 mm crop at one texel per pixel (100 %), and
``<surface>-800.png``, a 4 x 3 mm crop at eight pixels per texel (800 %) from the stroke's edge,
where the paint thins out onto the peaks of the tooth. Writes into DIR (default
``docs/gallery/surfaces``).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

#: The canvas: pixels and metres (0.1 mm texels).
PIXELS, SIZE_M = (400, 240), (0.04, 0.024)
#: The stroke: from, to (m), pressure, and the paint on the brush (m^3).
STROKE = ((0.006, 0.012), (0.034, 0.012), 0.3, 8e-9)
PIGMENT = "burnt_sienna"
#: The crops, canvas metres (x0, y0, x1, y1), and their zooms (screen pixels per texel).
CROPS = {"100": ((0.005, 0.004, 0.035, 0.020), 1), "800": ((0.018, 0.0125, 0.022, 0.0155), 8)}
SURFACES = ("fine_linen", "cotton_duck", "cold_press")


def register(figs: argparse._SubParsersAction) -> None:
    p = figs.add_parser(
        "surfaces",
        help="a dry-brush stroke on three canvas surfaces, at 100 %% and 800 %%",
        description=__doc__.split("\n\n", 1)[1],
    )
    p.add_argument(
        "--out",
        type=Path,
        default=Path("docs/gallery/surfaces"),
        metavar="DIR",
        help="output folder",
    )
    p.add_argument(
        "--surface", action="append", metavar="NAME", help="paint on this surface (repeatable)"
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from paintapp.canvas.surfaces import surface_spec
    from paintapp.output_paths import prepare_outputs

    surfaces = [surface_spec(s).name for s in dict.fromkeys(args.surface or SURFACES)]
    out: Path = args.out
    paths = {(s, z): out / f"{s}-{z}.png" for s in surfaces for z in CROPS}
    prepare_outputs([("--out", p) for p in paths.values()], [("--out", out)])
    for surface in surfaces:
        canvas = paint_stroke(surface)
        for zoom, picture in render_crops(canvas).items():
            write_png(paths[surface, zoom], picture)
            print(f"wrote {paths[surface, zoom]} ({picture.shape[1]} x {picture.shape[0]} px)")
    return 0


def paint_stroke(surface: str):
    """The canvas of ``surface`` with the figure's stroke painted on it."""
    from brushes import load_preset_named
    from paintapp.canvas.model import Canvas
    from paintapp.paint.paint_scene import load_paint_scene
    from paintapp.resources import asset_path
    from paintapp.session.painting import PaintingSession

    canvas = Canvas(PIXELS, SIZE_M, (PIGMENT,), surface=surface)
    preset = load_preset_named("round_large", asset_path("brushes"))
    session = PaintingSession(canvas, preset, load_paint_scene("live"))
    session.load_pigment(PIGMENT, STROKE[3])
    for sample in stroke_samples():
        session.sample(sample)
    return canvas


def stroke_samples(duration_s: float = 0.8, rate_hz: float = 200.0, ramp_s: float = 0.1):
    """The stylus samples of :data:`STROKE`: a straight line at an even pace, the pressure rising
    over ``ramp_s`` and falling at the end (zero at the first and last sample)."""
    from brushes import StylusSample

    (x0, y0), (x1, y1), pressure, _ = STROKE
    n = round(duration_s * rate_hz) + 1
    out = []
    for i in range(n):
        s = i / (n - 1)
        t = s * duration_s
        ramp = min(t, duration_s - t) / ramp_s
        p = 0.0 if i in (0, n - 1) else pressure * math.sin(0.5 * math.pi * min(ramp, 1.0))
        position = np.array([x0 + s * (x1 - x0), y0 + s * (y1 - y0), 0.0])
        out.append(StylusSample(t, position, p, np.zeros(2), 0.0, 1))
    return out


def render_crops(canvas) -> dict[str, np.ndarray]:
    """The lit crops of :data:`CROPS` (linear RGBA, row 0 = bottom), rendered headless through
    a :class:`~paintapp.render.view.ViewRect` of the crop at one pixel per texel, then each
    texel repeated ``zoom`` times along both axes: the painting window's magnified view (texels
    shaded once each, drawn sharp above 100 %)."""
    from paintapp.pigments.library import load_pigment_library
    from paintapp.render.context import create_headless_context
    from paintapp.render.renderer import CanvasRenderer
    from paintapp.render.view import ViewRect

    ctx = create_headless_context()
    try:
        renderer = CanvasRenderer(ctx, load_pigment_library())
        canvas.mark_all_dirty()
        renderer.update(canvas)
        texel = canvas.texel_size_m[0]
        out = {}
        for name, (box, zoom) in CROPS.items():
            size = (round((box[2] - box[0]) / texel), round((box[3] - box[1]) / texel))
            renderer.render(size=size, view=ViewRect(*box))
            picture = renderer.read_linear_rgba()
            out[name] = np.repeat(np.repeat(picture, zoom, axis=0), zoom, axis=1)
        renderer.release()
        return out
    finally:
        ctx.release()


def write_png(path: Path, rgba: np.ndarray) -> None:
    """Write ``rgba`` (row 0 = bottom) as an sRGB PNG."""
    from paintapp.canvas.preview import write_preview_png

    write_preview_png(path, rgba)
