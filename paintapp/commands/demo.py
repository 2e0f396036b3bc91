"""``paintapp demo [--out DIR]``: paint the bundled demo strokes and show what they felt like.

Replays ``assets/strokes/demo.jsonl`` (several brushes and pigments: blue and yellow mixing to
green, a thick red impasto stroke, white dragged through wet paint, and a clean square probe
dragged through the impasto) through the painting session and the 1 kHz servo loop, then writes
into DIR (default ``paintapp-demo/``): ``canvas.exr`` (the painted canvas with its paint layers),
``preview.png``, ``forces.csv`` (the force trace written to the device, one row per servo tick)
and ``forces.png`` (a plot of it). ``--fidelity``, ``--explain`` and ``--device`` work as for
``paintapp replay``. ``--canvas-size`` (a paper size such as ``a4``, or ``WxH`` mm) and
``--texel-mm`` paint the same strokes (in metres, from the lower-left corner) on another canvas;
by default the demo's own, 12 x 12 cm at 0.25 mm texels.
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path
from typing import TYPE_CHECKING

from paintapp.commands.replay import add_replay_options, print_explanation, replay_with_progress

if TYPE_CHECKING:
    from paintapp.strokes.files import StrokeFile

DEMO_STROKES = ("strokes", "demo.jsonl")
OUTPUT_NAMES = ("canvas.exr", "preview.png", "forces.csv", "forces.png")


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
        metavar="a4|a5|a6[-landscape]|WxH",
        help="paint on a canvas of this size instead of the file's (paper size or WxH mm)",
    )
    parser.add_argument(
        "--texel-mm",
        type=float,
        default=0.1,
        metavar="MM",
        help="texel size with --canvas-size, mm (default 0.1)",
    )
    add_replay_options(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from paintapp.resources import asset_path
    from paintapp.session.outputs import plot_forces, write_canvas_outputs, write_forces_csv
    from paintapp.strokes.files import read_strokes

    start = time.perf_counter()
    source = args.strokes or asset_path(*DEMO_STROKES)
    strokes = read_strokes(source)
    if args.canvas_size is not None:
        strokes = on_canvas(strokes, args.canvas_size, args.texel_mm)
    out = args.out
    files = [("--out", out / name) for name in OUTPUT_NAMES]
    spec = strokes.header.canvas
    print(
        f"painting {source} ({len(strokes.records)} records, {strokes.duration_s:.1f} s) on "
        f"{spec.pixels[0]} x {spec.pixels[1]} texels, {spec.size_m[0] * 1e3:g} x "
        f"{spec.size_m[1] * 1e3:g} mm"
    )
    result = replay_with_progress(
        strokes, args.scene, args.fidelity, args.device, outputs=files, folders=[("--out", out)]
    )
    if args.explain:
        print_explanation(result, args.fidelity)
    write_canvas_outputs(
        result.canvas, out / "canvas.exr", out / "preview.png", lit=not args.flat, half=args.half
    )
    write_forces_csv(out / "forces.csv", result.forces)
    plot_forces(out / "forces.png", result.forces, f"force on the brush: {Path(source).name}")
    stats, forces = result.session.stats, result.forces
    peak = float(np.linalg.norm(forces[:, 1:4], axis=1).max()) if len(forces) else 0.0
    print(
        f"{stats.paint_steps} paint steps (median {np.median(stats.step_ms or [0.0]):.0f} ms), "
        f"{len(forces)} servo ticks, peak force {peak:.3g} N"
    )
    for name in OUTPUT_NAMES:
        print(f"wrote {out / name}")
    print(f"done in {time.perf_counter() - start:.1f} s")
    return 0


def on_canvas(strokes: StrokeFile, size: str, texel_mm: float) -> StrokeFile:
    """``strokes`` with its header's canvas replaced by one of ``size`` at ``texel_mm``."""
    from paintapp.canvas.sizes import canvas_size
    from paintapp.strokes.records import CanvasSpec

    pixels, size_m = canvas_size(size, texel_mm)
    header = dataclasses.replace(strokes.header, canvas=CanvasSpec(pixels, size_m))
    return dataclasses.replace(strokes, header=header)
