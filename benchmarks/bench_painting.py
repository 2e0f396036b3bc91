"""Time the painting step (paint grid step + transfer), the canvas render, and the demo replay.

Painting step: a loaded small round brush drags across a canvas already covered with wet paint
of four pigments, through each painting scene's model, on canvases of 1024 and 4096 pixels (the
canvas size sets the cell size in texels, so the transfer's cost); median over the steps after a
warm-up, with the phases (follow: the grid re-centred on the tip, with the fluid's state; read:
canvas to grid; solver; exchange with the brush; transport; write: grid to canvas). The exchange
runs within the solver's step (on the other thread beside the pressure solve with two solver
threads, after it with one): its time is part of the solver's, not added to the step. Likewise
the canvas's columns are read within the re-centring (beside it with two threads), so the follow
phase holds that part of the read. Two last rows
take the painting window's defaults instead: its new canvas (A4 at 0.1 mm) and brush
(``round_large``) with the window's one solver thread, in the window's scene (``live``: the grid
fitted to the brush) and in the ``default`` scene (``--window-steps 0`` skips them). Canvas
render: :func:`paintapp.bench.render_timing.time_render` (Mesa llvmpipe here). Demo: the
``paintapp demo`` replay as that command paints it (its A4 sheet, its scene; session + servo
loop, no files), with its real-time ratio (wall seconds per second of the recording) and the
edge width of the canvas it paints (:mod:`paintapp.canvas.edges`).

    python benchmarks/bench_painting.py [--steps N] [--demo-runs N] [--sizes 1024 4096]
                                        [--window-steps N]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from tqdm import tqdm

from brushes import BrushPreset
from paintapp.app.options import PaintOptions
from paintapp.app.settings import PaintSettings, make_preset, make_scene
from paintapp.canvas.edges import EdgeWidth, paint_edge_widths
from paintapp.canvas.model import Canvas
from paintapp.commands.demo import DEMO_SCENE, DEMO_SHEET, on_canvas
from paintapp.paint.paint_scene import PaintScene, load_paint_scene
from paintapp.resources import asset_path
from paintapp.session.painting import PaintingSession
from paintapp.session.playback import replay
from paintapp.strokes.files import read_strokes

# the synthetic stroke generator is test tooling (tests/support), beside this script's folder
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from tests.support.demo_strokes import StrokeSpec, stroke_samples

PIGMENTS = ("ultramarine_blue", "cadmium_yellow", "cadmium_red", "titanium_white")
SCENES = ("default", "push_rings", "open_sides", "follow_cells", "thin_glaze", "no_fluid")
PHASES = ("follow", "read", "solver", "exchange", "transport", "write")
#: Canvas width in metres for each pixel count (a 20 cm and a 40 cm canvas).
CANVAS_M = {1024: 0.2, 4096: 0.4}


def wet_canvas(pixels: int | tuple[int, int], size_m: tuple[float, float] | None = None) -> Canvas:
    """A canvas (square, or (W, H) texels over ``size_m``) covered with smoothly varying wet
    paint of four pigments."""
    w, h = (pixels, pixels) if isinstance(pixels, int) else pixels
    if size_m is None:
        side = CANVAS_M.get(w, 0.2)
        size_m = (side, side)
    y, x = np.mgrid[0:h, 0:w] / max(w, h)
    paint = np.stack(
        [
            (1e-4 * (1.0 + np.sin(9.0 * x * (i + 1) + 4.0 * y * i))).astype(np.float32)
            for i in range(4)
        ]
    )
    wet = np.ones((h, w), np.float32)
    return Canvas((w, h), size_m, PIGMENTS, paint, wet)


def window_case(scene_name: str = "live") -> tuple[Canvas, BrushPreset, PaintScene]:
    """The painting window's defaults: its new canvas, brush and scene (one solver thread), the
    bundled scene ``scene_name`` in place of its own (``live``) if named."""
    settings, options = PaintSettings(), PaintOptions()
    canvas = wet_canvas(options.pixels, options.size_m)
    if scene_name != "live":
        return canvas, make_preset(settings), make_scene(settings, load_paint_scene(scene_name))
    return canvas, make_preset(settings), make_scene(settings, None)


def bench_step(
    scene_name: str, pixels: int, steps: int, case: tuple | None = None
) -> dict[str, float]:
    """Median ms of a paint step and of its phases (``case``: a canvas, brush and scene of
    its own instead, as :func:`window_case` gives)."""
    if case is None:
        canvas = wet_canvas(pixels)
        session = PaintingSession(canvas, "round_small", load_paint_scene(scene_name))
    else:
        canvas = case[0]
        session = PaintingSession(canvas, case[1], case[2])
    session.load_pigment(PIGMENTS[0], 1e-8)
    size = canvas.size_m[0]
    spec = StrokeSpec((0.3 * size, 0.5 * size), (0.7 * size, 0.52 * size), (steps + 10) / 60.0,
                      0.8, (0.2, 0.0))  # fmt: skip
    rows = []
    for i, sample in enumerate(tqdm(stroke_samples(spec, 0.0), desc=f"{scene_name} {pixels}",
                                    leave=False, file=sys.stderr, disable=None)):  # fmt: skip
        step = session.sample(sample)
        if i >= 8 and step.paint is not None:
            rows.append(step.paint)
    out = {"step": statistics.median(r.step_ms for r in rows)}
    for phase in PHASES:
        out[phase] = statistics.median(r.phase_ms.get(phase, 0.0) for r in rows)
    out["cell_mm"] = 1e3 * session.model.cell_size_m
    return out


def bench_render(pixels: int, repeats: int) -> dict[str, float] | None:
    """Render timings (ms) from the renderer's own benchmark, or None without OpenGL."""
    try:
        from paintapp.bench.render_timing import time_render

        t = time_render(pixels, repeats)
    except Exception as exc:  # no EGL context here: report and go on
        print(f"render benchmark unavailable: {exc}", file=sys.stderr)
        return None
    return {"render": 1e3 * t.render_s, "upload": 1e3 * t.full_upload_s,
            "dirty": 1e3 * t.dirty_64_upload_s, "readback": 1e3 * t.readback_s}  # fmt: skip


