"""``paintapp paint [CANVAS.exr] [--device sim|hid:VID:PID|none] [--scene SCENE.toml]
[--record S.jsonl] [--canvas-size a4|WxH] [--texel-mm MM] [--surface NAME]``: the interactive
painting window.

Paint with a pen tablet (pressure, tilt, twist) or the mouse on a canvas of viscous paint,
simulated live; with a haptic device (``--device``) the brush is steered by the device and its
force reaches the hand through the 1 kHz servo loop (``sim`` is a simulated hand that follows the
pointer; ``openhaptics[:NAME]``, ``dhd`` and ``haply[:ID]`` drive a 3D Systems Touch or Phantom, a
Force Dimension device or Novint Falcon, a Haply Inverse3). A new canvas is A4 at 0.1 mm texels unless ``--canvas-size`` and ``--texel-mm`` say
otherwise, on the flat ``smooth`` surface unless ``--surface`` names one with tooth (``gesso``,
``fine_linen``, ``cotton_duck``, ``cold_press``): thin paint catches on its peaks, the lighting
shows it and a haptic device feels it. File > New asks for the size and the surface again. Every stroke is journalled to ``--record`` as it is painted; the canvas is autosaved
for crash recovery. Press F1 in the window for the keyboard shortcuts.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING, TextIO

from common.errors import InputError
from paintapp.paint.paint_scene import SCENE_FLUID_MODELS, load_paint_scene

if TYPE_CHECKING:
    from paintapp.app.options import PaintOptions


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "paint",
        help="open the painting window (tablet, mouse or haptic device)",
        description=__doc__.split("\n\n", 1)[1],
    )
    parser.add_argument("canvas", nargs="?", type=Path, metavar="CANVAS.exr", help="canvas to open")
    parser.add_argument(
        "--device",
        default="none",
        metavar="sim|hid:VID:PID|openhaptics|dhd|haply|none",
        help="haptic device",
    )
    parser.add_argument(
        "--scene",
        metavar="SCENE",
        help="painting scene: a name or a .toml file (default: live, the 3D grid fitted to the brush)",
    )
    parser.add_argument("--record", type=Path, metavar="S.jsonl", help="journal every stroke here")
    parser.add_argument(
        "--overwrite", action="store_true", help="allow --record to replace an existing file"
    )
    parser.add_argument(
        "--canvas-size",
        default="a4",
        metavar="a4|a5|a6[-landscape]|WxH",
        help="size of a new canvas: a paper size or WxH millimetres (default a4)",
    )
    parser.add_argument(
        "--texel-mm", type=float, default=0.1, metavar="MM", help="texel of a new canvas, mm"
    )
    parser.add_argument(
        "--surface",
        default="smooth",
        metavar="NAME",
        help="surface of a new canvas: smooth (default), gesso, fine_linen, cotton_duck, cold_press",
    )
    parser.add_argument("--brush", default="round_large", help="brush preset to start with")
    parser.add_argument("--model", choices=SCENE_FLUID_MODELS, help="fluid model to start with")
    parser.add_argument("--force-scale", type=float, default=4.0, help="haptic force scale")
    parser.add_argument(
        "--autosave", type=float, default=60.0, metavar="S", help="autosave interval (0: off)"
    )
    parser.add_argument(
        "--simulation",
        choices=("thread", "process"),
        default="thread",
        help="run the simulation in a thread of the window (default) or a process of its own",
    )
    parser.add_argument("--recovery-dir", type=Path, help="autosave folder")
    parser.add_argument(
        "--recover", choices=("ask", "yes", "no"), default="ask", help="after a crash"
    )
    parser.set_defaults(func=run)


def options_from_args(args: argparse.Namespace) -> PaintOptions:
    """Validate the arguments into :class:`PaintOptions` (InputError on bad values)."""
    from paintapp.app.haptic_link import parse_device
    from paintapp.app.options import PaintOptions
    from paintapp.app.recovery import default_recovery_dir
    from paintapp.app.settings import PaintSettings, brush_names
    from paintapp.canvas.sizes import canvas_size

    if args.brush not in brush_names():
        raise InputError(f"unknown brush {args.brush!r}; known: {', '.join(brush_names())}")
    if args.record is not None and args.record.exists() and not args.overwrite:
        raise InputError("the recording file exists; use --overwrite", source=str(args.record))
    if args.canvas is not None and not args.canvas.is_file():
        raise InputError("no such canvas file", source=str(args.canvas))
    if not 0.0 <= args.autosave <= 86400.0:
        raise InputError("expected an interval in [0, 86400] s", key="--autosave")
    pixels, size_m = canvas_size(args.canvas_size, args.texel_mm)
    scene = load_paint_scene(args.scene) if args.scene else None
    model = args.model or (scene.fluid_model if scene else "grid3d")
    settings = PaintSettings(
        brush=args.brush, fluid_model=model, force_scale=args.force_scale, surface=args.surface
    )
    return PaintOptions(
        canvas_path=args.canvas,
        device=parse_device(args.device),
        scene=scene,
        record=args.record,
        overwrite_record=args.overwrite,
        recovery_dir=args.recovery_dir or default_recovery_dir(),
        autosave_s=args.autosave,
        recover=args.recover,
        settings=settings,
        pixels=pixels,
        size_m=size_m,
        simulation=args.simulation,
    )


def run(args: argparse.Namespace) -> int:
    from paintapp.app.launch import NO_DISPLAY, display_available

    if not display_available():
        print(f"paintapp paint: {NO_DISPLAY}", file=sys.stderr)
        return 2
    options = options_from_args(args)
    from paintapp.app.launch import run_paint

    announce_compilation()
    return run_paint(options)


def announce_compilation(stream: TextIO | None = None) -> bool:
    """On a cold kernel cache, say on ``stream`` (default stderr), when it is a terminal, that
    the window's first minute goes to compiling the kernels: its simulation worker compiles
    them before the first stroke (:mod:`paintapp.app.warmup`), the HUD saying ``preparing the
    simulation...`` meanwhile. Returns whether it said so."""
    from paintapp.first_run import MESSAGE, is_terminal, kernels_cold

    stream = stream if stream is not None else sys.stderr
    if not is_terminal(stream) or not kernels_cold():
        return False
    print(
        f"{MESSAGE}: about a minute, while the window says 'preparing the simulation...'",
        file=stream,
    )
    return True
