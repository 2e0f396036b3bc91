"""``paintapp demo [--out DIR]``: paint the bundled demo strokes and show what they felt like.

Replays ``assets/strokes/demo.jsonl`` (several brushes and pigments: blue and yellow mixing to
green, a thick red impasto stroke, white dragged through wet paint, and a clean square probe
dragged through the impasto) through the painting session and the 1 kHz servo loop, then writes
into DIR (default ``paintapp-demo/``): ``canvas.exr`` (the painted canvas with its paint layers),
``preview.png``, ``forces.csv`` (the force trace written to the device, one row per servo tick)
and ``forces.png`` (a plot of it), and ``strokes.jsonl`` (the strokes as painted, on that
canvas). The demo paints as the painting window does, with the ``live`` scene (the 3D grid
fitted to each brush), unless the stroke file or ``--scene`` names another.
``--fidelity``, ``--explain`` and ``--device`` work as for ``paintapp replay``. Its
summary gives the painting's real-time ratio (the replay's wall time over the recording's
length: below 1 is faster than the hand that painted it) and the paint's edge width
(:mod:`paintapp.canvas.edges`).

The demo paints on an artist's sheet: A4 portrait at 0.1 mm texels (2100 x 2970), its strokes
(written for a 12 x 12 cm canvas) centred on it. ``--canvas-size`` (a paper size such as ``a5``,
``WxH`` mm, or ``own`` for the stroke file's canvas) and ``--texel-mm`` choose another; a file
given with ``--strokes`` is painted on its own canvas unless ``--canvas-size`` says otherwise.
Strokes are centred on a larger canvas and kept at its lower-left corner on a smaller one.
``--surface`` paints on a canvas surface with tooth (``fine_linen``, ``cotton_duck``,
``cold_press``, ``gesso``; default ``smooth``, the flat canvas): the paint catches on its peaks,
the preview lights it, the force trace feels it, and ``canvas.exr`` keeps it.
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from concurrent.futures import ThreadPoolExecutor, wait
from pathlib import Path
from typing import TYPE_CHECKING

from paintapp.commands.replay import add_replay_options, print_explanation, replay_with_progress

if TYPE_CHECKING:
    from paintapp.strokes.files import StrokeFile

DEMO_STROKES = ("strokes", "demo.jsonl")
OUTPUT_NAMES = ("canvas.exr", "preview.png", "forces.csv", "forces.png", "strokes.jsonl")
#: The demo's sheet unless ``--canvas-size`` names another; ``own`` keeps the file's canvas.
DEMO_SHEET = "a4"
OWN_CANVAS = "own"
#: The scene the demo paints with when neither ``--scene`` nor the stroke file names one: the
#: painting window's.
DEMO_SCENE = "live"


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "demo",
        help="replay the bundled demo strokes; write canvas, preview and force trace",
        description=__doc__.split("\n\n", 1)[1],
    )
    parser.add_argument(
        "--out", type=Path, default=Path("paintapp-demo"), metavar="DIR", help="output folder"
    )
    parser.add_argument(
        "--strokes", type=Path, metavar="FILE.jsonl", help="replay this file instead of the demo"
    )
    parser.add_argument(
        "--canvas-size",
        metavar="a4|a5|a6[-landscape]|WxH|own",
        help=f"paint on a canvas of this size (paper size, WxH mm, or {OWN_CANVAS!r}: the stroke "
        f"file's own); default {DEMO_SHEET} for the demo, the file's own for --strokes",
    )
    parser.add_argument(
        "--texel-mm",
        type=float,
        default=0.1,
        metavar="MM",
        help="texel size of the sheet, mm (default 0.1; the file's own with --canvas-size own)",
    )
    parser.add_argument(
        "--surface",
        default="smooth",
        metavar="NAME",
        help="canvas surface: smooth (default), gesso, fine_linen, cotton_duck, cold_press",
    )
    add_replay_options(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from paintapp.canvas.edges import paint_edge_widths
    from paintapp.canvas.surfaces import surface_spec
    from paintapp.resources import asset_path
    from paintapp.session.outputs import (
        canvas_picture,
        plot_forces,
        write_canvas_outputs,
        write_forces_csv,
    )
    from paintapp.strokes.files import read_strokes

    start = time.perf_counter()
    surface = surface_spec(args.surface)
    source = args.strokes or asset_path(*DEMO_STROKES)
    strokes = read_strokes(source)
    size = args.canvas_size or (OWN_CANVAS if args.strokes else DEMO_SHEET)
    if size.strip().lower() != OWN_CANVAS:
        strokes = on_canvas(strokes, size, args.texel_mm)
    out = args.out
    files = [("--out", out / name) for name in OUTPUT_NAMES]
    spec = strokes.header.canvas
    print(
        f"painting {source} ({len(strokes.records)} records, {strokes.duration_s:.1f} s) on "
        f"{spec.pixels[0]} x {spec.pixels[1]} texels, {spec.size_m[0] * 1e3:g} x "
        f"{spec.size_m[1] * 1e3:g} mm" + ("" if surface.flat else f", {surface.describe()}")
    )
    canvas, servo = surface_canvas(strokes, surface.name)
    result = replay_with_progress(
        strokes,
        scene_for(strokes, args.scene),
        args.fidelity,
        args.device,
        outputs=files,
        folders=[("--out", out)],
        canvas=canvas,
        servo_config=servo,
    )
    if args.explain:
        print_explanation(result, args.fidelity)
    # the picture first, alone (its draw holds the interpreter lock); then the force plot on a
    # thread of its own while the canvas's files are written
    picture = canvas_picture(result.canvas, lit=not args.flat)
    with ThreadPoolExecutor(max_workers=1, thread_name_prefix="plot") as pool:
        title = f"force on the brush: {Path(source).name}"
        plot = pool.submit(plot_forces, out / "forces.png", result.forces, title)
        try:
            write_canvas_outputs(
                result.canvas,
                out / "canvas.exr",
                out / "preview.png",
                half=args.half,
                picture=picture,
            )
            write_forces_csv(out / "forces.csv", result.forces)
            write_strokes(out / "strokes.jsonl", strokes)
            edges = paint_edge_widths(result.canvas.paint_m)  # while the plot is drawn
        finally:
            wait([plot])  # an error above goes first
        plot.result()
    stats, forces = result.session.stats, result.forces
    peak = float(np.linalg.norm(forces[:, 1:4], axis=1).max()) if len(forces) else 0.0
    print(
        f"{stats.paint_steps} paint steps (median {np.median(stats.step_ms or [0.0]):.0f} ms), "
        f"{len(forces)} servo ticks, peak force {peak:.3g} N; "
        f"{realtime(result.wall_s, strokes.duration_s)}"
    )
    texel = result.canvas.texel_size_m[0]
    for width in edges:
        print(f"paint {width.describe(texel)}")
    for name in OUTPUT_NAMES:
        print(f"wrote {out / name}")
    print(f"done in {time.perf_counter() - start:.1f} s")
    return 0


def scene_for(strokes: StrokeFile, named: str | None) -> str | None:
    """The scene the demo paints ``strokes`` with: the one ``--scene`` named, else None (the one
    the file names) where the file names one, else :data:`DEMO_SCENE`."""
    if named is not None:
        return named
    return DEMO_SCENE if strokes.header.scene is None else None


def surface_canvas(strokes: StrokeFile, surface: str):
    """(canvas, servo configuration) to replay ``strokes`` on ``surface``: a blank canvas of the
    file's size with that surface and a servo whose canvas contact follows its tooth; (None,
    None), the replay's own, for ``smooth``."""
    from paintapp.canvas.model import Canvas
    from paintapp.canvas.surfaces import SMOOTH
    from paintapp.haptics.contact import ContactConfig
    from paintapp.haptics.servo import ServoConfig

    if surface == SMOOTH:
        return None, None
    header = strokes.header
    canvas = Canvas(header.canvas.pixels, header.canvas.size_m, header.pigments, surface=surface)
    return canvas, ServoConfig(contact=ContactConfig(surface=surface))


