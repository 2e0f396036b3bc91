"""Timing the canvas renderer: ``python -m paintapp.bench.render_timing [SIZE ...]``.

Builds a square canvas 0.4 m wide with six pigments of varying thickness, then times (median
of ``repeats`` runs, GPU work finished with ``ctx.finish()``):

- a full upload of the canvas to the textures,
- a full-canvas render (Kubelka-Munk mixing + lighting, one pixel per texel),
- the readback of the float framebuffer,
- the upload of a 64x64 dirty region (what one brush step typically sends).
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable
from dataclasses import dataclass

import moderngl
import numpy as np

from paintapp.canvas.model import Canvas
from paintapp.pigments.library import load_pigment_library
from paintapp.render.context import create_headless_context
from paintapp.render.renderer import CanvasRenderer

PIGMENTS = (
    "titanium_white",
    "ultramarine_blue",
    "cadmium_yellow",
    "cadmium_red",
    "burnt_sienna",
    "ivory_black",
)


@dataclass(frozen=True)
class RenderTiming:
    """Median seconds of each stage for one canvas size (pixels x pixels)."""

    pixels: int
    full_upload_s: float
    render_s: float
    readback_s: float
    dirty_64_upload_s: float
    renderer: str


def benchmark_canvas(pixels: int) -> Canvas:
    """A square test canvas with smoothly varying paint of every pigment in :data:`PIGMENTS`."""
    canvas = Canvas((pixels, pixels), (0.4, 0.4))
    y, x = np.mgrid[0:pixels, 0:pixels] / pixels
    for i, name in enumerate(PIGMENTS):
        canvas.add_pigment(name)
        canvas.paint_m[i] = 1e-4 * (1.0 + np.sin(7.0 * x * (i + 1) + 3.0 * y * i))
    canvas.wetness[:] = 0.5
    return canvas


def _median_time(ctx: moderngl.Context, work: Callable[[], object], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        work()
        ctx.finish()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def time_render(pixels: int, repeats: int = 5, ctx: moderngl.Context | None = None) -> RenderTiming:
    """Time upload, render and readback of a ``pixels`` x ``pixels`` canvas."""
    own = ctx is None
    ctx = ctx or create_headless_context()
    canvas = benchmark_canvas(pixels)
    renderer = CanvasRenderer(ctx, load_pigment_library())
    try:
        renderer.update(canvas)
        renderer.render()  # warm-up: shader compilation, target allocation
        renderer.read_linear_rgba()

        def full_upload() -> None:
            canvas.mark_all_dirty()
            renderer.update(canvas)

        def dirty_upload() -> None:
            canvas.mark_dirty(100, 100, 164, 164)
            renderer.update(canvas)

        return RenderTiming(
            pixels=pixels,
            full_upload_s=_median_time(ctx, full_upload, repeats),
            render_s=_median_time(ctx, renderer.render, repeats),
            readback_s=_median_time(ctx, renderer.read_linear_rgba, repeats),
            dirty_64_upload_s=_median_time(ctx, dirty_upload, repeats),
            renderer=ctx.info["GL_RENDERER"],
        )
    finally:
        renderer.release()
        if own:
            ctx.release()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("sizes", type=int, nargs="*", default=[1024, 4096])
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args(argv)
    print("| canvas | full upload | render | readback | 64x64 dirty upload |")
    print("|---|---|---|---|---|")
    for size in args.sizes:
        t = time_render(size, args.repeats)
        print(
            f"| {size}x{size} | {t.full_upload_s * 1e3:.0f} ms | {t.render_s * 1e3:.0f} ms "
            f"| {t.readback_s * 1e3:.0f} ms | {t.dirty_64_upload_s * 1e3:.2f} ms |"
        )
    print(f"renderer: {t.renderer}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
