"""``paintapp replay STROKES.jsonl --out CANVAS.exr [--preview P.png] [--forces F.csv]``.

Replays a stroke file through the same path as live painting -- stylus, brush, paint grid,
canvas, and the force path through the 1 kHz servo loop -- on a virtual clock, so the same file
always gives the same canvas and the same force trace. Writes the canvas EXR (picture, paint
height, wetness and pigment layers), optionally a PNG preview and the forces CSV (a header row,
then per servo tick: time, force x/y/z in N, torque x/y/z in N m, as written to the device).

``--fidelity draft|standard|high`` replays with another fidelity's fluid settings (paint at
draft, render the final canvas at high); ``--explain`` prints every modelling decision with its
reason and what ran; ``--device 6dof|3dof|tablet`` plays on a device with less output.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from common.errors import InputError
from paintapp.paint.fidelity import FIDELITIES, FIDELITY_NAMES
from paintapp.paint.paint_scene import load_paint_scene

if TYPE_CHECKING:
    from paintapp.canvas.model import Canvas
    from paintapp.haptics.servo import ServoConfig
    from paintapp.output_paths import Outputs
    from paintapp.session.playback import ReplayResult
    from paintapp.strokes.files import StrokeFile


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "replay",
        help="replay a stroke file onto a canvas (EXR), with its force trace",
        description=__doc__.split("\n\n", 1)[1],
    )
    parser.add_argument("strokes", type=Path, metavar="STROKES.jsonl", help="a stroke file")
    parser.add_argument("--out", type=Path, required=True, metavar="CANVAS.exr", help="canvas EXR")
    parser.add_argument("--preview", type=Path, metavar="P.png", help="also write a PNG preview")
    parser.add_argument("--forces", type=Path, metavar="F.csv", help="also write the force trace")
    add_replay_options(parser)
    parser.set_defaults(func=run)


def add_replay_options(parser: argparse.ArgumentParser) -> None:
    """Options shared by ``replay`` and ``demo``."""
    from paintapp.session.replay_devices import REPLAY_DEVICES

    parser.add_argument(
        "--scene",
        metavar="NAME|FILE.toml",
        help="painting scene (default: the one the stroke file names, else 'default')",
    )
    parser.add_argument(
        "--flat", action="store_true", help="unlit colour in the picture (no OpenGL needed)"
    )
    parser.add_argument("--float", dest="half", action="store_false", help="32-bit EXR")
    parser.add_argument(
        "--fidelity",
        choices=FIDELITY_NAMES,
        help="fluid settings on top of the scene: "
        + "; ".join(f"{f.name}: {f.description}" for f in FIDELITIES.values()),
    )
    parser.add_argument(
        "--explain", action="store_true", help="print each modelling decision, its reason, counts"
    )
    parser.add_argument(
        "--device",
        choices=tuple(REPLAY_DEVICES),
        default="6dof",
        help="device played on: 6dof (force and torque, default), 3dof (no torque), tablet "
        "(no force feedback: no force work at all)",
    )


def check_suffix(path: Path | None, suffix: str, what: str) -> None:
    """InputError unless ``path`` (if given) ends in ``suffix``."""
    if path is not None and path.suffix.lower() != suffix:
        raise InputError(f"the {what} must be a {suffix} file", source=str(path))


#: Pauses in a stroke file warned about one by one; the rest are counted.
GAP_WARNINGS_SHOWN = 3


def replay_with_progress(
    strokes: StrokeFile,
    scene_name: str | None,
    fidelity: str | None = None,
    device: str | None = None,
    *,
    outputs: Outputs = (),
    folders: Outputs = (),
    canvas: Canvas | None = None,
    servo_config: ServoConfig | None = None,
) -> ReplayResult:
    """Replay with a progress bar on stderr, after the kernels' first compilation when their
    cache is cold (:func:`~paintapp.first_run.warm_up`; a second process compiles them from the
    other end meanwhile, :mod:`paintapp.compile_ahead`). Before any work: the scene, the brush
    presets and pigments the file names, and the ``outputs`` (files) and ``folders`` the
    command will write (:func:`~paintapp.output_paths.prepare_outputs`) are checked; a
    truncated file and long pauses are warned about. ``canvas`` and ``servo_config`` go to
    :func:`~paintapp.session.playback.replay` (a canvas of another surface, its felt tooth)."""
    from tqdm import tqdm

    from paintapp.compile_ahead import compiling_ahead
    from paintapp.first_run import warm_up
    from paintapp.output_paths import prepare_outputs
    from paintapp.pigments.library import load_pigment_library
    from paintapp.session.playback import check_stroke_names, replay
    from paintapp.strokes.files import MAX_GAP_S

    if strokes.truncated:
        print(f"warning: {strokes.source}: {strokes.warning}", file=sys.stderr)
    if scene_name is not None:
        scene = load_paint_scene(scene_name)
    else:
        try:
            scene = load_paint_scene(strokes.header.scene)
        except InputError as exc:
            raise InputError(exc.message, strokes.source, "scene", 1) from None
    check_stroke_names(strokes, pigments=set(load_pigment_library()))
    prepare_outputs(outputs, folders)
    for line, gap in strokes.gaps[:GAP_WARNINGS_SHOWN]:
        print(
            f"warning: {strokes.source}, line {line}: {gap:.3g} s after the record before it "
            f"(a pause longer than {MAX_GAP_S:g} s): replayed with the pen lifted; the force "
            f"trace keeps its first {MAX_GAP_S:g} s",
            file=sys.stderr,
        )
    if len(strokes.gaps) > GAP_WARNINGS_SHOWN:
        more = len(strokes.gaps) - GAP_WARNINGS_SHOWN
        print(f"warning: {strokes.source}: {more} more such pause(s)", file=sys.stderr)
    with compiling_ahead():
        warm_up(strokes, scene, fidelity, device)
        with tqdm(
            total=len(strokes.records),
            unit="record",
            desc="replay",
            file=sys.stderr,
            disable=None,
            leave=False,
        ) as bar:
            return replay(
                strokes,
                scene,
                canvas=canvas,
                servo_config=servo_config,
                progress=bar.update,
                fidelity=fidelity,
                device=device,
            )


def print_explanation(result: ReplayResult, fidelity: str | None) -> None:
    """Print the ``--explain`` report of a replay."""
    from paintapp.session.explain import explain_session

    s = result.session.scene
    name = fidelity or "standard"
    header = (
        f"scene {s.name!r} ({s.fluid_model}), fidelity {name} ({FIDELITIES[name].description}): "
        f"cells {'x'.join(map(str, s.cells))}, pressure tol {s.solver.pressure_tolerance:g}, "
        f"viscosity tol {s.solver.viscosity_tolerance:g}, cap {s.solver.max_iterations}, "
        f"advection {s.solver.advection}, max step {s.max_step_s:.4g} s, travel per step at "
        f"most {s.max_travel_cells:g} cells (up to {s.max_travel_substeps} sub-steps), "
        + (
            f"paint still below {s.still_rate_per_s:g} of a column a second"
            if s.still_rate_per_s > 0.0
            else "every change written"
        )
    )
    print(explain_session(result.session, header))


def run(args: argparse.Namespace) -> int:
    from paintapp.session.outputs import write_canvas_outputs, write_forces_csv
    from paintapp.strokes.files import read_strokes

    check_suffix(args.out, ".exr", "canvas output")
    check_suffix(args.preview, ".png", "preview")
    check_suffix(args.forces, ".csv", "forces output")
    strokes = read_strokes(args.strokes)
    outputs = [("--out", args.out), ("--preview", args.preview), ("--forces", args.forces)]
    result = replay_with_progress(strokes, args.scene, args.fidelity, args.device, outputs=outputs)
    if args.explain:
        print_explanation(result, args.fidelity)
    write_canvas_outputs(result.canvas, args.out, args.preview, lit=not args.flat, half=args.half)
    if args.forces is not None:
        write_forces_csv(args.forces, result.forces)
    stats = result.session.stats
    n = result.skipped_ticks
    skipped = f", {n if n < 10**9 else format(float(n), '.3g')} skipped in pauses" if n else ""
    print(
        f"replayed {len(strokes.records)} records ({stats.paint_steps} paint steps, "
        f"{len(result.forces)} servo ticks{skipped}) in {result.wall_s:.1f} s; wrote {args.out}"
        + "".join(f", {p}" for p in (args.preview, args.forces) if p is not None)
    )
    return 0