def realtime(wall_s: float, duration_s: float) -> str:
    """The painting's real-time ratio in words: wall seconds per second of the recording."""
    if duration_s <= 0.0:
        return f"painted in {wall_s:.1f} s (a recording of no length: no real-time ratio)"
    return (
        f"painted in {wall_s:.1f} s for {duration_s:.1f} s of strokes "
        f"({wall_s / duration_s:.2f} s per recorded s)"
    )


def on_canvas(strokes: StrokeFile, size: str, texel_mm: float) -> StrokeFile:
    """``strokes`` moved onto a canvas of ``size`` at ``texel_mm``: its header's canvas replaced,
    and every sample shifted so that the file's canvas sits at the centre of the new one (at its
    lower-left corner along an axis where the new one is smaller)."""
    import numpy as np

    from brushes import StylusSample
    from paintapp.canvas.sizes import canvas_size
    from paintapp.strokes.records import CanvasSpec

    pixels, size_m = canvas_size(size, texel_mm)
    old = strokes.header.canvas.size_m
    shift = np.array([max(0.0, 0.5 * (size_m[i] - old[i])) for i in (0, 1)] + [0.0])
    header = dataclasses.replace(strokes.header, canvas=CanvasSpec(pixels, size_m))
    records = [
        dataclasses.replace(r, position_m=np.asarray(r.position_m, dtype=float) + shift)
        if isinstance(r, StylusSample)
        else r
        for r in strokes.records
    ]
    return dataclasses.replace(strokes, header=header, records=tuple(records))


def write_strokes(path: Path, strokes: StrokeFile) -> None:
    """Write ``strokes`` (header and records) as a stroke file at ``path``, replacing it."""
    from paintapp.strokes.recorder import StrokeRecorder

    with StrokeRecorder(path, strokes.header, overwrite=True) as recorder:
        for record in strokes.records:
            recorder.write(record)