def bench_demo(runs: int) -> tuple[list[float], float, tuple[EdgeWidth, EdgeWidth]]:
    """Wall seconds of each whole demo replay, the recording's length (s), and the edge widths
    (global and local) of the last replay's canvas (:mod:`paintapp.canvas.edges`)."""
    strokes = on_canvas(read_strokes(asset_path("strokes", "demo.jsonl")), DEMO_SHEET, 0.1)
    scene = load_paint_scene(DEMO_SCENE)
    result = replay(strokes, scene)  # warm-up: compiled kernels, caches
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        result = replay(strokes, scene)
        times.append(time.perf_counter() - start)
    return times, strokes.duration_s, paint_edge_widths(result.canvas.paint_m)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=40, help="timed paint steps per case")
    parser.add_argument("--demo-runs", type=int, default=3)
    parser.add_argument("--render-repeats", type=int, default=5, help="0 skips the render")
    parser.add_argument("--sizes", type=int, nargs="+", default=[1024, 4096])
    parser.add_argument("--window-steps", type=int, default=40,
                        help="timed paint steps of the window's defaults (0 skips them)")  # fmt: skip
    args = parser.parse_args(argv)
    if args.steps < 1 or min(args.window_steps, args.demo_runs, args.render_repeats) < 0:
        parser.error("--steps must be at least 1; --window-steps, --demo-runs and "
                     "--render-repeats at least 0")  # fmt: skip
    print("Painting step (median ms; round_small brush, 60 Hz samples)\n")
    print("| scene (model) | canvas | cell | step | " + " | ".join(PHASES) + " |")
    print("|---|---|---|---|" + "---|" * len(PHASES))
    for scene in SCENES:
        model = load_paint_scene(scene).fluid_model
        for pixels in args.sizes:
            r = bench_step(scene, pixels, args.steps)
            phases = " | ".join(f"{r[p]:.1f}" for p in PHASES)
            print(
                f"| {scene} ({model}) | {pixels}² | {r['cell_mm']:.2f} mm | {r['step']:.1f} | {phases} |"
            )
    for scene_name in ("live", "default") if args.window_steps > 0 else ():
        case = window_case(scene_name)
        r = bench_step(case[2].name, 0, args.window_steps, case)
        phases = " | ".join(f"{r[p]:.1f}" for p in PHASES)
        w, h = case[0].pixels
        print(f"| window: {case[2].name}, {case[1].name}, 1 thread | {w}x{h} | "
              f"{r['cell_mm']:.2f} mm | {r['step']:.1f} | {phases} |")  # fmt: skip
    if args.render_repeats > 0:
        print("\nCanvas render (median ms)\n")
        print("| canvas | full render | full upload | 64x64 dirty upload | readback |")
        print("|---|---|---|---|---|")
        for pixels in args.sizes:
            t = bench_render(pixels, args.render_repeats)
            if t is not None:
                print(
                    f"| {pixels}² | {t['render']:.0f} | {t['upload']:.0f} | {t['dirty']:.2f} | {t['readback']:.0f} |"
                )
    if args.demo_runs > 0:
        times, duration_s, edge = bench_demo(args.demo_runs)
        print(f"\nDemo replay (session + servo loop, no files): median {statistics.median(times):.1f} s "
              f"over {len(times)} runs ({', '.join(f'{t:.1f}' for t in times)} s)")  # fmt: skip
        if duration_s > 0:
            ratios = [t / duration_s for t in times]
            print(f"Demo real-time ratio (wall s per recorded s, {duration_s:.1f} s recorded): "
                  f"median {statistics.median(ratios):.2f} ({', '.join(f'{r:.2f}' for r in ratios)})")  # fmt: skip
        print(f"Demo canvas {edge[0].describe()}")
        print(f"Demo canvas {edge[1].describe()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
