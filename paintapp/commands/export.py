"""``paintapp export CANVAS.exr --out OUT.exr|OUT.png``: re-render or convert a canvas file.

The picture is rendered again from the paint channels (Kubelka-Munk colour, impasto lighting with
the given light) unless ``--keep-picture`` reuses the file's RGBA, or ``--flat`` asks for the unlit
colour (computed on the CPU, no OpenGL needed). An ``.exr`` output is a full canvas file (paint
channels included, half or float); a ``.png`` output is an 8-bit sRGB preview.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from common.errors import InputError

if TYPE_CHECKING:
    import numpy as np

    from paintapp.canvas.model import Canvas
    from paintapp.pigments.library import PigmentLibrary


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "export",
        help="re-render a canvas EXR to a new EXR or a PNG preview",
        description=__doc__.split("\n\n", 1)[1],
    )
    parser.add_argument("canvas", type=Path, metavar="CANVAS.exr", help="a canvas file")
    parser.add_argument(
        "--out", type=Path, required=True, metavar="OUT", help="output .exr (canvas) or .png"
    )
    parser.add_argument("--preview", type=Path, metavar="P.png", help="also write a PNG preview")
    precision = parser.add_mutually_exclusive_group()
    precision.add_argument(
        "--half", dest="half", action="store_true", default=True, help="16-bit EXR (default)"
    )
    precision.add_argument("--float", dest="half", action="store_false", help="32-bit EXR")
    picture = parser.add_mutually_exclusive_group()
    picture.add_argument("--flat", action="store_true", help="unlit colour (no OpenGL needed)")
    picture.add_argument(
        "--keep-picture", action="store_true", help="reuse the file's RGBA instead of rendering"
    )
    light = parser.add_argument_group("lighting")
    light.add_argument(
        "--light-angle",
        type=float,
        default=135.0,
        metavar="DEG",
        help="light azimuth, counter-clockwise from the canvas's +x axis (default 135: upper left)",
    )
    light.add_argument(
        "--light-elevation",
        type=float,
        default=45.0,
        metavar="DEG",
        help="light height above the canvas plane, (0, 90] degrees (default 45)",
    )
    light.add_argument(
        "--relief", type=float, default=1.0, help="paint height exaggeration (default 1)"
    )
    light.add_argument(
        "--exposure", type=float, default=0.0, metavar="STOPS", help="PNG exposure (default 0)"
    )
    parser.add_argument(
        "--pigments",
        type=Path,
        action="append",
        default=[],
        metavar="DIR",
        help="extra pigment directory (repeatable; overrides bundled pigments of the same name)",
    )
    parser.set_defaults(func=run)


def _picture(args: argparse.Namespace, canvas: Canvas, library: PigmentLibrary) -> np.ndarray:
    """The RGBA picture (H, W, 4), row 0 = bottom, as the options ask."""
    from paintapp.canvas.exr import read_exr_rgba, unlit_rgba

    if args.keep_picture:
        return read_exr_rgba(args.canvas)
    if args.flat:
        return unlit_rgba(canvas, library)
    from paintapp.render import Lighting, RenderUnavailable, render_canvas_rgba

    try:
        lighting = Lighting(
            azimuth_deg=args.light_angle, elevation_deg=args.light_elevation, relief=args.relief
        )
    except ValueError as exc:
        raise InputError(str(exc), key="lighting") from exc
    try:
        return render_canvas_rgba(canvas, library, lighting)
    except RenderUnavailable as exc:
        print(f"paintapp export: {exc}; writing the unlit colour instead", file=sys.stderr)
        return unlit_rgba(canvas, library)


def _check_options(args: argparse.Namespace) -> None:
    """Every lighting option is finite and in range, whether or not this export uses it."""
    from paintapp.canvas.preview import EXPOSURE_RANGE_STOPS

    lo, hi = EXPOSURE_RANGE_STOPS
    checks = [
        ("--exposure", args.exposure, lo <= args.exposure <= hi, f"of stops in [{lo:g}, {hi:g}]"),
        ("--light-angle", args.light_angle, True, "of degrees"),
        ("--light-elevation", args.light_elevation, 0 < args.light_elevation <= 90, "in (0, 90]"),
        ("--relief", args.relief, True, "(1: the true paint height)"),
    ]
    for flag, value, in_range, wanted in checks:
        if not (math.isfinite(value) and in_range):
            raise InputError(f"expected a finite number {wanted}, got {value}", key=flag)


def run(args: argparse.Namespace) -> int:
    from paintapp.canvas.exr import read_canvas_exr, write_canvas_exr
    from paintapp.canvas.preview import write_preview_png
    from paintapp.output_paths import prepare_outputs
    from paintapp.pigments.library import load_pigment_library

    outputs = [args.out, *([args.preview] if args.preview else [])]
    for out in outputs:
        if out.suffix.lower() not in (".exr", ".png"):
            raise InputError("output must end in .exr or .png", source=str(out))
    if args.preview and args.preview.suffix.lower() != ".png":
        raise InputError("the preview must be a .png", source=str(args.preview))
    _check_options(args)
    canvas = read_canvas_exr(args.canvas)
    library = load_pigment_library(*args.pigments)
    library.require(canvas.pigment_names, source=str(args.canvas))
    prepare_outputs([("--out", args.out), ("--preview", args.preview)])
    rgba = _picture(args, canvas, library)
    for out in outputs:
        if out.suffix.lower() == ".exr":
            write_canvas_exr(out, canvas, rgba, half=args.half)
        else:
            write_preview_png(out, rgba, args.exposure)
        print(f"wrote {out} ({canvas.width}x{canvas.height}, {', '.join(canvas.pigment_names)})")
    return 0
